"""Re-scoring a board from its stored per-episode returns (agents.leaderboard.rescore): against
the references it was scored with it changes nothing; against a new planner it gives the
normalised score of the formula, computed here by hand; a store that is not the board's is refused."""

import copy
import dataclasses

import numpy as np
import pytest

from agents.leaderboard import board as leaderboard
from agents.leaderboard import rescore as rs
from agents.leaderboard.results_file import header
from agents.leaderboard.scoring import DENOMINATOR_FLOOR
from agents.leaderboard.tables import score_fields
from agents.references.store import load_references

from tests.agents.leaderboard.test_board import untrained_runs

SCORE_KEYS = ("normalised_score_iqm", "ci_low", "ci_high", "normalised_score_mean", "above_one_fraction",
              "probability_of_improvement", "poi_ci_low", "poi_ci_high")


@pytest.fixture(scope="module")
def smoke_board(tmp_path_factory):
    """A smoke board of the transient tier with an untrained PPO (two seeds) and its stored references."""
    tmp = tmp_path_factory.mktemp("rescore")
    groups = leaderboard.learned_groups(untrained_runs(tmp), pretrained=False)
    s = leaderboard.SMOKE
    tier = leaderboard.run_tier("transient", s, groups, out_dir=tmp, progress=False, contextual_dir=tmp,
                                save_references_to=tmp / "refs")
    results = header("smoke", "test", s.bootstrap_reps, s.poi_reps)
    results["tiers"]["transient"] = tier
    return results, tmp / "refs", tmp, groups


def test_rescoring_against_the_same_references_changes_no_score(smoke_board):
    results, refs_dir, _, _ = smoke_board
    again = rs.rescore(copy.deepcopy(results), refs_dir, "rescore-test")
    before, after = results["tiers"]["transient"], again["tiers"]["transient"]
    assert list(after["policies"]) == list(before["policies"])            # the same rows in the same order
    for name, row in before["policies"].items():
        for key in SCORE_KEYS + ("poi_over", "seed_ci_low", "seed_ci_high"):
            assert after["policies"][name].get(key) == row.get(key), (name, key)
    assert after["planner_minus_hindsight"] == before["planner_minus_hindsight"]
    assert after["rescored_by"] == "rescore-test"


def test_a_better_planner_rescales_every_score_as_the_formula_says(smoke_board, tmp_path):
    results, refs_dir, _, _ = smoke_board
    refs = load_references("transient", refs_dir)
    gain = np.array([7.0, 0.25])                 # a planner that found more on both episodes
    refs.planner.returns = np.asarray(refs.planner.returns) + gain
    refs.save(tmp_path)
    out = rs.rescore(copy.deepcopy(results), tmp_path, "rescore-test")["tiers"]["transient"]
    r0 = np.asarray(refs.validation_constant.returns)
    r1 = np.asarray(refs.planner.returns)
    rows = out["policies"]
    contextual = np.atleast_2d(rows["contextual constant"]["episode_returns"])
    for name, row in rows.items():
        ret = np.asarray(row["episode_returns"])
        by_hand = (ret - r0) / np.maximum(r1 - r0, DENOMINATOR_FLOOR)      # the score's definition
        assert row["normalised_score_mean"] == pytest.approx(by_hand.mean(), rel=1e-12, abs=1e-12), name
        assert row["above_one_fraction"] == pytest.approx(np.mean(by_hand > 1.0)), name
        # every score field (intervals, probabilities of improvement) as the board computes them
        versus = {"contextual constant": contextual} if "poi_over" in row else None
        fresh = score_fields(ret, r0, r1, results["statistics"]["bootstrap_reps"], results["statistics"]["poi_reps"],
                             versus)
        assert {k: row[k] for k in fresh} == fresh, name
    planner = out["policies"][leaderboard.PLANNER_ROW]
    assert planner["episode_returns"] == [list(r1)]
    old_gain = results["tiers"]["transient"]["planner_minus_hindsight"]["mean"]
    assert out["planner_minus_hindsight"]["mean"] == pytest.approx(old_gain + gain.mean(), abs=1e-9)


def test_a_board_without_the_planner_gains_its_row_and_loses_the_deviation(smoke_board, tmp_path):
    with_planner, refs_dir, tmp, groups = smoke_board
    s = dataclasses.replace(leaderboard.SMOKE, planner=None)
    refs = load_references("transient", refs_dir)
    tier = leaderboard.run_tier("transient", s, groups, out_dir=tmp, progress=False, contextual_dir=tmp, stored=refs)
    assert any(d.startswith("no planner") for d in tier["protocol_deviations"])
    assert leaderboard.PLANNER_ROW not in tier["policies"]
    results = header("smoke", "test", s.bootstrap_reps, s.poi_reps)
    results["tiers"]["transient"] = tier
    out = rs.rescore(results, refs_dir, "rescore-test")["tiers"]["transient"]
    # the deviations of the board that ran with the (smoke) planner: no "no planner" left
    assert out["protocol_deviations"] == with_planner["tiers"]["transient"]["protocol_deviations"]
    assert not any(d.startswith("no planner") for d in out["protocol_deviations"])
    names = list(out["policies"])
    assert names.index(leaderboard.PLANNER_ROW) == names.index("PPO (trained)") - 1     # before the learned rows
    assert out["planner_episodes"] == 2 and out["upper_reference"].startswith("the planner")


@pytest.mark.parametrize("row", ["validation_constant", "hindsight"])
def test_a_store_that_is_not_the_boards_is_refused(smoke_board, tmp_path, row):
    results, refs_dir, _, _ = smoke_board
    refs = load_references("transient", refs_dir)
    ref = getattr(refs, row)
    ref.returns = np.asarray(ref.returns).copy()
    ref.returns[1] = np.nextafter(ref.returns[1], 0.0)     # one ulp
    refs.save(tmp_path)
    with pytest.raises(ValueError, match=f"{row.replace('_', ' ')}.*bit for bit"):
        rs.rescore(copy.deepcopy(results), tmp_path, "rescore-test")
    other_search = load_references("transient", refs_dir)
    other_search.planner_settings = {**other_search.planner_settings, "replan_every": 2}
    other_search.save(tmp_path)
    with pytest.raises(ValueError, match="stored planner of tier transient searched with.*planner_runs"):
        rs.rescore(copy.deepcopy(results), tmp_path, "rescore-test")
    other = copy.deepcopy(results)
    other["kernel_hash"] = "0123456789abcdef"
    with pytest.raises(ValueError, match="kernel 0123456789abcdef"):
        rs.rescore(other, refs_dir, "rescore-test")


def test_the_command_rewrites_the_file_and_its_table(smoke_board, tmp_path):
    import json
    results, refs_dir, _, _ = smoke_board
    path = tmp_path / "results.json"
    path.write_text(json.dumps(results))
    rs.main(["--results", str(path), "--references-dir", str(refs_dir)])
    table = (tmp_path / "results_table.md").read_text()
    assert "re-computed from the rows' stored per-episode returns" in table
    assert json.loads(path.read_text())["tiers"]["transient"]["rescored_by"].startswith("python -m agents.leaderboard.rescore")
    with pytest.raises(SystemExit, match="rescore: no stored test references"):
        rs.main(["--results", str(path), "--references-dir", str(tmp_path / "none")])
