"""A submission file round-trips into a board as a row marked submitted, with the numbers the API
scored; a stale or foreign one is refused, saying which check failed."""

import dataclasses
import json

import numpy as np
import pytest

from agents.leaderboard import board as leaderboard
from agents.leaderboard.results_file import header, write
from agents.leaderboard.settings import FULL
from agents.submit import SubmissionRefused, add_submission, check_submission, load_submission, score
from agents.submit.__main__ import main as submit_main

from tests.agents.submit.test_api import NUMBERS, REPS, qp_rule

TIER, EPISODES = "transient", 3


@pytest.fixture(scope="module")
def board_and_submission(tmp_path_factory):
    """A board of the first 3 transient test episodes (the references' rows, the contextual
    constant and the oracle) and a NumPy rule scored on the same episodes, saved."""
    from agents.references.store import load_references
    d = tmp_path_factory.mktemp("board")
    s = dataclasses.replace(FULL, episodes=EPISODES, **REPS)
    results = header("full", "test board", s.bootstrap_reps, s.poi_reps)
    results["tiers"][TIER] = leaderboard.run_tier(TIER, s, [], stored=load_references(TIER), progress=False)
    board_path = d / "results.json"
    write(results, board_path)
    scored = score(qp_rule, tier=TIER, episodes=EPISODES, name="qp rule", progress=False, **REPS)
    sub_path = scored.save(d / "qp_rule.json", algorithm="rule", training_steps=0, training_seeds=[7],
                           library="numpy", library_version=np.__version__, code="tests/agents/submit")
    return board_path, sub_path, scored


def test_a_submission_joins_the_board_as_a_submitted_row_with_the_scored_numbers(board_and_submission):
    board_path, sub_path, scored = board_and_submission
    board = json.loads(board_path.read_text())
    sub = load_submission(sub_path)
    assert sub["training_seeds"] == [7] and sub["library"] == "numpy" and sub["tier"] == TIER
    assert len(sub["runs"]) == 1 and len(sub["runs"][0]["returns"]) == EPISODES
    name, row = add_submission(sub, board)
    assert name == "qp rule (submitted)" and row["kind"] == "submitted" and row["algorithm"] == "rule"
    for key in NUMBERS:
        assert row[key] == scored.row[key], key
    # through the command: the table gets the row too
    assert submit_main(["add", str(sub_path), "--board", str(board_path)]) == 0
    assert "| qp rule (submitted) |" in board_path.with_suffix(".md").read_text()
    assert submit_main(["add", str(sub_path), "--board", str(board_path)]) == 2          # the name is taken
    assert submit_main(["add", str(sub_path), "--board", str(board_path), "--replace"]) == 0


@pytest.mark.parametrize("change,match", [
    (lambda s: s.update(kernel_hash="0123456789abcdef"), "made by kernel 0123456789abcdef"),
    (lambda s: s.update(protocol_version=0), "protocol version 0"),
    (lambda s: s.update(test_seeds=[300001, 300003]), "test seeds"),
    (lambda s: s.update(episodes=2, test_seeds=[300000, 300001]), "test seeds"),
    (lambda s: s.update(tier="field"), "tier 'field'"),
    (lambda s: s.update(variant="constrained"), "constrained"),
    (lambda s: s.update(privileged=True), "privileged information"),
    (lambda s: s["runs"][0].update(returns=s["runs"][0]["returns"][:2]), "3 episode returns"),
])
def test_a_stale_or_foreign_submission_is_refused_saying_why(board_and_submission, change, match, tmp_path, capsys):
    board_path, sub_path, _ = board_and_submission
    sub = load_submission(sub_path)
    change(sub)
    with pytest.raises(SubmissionRefused, match=match):
        check_submission(sub, json.loads(board_path.read_text()))
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(sub))
    assert submit_main(["check", str(bad), "--board", str(board_path)]) == 2
    assert "refused" in capsys.readouterr().err


def test_a_board_of_another_kernel_takes_no_submission(board_and_submission):
    board_path, sub_path, _ = board_and_submission
    board = json.loads(board_path.read_text())
    board["kernel_hash"] = "fedcba9876543210"
    with pytest.raises(SubmissionRefused, match="regenerate the board"):
        check_submission(load_submission(sub_path), board)


def test_a_file_that_is_not_a_submission_is_refused(tmp_path):
    p = tmp_path / "x.json"
    p.write_text(json.dumps({"tiers": {}}))
    with pytest.raises(SubmissionRefused, match="not a submission file"):
        load_submission(p)
    p.write_text("{")
    with pytest.raises(SubmissionRefused, match="not a readable submission"):
        load_submission(p)


def test_the_submission_names_one_training_seed_per_run(board_and_submission):
    _, _, scored = board_and_submission
    with pytest.raises(ValueError, match="one per run"):
        scored.submission("rule", training_seeds=[1, 2])
    with pytest.raises(ValueError, match="algorithm must name"):
        scored.submission(" ")
