"""The batched step kernel shared by the single and the vector environment.

``step_batch`` advances every active environment of a batch by one control interval in a
``prange`` loop: every actuator update interval it sets the operating point (shaft speed ramp,
radial-load step) from the scenario schedule, moves the preload by the actuator dynamics, and
runs the Newmark integrator (:func:`bearing_gym.physics.rotor.integrate`); at the end it
computes the window features (:func:`bearing_gym.analysis.window.window_features`).

Schedule row (``Scenario.schedule_array``): 0 start speed, 1 end speed (rad/s), 2 ramp start,
3 ramp end (s), 4-5 radial load (x, y) before the step, 6-7 after, 8 step time (s).
"""

from __future__ import annotations

from numba import njit, prange

from bearing_gym.analysis.window import window_features
from bearing_gym.physics.layout import I_DT, I_OMEGA, I_PX, I_PY, I_PZ
from bearing_gym.physics.rotor import integrate

from .actuator import actuator_update


@njit(cache=True, inline="always")
def operating_point(row, t):
    """Shaft speed (rad/s) and radial load (x, y) of a schedule row at time t."""
    if t <= row[2] or row[3] <= row[2]:
        omega = row[0] if t <= row[2] else row[1]
    elif t >= row[3]:
        omega = row[1]
    else:
        omega = row[0] + (t - row[2]) / (row[3] - row[2]) * (row[1] - row[0])
    if t < row[8]:
        return omega, row[4], row[5]
    return omega, row[6], row[7]


@njit(cache=True)
def step_one(prm, race_wav, ball_wav, ball_phase, ball_size, X, V, A, scal, psi_b, ball_v,
             ball_out, state, sched, act, n_sub, steps_per_sub, rec, feats):
    """Advance one environment by ``n_sub`` actuator intervals of ``steps_per_sub`` Newmark
    steps. ``state`` = [preload, setpoint, t_episode] (updated). Returns (status, rows)."""
    rows_total = 0
    st = 0
    h = steps_per_sub * prm[I_DT]
    for _ in range(n_sub):
        omega, fx, fy = operating_point(sched, state[2])
        prm[I_OMEGA] = omega
        prm[I_PX] = fx
        prm[I_PY] = fy
        state[0] = actuator_update(state[0], state[1], h, act[0], act[1])
        prm[I_PZ] = state[0]
        st, done, rows = integrate(prm, race_wav, ball_wav, ball_phase, ball_size, X, V, A, scal,
                                   psi_b, ball_v, ball_out, steps_per_sub, 1, rec[rows_total:])
        rows_total += rows
        state[2] += done * prm[I_DT]
        if st != 0:
            break
    window_features(rec, rows_total, feats)
    return st, rows_total


@njit(cache=True, parallel=True)
def step_batch(active, prm, race_wav, n_race, ball_wav, n_ball, ball_phase, ball_size, X, V, A,
               scal, psi_b, ball_v, ball_out, env_state, schedule, act, n_sub, steps_per_sub, rec,
               rows_out, status_out, feats):
    """Advance each env ``b`` with ``active[b]`` by one control interval (prange over envs).
    ``env_state[b]`` = [preload, setpoint, t_episode]. Writes rows_out, status_out (0 = ok)
    and feats."""
    n_env = X.shape[0]
    for b in prange(n_env):
        if active[b]:
            st, rows = step_one(prm[b], race_wav[b, :n_race[b]], ball_wav[b, :n_ball[b]],
                                ball_phase[b, :, :n_ball[b]], ball_size[b], X[b], V[b], A[b],
                                scal[b], psi_b[b], ball_v[b], ball_out[b], env_state[b],
                                schedule[b], act, n_sub, steps_per_sub, rec[b], feats[b])
            status_out[b] = st
            rows_out[b] = rows


@njit(cache=True)
def step_batch_serial(active, prm, race_wav, n_race, ball_wav, n_ball, ball_phase, ball_size, X, V,
                      A, scal, psi_b, ball_v, ball_out, env_state, schedule, act, n_sub,
                      steps_per_sub, rec, rows_out, status_out, feats):
    """:func:`step_batch` without threads (same ``step_one`` per env): for a batch of one, where
    a thread pool only costs time when other processes share the cores."""
    for b in range(X.shape[0]):
        if active[b]:
            st, rows = step_one(prm[b], race_wav[b, :n_race[b]], ball_wav[b, :n_ball[b]],
                                ball_phase[b, :, :n_ball[b]], ball_size[b], X[b], V[b], A[b],
                                scal[b], psi_b[b], ball_v[b], ball_out[b], env_state[b],
                                schedule[b], act, n_sub, steps_per_sub, rec[b], feats[b])
            status_out[b] = st
            rows_out[b] = rows
