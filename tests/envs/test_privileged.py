"""The privileged observation (the hidden scenario parameters appended) and time-to-go through
Gymnasium's own wrapper."""

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.wrappers import TimeAwareObservation

import bearing_gym  # noqa: F401
from bearing_gym.envs import (PRIVILEGED_FEATURE_NAMES, BearingPreloadVectorEnv, PrivilegedObservation,
                              PrivilegedObservationVector)
from bearing_gym.envs.privileged import speed_setpoint_rpm
from bearing_gym.envs.scenario import Scenario


def test_the_privileged_features_are_the_scenarios_hidden_parameters_scaled():
    env = PrivilegedObservation(gym.make("BearingPreload-v0"))
    obs, _ = env.reset(seed=5)
    sc = env.unwrapped.scenario
    assert env.observation_space.shape == (15 + len(PRIVILEGED_FEATURE_NAMES),)
    assert env.observation_space.contains(obs)
    expect = [sc.eccentricity_m / 30e-6, sc.clearance_m / 30e-6, sc.waviness_amplitude_m / 2e-6,
              sc.radial_load_profile[0][1] / 500.0, speed_setpoint_rpm(sc, 0.0) / 25000.0]
    np.testing.assert_allclose(obs[15:], expect, rtol=1e-6)
    plain, _ = gym.make("BearingPreload-v0").reset(seed=5)
    np.testing.assert_array_equal(obs[:15], plain)           # the sensor's features untouched


def test_the_speed_setpoint_is_where_the_ramp_heads():
    sc = Scenario(speed_profile=((0.0, 20000.0), (1.0, 20000.0), (1.2, 15000.0)))
    assert speed_setpoint_rpm(sc, 0.5) == 20000.0
    assert speed_setpoint_rpm(sc, 1.1) == 15000.0
    assert speed_setpoint_rpm(sc, 2.0) == 15000.0


def test_the_vector_wrapper_gives_each_env_its_own_scenario():
    venv = PrivilegedObservationVector(BearingPreloadVectorEnv(num_envs=2, max_episode_steps=None))
    obs, _ = venv.reset(seed=5)
    single, _ = PrivilegedObservation(gym.make("BearingPreload-v0")).reset(seed=6)
    np.testing.assert_array_equal(obs[1], single)
    obs, *_ = venv.step(np.zeros((2, 1), np.float32))
    assert obs.shape == (2, 20) and venv.observation_space.contains(obs)


def test_only_a_bearing_preload_env_can_be_wrapped():
    with pytest.raises(TypeError, match="wraps a BearingPreload env"):
        PrivilegedObservation(gym.make("Pendulum-v1"))


def test_time_to_go_comes_from_gymnasiums_wrapper():
    """docs/benchmark.md: TimeAwareObservation appends the step count of the registered limit."""
    env = TimeAwareObservation(gym.make("BearingPreload-v0", scenario="paper"))
    obs, _ = env.reset(seed=0)
    assert obs.shape == (16,) and obs[-1] == 0
    for k in range(1, 4):
        obs, *_ = env.step(np.zeros(1, np.float32))
    assert obs[-1] == 3
