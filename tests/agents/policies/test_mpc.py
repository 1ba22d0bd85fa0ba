"""The MPC reference: a copy of the env continues identically, and with a horizon that covers
the episode it picks the best of its candidates in hindsight."""

import copy

import numpy as np
import pytest

from agents.policies.mpc import RecedingHorizonMPC, run_constant
from bearing_gym.envs import BearingPreloadEnv


def test_a_deepcopy_mid_episode_continues_identically():
    env = BearingPreloadEnv(tier="transient", episode_steps=8)
    env.reset(seed=7)
    a = np.array([0.1], np.float32)
    for _ in range(3):
        env.step(a)
    twin = copy.deepcopy(env)
    for _ in range(4):
        o1, r1, *_ = env.step(a)
        o2, r2, *_ = twin.step(a)
        np.testing.assert_array_equal(o1, o2)
        assert r1 == r2


def test_a_whole_episode_horizon_picks_the_best_candidate_in_hindsight():
    steps, candidates = 6, (600.0, 1000.0, 1400.0)
    env = BearingPreloadEnv(tier="paper", episode_steps=steps)
    constants = [run_constant(env, p, seed=0).episode_return for p in candidates]
    mpc = RecedingHorizonMPC(candidates_n=candidates, horizon=steps, replan_every=steps)
    out = mpc.run_episode(env, seed=0)
    assert out.episode_return == pytest.approx(max(constants), rel=1e-12)
    assert out.preload_n[-1] == pytest.approx(candidates[int(np.argmax(constants))], abs=50.0)
