"""Env copies (``BearingPreloadVectorEnv.copy_env``): a copy made mid-episode continues the
episode bit for bit like its source under the same actions, and leaves the source untouched
when it takes others - what a planner's branch point needs."""

import numpy as np
import pytest

from bearing_gym.envs import BearingPreloadVectorEnv


def _run(env, idx, actions, steps):
    rewards, obs = [], []
    for _ in range(steps):
        a = np.zeros(env.num_envs)
        a[idx] = actions
        o, r, term, trunc, _ = env.step_some(a, np.asarray(idx))
        rewards.append(r.copy())
        obs.append(o.copy())
    return np.array(rewards), np.array(obs)


@pytest.mark.parametrize("tier", ["transient", "field"])
def test_a_copy_continues_its_source_bit_for_bit_and_a_diverging_copy_leaves_it_alone(tier):
    env = BearingPreloadVectorEnv(num_envs=3, tier=tier, episode_steps=12, max_episode_steps=12)
    env.reset(seed=[300007] * 3)
    _run(env, [0], [0.1], 4)                                   # env 0 four intervals in
    env.copy_env(0, [1, 2])
    same, same_obs = _run(env, [0, 1], [-0.2, -0.2], 5)         # env 1: the same actions as env 0
    np.testing.assert_array_equal(same[:, 0], same[:, 1])
    np.testing.assert_array_equal(same_obs[:, 0], same_obs[:, 1])
    assert env.batch.X[0].tolist() == env.batch.X[1].tolist()
    # env 2 took none of those steps; from the copy it replays them alone: the same bits again
    env.copy_env(2, [1])                                       # env 1 back to the branch point
    replay, _ = _run(env, [1], [-0.2], 5)
    np.testing.assert_array_equal(replay[:, 0], same[:, 0])
    # a copy that takes other actions does not move its source
    env.copy_env(0, [1])
    _run(env, [1], [0.9], 3)
    untouched, _ = _run(env, [0], [-0.2], 3)
    fresh = BearingPreloadVectorEnv(num_envs=1, tier=tier, episode_steps=12, max_episode_steps=12)
    fresh.reset(seed=300007)
    _run(fresh, [0], [0.1], 4)
    _run(fresh, [0], [-0.2], 5)
    reference, _ = _run(fresh, [0], [-0.2], 3)
    np.testing.assert_array_equal(untouched[:, 0], reference[:, 0])


def test_copy_env_names_bad_indices():
    env = BearingPreloadVectorEnv(num_envs=2, tier="paper", episode_steps=3, max_episode_steps=3)
    env.reset(seed=0)
    with pytest.raises(ValueError, match="src must be"):
        env.copy_env(2, 0)
    with pytest.raises(ValueError, match="other than src"):
        env.copy_env(0, [0])
