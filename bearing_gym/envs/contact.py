"""The bearing's contact state over one control interval (used by the env's step kernel): what
the fatigue term of the reward and a spindle engineer's ``info`` read.

``interval_contact`` fills one row (``C_*`` columns, SI units) from the contact-load
accumulators :func:`bearing_gym.physics.rotor.integrate` keeps in its scalar state (zeroed by
the kernel at the start of the interval) and from the bearing stiffness at the operating point:

* ``C_INNER_Q3_MEAN``, ``C_OUTER_Q10_3_MEAN``: the mean over the interval's Newmark steps and the
  balls of Q_i^3 (N^3) and Q_o^(10/3) (N^(10/3)), the contact loads of each accepted step (each
  ball in quasi-static equilibrium with its centrifugal force): what the Lundberg-Palmgren
  equivalent loads of :mod:`bearing_gym.physics.rating` are made of (Palmgren-Miner: the
  damage of a varying load is the mean of Q^w over time);
* ``C_MAX_INNER_N``, ``C_MAX_OUTER_N``: the largest inner and outer contact load of the interval;
* ``C_SHAFT_SPEED_MEAN`` (rad/s): the shaft angle the interval turned over the time it took (its
  record rows, first to last): the revolutions per second that use the life, also while the
  speed ramps within the interval;
* ``C_RADIAL_STIFFNESS``, ``C_AXIAL_STIFFNESS`` (N/m): the bearing's direct stiffness at the
  interval's mean displacement, by central differences of the bearing force (eq 33):
  K_kk = -(F_k(U + h e_k) - F_k(U - h e_k)) / (2 h), h = ``STIFFNESS_STEP_M``, the other four
  coordinates held, at the ball positions (cage, shaft and spin angles) of the interval's end,
  each ball solved from copies of its final state (the integrator's state is not touched).
  Radial = (K_xx + K_yy) / 2 (the mean over directions of the radial stiffness: the same for any
  orientation of the x and y axes; with radial load K_xx and K_yy differ), axial = K_zz. In
  quasi-periodic motion it is the stiffness about the mean position, not of the motion. Seven
  force evaluations per interval of 800 steps (< 1 % of the step's price); NaN if a ball has
  no equilibrium there.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from bearing_gym.physics.bearing import N_GEO, ball_geometry, bearing_force_on
from bearing_gym.physics.layout import I_NB, O_OMEGA
from bearing_gym.physics.rotor import (R_SHAFT, R_T, R_X, S_CAGE, S_LOAD_STEPS, S_MAX_QI, S_MAX_QO, S_SHAFT, S_SUM_QI3,
                                       S_SUM_QO10_3)

C_INNER_Q3_MEAN = 0     # mean over steps and balls of Q_i^3 (N^3)
C_OUTER_Q10_3_MEAN = 1  # mean over steps and balls of Q_o^(10/3) (N^(10/3))
C_MAX_INNER_N = 2       # largest inner contact load (N)
C_MAX_OUTER_N = 3       # largest outer contact load (N)
C_RADIAL_STIFFNESS = 4  # (K_xx + K_yy) / 2 (N/m)
C_AXIAL_STIFFNESS = 5   # K_zz (N/m)
C_SHAFT_SPEED_MEAN = 6  # the interval's mean shaft speed (rad/s): shaft angle turned / time taken
N_CONTACT = 7
STIFFNESS_STEP_M = 1e-8  # central-difference step: (h / delta)^2 < 1e-4 for deflections > 1 um


@njit(cache=True)
def reset_contact_accumulators(scal):
    """Zero the integrator's contact-load accumulators (the start of a control interval)."""
    for k in range(S_SUM_QI3, S_MAX_QO + 1):
        scal[k] = 0.0


@njit(cache=True)
def interval_contact(prm, op, race_wav, ball_wav, ball_phase, ball_size, scal, psi_b, ball_v, ball_out,
                     rec, rows, out):
    """Fill ``out`` (N_CONTACT,) for the interval whose steps ``scal``'s accumulators and whose
    record rows ``rec[:rows]`` hold (module docstring). Zeros (and no stiffness) for an interval
    without steps."""
    for k in range(N_CONTACT):
        out[k] = 0.0
    n = int(prm[I_NB])
    steps = scal[S_LOAD_STEPS]
    if steps <= 0.0 or rows < 1:
        return
    out[C_INNER_Q3_MEAN] = scal[S_SUM_QI3] / (steps * n)
    out[C_OUTER_Q10_3_MEAN] = scal[S_SUM_QO10_3] / (steps * n)
    out[C_MAX_INNER_N] = scal[S_MAX_QI]
    out[C_MAX_OUTER_N] = scal[S_MAX_QO]
    last = rows - 1
    if last > 0:
        out[C_SHAFT_SPEED_MEAN] = (rec[last, R_SHAFT] - rec[0, R_SHAFT]) / (rec[last, R_T] - rec[0, R_T])
    else:
        out[C_SHAFT_SPEED_MEAN] = op[O_OMEGA]
    U = np.zeros(5)
    for r in range(rows):
        for k in range(5):
            U[k] += rec[r, R_X + k]
    for k in range(5):
        U[k] /= rows
    geo = np.zeros((n, N_GEO))
    ball_geometry(scal[S_CAGE], scal[S_SHAFT], psi_b, prm, race_wav, ball_wav, ball_phase, geo)
    omega = op[O_OMEGA]
    v0 = ball_v.copy()
    out0 = ball_out.copy()
    F = np.zeros(5)
    if bearing_force_on(U, geo, prm, omega, ball_size, v0, out0, F) != 0:     # the balls at the mean
        out[C_RADIAL_STIFFNESS] = np.nan
        out[C_AXIAL_STIFFNESS] = np.nan
        return
    v = v0.copy()
    bo = out0.copy()
    diag = np.zeros(3)
    for k in range(3):
        dF = 0.0
        for sign in (1.0, -1.0):
            _copy_into(v, v0)
            _copy_into(bo, out0)
            u_k = U[k]
            U[k] = u_k + sign * STIFFNESS_STEP_M
            st = bearing_force_on(U, geo, prm, omega, ball_size, v, bo, F)
            U[k] = u_k
            if st != 0:
                out[C_RADIAL_STIFFNESS] = np.nan
                out[C_AXIAL_STIFFNESS] = np.nan
                return
            dF += sign * F[k]
        diag[k] = 0.0 - dF / (2.0 * STIFFNESS_STEP_M)       # 0 - x: +0.0, not -0.0, where no ball touches
    out[C_RADIAL_STIFFNESS] = 0.5 * (diag[0] + diag[1])
    out[C_AXIAL_STIFFNESS] = diag[2]


@njit(cache=True, inline="always")
def _copy_into(dst, src):
    """dst[:] = src for 2-D arrays of one shape, element by element (numba compiles the slice
    assignment with a call of libm's floor and log10)."""
    for i in range(src.shape[0]):
        for j in range(src.shape[1]):
            dst[i, j] = src[i, j]
