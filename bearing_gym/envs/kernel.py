"""The batched step kernel shared by the single and the vector environment.

``step_batch`` advances every active environment of a batch by one control interval in a
``prange`` loop: every actuator update interval it sets the operating point (shaft speed ramp,
radial-load step) from the scenario schedule, moves the preload by the actuator dynamics, and
runs the Newmark integrator (:func:`bearing_gym.physics.rotor.integrate`); at the end it
computes the window features (:func:`bearing_gym.envs.features.window_features`) and the
interval's contact loads and bearing stiffness (:func:`bearing_gym.envs.contact.interval_contact`).

Schedule row (``Scenario.schedule_array``): the number of speed knots, then (t, omega) pairs
(``MAX_EVENTS`` slots), then the number of load steps, then (t, F_x, F_y) triples.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit, prange

from bearing_gym.physics.layout import I_DT, O_OMEGA, O_PX, O_PY, O_PZ
from bearing_gym.physics.rotor import integrate

from .contact import interval_contact, reset_contact_accumulators
from .features import window_features

from .actuator import actuator_update
from .scenario import MAX_EVENTS

# columns of an env's state row (PreloadBatch.env_state); the actual preload is the operating
# point's (op[O_PZ]), its one home
E_SETPOINT = 0      # set-point (N)
E_T = 1             # time in the episode (s)
N_ENV_STATE = 2


class BatchArrays(NamedTuple):
    """What the batch kernel works on, per env ``b`` (first axis): the spindle's constants
    ``prm`` (``I_*``), its operating point ``op`` (``O_*``: speed, radial loads, preload - the
    kernel sets them every actuator update - and the damping's factors, 1 but in the settle's aid), the waviness and ball sizes (``n_race``/``n_ball``
    rows of each in use), the integrator state (X, V, A, scal, psi_b, ball_v, ball_out), the
    env state (``E_*``), the scenario's schedule, and the outputs of the last interval (record
    rows, their count, the status, the window features, the contact state ``C_*``)."""

    prm: np.ndarray
    op: np.ndarray
    race_wav: np.ndarray
    n_race: np.ndarray
    ball_wav: np.ndarray
    n_ball: np.ndarray
    ball_phase: np.ndarray
    ball_size: np.ndarray
    X: np.ndarray
    V: np.ndarray
    A: np.ndarray
    scal: np.ndarray
    psi_b: np.ndarray
    ball_v: np.ndarray
    ball_out: np.ndarray
    env_state: np.ndarray
    sched: np.ndarray
    rec: np.ndarray
    rows: np.ndarray
    status: np.ndarray
    feats: np.ndarray
    contact: np.ndarray


@njit(cache=True, inline="always")
def operating_point(row, t):
    """Shaft speed (rad/s, piecewise linear through the knots) and radial load (x, y; piecewise
    constant) of a schedule row at time t."""
    n_speed = int(row[0])
    omega = row[2 * n_speed]                      # after the last knot
    for k in range(n_speed - 1):
        t0 = row[1 + 2 * k]
        t1 = row[3 + 2 * k]
        if t < t1:
            w0 = row[2 + 2 * k]
            omega = w0 + (max(t, t0) - t0) / (t1 - t0) * (row[4 + 2 * k] - w0)
            break
    base = 1 + 2 * MAX_EVENTS
    n_load = int(row[base])
    j = 0
    for k in range(1, n_load):
        if t >= row[base + 1 + 3 * k]:
            j = k
    return omega, row[base + 2 + 3 * j], row[base + 3 + 3 * j]


@njit(cache=True)
def step_one(prm, op, race_wav, ball_wav, ball_phase, ball_size, X, V, A, scal, psi_b, ball_v,
             ball_out, state, sched, act, n_sub, steps_per_sub, rec, feats, contact):
    """Advance one environment by ``n_sub`` actuator intervals of ``steps_per_sub`` Newmark
    steps: each sets the operating point ``op`` from the schedule and moves its preload by the
    actuator. ``state`` = [setpoint, t_episode] (updated). Returns (status, rows)."""
    reset_contact_accumulators(scal)
    rows_total = 0
    st = 0
    h = steps_per_sub * prm[I_DT]
    for _ in range(n_sub):
        omega, fx, fy = operating_point(sched, state[E_T])
        op[O_OMEGA] = omega
        op[O_PX] = fx
        op[O_PY] = fy
        op[O_PZ] = actuator_update(op[O_PZ], state[E_SETPOINT], h, act[0], act[1])
        st, done, rows = integrate(prm, op, race_wav, ball_wav, ball_phase, ball_size, X, V, A, scal,
                                   psi_b, ball_v, ball_out, steps_per_sub, 1, rec[rows_total:])
        rows_total += rows
        state[E_T] += done * prm[I_DT]
        if st != 0:
            break
    window_features(rec, rows_total, feats)
    # a failed interval's contact state means nothing (zeros), as its features
    interval_contact(prm, op, race_wav, ball_wav, ball_phase, ball_size, scal, psi_b, ball_v, ball_out, rec,
                     rows_total if st == 0 else 0, contact)
    return st, rows_total


def _compile_step_batch(name: str, parallel: bool):
    """The batch kernel compiled once per threading mode from one body (its own name each, so
    the two never share a cache entry)."""
    def kernel(active, a, act, n_sub, steps_per_sub):
        n_env = a.X.shape[0]
        status_out = a.status        # bound outside the prange: numba's parfor drops a setitem
        rows_out = a.rows            # on a tuple's attribute inside it (measured: rows stayed 0)
        for b in prange(n_env):
            if active[b]:
                st, rows = step_one(a.prm[b], a.op[b], a.race_wav[b, :a.n_race[b]], a.ball_wav[b, :a.n_ball[b]],
                                    a.ball_phase[b, :, :a.n_ball[b]], a.ball_size[b], a.X[b], a.V[b], a.A[b],
                                    a.scal[b], a.psi_b[b], a.ball_v[b], a.ball_out[b], a.env_state[b],
                                    a.sched[b], act, n_sub, steps_per_sub, a.rec[b], a.feats[b], a.contact[b])
                status_out[b] = st
                rows_out[b] = rows
    kernel.__name__ = kernel.__qualname__ = name
    return njit(cache=True, parallel=parallel)(kernel)


#: Advance each env ``b`` with ``active[b]`` of the :class:`BatchArrays` by one control interval
#: (prange over envs); writes their op, env_state, rec, rows, status (0 = ok), feats and contact.
step_batch = _compile_step_batch("step_batch", parallel=True)
#: The same without threads (prange is range without parallel=True): for a batch of one, where a
#: thread pool only costs time when other processes share the cores.
step_batch_serial = _compile_step_batch("step_batch_serial", parallel=False)
