"""The native vector env and the SB3 adapter behave as Gymnasium's and SB3's own vector envs
over the single env: same observations, rewards, infos, seeds, partial resets, frames, errors."""

import gymnasium as gym
import numba
import numpy as np
import pytest
from gymnasium.utils.env_checker import data_equivalence

import bearing_gym  # noqa: F401  (registers the env)
from bearing_gym.envs import BearingPreloadEnv, BearingPreloadVectorEnv
from bearing_gym.envs.vector import ResetMaskError


def _pair(**kwargs):
    """The same configuration vectorised by Gymnasium (sync) and natively."""
    sync = gym.make_vec("BearingPreload-v0", num_envs=2, vectorization_mode="sync", **kwargs)
    native = gym.make_vec("BearingPreload-v0", num_envs=2, vectorization_mode="vector_entry_point",
                          **kwargs)
    assert isinstance(native.unwrapped, BearingPreloadVectorEnv)
    return sync, native


def _same(a, b):
    assert len(a) == len(b)
    for x, y in zip(a, b):
        assert data_equivalence(x, y), (x, y)


def test_native_equals_sync_with_infos_seeds_partial_resets_and_frames():
    sync, native = _pair(max_episode_steps=3, render_mode="rgb_array")
    assert native.metadata["render_fps"] == sync.metadata["render_fps"]
    _same(sync.reset(seed=3), native.reset(seed=3))     # obs and reset infos (same keys, values)
    assert native.np_random_seed == sync.np_random_seed == (3, 4)
    rng = np.random.default_rng(0)
    for k in range(4):                                   # truncation at 3, NEXT_STEP autoreset at 4
        a = rng.uniform(-1, 1, size=(2, 1)).astype(np.float32)
        _same(sync.step(a), native.step(a))
    frames = native.render()
    assert isinstance(frames, tuple) and len(frames) == 2
    assert frames[0].dtype == np.uint8 and frames[0].ndim == 3
    _same(sync.render(), frames)
    # a partial reset reseeds only the envs it resets; env 0's generator runs on, as in sync
    mask = np.array([False, True])
    _same(sync.reset(seed=[10, 11], options={"reset_mask": mask.copy()}),
          native.reset(seed=[10, 11], options={"reset_mask": mask.copy()}))
    assert native.np_random_seed == sync.np_random_seed == (3, 11)
    for k in range(4):                                   # env 0 autoresets from its own generator
        a = rng.uniform(-1, 1, size=(2, 1)).astype(np.float32)
        _same(sync.step(a), native.step(a))
    _same(sync.render(), native.render())
    native.reset(seed=None)
    assert native.np_random_seed == (3, 11)              # seed=None keeps the generators


def test_reset_info_has_the_single_env_keys():
    _, info = BearingPreloadEnv(scenario="paper").reset(seed=0)
    _, vinfo = BearingPreloadVectorEnv(num_envs=2, scenario="paper").reset(seed=0)
    assert set(vinfo) == set(info) | {f"_{k}" for k in info}


def test_unseeded_envs_report_the_seeds_they_drew():
    v = BearingPreloadVectorEnv(num_envs=3, scenario="paper")
    seeds = v.np_random_seed
    assert len(seeds) == 3 and len(set(seeds)) == 3 and all(isinstance(s, int) for s in seeds)
    v.reset()
    assert v.np_random_seed == seeds
    assert len(v.np_random) == 3 and all(isinstance(g, np.random.Generator) for g in v.np_random)


@pytest.mark.parametrize("mask, problem", [
    (np.array([True, True, True, False]), "shape"),         # length 4 on 3 envs
    (np.array([[True, True, True]]), "shape"),
    (np.array([1, 0, 1]), "dtype"),
    (np.array([1.0, 0.0, 1.0]), "dtype"),
    (np.array([False, False, False]), "at least one"),
])
def test_bad_reset_mask_raises_naming_the_problem(mask, problem):
    v = BearingPreloadVectorEnv(num_envs=3, scenario="paper")
    v.reset(seed=0)
    with pytest.raises(ResetMaskError, match=problem) as err:
        v.reset(options={"reset_mask": mask})
    assert isinstance(err.value, ValueError) and isinstance(err.value, TypeError)


def test_first_reset_must_reset_every_env():
    v = BearingPreloadVectorEnv(num_envs=2, scenario="paper")
    with pytest.raises(ValueError, match="first reset"):
        v.reset(options={"reset_mask": np.array([True, False])})
    v.reset(seed=0, options={"reset_mask": np.array([True, True])})


@pytest.mark.parametrize("num_envs", [1, 2])
def test_scalar_action_is_a_type_error(num_envs):
    v = BearingPreloadVectorEnv(num_envs=num_envs, scenario="paper")
    v.reset(seed=0)
    for scalar in (0.0, np.float32(0.0), np.array(0.0)):
        with pytest.raises(TypeError, match="scalar"):
            v.step(scalar)
    v.step(np.zeros((num_envs, 1), dtype=np.float32))


def test_sb3_adapter_rejects_a_scalar_action():
    from bearing_gym.envs import BearingPreloadSB3VecEnv
    venv = BearingPreloadSB3VecEnv(num_envs=1, scenario="paper")
    venv.reset()
    with pytest.raises(TypeError, match="scalar"):
        venv.step(0.0)


def test_native_human_render_mode_is_refused_with_the_alternatives():
    with pytest.raises(ValueError, match="HumanRendering"):
        BearingPreloadVectorEnv(num_envs=2, render_mode="human")
    v = BearingPreloadVectorEnv(num_envs=2, scenario="paper")
    v.reset(seed=0)
    assert v.render() == (None, None)                    # as SyncVectorEnv without a render mode


@pytest.mark.skipif(numba.config.NUMBA_NUM_THREADS < 2, reason="needs 2 numba threads")
def test_num_threads_applies_to_the_kernel_call_only():
    v = BearingPreloadVectorEnv(num_envs=2, scenario="paper", num_threads=1)
    v.reset(seed=0)
    seen = []
    kernel_step = v.batch.step

    def spy(*args):
        seen.append(numba.get_num_threads())
        return kernel_step(*args)

    v.batch.step = spy
    callers = numba.get_num_threads()
    numba.set_num_threads(2)
    try:
        v.step(np.zeros((2, 1), dtype=np.float32))
        assert seen == [1]                               # the kernel ran with the env's count
        assert numba.get_num_threads() == 2              # and the caller's count is back
    finally:
        numba.set_num_threads(callers)


@pytest.mark.skipif(numba.config.NUMBA_NUM_THREADS < 2, reason="needs 2 numba threads")
def test_the_thread_count_does_not_change_a_bit():
    """Each environment's arithmetic is its own: one thread or two give identical trajectories
    (what lets protocol runs share the cores with ``train.py --threads 1``)."""
    out = []
    for threads in (1, 2):
        v = BearingPreloadVectorEnv(num_envs=3, tier="transient", episode_steps=4, num_threads=threads)
        obs, _ = v.reset(seed=7)
        rows = [obs]
        for k in range(4):
            obs, rew, term, trunc, _ = v.step(np.full((3, 1), 0.2 * k - 0.3, dtype=np.float32))
            rows += [obs, rew, term, trunc]
        out.append(rows)
    for a, b in zip(*out):
        np.testing.assert_array_equal(a, b)


def test_gymnasium_checkers_with_rendering(monkeypatch, tmp_path):
    import tempfile

    from gymnasium.utils.env_checker import check_env
    from gymnasium.utils.env_match import check_environments_match
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))   # check_env also renders "human"
    check_env(gym.make("BearingPreload-v0", scenario="paper", render_mode="rgb_array").unwrapped)
    check_environments_match(
        gym.make("BearingPreload-v0", scenario="paper", render_mode="rgb_array", max_episode_steps=2),
        gym.wrappers.TimeLimit(BearingPreloadEnv(scenario="paper", render_mode="rgb_array"), 2),
        num_steps=3)


def test_sb3_env_checker_with_rendering():
    import warnings

    from stable_baselines3.common.env_checker import check_env
    with warnings.catch_warnings():
        warnings.simplefilter("error", UserWarning)      # any finding fails the test
        check_env(BearingPreloadEnv(scenario="paper", render_mode="rgb_array"), warn=True,
                  skip_render_check=False)


def test_sb3_adapter_equals_sb3_dummy_vec_env():
    from stable_baselines3.common.vec_env import DummyVecEnv

    from bearing_gym.envs import BearingPreloadSB3VecEnv
    dummy = DummyVecEnv([lambda: gym.make("BearingPreload-v0", max_episode_steps=2,
                                          render_mode="rgb_array") for _ in range(2)])
    native = BearingPreloadSB3VecEnv(num_envs=2, max_episode_steps=2, render_mode="rgb_array")
    dummy.seed(5)
    native.seed(5)
    assert data_equivalence(dummy.reset(), native.reset())
    assert data_equivalence(dummy.reset_infos, native.reset_infos)
    rng = np.random.default_rng(1)
    for _ in range(3):                                   # through SB3's same-step reset
        a = rng.uniform(-1, 1, size=(2, 1)).astype(np.float32)
        for x, y in zip(dummy.step(a), native.step(a)):
            assert data_equivalence(x, y), (x, y)
        assert data_equivalence(dummy.reset_infos, native.reset_infos)
    assert data_equivalence(dummy.get_images(), native.get_images())
    assert native.render().shape == dummy.render().shape
