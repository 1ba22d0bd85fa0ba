"""The plain-NumPy reference (benchmarks/numpy_reference.py) reproduces the numba kernels:
bearing force (eqs 3-33, per-ball Newton of eq 31) and Newmark steps (eq 35).

Both start from the same state (the static equilibrium of the default parameters, same ball
warm starts), so they follow the same iteration path and must agree to rounding error. Forces are
compared with the moments divided by r_p (N at the groove radius), relative to the largest
component; trajectories per DOF, relative to that DOF's largest excursion.
"""


import numpy as np
import pytest

import bearing_gym
from bearing_gym.physics import Simulator
from bearing_gym.physics import ball as ball_mod
from bearing_gym.physics.bearing import bearing_force
from bearing_gym.physics.layout import pack_params
from bearing_gym.physics.rotor import N_REC, R_F, R_V, R_X, S_CAGE_SPEED, integrate

from benchmarks import numpy_reference as ref

PERTURBATION = np.array([2e-6, -1e-6, 1e-6, 1e-5, -2e-5])


@pytest.fixture(scope="module")
def default_sim():
    """Simulator at the static equilibrium of the default parameters (20,000 rpm, 800 N)."""
    return Simulator(bearing_gym.default_params())


def _setup(default_sim, race_control, **overrides):
    params = bearing_gym.default_params(race_control=race_control, **overrides)
    damping = default_sim.damping_coefficients
    packed = pack_params(params, damping)
    state = default_sim.state
    state.ball_out[:, ball_mod.B_CTRL] = 1.0 if race_control == "inner" else 0.0
    return params, packed, state, ref.NumpyModel(params, damping=damping)


def _numba_force(packed, state, U, cage_angle=0.0, shaft_angle=0.0):
    ball_v, ball_out, F = state.ball_v.copy(), state.ball_out.copy(), np.zeros(5)
    status = bearing_force(U, cage_angle, shaft_angle, state.psi_b, packed.prm, packed.op[0], packed.race_wav,
                           packed.ball_wav, packed.ball_phase, packed.ball_size, ball_v, ball_out, F)
    return F, status, ball_v, ball_out


def _rel_force_error(F_ref, F_nb, r_p):
    scale = np.array([1.0, 1.0, 1.0, 1.0 / r_p, 1.0 / r_p])
    return np.max(np.abs((F_ref - F_nb) * scale)) / np.max(np.abs(F_nb * scale))


def test_friction_onset_constant_matches_package():
    assert ref.FRICTION_ONSET_M == ball_mod.FRICTION_ONSET_M


@pytest.mark.parametrize("race_control", ["outer", "inner"])
@pytest.mark.parametrize("perturbed", [False, True], ids=["equilibrium", "perturbed"])
def test_bearing_force_matches_numba(default_sim, race_control, perturbed):
    params, packed, state, model = _setup(default_sim, race_control)
    U = state.X + (PERTURBATION if perturbed else 0.0)
    F_nb, st_nb, v_nb, out_nb = _numba_force(packed, state, U)
    balls = ref.ball_state_from_arrays(state.ball_v, state.ball_out)
    F_np, st_np = model.bearing_force(U, 0.0, 0.0, state.psi_b, balls)
    assert st_nb == 0 and st_np == 0
    assert _rel_force_error(F_np, F_nb, model.r_p) < 1e-9, (F_np, F_nb)
    # and the per-ball solutions (the next warm starts) agree
    assert np.max(np.abs(balls.v - v_nb)) < 1e-15
    np.testing.assert_allclose(balls.q_i, out_nb[:, ball_mod.B_QI], rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(balls.q_o, out_nb[:, ball_mod.B_QO], rtol=1e-9, atol=1e-9)
    if perturbed:   # the perturbation is large enough to make the force differ
        F0, *_ = _numba_force(packed, state, state.X)
        assert _rel_force_error(F0, F_nb, model.r_p) > 1e-2


@pytest.mark.parametrize("race_control", ["outer", "inner", "auto"])
def test_bearing_force_with_waviness_matches_numba(default_sim, race_control):
    wav = bearing_gym.Waviness(
        inner=bearing_gym.RaceWaviness(orders=(18, 36), radial_amplitudes_m=(1e-7, 5e-8),
                                       radial_phases_rad=(0.3, 1.0),
                                       axial_amplitudes_m=(2e-8, 0.0), axial_phases_rad=(0.1, 0.0)),
        outer=bearing_gym.RaceWaviness(orders=(17,), radial_amplitudes_m=(1e-7,),
                                       radial_phases_rad=(0.5,)),
        balls=bearing_gym.BallWaviness(orders=(2, 4), amplitudes_m=(5e-8, 2e-8),
                                       phases_rad=(0.2, 0.4),
                                       oversize_m=tuple(np.linspace(-1e-7, 1e-7, 18))))
    params, packed, state, model = _setup(default_sim, race_control, waviness=wav)
    state.psi_b[:] = np.linspace(0.0, 3.0, state.psi_b.size)
    U = state.X + PERTURBATION
    F_nb, st_nb, v_nb, out_nb = _numba_force(packed, state, U, cage_angle=0.3, shaft_angle=1.1)
    balls = ref.ball_state_from_arrays(state.ball_v, state.ball_out)
    F_np, st_np = model.bearing_force(U, 0.3, 1.1, state.psi_b, balls)
    assert st_nb == 0 and st_np == 0
    assert _rel_force_error(F_np, F_nb, model.r_p) < 1e-9, (F_np, F_nb)
    assert np.array_equal(balls.inner_control, out_nb[:, ball_mod.B_CTRL] > 0.5)


@pytest.mark.parametrize("race_control", ["outer", "inner"])
def test_newmark_steps_match_numba(default_sim, race_control):
    n_steps = 50
    params, packed, state, model = _setup(default_sim, race_control)
    # numba
    s = state.copy()
    rec = np.zeros((n_steps, N_REC))
    status, done, rows = integrate(packed.prm, packed.op, packed.race_wav, packed.ball_wav, packed.ball_phase,
                                   packed.ball_size, s.X, s.V, s.A, s.scal, s.psi_b, s.ball_v,
                                   s.ball_out, n_steps, 1, rec)
    assert (status, done, rows) == (0, n_steps, n_steps)
    # NumPy reference
    rs = ref.state_from_simulator(state)
    X = np.zeros((n_steps, 5))
    V = np.zeros((n_steps, 5))
    F = np.zeros((n_steps, 5))
    for k in range(n_steps):
        assert model.newmark_step(rs) == 0
        X[k], V[k], F[k] = rs.X, rs.V, rs.F
    for ours, theirs in ((X, rec[:, R_X:R_X + 5]), (V, rec[:, R_V:R_V + 5]),
                         (F, rec[:, R_F:R_F + 5])):
        scale = np.maximum(np.max(np.abs(theirs), axis=0), 1e-30)
        err = np.max(np.abs(ours - theirs), axis=0) / scale
        assert np.all(err < 1e-8), err
    # the motion is not trivial: the unbalance has moved the rotor by more than a nanometre
    assert np.max(np.abs(X[:, 0] - state.X[0])) > 1e-9
    np.testing.assert_allclose(rs.cage_speed, s.scal[S_CAGE_SPEED], rtol=1e-9)
    np.testing.assert_allclose(rs.balls.v, s.ball_v, rtol=0, atol=1e-15)
