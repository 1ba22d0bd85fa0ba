"""The engineering quantities in ``info`` (envs/contact.py, composition._info): present, in their
units, finite, and the stiffness against the static equilibrium's (another method: the
Newton Jacobian of the quasi-static 5-DOF equilibrium, physics/equilibrium.py)."""

import math

import numpy as np
import pytest

from bearing_gym.envs import BearingPreloadEnv, BearingPreloadVectorEnv
from bearing_gym.envs.contact import N_CONTACT, interval_contact
from bearing_gym.params import default_params
from bearing_gym.physics import static_equilibrium

ENGINEERING_KEYS = ("radial_stiffness_n_per_m", "axial_stiffness_n_per_m", "max_inner_contact_load_n",
                    "max_outer_contact_load_n", "life_used_per_s", "l10_life_h", "friction_torque_n_m")


def _pinned(env, rpm, radial, clearance, preload, ecc=5e-6):
    return env.reset(seed=0, options={"shaft_speed_rpm": rpm, "radial_load_n": radial, "clearance_m": clearance,
                                      "eccentricity_m": ecc, "initial_preload_n": preload,
                                      "waviness_amplitude_m": 0.0})


def test_info_has_the_engineering_quantities_finite_and_in_their_units():
    env = BearingPreloadEnv()                  # the benchmark: transient tier
    _, info = env.reset(seed=3)
    infos = [info]
    for _ in range(4):
        *_, info = env.step(np.array([0.2], np.float32))
        infos.append(info)
    for info in infos:
        for k in ENGINEERING_KEYS:
            assert k in info and isinstance(info[k], float) and math.isfinite(info[k]), (k, info.get(k))
        assert 1e7 < info["radial_stiffness_n_per_m"] < 1e9 and 1e7 < info["axial_stiffness_n_per_m"] < 1e9
        # at 10,000-25,000 rpm the outer contacts carry the balls' centrifugal force (0.4-2.6 kN)
        assert info["max_outer_contact_load_n"] > 300.0
        assert info["max_outer_contact_load_n"] > info["max_inner_contact_load_n"]
        assert info["l10_life_h"] == pytest.approx(1.0 / (3600.0 * info["life_used_per_s"]), rel=1e-12)
        assert 0.0 < info["friction_torque_n_m"] < 1.0
    # the vector env carries them too
    venv = BearingPreloadVectorEnv(num_envs=2)
    _, vinfo = venv.reset(seed=5)
    assert all(k in vinfo and np.all(np.isfinite(vinfo[k])) for k in ENGINEERING_KEYS)
    venv.close()


@pytest.mark.parametrize("rpm, radial, clearance, preload", [(10000.0, 0.0, 4e-6, 800.0),
                                                              (17500.0, 250.0, 17e-6, 1500.0)])
def test_stiffness_is_the_static_equilibriums_at_a_period1_point(rpm, radial, clearance, preload):
    env = BearingPreloadEnv(tier="stationary")
    _pinned(env, rpm, radial, clearance, preload)
    *_, info = env.step(np.array([env.actuator.action_for(preload)], np.float32))
    assert not info["quasi_periodic"]
    k = static_equilibrium(default_params(shaft_speed_rpm=rpm, axial_preload_n=preload, radial_load_x_n=radial,
                                          clearance_inner_m=clearance, clearance_outer_m=clearance)).stiffness
    # the mean displacement of a period-1 interval is the static one up to the unbalance orbit's
    # curvature of the contact law: a few per cent
    assert info["radial_stiffness_n_per_m"] == pytest.approx(0.5 * (k[0, 0] + k[1, 1]), rel=0.03)
    assert info["axial_stiffness_n_per_m"] == pytest.approx(k[2, 2], rel=0.03)
    # and the largest inner load is at least the static equilibrium's largest (the orbit adds to it)
    eq = static_equilibrium(default_params(shaft_speed_rpm=rpm, axial_preload_n=preload, radial_load_x_n=radial,
                                           clearance_inner_m=clearance, clearance_outer_m=clearance))
    assert info["max_inner_contact_load_n"] > 0.95 * eq.q_i.max()


def test_the_stiffness_leaves_the_integrators_state_alone():
    env = BearingPreloadEnv(tier="stationary")
    _pinned(env, 20000.0, 500.0, 30e-6, 1000.0)
    env.step(np.array([0.0], np.float32))
    a = env.batch.arrays
    before = {n: getattr(a, n).copy() for n in ("X", "V", "A", "scal", "psi_b", "ball_v", "ball_out")}
    out = np.zeros(N_CONTACT)
    interval_contact(a.prm[0], a.op[0], a.race_wav[0, :a.n_race[0]], a.ball_wav[0, :a.n_ball[0]],
                     a.ball_phase[0, :, :a.n_ball[0]], a.ball_size[0], a.scal[0], a.psi_b[0], a.ball_v[0],
                     a.ball_out[0], a.rec[0], a.rows[0], out)
    assert np.array_equal(out, env.batch.contact[0])           # what the kernel wrote, again
    for n, arr in before.items():
        assert np.array_equal(arr, getattr(a, n)), n


def test_the_life_counts_the_revolutions_the_interval_turned():
    """The fatigue's revolutions per second are the interval's mean shaft speed: at a constant
    speed exactly that speed (to rounding), and the life used is 1 / L_10 per revolution times it."""
    from bearing_gym.envs import BearingPreloadEnv
    from bearing_gym.envs.contact import C_SHAFT_SPEED_MEAN
    env = BearingPreloadEnv(tier="stationary")
    env.reset(seed=0, options={"shaft_speed_rpm": 17500.0, "radial_load_n": 250.0, "clearance_m": 17e-6,
                               "initial_preload_n": 1200.0})
    env.step(np.array([0.0], dtype=np.float32))
    omega = 17500.0 * 2.0 * np.pi / 60.0
    # the shaft angle adds omega dt each step: each addition rounds by up to half an ulp of the
    # angle reached, so the angle turned in the interval's rows is exact to steps * eps * angle
    from bearing_gym.physics.rotor import S_SHAFT
    rows = int(env.batch.rows[0])
    turned = omega * 0.02
    bound = rows * np.finfo(float).eps * env.batch.scal[0, S_SHAFT] / turned
    assert env.batch.contact[0, C_SHAFT_SPEED_MEAN] == pytest.approx(omega, rel=bound)
