"""The native vector env equals single envs step by step; SB3 adapter; robustness."""

import gymnasium as gym
import numpy as np
import pytest

import bearing_gym  # noqa: F401
from bearing_gym.envs import BearingPreloadEnv, BearingPreloadSB3VecEnv, BearingPreloadVectorEnv
from bearing_gym.envs.observation import FEATURE_NAMES


def test_vector_env_equals_single_envs_including_autoreset():
    n, steps, horizon, seed = 2, 14, 6, 21
    rng = np.random.default_rng(0)
    actions = rng.uniform(-1, 1, size=(steps, n, 1)).astype(np.float32)
    venv = BearingPreloadVectorEnv(num_envs=n, max_episode_steps=horizon)
    vobs, _ = venv.reset(seed=seed)
    singles = [gym.wrappers.TimeLimit(BearingPreloadEnv(), horizon) for _ in range(n)]
    sobs = [e.reset(seed=seed + i)[0] for i, e in enumerate(singles)]
    np.testing.assert_array_equal(vobs, np.array(sobs))
    need_reset = [False] * n
    autoresets = [0] * n
    for k in range(steps):
        vobs, vrew, vterm, vtrunc, _ = venv.step(actions[k])
        for i, e in enumerate(singles):
            if need_reset[i]:                     # NEXT_STEP autoreset
                o, _ = e.reset()
                autoresets[i] += 1
                r, term, trunc = 0.0, False, False
            else:
                o, r, term, trunc, _ = e.step(actions[k, i])
            need_reset[i] = term or trunc
            np.testing.assert_array_equal(vobs[i], o)
            assert vrew[i] == r and vterm[i] == term and vtrunc[i] == trunc
    assert min(autoresets) >= 1           # the comparison went through an autoreset in every env


def test_make_vec_uses_the_native_vector_env():
    v = gym.make_vec("BearingPreload-v0", num_envs=2, vectorization_mode="vector_entry_point",
                     scenario="paper")
    assert isinstance(v.unwrapped, BearingPreloadVectorEnv)
    obs, _ = v.reset(seed=0)
    assert obs.shape == (2, len(FEATURE_NAMES))
    obs, rew, term, trunc, info = v.step(np.zeros((2, 1), dtype=np.float32))
    assert rew.shape == (2,) and "reward_vibration" in info


def test_vector_env_rejects_bad_actions():
    v = BearingPreloadVectorEnv(num_envs=2, scenario="paper")
    v.reset(seed=0)
    with pytest.raises(ValueError, match="NaN"):
        v.step(np.array([[0.0], [np.nan]], dtype=np.float32))
    with pytest.raises(ValueError, match="outside"):
        v.step(np.array([[0.0], [2.0]], dtype=np.float32))


def test_sb3_vec_env_adapter_resets_in_the_same_step():
    from stable_baselines3.common.vec_env import VecEnv
    venv = BearingPreloadSB3VecEnv(num_envs=2, scenario="paper", max_episode_steps=3)
    assert isinstance(venv, VecEnv)
    venv.seed(4)
    obs = venv.reset()
    assert obs.shape == (2, len(FEATURE_NAMES))
    for k in range(3):
        obs, rew, dones, infos = venv.step(np.zeros((2, 1), dtype=np.float32))
    assert dones.all()
    assert all(i["TimeLimit.truncated"] for i in infos)
    assert all(i["terminal_observation"].shape == (len(FEATURE_NAMES),) for i in infos)
    assert rew.dtype == np.float32


def test_2000_random_steps_over_transient_scenarios_stay_finite():
    # 2 x 1000 random actions over 20 transient-tier scenarios (with their speed ramps and load steps)
    venv = BearingPreloadVectorEnv(num_envs=2, max_episode_steps=100)
    obs, _ = venv.reset(seed=123)
    rng = np.random.default_rng(7)
    terminated = 0
    for _ in range(1000):
        obs, rew, term, trunc, info = venv.step(rng.uniform(-1, 1, size=(2, 1)).astype(np.float32))
        assert np.all(np.isfinite(obs)) and np.all(np.isfinite(rew))
        terminated += int(term.sum())
    assert terminated <= 10       # integrator failures must be rare, and never NaN
