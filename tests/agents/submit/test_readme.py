"""The README's "Any policy on the board" snippet runs as written, on 2 test episodes instead of
the protocol's 100 (the one change: ``episodes=2`` added to its ``score(...)`` call), and writes
the submission it promises."""

import ast
import json
from pathlib import Path

import pytest

from tests.agents.helpers import first_python_block

README = Path(__file__).resolve().parents[3] / "README.md"
SECTION = "## Any policy on the board"


def snippet() -> str:
    return first_python_block(README, SECTION)


@pytest.mark.slow          # ~40 s on 2 cores, most of it the board's 50,000 bootstrap draws (CI runs it)
def test_the_readme_snippet_scores_a_rule_and_saves_its_submission(tmp_path, monkeypatch, capsys):
    tree = ast.parse(snippet())
    calls = [n for n in ast.walk(tree) if isinstance(n, ast.Call) and getattr(n.func, "id", None) == "score"]
    assert len(calls) == 1 and not any(k.arg == "episodes" for k in calls[0].keywords)
    calls[0].keywords.append(ast.keyword("episodes", ast.Constant(2)))
    monkeypatch.chdir(tmp_path)
    exec(compile(ast.fix_missing_locations(tree), "README.md", "exec"), {})
    out = capsys.readouterr().out
    assert "| my rule | 1 | 2 |" in out
    sub = json.loads((tmp_path / "my_rule.json").read_text())
    assert sub["name"] == "my rule" and sub["episodes"] == 2 and sub["library"] == "numpy"
