"""The speed schedules' fit: coordinate ascent finds the optimum of a separable objective, keeps
the thresholds increasing, fits on training seeds only, and runs on the simulator."""

import json

import numpy as np
import pytest

from agents.references import speed_schedule_fit as F


def synthetic(target_levels, target_thresholds):
    """Mean return of each schedule: minus the squared distance of its levels and thresholds to
    the targets (separable: coordinate ascent reaches the optimum in one round)."""
    def evaluate(schedules):
        return np.array([-sum((a - b) ** 2 for a, b in zip(s.levels_n, target_levels))
                         - sum((a - b) ** 2 for a, b in zip(s.thresholds_rpm, target_thresholds)) for s in schedules])
    return evaluate


@pytest.mark.parametrize("kind,levels,thresholds", [
    ("2-level", (1500.0, 800.0), (20000.0,)),
    ("3-level", (1700.0, 1100.0, 500.0), (12500.0, 22500.0)),
    ("table", (2000.0, 1900.0, 1500.0, 1200.0, 900.0, 700.0, 600.0), F.TABLE_KNOTS_RPM),
])
def test_coordinate_ascent_reaches_the_optimum_of_a_separable_objective(kind, levels, thresholds):
    s, meta = F.fit_schedule("transient", kind, episodes=4, rounds=1, start_n=1150.0, progress=None,
                             evaluate=synthetic(levels, thresholds))
    assert s.levels_n == levels and s.thresholds_rpm == thresholds
    returns = [h["mean_return"] for h in meta["history"]]
    assert returns == sorted(returns) and returns[-1] == 0.0                  # never worse, then the optimum


def test_the_fit_refuses_seeds_outside_training():
    with pytest.raises(ValueError, match="training seeds"):
        F.fit_schedule("transient", "2-level", episodes=5, seed=50_000, progress=None, evaluate=lambda s: np.zeros(len(s)))
    with pytest.raises(ValueError, match="kind must be one of"):
        F.fit_schedule("transient", "4-level", progress=None, start_n=1000.0, evaluate=lambda s: np.zeros(len(s)))


def test_a_tiny_fit_on_the_simulator():
    s, meta = F.fit_schedule("transient", "2-level", episodes=2, episode_steps=3, grid_step_n=850.0, rounds=1,
                             start_n=1150.0, progress=None)
    returns = [h["mean_return"] for h in meta["history"]]
    assert returns == sorted(returns) and all(np.isfinite(returns))
    assert set(s.levels_n) <= {300.0, 1150.0, 2000.0} and s.thresholds_rpm[0] in F.THRESHOLD_CANDIDATES_RPM


def test_a_written_fit_records_its_start_and_the_adoption_check_sees_another(tmp_path):
    """write_fit starts from the store's validation constant by protocol v2's rule (on the fit's
    grid); fit_problems finds nothing for the same inputs and names the start for another store."""
    from agents.references.store import ValidationChoice, save_choice

    def store(path, best):
        means = tuple(-abs(p - best) for p in (300.0, 1150.0, 2000.0))
        save_choice(ValidationChoice("transient", best, (50_000, 50_001), 850.0, (300.0, 1150.0, 2000.0), means, 3,
                                     episode_returns=tuple((m, m) for m in means), rule="best_mean"), path)
        return path
    first = store(tmp_path / "a.json", 1150.0)
    out = F.write_fit("transient", "2-level", tmp_path / "s.json", episodes=2, rounds=1, episode_steps=3, store=first,
                      progress=None)
    d = json.loads(out.read_text())
    assert d["history"][0]["setting"]["levels_n"] == [1100.0, 1100.0]       # 1150 N on the 100 N grid
    assert F.fit_problems("transient", "2-level", out, 2, 1, 3, first) == []
    other = store(tmp_path / "b.json", 2000.0)
    assert [p.split(":")[0] for p in F.fit_problems("transient", "2-level", out, 2, 1, 3, other)] == ["start"]


class Interrupted(Exception):
    pass


def counting(evaluate, stop_after=None):
    """``evaluate`` that records every batch it runs and raises Interrupted after ``stop_after`` batches."""
    calls = []

    def wrapped(schedules):
        if stop_after is not None and len(calls) >= stop_after:
            raise Interrupted
        calls.append([s.to_json() for s in schedules])
        return evaluate(schedules)
    return wrapped, calls


def test_a_stopped_fit_resumes_from_its_journal_and_ends_as_an_uninterrupted_one(tmp_path):
    """Killed after 3 batches, the fit run again evaluates only the batches the journal lacks, and
    ends with the schedule and history of a fit that never stopped; the journal's context guards it."""
    target = synthetic((1500.0, 800.0, 1200.0), (12500.0, 20000.0))
    kw = dict(episodes=4, rounds=2, start_n=1150.0, progress=None)
    whole, whole_calls = counting(target)
    s_ref, meta_ref = F.fit_schedule("transient", "3-level", evaluate=whole, **kw)
    journal = tmp_path / "fit.partial.jsonl"
    first, first_calls = counting(target, stop_after=3)
    with pytest.raises(Interrupted):
        F.fit_schedule("transient", "3-level", evaluate=first, journal=journal, **kw)
    assert len(journal.read_text().splitlines()) == 1 + 3                      # the context, then 3 batches
    again, again_calls = counting(target)
    s, meta = F.fit_schedule("transient", "3-level", evaluate=again, journal=journal, **kw)
    assert s.to_json() == s_ref.to_json() and meta["history"] == meta_ref["history"]
    distinct = [c for k, c in enumerate(whole_calls) if c not in whole_calls[:k]]
    assert first_calls + again_calls == distinct     # nothing evaluated twice (a batch the ascent asks again included)
    other, other_calls = counting(target)                                      # another start: set aside
    F.fit_schedule("transient", "3-level", evaluate=other, journal=journal, **{**kw, "start_n": 900.0})
    assert other_calls[0] == [F.initial("3-level", 900.0).to_json()] and len(other_calls) > 3


def test_a_journaled_fit_stops_before_a_batch_that_would_pass_its_deadline(tmp_path):
    import time

    from agents.references.ascent import FitStopped
    journal = tmp_path / "fit.partial.jsonl"
    ev, calls = counting(synthetic((1500.0, 800.0), (20000.0,)))
    with pytest.raises(FitStopped, match="batches kept in"):
        F.fit_schedule("transient", "2-level", episodes=4, rounds=1, start_n=1150.0, progress=None, evaluate=ev,
                       journal=journal, until=time.time() - 1.0)
    assert len(calls) == 1                           # the first batch runs (no pace yet), then the deadline holds
    assert len(journal.read_text().splitlines()) == 2
