"""The batched step kernel shared by the single and the vector environment.

``step_batch`` advances every active environment of a batch by one control interval in a
``prange`` loop: every actuator update interval it sets the operating point (shaft speed ramp,
radial-load step) from the scenario schedule, moves the preload by the actuator dynamics, and
runs the Newmark integrator (:func:`bearing_gym.physics.rotor.integrate`); at the end it
computes the window features (:func:`bearing_gym.envs.features.window_features`).

Schedule row (``Scenario.schedule_array``): the number of speed knots, then (t, omega) pairs
(``MAX_EVENTS`` slots), then the number of load steps, then (t, F_x, F_y) triples.
"""

from __future__ import annotations

from numba import njit, prange

from .features import window_features
from bearing_gym.physics.layout import I_DT, I_OMEGA, I_PX, I_PY, I_PZ
from bearing_gym.physics.rotor import integrate

from .actuator import actuator_update
from .scenario import MAX_EVENTS

# columns of an env's state row (PreloadBatch.env_state)
E_PRELOAD = 0       # actual preload (N)
E_SETPOINT = 1      # set-point (N)
E_T = 2             # time in the episode (s)
N_ENV_STATE = 3


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
def step_one(prm, race_wav, ball_wav, ball_phase, ball_size, X, V, A, scal, psi_b, ball_v,
             ball_out, state, sched, act, n_sub, steps_per_sub, rec, feats):
    """Advance one environment by ``n_sub`` actuator intervals of ``steps_per_sub`` Newmark
    steps. ``state`` = [preload, setpoint, t_episode] (updated). Returns (status, rows)."""
    rows_total = 0
    st = 0
    h = steps_per_sub * prm[I_DT]
    for _ in range(n_sub):
        omega, fx, fy = operating_point(sched, state[E_T])
        prm[I_OMEGA] = omega
        prm[I_PX] = fx
        prm[I_PY] = fy
        state[E_PRELOAD] = actuator_update(state[E_PRELOAD], state[E_SETPOINT], h, act[0], act[1])
        prm[I_PZ] = state[E_PRELOAD]
        st, done, rows = integrate(prm, race_wav, ball_wav, ball_phase, ball_size, X, V, A, scal,
                                   psi_b, ball_v, ball_out, steps_per_sub, 1, rec[rows_total:])
        rows_total += rows
        state[E_T] += done * prm[I_DT]
        if st != 0:
            break
    window_features(rec, rows_total, feats)
    return st, rows_total


def _compile_step_batch(name: str, parallel: bool):
    """The batch kernel compiled once per threading mode from one body (its own name each, so
    the two never share a cache entry)."""
    def kernel(active, prm, race_wav, n_race, ball_wav, n_ball, ball_phase, ball_size, X, V, A,
               scal, psi_b, ball_v, ball_out, env_state, schedule, act, n_sub, steps_per_sub, rec,
               rows_out, status_out, feats):
        n_env = X.shape[0]
        for b in prange(n_env):
            if active[b]:
                st, rows = step_one(prm[b], race_wav[b, :n_race[b]], ball_wav[b, :n_ball[b]],
                                    ball_phase[b, :, :n_ball[b]], ball_size[b], X[b], V[b], A[b],
                                    scal[b], psi_b[b], ball_v[b], ball_out[b], env_state[b],
                                    schedule[b], act, n_sub, steps_per_sub, rec[b], feats[b])
                status_out[b] = st
                rows_out[b] = rows
    kernel.__name__ = kernel.__qualname__ = name
    return njit(cache=True, parallel=parallel)(kernel)


#: Advance each env ``b`` with ``active[b]`` by one control interval (prange over envs);
#: ``env_state[b]`` = [preload, setpoint, t_episode]; writes rows_out, status_out (0 = ok), feats.
step_batch = _compile_step_batch("step_batch", parallel=True)
#: The same without threads (prange is range without parallel=True): for a batch of one, where a
#: thread pool only costs time when other processes share the cores.
step_batch_serial = _compile_step_batch("step_batch_serial", parallel=False)
