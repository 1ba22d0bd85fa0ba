"""agents.leaderboard.breakdown: the scenarios it reconstructs are the env's, the scores it rebuilds
from results.json are the leaderboard's formula, and the rank correlation sees a planted
dependence."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

from agents.leaderboard import breakdown as sb
from agents.protocol import TEST


def test_features_are_the_scenarios_the_env_draws():
    seeds = [TEST.start + 3, TEST.start + 41]
    f = sb.episode_features("transient", seeds, 150)
    env = gym.make("BearingPreload-v0", tier="transient")
    for i, s in enumerate(seeds):
        env.reset(seed=s)
        sc = env.unwrapped.scenario
        assert f["start speed (rpm)"][i] == sc.speed_profile[0][1]
        assert f["end speed (rpm)"][i] == sc.speed_profile[-1][1]
        assert f["clearance (um)"][i] == pytest.approx(sc.clearance_m * 1e6, rel=1e-12)
        assert f["highest radial load (N)"][i] == max(v for _, v in sc.radial_load_profile)
    env.close()


def _results(n: int, learned: np.ndarray, planner: bool = True, tier: str = "transient") -> dict:
    r0 = -np.linspace(100.0, 50.0, n)
    hindsight = r0 + 10.0
    gain = np.where(np.arange(n) < 2, 5.0, 0.0)              # the planner gains 5 on the first 2 episodes
    rows = {"validation constant (1000 N)": {"episode_returns": [r0.tolist()]},
            "hindsight constant (50 N grid)": {"episode_returns": [hindsight.tolist()]},
            "contextual constant": {"episode_returns": [(r0 + 5.0).tolist()]},
            "SAC (2 seeds)": {"episode_returns": learned.tolist()}}
    if planner:
        rows["planner (true simulator, the episode's future)"] = {"episode_returns": [(hindsight + gain).tolist()]}
    return {"tiers": {tier: {"policies": rows, "planner_episodes": n if planner else 0, "episode_steps": 150,
                             "seeds": [TEST.start, TEST.start + n - 1]}}}


def test_scores_follow_the_leaderboard_formula():
    n = 6
    r0 = -np.linspace(100.0, 50.0, n)
    learned = np.array([r0 + 3.0, r0 + 6.0])
    r0_, r1, scores = sb.episode_scores(_results(n, learned)["tiers"]["transient"])
    # upper reference: the planner, hindsight (r0 + 10) + 5 on the first 2 episodes, the hindsight after
    np.testing.assert_allclose(r1 - r0_, [15, 15, 10, 10, 10, 10])
    np.testing.assert_allclose(scores["SAC (2 seeds)"][1], 6.0 / np.array([15, 15, 10, 10, 10, 10]))
    np.testing.assert_allclose(scores["contextual constant"][0], 5.0 / np.array([15, 15, 10, 10, 10, 10]))


def test_a_planted_dependence_on_a_feature_is_ranked_first(tmp_path):
    n = 12
    seeds = list(range(TEST.start, TEST.start + n))
    clearance = sb.episode_features("transient", seeds, 150)["clearance (um)"]
    r0 = -np.linspace(100.0, 50.0, n)
    learned = np.array([r0 + clearance, r0 + clearance])       # score rises with clearance
    b = sb.breakdown(_results(n, learned, planner=False), "transient", "SAC", data_dir=tmp_path)   # no stored refs
    top = max(b["features"], key=lambda r: abs(r["spearman_rho"]))
    assert top["feature"] == "clearance (um)"
    assert top["spearman_rho"] == pytest.approx(1.0, abs=1e-12)
    assert "hindsight best constant: mean applied preload (N)" not in [r["feature"] for r in b["features"]]
    assert "| clearance (um) | +1.00" in sb.to_markdown(b)


def test_an_ambiguous_row_name_is_refused():
    with pytest.raises(KeyError, match="several rows"):
        sb.breakdown(_results(4, np.zeros((1, 4))), "transient", "")


def test_features_equal_on_every_episode_share_one_row(tmp_path):
    """On stationary the speed does not change, so start, end, lowest and highest speed are one
    feature (one row, named by all four); on transient they differ and keep their rows."""
    n = 12
    learned = np.array([-np.linspace(100.0, 50.0, n) + np.arange(n)])
    speeds = ["start speed (rpm)", "end speed (rpm)", "lowest speed (rpm)", "highest speed (rpm)"]
    st = sb.breakdown(_results(n, learned, planner=False, tier="stationary"), "stationary", "SAC", data_dir=tmp_path)
    names = [r["feature"] for r in st["features"]]
    assert " = ".join(speeds) in names and not set(speeds) & set(names)
    tr = sb.breakdown(_results(n, learned, planner=False), "transient", "SAC", data_dir=tmp_path)
    assert {"start speed (rpm)", "end speed (rpm)"} <= {r["feature"] for r in tr["features"]}
