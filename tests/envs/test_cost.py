"""The safe-RL cost channel (``info["cost"]``) and the constrained variant's reward.

The convention is the one safe-RL libraries read from a Gymnasium env (Safety-Gymnasium's cost,
OmniSafe's wrappers of plain envs): a float in every step's info, the interval's constraint
violation; 0 in the reset info. Here: 1.0 for a quasi-periodic interval, 0.0 for a period-1 one;
on termination 1 + the intervals left (a crash never pays). The libraries pin an older
gymnasium, so the semantics are checked here directly.
"""

import gymnasium as gym
import numpy as np
import pytest

import bearing_gym  # noqa: F401
from bearing_gym.envs import BearingPreloadEnv, BearingPreloadVectorEnv, constrained_reward
from bearing_gym.envs.composition import interval_cost
from bearing_gym.task import COST_BUDGET_PER_EPISODE, EPISODE_STEPS

# paper scenario at 300 N: quasi-periodic (the paper's critical preload is ~580 N); 2000 N: period-1
LOW, HIGH = -1.0, 1.0


def _costs(env, action, steps):
    _, info = env.reset(seed=0)
    out = [(info["cost"], None)]
    for _ in range(steps):
        _, _, term, _, info = env.step(np.array([action], np.float32))
        out.append((info["cost"], info["quasi_periodic"]))
        if term:
            break
    return out


@pytest.mark.parametrize("action,expect_qp", [(LOW, True), (HIGH, False)])
def test_the_cost_is_the_intervals_quasi_periodic_indicator_and_zero_at_reset(action, expect_qp):
    out = _costs(gym.make("BearingPreload-v0", scenario="paper"), action, 12)
    assert out[0][0] == 0.0 and isinstance(out[0][0], float)
    for cost, qp in out[1:]:
        assert isinstance(cost, float) and cost == (1.0 if qp else 0.0)
    assert any(qp for _, qp in out[-6:]) == expect_qp      # the settled motion at that preload


def test_a_termination_costs_one_per_interval_left():
    env = BearingPreloadEnv(scenario="paper", params=bearing_gym.envs.env_params(divergence_limit_m=2e-5))
    env.reset(seed=0)
    for k in range(1, 21):
        *_, term, _, info = env.step(np.array([-1.0], dtype=np.float32))
        if term:
            break
    assert term and info["cost"] == 1.0 + (EPISODE_STEPS - k)
    assert interval_cost(True, False, 5) == 1.0 and interval_cost(False, False, 5) == 0.0
    assert interval_cost(False, True, 0) == 1.0


def test_the_vector_env_sums_to_the_quasi_periodic_intervals():
    venv = BearingPreloadVectorEnv(num_envs=2, tier="transient", max_episode_steps=None)
    _, info = venv.reset(seed=300)
    assert np.array_equal(info["cost"], [0.0, 0.0])
    cost = qp = 0.0
    for _ in range(10):
        _, _, _, _, info = venv.step(np.full((2, 1), -0.8, np.float32))
        cost += info["cost"]
        qp += info["quasi_periodic"]
    assert np.array_equal(cost, qp)


def test_the_constrained_reward_is_the_reward_without_its_vibration_term():
    """Same actions, same trajectory: the constrained reward equals the benchmark's minus its
    vibration term, step by step (no termination here), and charges no vibration."""
    plain = gym.make("BearingPreload-v0", scenario="paper")
    constrained = gym.make("BearingPreload-v0", scenario="paper", reward=constrained_reward())
    plain.reset(seed=0)
    constrained.reset(seed=0)
    saw_qp = False
    for a in np.linspace(-1, 1, 8):
        _, r, _, _, i = plain.step(np.array([a], np.float32))
        _, rc, _, _, ic = constrained.step(np.array([a], np.float32))
        saw_qp |= i["quasi_periodic"]
        assert rc == pytest.approx(r - i["reward_vibration"], rel=0, abs=1e-12)
        assert ic["reward_vibration"] == 0.0 and ic["cost"] == i["cost"]
    assert saw_qp, "the action sequence should pass through quasi-periodic intervals"
    assert 0 < COST_BUDGET_PER_EPISODE < EPISODE_STEPS
