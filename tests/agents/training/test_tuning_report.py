"""The tuning report reads the committed logs: counts by state, core hours, the best finished
trial (optuna's rule: the highest value among complete trials, the first on a tie)."""

import json

import pytest

from agents.training.tuning_report import main, report, summarise, to_markdown


def _trial(number, state, value, wall_s, params=None, scores=None):
    return {"number": number, "state": state, "value": value, "params": params or {"gamma": 0.99},
            "intermediate": {str(k): v for k, v in (scores or {}).items()},
            "user_attrs": {} if wall_s is None else {"wall_s": wall_s}}


def _log(trials):
    return {"study": "protocol2-sac", "budget": {}, "search_space": {}, "trials": trials}


def test_counts_core_hours_and_the_best_complete_trial():
    log = _log([_trial(0, "COMPLETE", 0.2, 1800.0),
                _trial(1, "PRUNED", 0.9, 600.0),                  # pruned: never the best, however high
                _trial(2, "COMPLETE", 0.5, 3600.0, {"gamma": 0.95, "utd": 1.0}, {20_000: 0.1, 40_000: 0.4, 60_000: 0.6}),
                _trial(3, "FAIL", None, None),
                _trial(4, "COMPLETE", 0.5, 1800.0)])              # a tie: the first keeps it
    s = summarise(log, trials=4)
    assert (s["complete"], s["pruned"], s["failed"], s["finished"]) == (3, 1, 1, 4)
    assert s["core_hours"] == pytest.approx((1800 + 600 + 3600 + 1800) / 3600, abs=1e-12)
    assert s["best_trial"] == 2 and s["best_value"] == 0.5 and s["done"]
    assert s["best_scores"] == {20_000: 0.1, 40_000: 0.4, 60_000: 0.6}
    assert not summarise(log, trials=5)["done"]


def test_the_table_and_the_command(tmp_path, capsys):
    (tmp_path / "sac.json").write_text(json.dumps(_log([_trial(0, "COMPLETE", 0.25, 3600.0, {"gamma": 0.95},
                                                               {20_000: 0.1, 60_000: 0.3})])))
    (tmp_path / "ppo.json").write_text(json.dumps(_log([_trial(0, "FAIL", None, None)])))
    rep = report(tmp_path)
    assert list(rep) == ["sac", "ppo"]                            # the search spaces' order
    text = to_markdown(rep)
    assert "| sac | 1 of 16 (1 / 0 / 0), **in progress** | 1.0 | 0 | 0.250 | 0.10 / - / 0.30 | gamma 0.95 |" in text
    assert "| ppo | 0 of 16 (0 / 0 / 1), **in progress** | 0.0 | - | - | - | - |" in text
    assert main(["--dir", str(tmp_path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["sac"]["best_trial"] == 0
    with pytest.raises(SystemExit, match="no tuning log"):
        main(["--dir", str(tmp_path / "none")])
