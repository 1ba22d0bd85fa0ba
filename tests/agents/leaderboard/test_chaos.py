"""agents.leaderboard.chaos: replica 0 is the board's run, a perturbed replica moves every displacement of
the settled start by a few ulp and nothing else, and the summary's spreads are the formulas."""

import numpy as np
import pytest

from agents.leaderboard.chaos import RELATIVE_PERTURBATION, perturbation, replica_returns, summarise
from agents.policies.scripted import ConstantPreload
from bearing_gym.envs import BearingPreloadVectorEnv


def test_a_perturbed_replica_moves_the_start_by_a_few_ulp_only():
    venv = BearingPreloadVectorEnv(num_envs=2, tier="transient", max_episode_steps=None)
    venv.reset(seed=[300000, 300001])
    before = venv.batch.X.copy()
    perturbation(0)(venv, [300000, 300001])
    np.testing.assert_array_equal(venv.batch.X, before)           # replica 0: the board's run
    perturbation(3)(venv, [300000, 300001])
    first = venv.batch.X.copy()
    rel = np.abs(first / before - 1.0)
    assert np.all(rel > 0.0) and np.all(rel <= 1.5 * RELATIVE_PERTURBATION)
    venv.batch.X[:] = before
    perturbation(3)(venv, [300000, 300001])
    np.testing.assert_array_equal(venv.batch.X, first)            # the same replica, the same nudge
    venv.batch.X[:] = before
    perturbation(4)(venv, [300000, 300001])
    assert not np.array_equal(venv.batch.X, first)                # another replica, another nudge


def test_replica_zero_repeats_bit_for_bit_and_a_replica_is_a_nearby_sample():
    pol = [ConstantPreload(1850.0)]
    a = replica_returns(pol, "transient", 2, 0, episode_steps=5, progress=False)
    b = replica_returns(pol, "transient", 2, 0, episode_steps=5, progress=False)
    assert a == b
    c = replica_returns(pol, "transient", 2, 1, episode_steps=5, progress=False)
    name = pol[0].name
    np.testing.assert_allclose(c[name], a[name], rtol=1e-3)        # 5 intervals: not yet apart


def test_summary_spreads_are_the_formulas():
    R = np.array([[1.0, 2.0, 3.0, 4.0], [1.0, 2.5, 3.0, 4.0], [1.0, 4.0, 3.0, 4.0]])
    row = summarise({"p": R})["p"]
    assert row["episodes_bit_identical"] == pytest.approx(0.75)
    assert row["episodes_moving_more_than_1"] == pytest.approx(0.25)
    sd = R.std(axis=0, ddof=1)
    assert row["episode_sd_median"] == pytest.approx(np.median(sd))
    scored = summarise({"p": R}, r0=np.zeros(4), r1=np.full(4, 10.0))["p"]
    np.testing.assert_allclose(scored["score_iqm_per_replica"], np.array(row["return_iqm_per_replica"]) / 10.0)
