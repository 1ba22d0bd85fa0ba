"""Bearing force vector: ball positions and waviness of a time step (eqs 6, 9-14), transformation
(eqs 3-5), ball contact forces on the inner race (eq 32, with the z- and phi-row errata corrected)
and their sum (eq 33); cage speed (eq 7)."""

from __future__ import annotations

import numpy as np
from numba import njit

from .ball import (B_CI, B_CO, B_CTRL, B_LAMI, B_MG, B_QI, B_QO, B_SI, B_SO, B_WM, BALL_OK,
                   prefers_outer_control, solve_ball)
from .layout import (CONTROL_AUTO, CONTROL_INNER, I_CONTROL, I_DB, I_NB, I_PHI0, I_RI,
                     I_RP, I_ZP)
from .portable_math import PI, sincos
from .waviness import ball_waviness, race_waviness_all_balls


# columns of the per-ball geometry of one time step (:func:`ball_geometry`)
G_COS = 0     # cos(phi_j), eq 6
G_SIN = 1     # sin(phi_j)
G_PI = 2      # inner-race radial waviness p_ij (eq 9)
G_QI = 3      # inner-race axial waviness q_ij (eq 11)
G_PO = 4      # outer-race radial waviness p_oj (eq 10)
G_QO = 5      # outer-race axial waviness q_oj (eq 12)
G_WI = 6      # ball waviness at the inner contact w_ij (eq 13)
G_WO = 7      # ball waviness at the outer contact w_oj (eq 14)
N_GEO = 8


@njit(cache=True, inline="always")
def ball_angle(j, n_balls, cage_angle, phi0):
    """Angular location of ball j (eq 6, j counted from 0)."""
    return 2.0 * PI * j / n_balls + cage_angle + phi0


@njit(cache=True)
def ball_geometry(cage_angle, shaft_angle, psi_b, prm, race_wav, ball_wav, ball_phase, geo):
    """What the bearing force needs of the angles at one time step, written into ``geo`` (N, N_GEO):
    cos and sin of each ball's angle (eq 6) and its race and ball waviness (eqs 9-14).

    The cage, shaft and ball spin angles advance explicitly between steps (eqs 8, 15), so these
    are fixed while the Newmark iterations of a step evaluate the force again and again.
    """
    n = int(prm[I_NB])
    cage_phase = cage_angle + prm[I_PHI0]                     # phi_0 of ball 0 (eq 6)
    s, c = sincos(cage_phase)
    sd, cd = sincos(2.0 * PI / n)
    for j in range(n):
        # eq 6 by rotation: ball j + 1 sits 2 pi / N further on
        geo[j, G_COS] = c
        geo[j, G_SIN] = s
        c, s = c * cd - s * sd, s * cd + c * sd
        for col in range(G_PI, N_GEO):
            geo[j, col] = 0.0
        w_i, w_o = ball_waviness(ball_wav, ball_phase, j, psi_b[j])
        geo[j, G_WI] = w_i
        geo[j, G_WO] = w_o
    race_waviness_all_balls(race_wav, cage_phase, shaft_angle, n, geo, G_PI)


@njit(cache=True)
def bearing_force(U, cage_angle, shaft_angle, psi_b, prm, omega, race_wav, ball_wav, ball_phase,
                  ball_size, ball_v, ball_out, F):
    """Total bearing force on the rotor at the given angles (eqs 3-33), written into F: the
    ball geometry of :func:`ball_geometry`, then :func:`bearing_force_on`. Returns the worst
    ball status (0 = all converged). The integrator calls the two parts itself (the geometry
    once per step)."""
    geo = np.empty((int(prm[I_NB]), N_GEO))
    ball_geometry(cage_angle, shaft_angle, psi_b, prm, race_wav, ball_wav, ball_phase, geo)
    return bearing_force_on(U, geo, prm, omega, ball_size, ball_v, ball_out, F)


@njit(cache=True)
def bearing_force_on(U, geo, prm, omega, ball_size, ball_v, ball_out, F):
    """Total bearing force on the rotor, F = sum_j T_j^T Q_j (eqs 3-5, 32-33), written into F.

    ``U`` = (x, y, z, theta_x, theta_y); ``geo`` the step's ball geometry
    (:func:`ball_geometry`); ``omega`` the shaft speed (rad/s); ``ball_v`` (N, 2) holds each ball's (v_r, v_z), used as the Newton
    warm start and overwritten with the solution; ``ball_out`` receives the contact state
    (``ball.B_*`` columns). Returns the worst ball status (0 = all converged).
    """
    n = int(prm[I_NB])
    db = prm[I_DB]
    ri = prm[I_RI]
    control = int(prm[I_CONTROL])
    half_db = 0.5 * db
    for k in range(5):
        F[k] = 0.0
    worst = BALL_OK
    for j in range(n):
        c = geo[j, G_COS]
        s = geo[j, G_SIN]
        p_i = geo[j, G_PI]
        q_i = geo[j, G_QI]
        p_o = geo[j, G_PO]
        q_o = geo[j, G_QO]
        zp = prm[I_ZP] + q_i
        rp = prm[I_RP] + p_i
        # eq 3-5: u = T U + dW
        ur = U[0] * c + U[1] * s + zp * (-U[3] * s + U[4] * c) + (p_i - p_o)
        uz = U[2] + rp * (U[3] * s - U[4] * c) + (q_i - q_o)
        size = half_db + 0.5 * ball_size[j]
        dist_i = ri - size - geo[j, G_WI]              # eq 16 + c_i
        dist_o = prm[I_RI + 1] - size - geo[j, G_WO]   # eq 17 + c_o (I_RO = I_RI + 1)
        if control == CONTROL_AUTO:
            inner_ctrl = ball_out[j, B_CTRL] > 0.5
        else:
            inner_ctrl = control == CONTROL_INNER
        vr, vz, st = solve_ball(ball_v[j, 0], ball_v[j, 1], ur, uz, dist_i, dist_o, omega,
                                inner_ctrl, prm, ball_out, j)
        if control == CONTROL_AUTO and st == BALL_OK:
            want_outer = prefers_outer_control(ball_out[j, B_QI], ball_out[j, B_QO],
                                               ball_out[j, B_CI], ball_out[j, B_SI],
                                               ball_out[j, B_CO], ball_out[j, B_SO], prm)
            if want_outer == inner_ctrl:
                inner_ctrl = not inner_ctrl
                vr, vz, st = solve_ball(vr, vz, ur, uz, dist_i, dist_o, omega, inner_ctrl,
                                        prm, ball_out, j)
        ball_v[j, 0] = vr
        ball_v[j, 1] = vz
        if st > worst:
            worst = st
        qi = ball_out[j, B_QI]
        ci = ball_out[j, B_CI]
        si = ball_out[j, B_SI]
        mg = ball_out[j, B_MG]
        lam_i = ball_out[j, B_LAMI]
        # eq 32 (corrected): force and moment of ball j on the inner race
        q_r = -qi * ci - lam_i * mg / db * si
        q_z = -qi * si + lam_i * mg / db * ci
        q_phi = lam_i * mg * ri / db
        # eq 33: F += T_j^T Q_j
        F[0] += c * q_r
        F[1] += s * q_r
        F[2] += q_z
        F[3] += -zp * s * q_r + rp * s * q_z - s * q_phi
        F[4] += zp * c * q_r - rp * c * q_z + c * q_phi
    return worst


@njit(cache=True, inline="always")
def cage_speed(ball_out, n_balls, previous):
    """Cage speed, eq 7: mean orbital speed of the balls touching the inner race.

    With no ball on the inner race the cage is not driven; it keeps ``previous`` (it coasts).
    """
    total = 0.0
    count = 0
    for j in range(n_balls):
        if ball_out[j, B_QI] > 0.0:
            total += ball_out[j, B_WM]
            count += 1
    if count == 0:
        return previous
    return total / count
