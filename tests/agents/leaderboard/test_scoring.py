"""Normalised scores (limit cases, the denominator floor) and the rliable aggregation checked
against direct NumPy computations on hand-made arrays."""

import numpy as np
import pytest

from agents.leaderboard import scoring


R0 = np.array([-50.0, -80.0, -30.0, -60.0])
R1 = np.array([-40.0, -50.0, -29.5, -60.0])      # gaps 10, 30, 0.5 (< floor), 0 (< floor)


def test_the_validation_constant_scores_0_and_the_upper_reference_1():
    np.testing.assert_array_equal(scoring.normalised_scores(R0, R0, R1), np.zeros(4))
    s = scoring.normalised_scores(R1, R0, R1)
    np.testing.assert_allclose(s[:2], [1.0, 1.0], rtol=0, atol=1e-12)
    # halfway between the references scores 0.5; scores are not clipped on either side
    np.testing.assert_allclose(scoring.normalised_scores(R0 + 0.5 * (R1 - R0), R0, R1)[:2], [0.5, 0.5], atol=1e-12)
    np.testing.assert_allclose(scoring.normalised_scores(R0 - 20.0, R0, R1)[:2], [-2.0, -20.0 / 30.0], atol=1e-12)
    np.testing.assert_allclose(scoring.normalised_scores(R1 + 10.0, R0, R1)[:2], [2.0, 1.0 + 1.0 / 3.0], atol=1e-12)


def test_the_denominator_floor_holds_where_the_references_nearly_agree():
    floor = scoring.DENOMINATOR_FLOOR
    s = scoring.normalised_scores(R0 + 2.0, R0, R1)
    # gap 0.5 and 0 are below the floor: the score is the return difference over the floor
    np.testing.assert_allclose(s[2:], [2.0 / floor, 2.0 / floor], atol=1e-12)
    assert scoring.normalised_scores(R1, R0, R1)[2] == pytest.approx(0.5 / floor, abs=1e-12)
    assert scoring.floored_episodes(R0, R1) == 2
    # a smaller floor gives larger scores there, and nothing changes where the gap exceeds both
    s_small = scoring.normalised_scores(R0 + 2.0, R0, R1, floor=0.25)
    np.testing.assert_allclose(s_small[2:], [4.0, 8.0], atol=1e-12)
    np.testing.assert_allclose(s_small[:2], s[:2], atol=1e-12)
    with pytest.raises(ValueError, match="floor"):
        scoring.normalised_scores(R0, R0, R1, floor=0.0)


def test_the_floor_is_the_smallest_cost_of_one_quasi_periodic_interval():
    from bearing_gym.envs.reward import VibrationFirstReward
    cost = float(VibrationFirstReward().vibration_cost(True, 0.0))
    assert scoring.DENOMINATOR_FLOOR == pytest.approx(cost, abs=1e-12)


def test_runs_by_episodes_are_scored_against_the_same_episode_references():
    runs = np.vstack([R0, R1])
    s = scoring.normalised_scores(runs, R0, R1)
    assert s.shape == (2, 4)
    np.testing.assert_array_equal(s[0], np.zeros(4))


def test_the_upper_reference_is_the_planner_and_a_planner_below_the_hindsight_constant_is_refused():
    hind = np.array([-40.0, -50.0, -30.0])
    planner = np.array([-35.0, -50.0, -29.0])
    np.testing.assert_array_equal(scoring.upper_reference(hind, planner), planner)
    np.testing.assert_array_equal(scoring.upper_reference(hind), hind)          # no planner: the hindsight alone
    for broken in (np.array([-35.0, np.nextafter(-50.0, -np.inf), -29.0]), np.array([-35.0, np.nan, -29.0])):
        with pytest.raises(ValueError, match="below the hindsight constant's"):
            scoring.upper_reference(hind, broken)
    with pytest.raises(ValueError, match="every episode"):
        scoring.upper_reference(hind, planner[:2])


def _numpy_iqm(x: np.ndarray) -> float:
    """Mean of the middle 50 % of the sorted values (n divisible by 4: no partial weights)."""
    v = np.sort(x.ravel())
    n = len(v)
    return float(np.mean(v[n // 4: n - n // 4]))


def test_rliable_iqm_is_the_mean_of_the_middle_half():
    x = np.array([[0.0, 1.0, 2.0, 3.0, 100.0, -100.0],
                  [0.5, 1.5, 2.5, 3.5, 50.0, -50.0]])          # 12 values: the middle 6 count
    assert scoring.iqm(x) == pytest.approx(_numpy_iqm(x), abs=1e-12)
    assert scoring.iqm(x) == pytest.approx(np.mean([0.5, 1.0, 1.5, 2.0, 2.5, 3.0]), abs=1e-12)


def test_the_bootstrap_interval_brackets_the_iqm_and_is_reproducible():
    rng = np.random.default_rng(3)
    x = rng.normal(0.4, 0.3, size=(5, 40))
    point, lo, hi = scoring.iqm_interval(x, reps=500)
    assert point == pytest.approx(_numpy_iqm(x), abs=1e-12)
    assert lo < point < hi and hi - lo < 0.3               # 200 values of sd 0.3: a narrow interval
    assert scoring.iqm_interval(x, reps=500) == (point, lo, hi)
    # seeds only (episodes fixed) is narrower than seeds and episodes
    _, slo, shi = scoring.seed_interval(x, reps=500)
    assert shi - slo < hi - lo
    # a single run: a bootstrap over episodes, still a real interval
    _, lo1, hi1 = scoring.iqm_interval(x[:1], reps=500)
    assert lo1 < hi1


def test_probability_of_improvement_counts_wins_per_episode_with_half_ties():
    x = np.array([[1.0, -1.0, 0.0, 2.0],
                  [1.0, 1.0, -1.0, 2.0]])
    y = np.zeros((1, 4))
    # per episode: 2/2, 1/2, (tie + loss) 0.5/2, 2/2 -> mean (1 + 0.5 + 0.25 + 1) / 4
    p, lo, hi = scoring.probability_of_improvement(x, y, reps=50)
    assert p == pytest.approx(0.6875, abs=1e-12)
    assert lo is not None and lo <= p <= hi
    p1, lo1, hi1 = scoring.probability_of_improvement(x[:1], y, reps=200)
    assert p1 == pytest.approx((1 + 0 + 0.5 + 1) / 4, abs=1e-12)
    assert 0.0 <= lo1 < p1 < hi1 <= 1.0          # one run each: the episodes alone are redrawn


def test_the_improvement_interval_redraws_episodes_and_keeps_them_paired():
    """Two runs that win on exactly half the episodes: P = 0.5 whatever the runs, so a run-only
    bootstrap gives a zero-width interval; redrawing episodes gives the binomial spread of a mean of
    m coin flips (sd 0.5 / sqrt(m)): a 95 % interval about 4 sd wide. Paired draws keep P(x > x)
    at exactly one half in every replicate."""
    m = 100
    x = np.tile(np.r_[np.ones(m // 2), -np.ones(m // 2)], (3, 1))
    y = np.zeros((2, m))
    p, lo, hi = scoring.probability_of_improvement(x, y, reps=2000)
    assert p == 0.5
    assert (hi - lo) == pytest.approx(4 * 0.5 / np.sqrt(m), rel=0.15)
    assert scoring.probability_of_improvement(x[:1], x[:1], reps=200) == (0.5, 0.5, 0.5)


def test_the_vectorised_improvement_is_rliables():
    from rliable import metrics
    rng = np.random.default_rng(5)
    x = np.round(rng.normal(size=(4, 30)), 1)           # rounded: ties too
    y = np.round(rng.normal(size=(2, 30)), 1)
    assert scoring._improvement(x[None], y[None])[0] == pytest.approx(metrics.probability_of_improvement(x, y), abs=1e-12)


def test_poi_over_another_row_is_one_half_against_itself_and_one_against_a_worse_row():
    from agents.leaderboard.tables import summarise
    from agents.evaluation.result import EvalResult
    from bearing_gym.envs.reward import REWARD_TERMS
    rng = np.random.default_rng(3)
    n = 12
    r0, r1 = rng.normal(-150, 10, n), rng.normal(-100, 10, n)

    def result(returns):
        return EvalResult("p", returns, {k: np.zeros(n) for k in REWARD_TERMS}, np.zeros(n), np.full(n, 900.0))
    mine = result(rng.normal(-120, 10, n))
    worse = result(mine.returns - 5.0)          # 5 reward units below on every episode
    row = summarise("learned", [mine], r0, r1, bootstrap_reps=200, poi_reps=50,
                    versus={"itself": mine, "worse": worse})
    assert row["poi_over"]["itself"][0] == pytest.approx(0.5, abs=1e-12)    # ties count one half
    assert row["poi_over"]["worse"][0] == pytest.approx(1.0, abs=1e-12)
