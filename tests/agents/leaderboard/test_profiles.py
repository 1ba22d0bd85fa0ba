"""The board's distribution statistics: performance profiles, the optimality gap and the pairwise
probabilities of improvement, each against a direct calculation."""

import numpy as np
import pytest

pytest.importorskip("rliable")

from agents.leaderboard import profiles, scoring                                   # noqa: E402
from agents.leaderboard.tables import pairwise_improvement                         # noqa: E402


def _results():
    r0 = [-10.0, -20.0, -30.0, -40.0]
    hind = [-6.0, -15.0, -30.0, -20.0]
    plan = [-5.0, -10.0, -29.5, -20.0]            # episode 2: a gap of 0.5 < the floor (1)
    pol = {"validation constant (1000 N)": {"kind": "reference", "episode_returns": [r0]},
           "hindsight constant (50 N grid)": {"kind": "reference", "episode_returns": [hind]},
           "planner (true simulator, the episode's future)": {"kind": "reference", "episode_returns": [plan]},
           "A (trained)": {"kind": "learned", "episode_returns": [[-5.0, -15.0, -30.0, -30.0],
                                                                   [-10.0, -10.0, -29.0, -50.0]]}}
    return {"tiers": {"t": {"episodes": 4, "denominator_floor": 1.0, "policies": pol}}}


def test_scores_are_the_boards_and_the_profile_counts_them():
    s = profiles.tier_scores(_results(), "t")
    assert "planner (true simulator, the episode's future)" not in s
    # by hand: (R - R0) / max(R1 - R0, 1)
    want = np.array([[5 / 5, 5 / 10, 0 / 1, 10 / 20], [0 / 5, 10 / 10, 1 / 1, -10 / 20]])
    np.testing.assert_allclose(s["A (trained)"], want, rtol=0, atol=1e-15)
    point, band = profiles.profiles({"A": s["A (trained)"]}, taus=np.array([-0.6, 0.25, 0.75, 1.0]), reps=200)
    np.testing.assert_allclose(point["A"], [8 / 8, 5 / 8, 3 / 8, 0 / 8])
    assert band["A"].shape == (2, 4) and np.all(band["A"][0] <= point["A"] + 1e-12)


def test_optimality_gap_is_the_mean_shortfall_below_one():
    s = profiles.tier_scores(_results(), "t")["A (trained)"]
    gap, lo, hi = scoring.optimality_gap_interval(s, reps=500)
    assert gap == pytest.approx(np.mean(np.maximum(1.0 - s, 0.0)), abs=1e-15)
    assert lo <= gap <= hi


def test_pairwise_probabilities_are_complementary_and_see_dominance():
    r0, r1 = np.zeros(5), np.ones(5)
    rng = np.random.default_rng(3)
    a, b = rng.normal(size=(3, 5)), rng.normal(size=(2, 5))
    out = pairwise_improvement({"a": a, "b": b, "top": np.full((1, 5), 10.0)}, r0, r1, poi_reps=200)
    assert set(out) == {"a", "b"} and set(out["a"]) == {"b", "top"} and set(out["b"]) == {"top"}
    back = pairwise_improvement({"b": b, "a": a}, r0, r1, poi_reps=200)
    assert out["a"]["b"][0] + back["b"]["a"][0] == pytest.approx(1.0, abs=1e-12)
    assert out["a"]["top"][0] == 0.0 and out["b"]["top"] == [0.0, 0.0, 0.0]


def test_the_figure_shows_each_learned_rows_selection_the_best_industry_row_and_the_references():
    res = _results()
    pol = res["tiers"]["t"]["policies"]
    ret = [[-6.0, -14.0, -30.0, -35.0]]
    pol["A (trained, best up to 100k steps)"] = {"kind": "learned", "early_row_steps": 100_000, "episode_returns": ret}
    pol["switch"] = {"kind": "industry", "normalised_score_iqm": 0.1, "episode_returns": ret}
    pol["table"] = {"kind": "industry", "normalised_score_iqm": 0.3, "episode_returns": ret}
    pol["causal MPC"] = {"kind": "model-based", "episode_returns": ret}
    pol["someone's rule"] = {"kind": "submitted", "episode_returns": ret}
    shown = profiles.plotted(res, "t")
    assert set(shown) == {"hindsight constant (50 N grid)", "A (trained)", "table", "causal MPC"}
    np.testing.assert_array_equal(shown["A (trained)"], profiles.tier_scores(res, "t")["A (trained)"])
