"""The scripted baselines: inside the action space, their rules, the oracle on the paper preset."""

import numpy as np
import pytest

from bearing_gym.envs import BearingPreloadEnv
from bearing_gym.envs.observation import FEATURE_NAMES

from agents.evaluation.episodes import run_policies
from agents.policies.scripted import ConstantPreload, FeedbackRule, OraclePreload, SpeedScheduledPreload
from agents.policies.stability_table import DEFAULT_PATH, StabilityTable


@pytest.fixture(scope="module")
def table():
    return StabilityTable.load(DEFAULT_PATH)


def all_policies(table):
    return [ConstantPreload(900.0), FeedbackRule(), SpeedScheduledPreload(table), OraclePreload(table)]


def test_scripted_policies_act_within_the_action_space(table):
    env = BearingPreloadEnv()
    rng = np.random.default_rng(0)
    obs = np.array([env.observation_space.sample() for _ in range(16)])
    obs[:, 8] = rng.uniform(0, 1.5, 16)          # quasi-periodicity index
    for pol in all_policies(table):
        if isinstance(pol, OraclePreload):
            pol.set_conditions(rng.uniform(0, 40000, 16), rng.uniform(0, 800, 16), rng.uniform(0, 4e-5, 16))
        act, _ = pol.predict(obs)
        assert act.shape == (16, 1) and act.dtype == np.float32
        assert np.all(act >= -1.0) and np.all(act <= 1.0), pol.name


def test_constant_preload_rejects_out_of_range():
    with pytest.raises(ValueError, match="preload_n"):
        ConstantPreload(5000.0)


def test_feedback_rule_raises_on_quasi_periodic_and_lowers_slowly():
    pol = FeedbackRule(start_n=1000.0, raise_n=200.0, lower_n=10.0, hold_steps=2)
    obs = np.zeros((1, len(FEATURE_NAMES)))
    obs[0, 8] = 0.9
    _, st = pol.predict(obs, episode_start=np.array([True]))
    assert st[0, 0] == 1200.0
    obs[0, 8] = 0.01
    for _ in range(3):
        _, st = pol.predict(obs, state=st)
    assert st[0, 0] == 1190.0


def test_oracle_keeps_the_paper_preset_periodic(table):
    res = run_policies([OraclePreload(table)], episodes=1, seed=0, episode_steps=40,
                       env_kwargs={"scenario": "paper"})[0]
    assert res.trace["qpi"][-10:].max() < 0.1
    crit = table.critical([20000.0], [0.0], [4e-6])[0]
    assert res.trace["preload_n"][-1] == pytest.approx(crit + 100.0, rel=1e-3)
