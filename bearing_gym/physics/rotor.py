"""Rotor equations of motion (paper eq 35) with viscous damping, and the Newmark-beta
integrator with equilibrium iterations at every step (section 2.4).

Eq 35 with the damping the paper leaves out (see ``params.Damping``):

    m x''  + c_x x'  = F_x + P_x + m e omega^2 cos(theta_s)
    m y''  + c_y y'  = F_y + P_y + m e omega^2 sin(theta_s)
    m z''  + c_z z'  = F_z + P
    I_r tx'' + c_tx tx' + I_z omega ty' = M_x
    I_r ty'' + c_ty ty' - I_z omega tx' = M_y

theta_s is the shaft angle (omega t at constant speed). The bearing force depends on the
displacement only (the balls are quasi-static), so each Newmark step is solved by fixed-point
iteration on the displacement (predictor: a_{n+1} extrapolated quadratically from a_n, a_{n-1},
a_{n-2}, and each ball's Newton warm start extrapolated quadratically from its last three steps): for a given F(X_{n+1}) the acceleration follows from the
linear system (M + gamma dt (C + G)) a = F + P - (C + G) v*, with v* = v_n + (1 - gamma) dt a_n,
then X_{n+1} = X_n + dt v_n + dt^2 ((1/2 - beta) a_n + beta a_{n+1}); the iteration contracts
by theta ~ beta (omega_max dt)^2 per pass (measured: 1e-4 to 4e-4 at dt = 10 us). The cage angle
(eq 8) and the ball spin angles (eq 15) advance explicitly with the speeds of the previous step.

Stopping rule (a posteriori, as RADAU5's simplified Newton iteration: Hairer & Wanner, *Solving
ODEs II*, 2nd ed., section IV.8, eqs 8.10-8.12): an iterate X_k whose change was |dX_k| is within
eta |dX_k| of the fixed point, eta = theta / (1 - theta), theta = |dX_k| / |dX_{k-1}| the observed
contraction; it is accepted when eta |dX_k| < ``newmark_tol_m`` (rotations compared at the groove
radius). On the first pass of a step, before a contraction is observed, eta is the last measured
one raised to 0.8 (``max(eta_old, EPS)^0.8``: it grows back towards 1 from step to step, so it is
measured again every few steps); eta is 1 (the plain criterion |dX| < tol) until the first
measurement. Accepting on an error estimate instead of on |dX| < tol saves the second
bearing-force evaluation of most steps where a fast forcing (race waviness of order 18 passes a
ball in ~12 steps) defeats the acceleration predictor.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .ball import B_QI, B_QO, B_VR_PREV, B_VR_PREV2, B_VZ_PREV, B_VZ_PREV2, B_WB
from .bearing import N_GEO, ball_geometry, bearing_force_on, cage_speed
from .layout import (I_CTX, I_CTY, I_CX, I_CY, I_CZ, I_DIVLIM, I_DT, I_ECC, I_IR, I_IZ, I_MASS,
                     I_NB, I_NBETA, I_NGAMMA, I_NM_MAXIT, I_NM_TOL, I_RP, O_DAMPING, O_OMEGA,
                     O_PX, O_PY, O_PZ)
from .portable_math import cube_root_near, pow, sincos
from .status import ST_DIVERGED, ST_NEWMARK_NOT_CONVERGED, ST_OK  # noqa: F401 - ST_OK re-exported

# status codes of integrate(): .status (ST_OK, ST_NEWMARK_NOT_CONVERGED, ST_DIVERGED; the ball
# solver's codes pass through)

# scalar state vector ``scal``
S_T = 0            # time (s)
S_SHAFT = 1        # shaft angle theta_s (rad)
S_CAGE = 2         # cage angle psi_c (rad), eq 8
S_CAGE_SPEED = 3   # cage speed omega_c (rad/s), eq 7
S_A_PREV = 4       # 4..8: acceleration of the previous step (predictor extrapolation)
S_N_EVAL = 9       # bearing-force evaluations so far (diagnostics)
S_A_PREV2 = 10     # 10..14: acceleration two steps back
S_ETA = 15         # eta = theta / (1 - theta) of the last measured contraction (0: not yet measured)
# contact-load accumulators over accepted steps (Lundberg-Palmgren life, :mod:`.rating`); they
# only add up (the env's kernel zeroes them at the start of each control interval)
S_SUM_QI3 = 16     # sum over steps of sum_j Q_ij^3 (N^3), inner contacts
S_SUM_QO10_3 = 17  # sum over steps of sum_j Q_oj^(10/3) (N^(10/3)), outer contacts
S_LOAD_STEPS = 18  # steps accumulated
S_MAX_QI = 19      # largest inner contact load (N)
S_MAX_QO = 20      # largest outer contact load (N)
N_SCAL = 21

ETA_GROWTH = 0.8   # eta_0 = max(eta_old, EPS)^0.8 on a step's first pass (Hairer & Wanner IV.8)
THETA_MAX = 0.99   # contraction beyond which eta is capped (the iteration is failing)
EPS = 2.220446049250313e-16

# record columns
R_T = 0
R_X = 1            # 1..5: x, y, z, theta_x, theta_y
R_V = 6            # 6..10: velocities
R_CAGE_SPEED = 11
R_CAGE_ANGLE = 12
R_F = 13           # 13..17: bearing force F_x, F_y, F_z, M_x, M_y
R_SHAFT = 18
R_N_INNER = 19     # number of balls touching the inner race
N_REC = 20


@njit(cache=True, inline="always")
def solve_acceleration(F, prm, op, cos_shaft, sin_shaft, vstar, a_out):
    """Solve eq 35 (with damping) for the acceleration at velocity v = v* + gamma dt a.

    (M + gamma dt (C + G)) a = F + P + unbalance - (C + G) v*, with the unbalance force
    m e omega^2 (cos theta_s, sin theta_s) at the shaft angle theta_s; speed, loads and the
    damping's factors from the operating point ``op`` (``O_*``).
    """
    m = prm[I_MASS]
    ir = prm[I_IR]
    omega = op[O_OMEGA]
    gdt = prm[I_NGAMMA] * prm[I_DT]
    unb = m * prm[I_ECC] * omega * omega
    cx = prm[I_CX] * op[O_DAMPING]          # the damping in effect: the nominal times op's factor
    cy = prm[I_CY] * op[O_DAMPING + 1]
    cz = prm[I_CZ] * op[O_DAMPING + 2]
    ctx = prm[I_CTX] * op[O_DAMPING + 3]
    cty = prm[I_CTY] * op[O_DAMPING + 4]
    a_out[0] = (F[0] + op[O_PX] + unb * cos_shaft - cx * vstar[0]) / (m + gdt * cx)
    a_out[1] = (F[1] + op[O_PY] + unb * sin_shaft - cy * vstar[1]) / (m + gdt * cy)
    a_out[2] = (F[2] + op[O_PZ] - cz * vstar[2]) / (m + gdt * cz)
    g = prm[I_IZ] * omega
    # [[ir + gdt ctx, gdt g], [-gdt g, ir + gdt cty]] (atx, aty) = (rx, ry)
    rx = F[3] - ctx * vstar[3] - g * vstar[4]
    ry = F[4] - cty * vstar[4] + g * vstar[3]
    a11 = ir + gdt * ctx
    a12 = gdt * g
    a21 = -gdt * g
    a22 = ir + gdt * cty
    det = a11 * a22 - a12 * a21
    a_out[3] = (a22 * rx - a12 * ry) / det
    a_out[4] = (-a21 * rx + a11 * ry) / det


@njit(cache=True, inline="always")
def newmark_predictor(X, V, A, dt, beta, gam, base, vstar):
    """Newmark-beta: the parts of X_{n+1} and V_{n+1} known before a_{n+1}.

    X_{n+1} = base + beta dt^2 a_{n+1},   base = X_n + dt V_n + (1/2 - beta) dt^2 A_n
    V_{n+1} = vstar + gamma dt a_{n+1},   vstar = V_n + (1 - gamma) dt A_n
    """
    for k in range(X.shape[0]):
        vstar[k] = V[k] + (1.0 - gam) * dt * A[k]
        base[k] = X[k] + dt * V[k] + (0.5 - beta) * dt * dt * A[k]


@njit(cache=True, inline="always")
def newmark_displacement(base_k, a_k, dt, beta):
    """X_{n+1} = base + beta dt^2 a_{n+1} (see :func:`newmark_predictor`)."""
    return base_k + beta * dt * dt * a_k


@njit(cache=True, inline="always")
def newmark_velocity(vstar_k, a_k, dt, gam):
    """V_{n+1} = vstar + gamma dt a_{n+1} (see :func:`newmark_predictor`)."""
    return vstar_k + gam * dt * a_k


@njit(cache=True)
def integrate(prm, op, race_wav, ball_wav, ball_phase, ball_size, X, V, A, scal, psi_b, ball_v,
              ball_out, n_steps, record_every, rec):
    """Advance the rotor-bearing system ``n_steps`` Newmark steps in place.

    Constants ``prm`` (``I_*``), operating point ``op`` (``O_*``: speed, loads, preload; read, not
    written). State: X, V, A (5,), ``scal`` (S_* entries), ball spin angles ``psi_b`` (N,), ball
    displacements ``ball_v`` (N, 2) and contact state ``ball_out``. Every ``record_every``
    steps one row of ``rec`` (R_* columns) is written. Returns (status, steps_done, rows).
    No allocation happens inside the step loop.
    """
    n = int(prm[I_NB])
    dt = prm[I_DT]
    beta = prm[I_NBETA]
    gam = prm[I_NGAMMA]
    tol = prm[I_NM_TOL]
    maxit = int(prm[I_NM_MAXIT])
    divlim = prm[I_DIVLIM]
    omega = op[O_OMEGA]
    rot_scale = prm[I_RP]          # rotations compared as displacements at the groove radius
    F = np.zeros(5)
    Xn = np.zeros(5)
    a_new = np.zeros(5)
    vstar = np.zeros(5)
    base = np.zeros(5)
    geo = np.zeros((n, N_GEO))
    qo_cbrt = np.zeros(n)          # each outer load's cube root at the last step (Q^(10/3) = Q^3 Q^(1/3))
    status = ST_OK
    rows = 0
    done = 0
    for step in range(n_steps):
        # explicit kinematic updates, eqs 8 and 15
        scal[S_T] += dt
        scal[S_SHAFT] += omega * dt
        scal[S_CAGE] += scal[S_CAGE_SPEED] * dt
        for j in range(n):
            psi_b[j] += ball_out[j, B_WB] * dt
            # warm start of the ball Newton: quadratic extrapolation of the last three steps
            vr = ball_v[j, 0]
            vz = ball_v[j, 1]
            ball_v[j, 0] = 3.0 * vr - 3.0 * ball_out[j, B_VR_PREV] + ball_out[j, B_VR_PREV2]
            ball_v[j, 1] = 3.0 * vz - 3.0 * ball_out[j, B_VZ_PREV] + ball_out[j, B_VZ_PREV2]
            ball_out[j, B_VR_PREV2] = ball_out[j, B_VR_PREV]
            ball_out[j, B_VZ_PREV2] = ball_out[j, B_VZ_PREV]
            ball_out[j, B_VR_PREV] = vr
            ball_out[j, B_VZ_PREV] = vz
        # what the angles fix for the whole step: ball positions and waviness, unbalance phase
        ball_geometry(scal[S_CAGE], scal[S_SHAFT], psi_b, prm, race_wav, ball_wav, ball_phase,
                      geo)
        sin_shaft, cos_shaft = sincos(scal[S_SHAFT])
        newmark_predictor(X, V, A, dt, beta, gam, base, vstar)
        for k in range(5):
            # predictor: a_{n+1} extrapolated quadratically from a_n, a_{n-1}, a_{n-2}
            a_pred = 3.0 * A[k] - 3.0 * scal[S_A_PREV + k] + scal[S_A_PREV2 + k]
            scal[S_A_PREV2 + k] = scal[S_A_PREV + k]
            scal[S_A_PREV + k] = A[k]
            Xn[k] = newmark_displacement(base[k], a_pred, dt, beta)
        converged = False
        eta = scal[S_ETA]
        eta = 1.0 if eta <= 0.0 else pow(max(eta, EPS), ETA_GROWTH)
        diff_prev = 0.0
        for it in range(maxit):
            scal[S_N_EVAL] += 1.0
            st = bearing_force_on(Xn, geo, prm, omega, ball_size, ball_v, ball_out, F)
            if st != 0:
                status = st
                break
            solve_acceleration(F, prm, op, cos_shaft, sin_shaft, vstar, a_new)
            diff = 0.0
            for k in range(5):
                x_new = newmark_displacement(base[k], a_new[k], dt, beta)
                d = abs(x_new - Xn[k])
                if k >= 3:
                    d *= rot_scale
                if d > diff:
                    diff = d
                Xn[k] = x_new
            if it > 0 and diff_prev > 0.0:
                theta = min(diff / diff_prev, THETA_MAX)
                eta = theta / (1.0 - theta)
            diff_prev = diff
            if eta * diff < tol:
                converged = True
                break
        scal[S_ETA] = eta
        if status != ST_OK:
            break
        if not converged:
            status = ST_NEWMARK_NOT_CONVERGED
            break
        bad = False
        for k in range(5):
            X[k] = Xn[k]
            A[k] = a_new[k]
            V[k] = newmark_velocity(vstar[k], a_new[k], dt, gam)
            if not math.isfinite(X[k]) or not math.isfinite(V[k]):
                bad = True
        if bad or abs(X[0]) > divlim or abs(X[1]) > divlim or abs(X[2]) > divlim \
                or abs(X[3]) * rot_scale > divlim or abs(X[4]) * rot_scale > divlim:
            status = ST_DIVERGED
            break
        scal[S_CAGE_SPEED] = cage_speed(ball_out, n, scal[S_CAGE_SPEED])
        done += 1
        accumulate_contact_loads(ball_out, n, scal, qo_cbrt)
        if done % record_every == 0 and rows < rec.shape[0]:
            rec[rows, R_T] = scal[S_T]
            n_inner = 0
            for j in range(n):
                if ball_out[j, B_QI] > 0.0:
                    n_inner += 1
            for k in range(5):
                rec[rows, R_X + k] = X[k]
                rec[rows, R_V + k] = V[k]
                rec[rows, R_F + k] = F[k]
            rec[rows, R_CAGE_SPEED] = scal[S_CAGE_SPEED]
            rec[rows, R_CAGE_ANGLE] = scal[S_CAGE]
            rec[rows, R_SHAFT] = scal[S_SHAFT]
            rec[rows, R_N_INNER] = n_inner
            rows += 1
    return status, done, rows


@njit(cache=True, inline="always")
def accumulate_contact_loads(ball_out, n, scal, qo_cbrt):
    """Add the accepted step's contact loads (``ball_out``, the step's last force evaluation) to
    the S_SUM_QI3 ... S_MAX_QO accumulators. Q_o^(10/3) = Q_o^3 Q_o^(1/3), the cube root by
    :func:`.portable_math.cube_root_near` from the same ball's root at the last step (``qo_cbrt``)."""
    s3 = 0.0
    s10 = 0.0
    qi_max = scal[S_MAX_QI]
    qo_max = scal[S_MAX_QO]
    for j in range(n):
        qi = ball_out[j, B_QI]
        qo = ball_out[j, B_QO]
        s3 += qi * qi * qi
        if qo > 0.0:
            qo_cbrt[j] = cube_root_near(qo, qo_cbrt[j])
            s10 += qo * qo * qo * qo_cbrt[j]
        if qi > qi_max:
            qi_max = qi
        if qo > qo_max:
            qo_max = qo
    scal[S_SUM_QI3] += s3
    scal[S_SUM_QO10_3] += s10
    scal[S_LOAD_STEPS] += 1.0
    scal[S_MAX_QI] = qi_max
    scal[S_MAX_QO] = qo_max
