"""Layout of the flat float64 arrays handed to the numba kernels.

The frozen dataclasses of :mod:`bearing_gym.params` are converted once, here
(:func:`pack_params`), to:

* ``prm``: one float64 vector of the spindle's constants, indexed by the ``I_*`` constants below
  (numba treats module-level integers as compile-time constants);
* ``op``: the operating point, what changes while the spindle runs - shaft speed, radial loads,
  axial preload, and factors on the damping (1 in operation; the env's settling aid raises them)
  - indexed by the ``O_*`` constants (apart from ``prm``, so nothing that runs the spindle writes
  into its constants);
* ``race_wav``: (n_terms, 5) rows ``[race, kind, order, amplitude_m, phase_rad]`` with race 0 =
  inner, 1 = outer and kind 0 = radial (p), 1 = axial (q) (eqs 9-12);
* ``ball_wav``: (n_terms, 2) rows ``[order, amplitude_m]`` and ``ball_phase`` (N, n_terms)
  (eqs 13-14);
* ``ball_size``: (N,) ball oversize h_j (eqs 16-17).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from .hertz import N_HERTZ_COEF, hertz_polynomial
from .portable_math import sincos

if TYPE_CHECKING:  # pragma: no cover
    from bearing_gym.params import BearingParams

# geometry and material
I_NB = 0          # number of balls N
I_DB = 1          # ball diameter D_b
I_DP = 2          # pitch diameter D_p
I_RI = 3          # inner groove radius r_i
I_RO = 4          # outer groove radius r_o
I_COSA0 = 5       # cos(alpha_0)
I_SINA0 = 6       # sin(alpha_0)
I_CI = 7          # clearance c_i
I_CO = 8          # clearance c_o
I_EEFF = 9        # E / (1 - nu^2)
I_MB = 10         # ball mass m_b
I_IB = 11         # ball inertia I_b
I_GAM = 12        # gamma = D_b / D_p
I_RP = 13         # r_p: radius of the inner groove-centre locus (eq 4)
I_ZP = 14         # z_p: axial offset of the inner groove-centre locus (eq 4)
I_LI0 = 15        # nominal L_i (eq 16 without ball terms) used for the geometry of eqs 18-21
I_LO0 = 16        # nominal L_o (eq 17 without ball terms)
I_RYI = 17        # R_y of the inner contact (A.6)
I_RYO = 18        # R_y of the outer contact (A.7)
I_CONTROL = 19    # race control: 0 outer, 1 inner, 2 auto (Jones/Harris)
I_PHI0 = 20       # initial cage angle phi_0 (eq 6)
# rotor
I_MASS = 21
I_IR = 22
I_IZ = 23
I_ECC = 24
# damping coefficients (x, y, z, theta_x, theta_y)
I_CX = 25
I_CY = 26
I_CZ = 27
I_CTX = 28
I_CTY = 29
# integrator
I_DT = 30
I_NBETA = 31
I_NGAMMA = 32
I_NM_TOL = 33
I_NM_MAXIT = 34
I_NT_TOL = 35
I_NT_MAXIT = 36
I_DIVLIM = 37
# Hertz constants K(cos alpha) of the inner and outer contact as polynomials (hertz.hertz_polynomial)
I_KI = 38                    # 38..62: inner, the coefficients of K and of dK/d(cos alpha_i)
I_KO = I_KI + N_HERTZ_COEF   # outer
N_PRM = I_KO + N_HERTZ_COEF

# the operating point ``op`` (settable between advance calls; the env's kernel sets it every
# actuator update)
O_OMEGA = 0       # shaft speed omega (rad/s)
O_PX = 1          # radial load P_x (N)
O_PY = 2          # radial load P_y (N)
O_PZ = 3          # axial preload P (N), eq 35
O_DAMPING = 4     # 4..8: factors on the rotor's damping (prm I_CX..I_CTY) of x, y, z, theta_x, theta_y;
                  # 1 while the spindle runs, raised by the env's settling aid (envs.core.settle)
N_OP = 9

CONTROL_OUTER = 0
CONTROL_INNER = 1
CONTROL_AUTO = 2
_CONTROL_CODES = {"outer": CONTROL_OUTER, "inner": CONTROL_INNER, "auto": CONTROL_AUTO}


class PackedParams(NamedTuple):
    prm: np.ndarray
    race_wav: np.ndarray
    ball_wav: np.ndarray
    ball_phase: np.ndarray
    ball_size: np.ndarray
    op: np.ndarray


def pack_params(p: "BearingParams", damping_coefficients: np.ndarray | None = None) -> PackedParams:
    """Convert validated parameters to the flat arrays of this module (done once per Simulator).

    ``damping_coefficients`` (5,) overrides ``p.damping``; when both are absent the damping
    entries are zero (the Simulator fills them from the static-equilibrium stiffness).
    """
    g, mat, rot, ld, integ = p.geometry, p.material, p.rotor, p.loads, p.integrator
    prm = np.zeros(N_PRM)
    db, dp = g.ball_diameter_m, g.pitch_diameter_m
    ri, ro = g.inner_groove_radius_m, g.outer_groove_radius_m
    a0 = g.contact_angle_rad
    li0 = ri - db / 2.0 - g.clearance_inner_m
    lo0 = ro - db / 2.0 - g.clearance_outer_m
    prm[I_NB] = g.n_balls
    prm[I_DB] = db
    prm[I_DP] = dp
    prm[I_RI] = ri
    prm[I_RO] = ro
    sin_a0, cos_a0 = sincos(a0)
    prm[I_COSA0] = cos_a0
    prm[I_SINA0] = sin_a0
    prm[I_CI] = g.clearance_inner_m
    prm[I_CO] = g.clearance_outer_m
    prm[I_EEFF] = mat.youngs_modulus_pa / (1.0 - mat.poisson_ratio * mat.poisson_ratio)
    # m_b and I_b enter the ball model only through the centrifugal force (eq 29) and the
    # gyroscopic moment (eq 30): a switched-off term is a zero mass or inertia
    prm[I_MB] = p.ball_mass_kg if p.include_centrifugal else 0.0
    prm[I_IB] = p.ball_inertia_kg_m2 if p.include_gyroscopic else 0.0
    prm[I_GAM] = db / dp
    # the inner groove centre lies on the nominal contact line, radially outside the ball
    # centre (docs/model.md; consistent with eqs 18-19): r_p = D_p/2 + L_i cos a0, z_p = L_i sin a0
    prm[I_RP] = dp / 2.0 + li0 * cos_a0
    prm[I_ZP] = li0 * sin_a0
    prm[I_LI0] = li0
    prm[I_LO0] = lo0
    prm[I_RYI] = ri / (2.0 * ri / db - 1.0)
    prm[I_RYO] = ro / (2.0 * ro / db - 1.0)
    prm[I_CONTROL] = _CONTROL_CODES[p.race_control]
    prm[I_PHI0] = p.initial_cage_angle_rad
    prm[I_MASS] = rot.mass_kg
    prm[I_IR] = rot.inertia_radial_kg_m2
    prm[I_IZ] = rot.inertia_polar_kg_m2
    prm[I_ECC] = rot.eccentricity_m
    if damping_coefficients is None and p.damping.coefficients is not None:
        damping_coefficients = np.asarray(p.damping.coefficients, dtype=np.float64)
    if damping_coefficients is not None:
        prm[I_CX:I_CTY + 1] = damping_coefficients
    prm[I_DT] = integ.dt_s
    prm[I_NBETA] = integ.newmark_beta
    prm[I_NGAMMA] = integ.newmark_gamma
    prm[I_NM_TOL] = integ.newmark_tol_m
    prm[I_NM_MAXIT] = integ.newmark_max_iter
    prm[I_NT_TOL] = integ.newton_tol_m
    prm[I_NT_MAXIT] = integ.newton_max_iter
    prm[I_DIVLIM] = integ.divergence_limit_m
    prm[I_KI:I_KI + N_HERTZ_COEF] = hertz_polynomial(db, dp, prm[I_RYI], prm[I_EEFF], outer=False)
    prm[I_KO:I_KO + N_HERTZ_COEF] = hertz_polynomial(db, dp, prm[I_RYO], prm[I_EEFF], outer=True)

    rows = []
    for race_code, rw in ((0, p.waviness.inner), (1, p.waviness.outer)):
        for k, n in enumerate(rw.orders):
            if rw.radial_amplitudes_m[k] != 0.0:
                rows.append((race_code, 0, n, rw.radial_amplitudes_m[k], rw.radial_phases_rad[k]))
            if rw.axial_amplitudes_m[k] != 0.0:
                rows.append((race_code, 1, n, rw.axial_amplitudes_m[k], rw.axial_phases_rad[k]))
    race_wav = np.array(rows, dtype=np.float64).reshape(-1, 5)

    bw = p.waviness.balls
    n_balls = g.n_balls
    keep = [k for k, a in enumerate(bw.amplitudes_m) if a != 0.0]
    ball_wav = np.array([(bw.orders[k], bw.amplitudes_m[k]) for k in keep],
                        dtype=np.float64).reshape(-1, 2)
    ball_phase = np.zeros((n_balls, len(keep)))
    if keep:
        if isinstance(bw.phases_rad[0], tuple):
            ball_phase[:] = np.array(bw.phases_rad, dtype=np.float64)[:, keep]
        else:
            ball_phase[:] = np.array(bw.phases_rad, dtype=np.float64)[keep][None, :]
    ball_size = np.zeros(n_balls)
    if bw.oversize_m:
        ball_size[:] = bw.oversize_m
    op = np.zeros(N_OP)
    op[O_OMEGA] = p.shaft_speed_rad_s
    op[O_PX] = ld.radial_load_x_n
    op[O_PY] = ld.radial_load_y_n
    op[O_PZ] = ld.axial_preload_n
    op[O_DAMPING:O_DAMPING + 5] = 1.0
    return PackedParams(prm, race_wav, ball_wav, ball_phase, ball_size, op)
