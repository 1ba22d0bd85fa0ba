"""Bearing ratings from contact loads: Lundberg-Palmgren fatigue life of the ball-race contacts,
the ISO 76 static load rating and Palmgren's load-dependent friction torque.

Fatigue life (Lundberg & Palmgren, *Dynamic capacity of rolling bearings*, Acta Polytechnica,
Mech. Eng. Ser. 1(3), 1947; as given by Harris & Kotzalas, *Rolling Bearing Analysis*, 5th ed.,
vol. 2 *Advanced Concepts of Bearing Technology*, ch. 8 "Fatigue life: basic theory and rating
standards"; the per-race formulas ISO/TS 16281:2008 builds its basic reference rating life on).
Per raceway, the basic dynamic capacity of a ball contact, the contact load for which 90 % of a
population of raceways survive 10^6 revolutions (N, with D in mm):

    Q_c = 98.1 (2 f / (2 f - 1))^0.41 (1 -+ gamma)^1.39 / (1 +- gamma)^(1/3) (gamma / cos alpha)^0.3
          D^1.8 Z^(-1/3)

upper signs for the inner race, lower for the outer; f = r / D the groove radius over the ball
diameter of that race, gamma = D cos alpha / d_m, Z the number of balls, alpha the nominal contact
angle (the operating angles differ by a few degrees at speed; through (1 -+ gamma) that moves
Q_c by under 1 %; (gamma / cos alpha)^0.3 = (D / d_m)^0.3 does not depend on it). The equivalent
load of a race is the mean of the ball loads over the balls (and over time: Palmgren-Miner) with
the exponent of the race's stress cycles: a point of the rotating inner race meets every ball
load, w = 3; a point of the stationary outer race meets the loads at its own angle, w = 10/3:

    Q_ei = (mean_j Q_ij^3)^(1/3),    Q_eo = (mean_j Q_oj^(10/3))^(3/10)
    L_i = (Q_ci / Q_ei)^3,  L_o = (Q_co / Q_eo)^3     (10^6 revolutions)
    L_10 = (L_i^(-10/9) + L_o^(-10/9))^(-9/10)         (the bearing: both races must survive)

The loads Q_ij, Q_oj are the model's (each ball in quasi-static equilibrium with its centrifugal
force, eq 28 of Bai & Xu), so the outer race carries the centrifugal force: at 20,000 rpm about
1.7 kN per ball, at 25,000 rpm 2.6 kN.

Static load rating (ISO 76:2006, radial and angular-contact ball bearings): C_0 = f_0 i Z D^2
cos alpha (N, mm) with f_0 from its Table 2 at D cos alpha / d_m (interpolated linearly; the
table assumes groove radii up to 0.52 D inner, 0.53 D outer), and the static equivalent load
P_0 = max(F_r, X_0 F_r + Y_0 F_a), X_0 = 0.5, Y_0 of a single-row angular-contact bearing from
ISO 76's table by contact angle.

Friction torque, load term (Palmgren, *Ball and Roller Bearing Engineering*, 3rd ed., 1959;
Harris & Kotzalas vol. 1 *Essential Concepts of Bearing Technology*, ch. "Friction in rolling
bearings"): M_1 = f_1 P_1 d_m with f_1 = 0.001 (P_0 / C_0)^0.33 for angular-contact ball
bearings and P_1 = max(F_a - 0.1 F_r, F_r) for a single-row angular-contact bearing. The
viscous term M_0 (lubricant, speed) is not modelled.

Everything that can feed the reward uses the portable powers of :mod:`.portable_math`.
"""

from __future__ import annotations

import math

import numpy as np

from .equilibrium import static_equilibrium
from .portable_math import TWO_PI, cbrt, cos, pow, pow_array

__all__ = ["dynamic_capacities_n", "life_used_per_revolution", "static_life_used_per_s", "static_capacity_n",
           "static_equivalent_load_n", "friction_torque_n_m",
           "INNER_LIFE_EXPONENT", "OUTER_LIFE_EXPONENT", "RACE_COMBINATION_EXPONENT"]

INNER_LIFE_EXPONENT = 3.0            # w of the rotating inner race
OUTER_LIFE_EXPONENT = 10.0 / 3.0     # w of the stationary outer race
RACE_COMBINATION_EXPONENT = 10.0 / 9.0
LIFE_REVOLUTIONS = 1e6               # L is counted in millions of revolutions
_CAPACITY_CONSTANT = 98.1            # N, with D in mm (Harris & Kotzalas)

# ISO 76:2006 Table 2, radial and angular-contact ball bearings: f_0 at D cos(alpha) / d_m =
# 0.00, 0.01, ..., 0.40
_F0_TABLE = (14.7, 14.9, 15.1, 15.3, 15.5, 15.7, 15.9, 16.1, 16.3, 16.5, 16.4, 16.1, 15.9, 15.6, 15.4, 15.2,
             14.9, 14.7, 14.4, 14.2, 14.0, 13.7, 13.5, 13.2, 13.0, 12.8, 12.5, 12.3, 12.1, 11.8, 11.6, 11.4,
             11.2, 10.9, 10.7, 10.5, 10.3, 10.0, 9.8, 9.6, 9.4)
# ISO 76:2006, single-row angular-contact ball bearings: Y_0 at alpha = 15, 20, ..., 45 deg; X_0 = 0.5
_Y0_ANGLES_DEG = (15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 45.0)
_Y0_TABLE = (0.46, 0.42, 0.38, 0.33, 0.29, 0.26, 0.22)
STATIC_X0 = 0.5
FRICTION_Z = 0.001                   # f_1 = z (P_0 / C_0)^y, angular-contact ball bearings
FRICTION_Y = 0.33


def _gamma(geometry) -> float:
    return geometry.ball_diameter_m * cos(geometry.contact_angle_rad) / geometry.pitch_diameter_m


def dynamic_capacities_n(geometry) -> tuple[float, float]:
    """(Q_ci, Q_co): basic dynamic capacity (N) of a ball contact on the inner and the outer race
    (module docstring; Harris & Kotzalas vol. 2 ch. 8), from a
    :class:`~bearing_gym.params.BearingGeometry` (SI units; D in mm inside the formula)."""
    d_mm = geometry.ball_diameter_m * 1e3
    gamma = _gamma(geometry)
    common = (_CAPACITY_CONSTANT * pow(geometry.ball_diameter_m / geometry.pitch_diameter_m, 0.3)
              * pow(d_mm, 1.8) / cbrt(float(geometry.n_balls)))
    out = []
    for groove_radius_m, sign in ((geometry.inner_groove_radius_m, -1.0), (geometry.outer_groove_radius_m, 1.0)):
        f = groove_radius_m / geometry.ball_diameter_m
        conformity = pow(2.0 * f / (2.0 * f - 1.0), 0.41)
        out.append(common * conformity * pow(1.0 + sign * gamma, 1.39) / cbrt(1.0 - sign * gamma))
    return out[0], out[1]


def life_used_per_revolution(inner_q3_mean, outer_q10_3_mean, capacities_n: tuple[float, float]) -> np.ndarray:
    """1 / (L_10 10^6): the fraction of the bearing's L10 life one revolution uses at the given
    means of Q_i^3 and Q_o^(10/3) over the balls (and time), N^3 and N^(10/3).

    Written with the inverse lives, so an unloaded race costs 0 instead of dividing by zero:
    1 / L_i = mean(Q_i^3) / Q_ci^3, 1 / L_o = mean(Q_o^(10/3))^(9/10) / Q_co^3 and
    1 / L_10 = ((1 / L_i)^(10/9) + (1 / L_o)^(10/9))^(9/10)."""
    q_ci, q_co = capacities_n
    inner = np.atleast_1d(np.asarray(inner_q3_mean, dtype=np.float64))
    outer = np.atleast_1d(np.asarray(outer_q10_3_mean, dtype=np.float64))
    inv_li = inner / (q_ci * q_ci * q_ci)
    inv_lo = pow_array(outer, INNER_LIFE_EXPONENT / OUTER_LIFE_EXPONENT) / (q_co * q_co * q_co)
    e = RACE_COMBINATION_EXPONENT
    inv_l10 = pow_array(pow_array(inv_li, e) + pow_array(inv_lo, e), 1.0 / e)
    return inv_l10 / LIFE_REVOLUTIONS


def static_life_used_per_s(params) -> float:
    """u (1/s): the fraction of the L10 life used per second at the static equilibrium of
    ``params`` (:func:`.equilibrium.static_equilibrium`: no unbalance; its speed and loads), the
    means over the balls as exact sums (``math.fsum``) and the powers the portable ones, so the
    same number on every CPU."""
    eq = static_equilibrium(params)
    z = len(eq.q_i)
    qi3 = math.fsum(float(q) * float(q) * float(q) for q in eq.q_i) / z
    qo10_3 = math.fsum(pow_array(np.asarray(eq.q_o, dtype=np.float64), OUTER_LIFE_EXPONENT).tolist()) / z
    per_rev = life_used_per_revolution(qi3, qo10_3, dynamic_capacities_n(params.geometry))[0]
    return float(per_rev * params.shaft_speed_rad_s / TWO_PI)


def _interp(x: float, xs, ys) -> float:
    """Linear interpolation in a table, held at its ends."""
    if x <= xs[0]:
        return ys[0]
    for k in range(1, len(xs)):
        if x <= xs[k]:
            w = (x - xs[k - 1]) / (xs[k] - xs[k - 1])
            return ys[k - 1] + w * (ys[k] - ys[k - 1])
    return ys[-1]


def static_capacity_n(geometry) -> float:
    """C_0 (N): ISO 76 basic static radial load rating of a single-row (i = 1) radial or
    angular-contact ball bearing, f_0 i Z D^2 cos(alpha) with D in mm."""
    gamma = _gamma(geometry)
    f0 = _interp(gamma, tuple(0.01 * k for k in range(len(_F0_TABLE))), _F0_TABLE)
    d_mm = geometry.ball_diameter_m * 1e3
    return f0 * geometry.n_balls * d_mm * d_mm * cos(geometry.contact_angle_rad)


def static_equivalent_load_n(geometry, radial_load_n, axial_load_n) -> np.ndarray:
    """P_0 (N): ISO 76 static equivalent load max(F_r, X_0 F_r + Y_0 F_a) of a single-row
    angular-contact ball bearing (Y_0 interpolated in ISO 76's table by the contact angle)."""
    y0 = _interp(math.degrees(geometry.contact_angle_rad), _Y0_ANGLES_DEG, _Y0_TABLE)
    fr = np.asarray(radial_load_n, dtype=np.float64)
    return np.maximum(fr, STATIC_X0 * fr + y0 * np.asarray(axial_load_n, dtype=np.float64))


def friction_torque_n_m(geometry, radial_load_n, axial_load_n) -> np.ndarray:
    """Palmgren's load-dependent friction torque M_1 = f_1 P_1 d_m (N m) of a single-row
    angular-contact ball bearing: f_1 = 0.001 (P_0 / C_0)^0.33, P_1 = max(F_a - 0.1 F_r, F_r)."""
    fr = np.atleast_1d(np.asarray(radial_load_n, dtype=np.float64))
    fa = np.atleast_1d(np.asarray(axial_load_n, dtype=np.float64))
    p0 = static_equivalent_load_n(geometry, fr, fa) / static_capacity_n(geometry)
    f1 = FRICTION_Z * pow_array(np.maximum(p0, 0.0), FRICTION_Y)
    p1 = np.maximum(fa - 0.1 * fr, fr)
    return f1 * p1 * geometry.pitch_diameter_m

