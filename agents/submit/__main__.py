"""``python -m agents.submit add FILE`` / ``check FILE`` / ``readd``: a submission onto a board
(:mod:`agents.submit.submission` says what is checked and where the board keeps it)."""

from __future__ import annotations

import argparse
import copy
import json
import sys
from pathlib import Path

from agents.paths import DATA_DIR, require_checkout
from agents.submit.submission import (SubmissionRefused, add_submission, load_submission, readd_stored,
                                      stored_path, write_submission)


def _board_path(given: str | None) -> Path:
    if given:
        return Path(given)
    try:
        return require_checkout("docs/results.json", "--board") / "docs" / "results.json"
    except ValueError as err:
        raise SystemExit(f"agents.submit: {err}") from None


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m agents.submit",
                                 description="Add a submission file (agents.submit.score(...).save(...)) to a board.")
    sub = ap.add_subparsers(dest="command", required=True)
    for name, what in (("add", "add the submission as a row marked submitted (and keep the file in submissions/ "
                               "beside the board, which a rebuilt board adds again)"),
                       ("check", "say whether the board would take it, and if not why (writes nothing)"),
                       ("readd", "add the submissions kept beside the board again (after the board was rebuilt)")):
        p = sub.add_parser(name, help=what)
        if name != "readd":
            p.add_argument("submission", help="the submission's JSON file")
        p.add_argument("--board", help="the board's results.json (default: docs/results.json of the checkout)")
        p.add_argument("--references-dir", default=str(DATA_DIR), help="the stored test references")
        if name == "add":
            p.add_argument("--replace", action="store_true", help="replace a submitted row of the same name")
    a = ap.parse_args(argv)
    board_path = _board_path(a.board)
    if a.command == "readd":
        from agents.leaderboard.results_file import write
        board = json.loads(board_path.read_text())
        for line in readd_stored(board, board_path, references_dir=Path(a.references_dir)):
            print(line)
        write(board, board_path, None)
        return 0
    try:
        submission = load_submission(a.submission)
        board = json.loads(board_path.read_text())
        if a.command == "check":                 # everything add does, on a copy
            add_submission(submission, copy.deepcopy(board), Path(a.references_dir), replace=True)
            print(f"{a.submission}: the board {board_path} takes it (tier {submission['tier']})")
            return 0
        name, row = add_submission(submission, board, Path(a.references_dir), replace=a.replace)
    except (SubmissionRefused, ValueError, RuntimeError, FileNotFoundError) as err:
        print(f"agents.submit {a.command}: refused: {err}", file=sys.stderr)
        return 2
    from agents.leaderboard.results_file import write
    kept = write_submission(submission, stored_path(board_path, submission))
    write(board, board_path, None)
    print(f"added {name!r} to tier {submission['tier']} of {board_path}: normalised score IQM "
          f"{row['normalised_score_iqm']:.3f} [{row['ci_low']:.3f}, {row['ci_high']:.3f}] over {row['n_seeds']} run(s); "
          f"the file is kept as {kept} (a rebuilt board adds it again)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
