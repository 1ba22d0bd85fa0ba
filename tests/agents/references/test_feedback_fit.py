"""The feedback rule's tuning: validation seeds only, a coordinate ascent that finds a separable
optimum, and a stored rule whose value is its own mean return run again."""

import json

import numpy as np
import pytest

from agents import protocol as P
from agents.evaluation.episodes import run_policies
from agents.references import feedback_fit as F


def test_the_ascent_finds_a_separable_optimum_and_keeps_ties():
    """A made-up return with its maximum at one candidate of each coordinate: one round finds it;
    a flat return keeps the rule's defaults (ties keep the current setting)."""
    def peaked(rules):
        return np.array([-abs(r.start_n - 900) - abs(r.raise_n - 100) - abs(r.lower_n - 25) - abs(r.hold_steps - 20)
                         for r in rules])
    rule, meta = F.fit_feedback("transient", rounds=1, evaluate=peaked, progress=None)
    assert (rule.start_n, rule.raise_n, rule.lower_n, rule.hold_steps) == (900.0, 100.0, 25.0, 20)
    assert meta["mean_return"] == 0.0 and len(meta["history"]) == 1 + len(F.CANDIDATES)
    flat, _ = F.fit_feedback("transient", rounds=1, evaluate=lambda rules: np.zeros(len(rules)), progress=None)
    default = F.FeedbackRule()
    assert (flat.start_n, flat.raise_n, flat.lower_n, flat.hold_steps) == \
        (default.start_n, default.raise_n, default.lower_n, default.hold_steps)


def test_only_validation_seeds_tune_it():
    for seed in (P.TEST.start, P.TRAIN.start):
        with pytest.raises(ValueError, match="must be validation seeds"):
            F.fit_feedback("transient", episodes=2, seed=seed, evaluate=lambda r: np.zeros(len(r)), progress=None)


def test_a_tuned_rule_is_stored_and_its_value_is_its_return(tmp_path, monkeypatch):
    """Tiny: one validation episode of the paper tier, 6 intervals, one round; the stored rule run
    again gives the stored mean return bit for bit."""
    real = F.fit_feedback

    def tiny(tier, episodes, **kw):
        return real(tier, episodes=1, episode_steps=6, rounds=1, progress=None)
    monkeypatch.setattr(F, "fit_feedback", tiny)
    out = tmp_path / "fb.json"
    F.main(["--tier", "paper", "--out", str(out)])
    stored = json.loads(out.read_text())
    rule = F.FeedbackRule(**stored["rule"])
    again, = run_policies([rule], 1, P.VALIDATION.start, 6, env_kwargs={"tier": "paper"})
    assert float(np.mean(again.returns)) == stored["mean_return"]
    monkeypatch.setattr(F, "feedback_path", lambda tier, data_dir=None: out if tier == "paper" else tmp_path / "none")
    assert F.load_feedback("paper").start_n == rule.start_n
    with pytest.raises(LookupError, match="feedback_fit --tier field"):
        F.load_feedback("field")
    # the regeneration's adoption check: nothing differs from a fit made now; another round count does
    assert F.fit_problems("paper", out, 1, 1, 6) == []
    assert [p.split(":")[0] for p in F.fit_problems("paper", out, 1, 2, 6)] == ["rounds"]
    assert F.fit_problems("paper", tmp_path / "none.json", 1, 1, 6)[0].startswith("no fit")
    # a fit made with other index thresholds, or from another start, is another fit
    other = dict(stored, fixed={"high": 0.0, "low": 0.0},
                 history=[{"setting": {"start_n": 300.0, "raise_n": 50.0, "lower_n": 0.0, "hold_steps": 3}}])
    (tmp_path / "other.json").write_text(json.dumps(other))
    assert sorted(p.split(":")[0] for p in F.fit_problems("paper", tmp_path / "other.json", 1, 1, 6)) == \
        ["fixed", "start"]
