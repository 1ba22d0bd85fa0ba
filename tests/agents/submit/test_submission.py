"""A submission file round-trips into a board as a row marked submitted, with the numbers the API
scored; a stale or foreign one is refused, saying which check failed."""

import dataclasses
import json

import numpy as np
import pytest

from agents.leaderboard import board as leaderboard
from agents.leaderboard.results_file import header, table_path, write
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


def test_a_submission_joins_the_board_as_a_submitted_row_with_the_scored_numbers(board_and_submission, tmp_path):
    pristine, sub_path, scored = board_and_submission
    board_path = tmp_path / "results.json"                 # a copy: the fixture's board stays without the row
    board_path.write_text(pristine.read_text())
    board = json.loads(board_path.read_text())
    sub = load_submission(sub_path)
    assert sub["training_seeds"] == [7] and sub["library"] == "numpy" and sub["tier"] == TIER
    assert len(sub["runs"]) == 1 and len(sub["runs"][0]["returns"]) == EPISODES
    name, row = add_submission(sub, board)
    assert name == "qp rule (submitted)" and row["kind"] == "submitted" and row["algorithm"] == "rule"
    for key in NUMBERS:
        if key == "poi_over":       # the board adds its best industry row to the API's comparisons
            assert {k: v for k, v in row[key].items() if k in scored.row[key]} == scored.row[key]
        else:
            assert row[key] == scored.row[key], key
    # compared with the board's best industry row as the board's own rows are (rliable's statistic
    # on the normalised scores, paired by episode; computed here directly)
    from agents.leaderboard import scoring
    from agents.leaderboard.upper import score_bounds
    from agents.submit.rows import test_references
    best = board["tiers"][TIER]["best_industry_row"]
    assert best is not None and board["tiers"][TIER]["policies"][best]["kind"] == "industry"
    r0, r1 = score_bounds(test_references(TIER, EPISODES))
    direct = scoring.probability_of_improvement(
        scoring.normalised_scores(np.array([r["returns"] for r in sub["runs"]]), r0, r1),
        scoring.normalised_scores(np.array(board["tiers"][TIER]["policies"][best]["episode_returns"]), r0, r1),
        reps=board["statistics"]["poi_reps"])
    assert row["poi_over"][best] == pytest.approx(list(direct), abs=1e-12)
    # through the command: the table gets the row too
    assert submit_main(["add", str(sub_path), "--board", str(board_path)]) == 0
    assert "| qp rule (submitted) |" in table_path(board_path).read_text()
    assert submit_main(["add", str(sub_path), "--board", str(board_path)]) == 2          # the name is taken
    assert submit_main(["add", str(sub_path), "--board", str(board_path), "--replace"]) == 0


@pytest.mark.parametrize("change,match", [
    (lambda s: s.update(kernel_hash="0123456789abcdef"), "made by kernel 0123456789abcdef"),
    (lambda s: s.update(protocol_version=0), "protocol version 0"),
    (lambda s: s.update(protocol_version=None), "protocol version None"),
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


def test_check_runs_what_add_runs_and_a_board_whose_rows_are_not_the_stores_refuses(board_and_submission, tmp_path):
    board_path, sub_path, _ = board_and_submission
    board = json.loads(board_path.read_text())
    name = next(n for n in board["tiers"][TIER]["policies"] if n.startswith("validation constant"))
    board["tiers"][TIER]["policies"][name]["episode_returns"][0][0] += 1.0
    other = tmp_path / "results.json"
    other.write_text(json.dumps(board))
    assert submit_main(["check", str(sub_path), "--board", str(other)]) == 2
    with pytest.raises(ValueError, match="does not hold the stored references' returns"):
        add_submission(load_submission(sub_path), board)


@pytest.mark.parametrize("change,match", [
    (lambda s: s.pop("name"), "'name' must be a str"),
    (lambda s: s["runs"][0].pop("terms"), "reward terms"),
    (lambda s: s["runs"][0]["returns"].__setitem__(0, float("nan")), "finite numbers"),
    (lambda s: s["runs"].__setitem__(0, 3), "not an object"),
    (lambda s: s["runs"][0].update(terminated=[1, 0, 0]), "booleans"),
])
def test_a_malformed_submission_is_refused_naming_the_field(board_and_submission, tmp_path, change, match):
    _, sub_path, _ = board_and_submission
    sub = json.loads(sub_path.read_text())
    change(sub)
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(sub))
    with pytest.raises(SubmissionRefused, match=match):
        load_submission(bad)


def test_a_submission_keeps_its_file_beside_the_board_and_a_rebuilt_board_adds_it_again(board_and_submission,
                                                                                          tmp_path):
    from agents.submit.submission import readd_stored, stored_path
    board_path, sub_path, scored = board_and_submission
    board = tmp_path / "results.json"
    board.write_text(board_path.read_text())
    assert submit_main(["add", str(sub_path), "--board", str(board)]) == 0
    kept = stored_path(board, load_submission(sub_path))
    assert kept.exists() and kept.parent == tmp_path / "submissions"
    rebuilt = json.loads(board_path.read_text())                     # the board as built, without the row
    assert "qp rule (submitted)" not in rebuilt["tiers"][TIER]["policies"]
    lines = readd_stored(rebuilt, board)
    assert lines == [f"{kept.name}: row 'qp rule (submitted)' on {TIER}"]
    row = rebuilt["tiers"][TIER]["policies"]["qp rule (submitted)"]
    assert row["episode_returns"] == scored.row["episode_returns"]
    assert any("training seed" in n for n in row["submission_notes"])              # 1 seed: the rules ask for 3
    from agents.leaderboard.tables import to_markdown
    assert "Submitted rows" in to_markdown(rebuilt)


def test_a_submitted_name_never_takes_a_reference_row(board_and_submission):
    from agents.leaderboard.rescore import row_named
    board_path, sub_path, _ = board_and_submission
    board = json.loads(board_path.read_text())
    sub = load_submission(sub_path)
    sub["name"] = "validation constant twin"
    add_submission(sub, board)
    rows = board["tiers"][TIER]["policies"]
    name, row = row_named(rows, "validation constant", TIER)            # still the reference row
    assert row["kind"] == "reference" and "validation constant twin (submitted)" in rows
