"""Race-control kinematics (paper App. B, eqs B.1-B.8) and their angle derivatives (C.21-C.33).

With the outer race stationary and the inner race at ``omega`` (rad/s), the ball orbital speed
omega_m, spin speed omega_b and the gyroscopic moment M_g = I_b omega_b omega_m sin(beta)
(eq 30, keeping the sign of omega_b, docs/model.md) are closed-form in alpha_i, alpha_o:

outer-race control (B.6-B.8), S = sqrt(1 + 2 gamma cos a_o + gamma^2), sin(beta) = sin a_o / S:
    omega_m = omega (1 - gamma cos a_i) / (1 + cos(a_i - a_o))
    omega_b = -omega S (1 - gamma cos a_i) / (gamma (1 + cos(a_i - a_o)))
    M_g     = -(I_b omega^2 / gamma) (1 - gamma cos a_i)^2 sin a_o / (1 + cos(a_i - a_o))^2
inner-race control (B.2-B.4), S' = sqrt(1 - 2 gamma cos a_i + gamma^2), sin(beta) = sin a_i / S':
    omega_m = omega (cos(a_i - a_o) - gamma cos a_o) / (1 + cos(a_i - a_o))
    omega_b = -omega S' (1 + gamma cos a_o) / (gamma (1 + cos(a_i - a_o)))
    M_g     = -(I_b omega^2 / gamma) (1 + gamma cos a_o)(cos(a_i - a_o) - gamma cos a_o) sin a_i
              / (1 + cos(a_i - a_o))^2
The derivatives below are the exact derivatives of these expressions (equivalent to C.21-C.33).
"""

from __future__ import annotations

import math

from numba import njit


@njit(cache=True, inline="always")
def race_control_kinematics(ci: float, si: float, co: float, so: float, omega: float,
                            gamma: float, ib: float, inner_control: bool):
    """Return (omega_m, domega_m/da_i, domega_m/da_o, M_g, dM_g/da_i, dM_g/da_o, omega_b).

    ``ci, si, co, so`` are cos/sin of alpha_i and alpha_o. The spin-axis angle beta, which the
    dynamics need only through sin(beta) (already in M_g), is :func:`spin_axis_angle`.
    """
    # one division for the whole group: 1/den and its powers by multiplication (this runs at
    # every ball residual; a division costs several multiplications)
    cd = ci * co + si * so          # cos(a_i - a_o)
    sd = si * co - ci * so          # sin(a_i - a_o)
    den = 1.0 + cd
    inv_g_den = 1.0 / (gamma * den)
    inv_den = gamma * inv_g_den     # 1 / den
    inv_den2 = inv_den * inv_den
    two_sd_den3 = 2.0 * sd * inv_den2 * inv_den
    cmg = ib * omega * omega * den * inv_g_den     # I_b omega^2 / gamma
    if not inner_control:
        a = 1.0 - gamma * ci
        wm = omega * a * inv_den
        dwm_dai = omega * (gamma * si * inv_den + a * sd * inv_den2)
        dwm_dao = -omega * a * sd * inv_den2
        mg = -cmg * a * a * so * inv_den2
        dmg_dai = -cmg * (2.0 * a * gamma * si * so * inv_den2 + a * a * so * two_sd_den3)
        dmg_dao = -cmg * (a * a * co * inv_den2 - a * a * so * two_sd_den3)
        s = math.sqrt(1.0 + 2.0 * gamma * co + gamma * gamma)
        wb = -omega * s * a * inv_g_den
    else:
        num = cd - gamma * co
        wm = omega * num * inv_den
        dwm_dai = omega * sd * (num - den) * inv_den2
        dwm_dao = omega * ((sd + gamma * so) * inv_den - num * sd * inv_den2)
        b = 1.0 + gamma * co
        pp = b * num
        dp_dai = -b * sd
        dp_dao = -gamma * so * num + b * (sd + gamma * so)
        mg = -cmg * pp * si * inv_den2
        dmg_dai = -cmg * (dp_dai * si * inv_den2 + pp * ci * inv_den2 + pp * si * two_sd_den3)
        dmg_dao = -cmg * (dp_dao * si * inv_den2 - pp * si * two_sd_den3)
        s = math.sqrt(1.0 - 2.0 * gamma * ci + gamma * gamma)
        wb = -omega * s * b * inv_g_den
    return wm, dwm_dai, dwm_dao, mg, dmg_dai, dmg_dao, wb


def spin_axis_angle(ci: float, si: float, co: float, so: float, gamma: float,
                    inner_control: bool) -> float:
    """Angle beta (rad) of the ball's spin axis (B.4 / B.8): atan2(sin a_o, cos a_o + gamma)
    under outer-race control, atan2(sin a_i, cos a_i - gamma) under inner-race control.

    A diagnostic (tests, analysis): it calls libm's atan2, so nothing that feeds the state uses
    it; the dynamics need only sin(beta), which :func:`race_control_kinematics` builds from
    basic operations."""
    if inner_control:
        return math.atan2(si, ci - gamma)
    return math.atan2(so, co + gamma)
