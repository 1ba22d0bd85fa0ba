"""Fitting the spindle makers' speed schedules (:mod:`agents.policies.speed_schedule`) on
training seeds: coordinate ascent of the mean return.

    python -m agents.references.speed_schedule_fit --tier transient --kind 2-level    # agents/data/speed_schedule_<tier>_<kind>.json
    python -m agents.references.speed_schedule_fit --tier field --kind table --until 18:00   # stops cleanly; run again to resume

Each ``kind`` starts from the tier's validation constant (protocol v2's rule) at every level, then, ``rounds`` times,
sets one coordinate at a time - a threshold among ``THRESHOLD_CANDIDATES_RPM`` (kept increasing),
a level on the ``grid_step_n`` preload grid - to the candidate with the best mean return on the
fit episodes, the others held (ties keep the current value, then the first candidate). Every
candidate of a coordinate runs in one batch (:func:`agents.evaluation.episodes.run_policies`).
A coordinate ascent, not a global search: what a practitioner tuning one switch at a time on
recorded cycles would find. Kinds: ``2-level`` (one threshold), ``3-level`` (two), ``table``
(a level at each of ``TABLE_KNOTS_RPM``, linear between).

A fit is resumable: every evaluated batch goes to a journal beside the output
(``speed_schedule_<tier>_<kind>.partial.jsonl``, :class:`agents.references.ascent.Journal`); run
the same command again and it replays what the journal holds and evaluates the rest. The journal
is removed when the fit is written; commit it to carry a fit over to another machine.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path
from typing import Any, Callable

import numpy as np

from bearing_gym.task import DEFAULT_TIER, EPISODE_STEPS, TIER_NAMES

from agents import protocol as P
from agents.paths import DATA_DIR
from agents.policies.speed_schedule import SpeedSchedule
from agents.references.ascent import FitStopped, Journal, coordinate_ascent, mean_returns, record_problems

__all__ = ["KINDS", "THRESHOLD_CANDIDATES_RPM", "TABLE_KNOTS_RPM", "initial", "fit_schedule", "schedule_path",
           "journal_path", "write_fit", "fit_problems", "candidates", "main"]

KINDS = ("2-level", "3-level", "table")
#: where a switch may sit (rpm): the tiers' speeds are 10,000-25,000 rpm
THRESHOLD_CANDIDATES_RPM = (12500.0, 15000.0, 17500.0, 20000.0, 22500.0)
#: the table's knots (rpm)
TABLE_KNOTS_RPM = (10000.0, 12500.0, 15000.0, 17500.0, 20000.0, 22500.0, 25000.0)


def initial(kind: str, level_n: float) -> SpeedSchedule:
    """The starting schedule of ``kind``: every level ``level_n``, the switches at the middle."""
    if kind == "2-level":
        return SpeedSchedule((17500.0,), (level_n, level_n))
    if kind == "3-level":
        return SpeedSchedule((15000.0, 20000.0), (level_n,) * 3)
    if kind == "table":
        return SpeedSchedule(TABLE_KNOTS_RPM, (level_n,) * len(TABLE_KNOTS_RPM), interpolate=True)
    raise ValueError(f"kind must be one of {', '.join(KINDS)}, got {kind!r}")


def _coordinates(s: SpeedSchedule) -> list[str]:
    """The coordinates of ``s`` in the order the ascent sets them: the thresholds, then the levels."""
    return ([f"threshold {k}" for k in range(len(s.thresholds_rpm))] if not s.interpolate else []) + \
        [f"level {k}" for k in range(len(s.levels_n))]


def _variants(s: SpeedSchedule, coord: str, grid: tuple[float, ...]) -> list[SpeedSchedule]:
    """``s`` with the coordinate ``coord`` at each of its candidates (thresholds kept increasing)."""
    kind, k = coord.split()[0], int(coord.split()[1])
    if kind == "threshold":
        t = s.thresholds_rpm
        lo = t[k - 1] if k else -np.inf
        hi = t[k + 1] if k + 1 < len(t) else np.inf
        return [SpeedSchedule(t[:k] + (c,) + t[k + 1:], s.levels_n) for c in THRESHOLD_CANDIDATES_RPM if lo < c < hi]
    return [SpeedSchedule(s.thresholds_rpm, s.levels_n[:k] + (p,) + s.levels_n[k + 1:], s.interpolate) for p in grid]


def fit_schedule(tier: str, kind: str, episodes: int = P.SCHEDULE_FIT_EPISODES, seed: int = P.SCHEDULE_FIT_SEED,
                 episode_steps: int = EPISODE_STEPS, grid_step_n: float = P.CONTEXTUAL_GRID_STEP_N,
                 rounds: int = P.SCHEDULE_FIT_ROUNDS, start_n: float | None = None,
                 progress: Callable[[str], None] | None = print,
                 evaluate: Callable[[list[SpeedSchedule]], np.ndarray] | None = None,
                 journal: Path | None = None, until: float | None = None,
                 **run_kw: Any) -> tuple[SpeedSchedule, dict[str, Any]]:
    """The fitted schedule of ``kind`` on ``tier`` and its record (module docstring). ``evaluate``:
    the mean return of each schedule (default: run them on the fit episodes); ``start_n``: the
    starting level (default: the tier's stored validation constant); ``journal``: a file that keeps
    the evaluated batches so a stopped fit resumes (``until``, a ``time.time()`` deadline: raise
    :class:`agents.references.ascent.FitStopped` before a batch that would end after it)."""
    if not (P.TRAIN.start <= seed and seed + episodes <= P.TRAIN.stop):
        raise ValueError(f"fit seeds {seed}..{seed + episodes - 1} must be training seeds ({P.TRAIN.start}.."
                         f"{P.TRAIN.stop - 1}): the schedule is fitted on training scenarios only")
    if evaluate is None:
        evaluate = mean_returns(tier, episodes, seed, episode_steps, **run_kw)
    grid = P.preload_grid(grid_step_n)
    start_n = _start_n(tier, None, grid_step_n) if start_n is None else min(grid, key=lambda p: abs(p - start_n))
    meta = {"tier": tier, "kind": kind, "seeds": [seed, seed + episodes - 1], "episode_steps": episode_steps,
            "grid_step_n": grid_step_n, "rounds": rounds, "candidates": candidates()}

    def key(sch: SpeedSchedule) -> str:
        return json.dumps(sch.to_json(), sort_keys=True)
    if journal is not None:
        from bearing_gym.envs.provenance import kernel_hash
        evaluate = Journal(evaluate, journal, {**meta, "start_n": start_n, "kernel_hash": kernel_hash()}, key,
                           until, progress)
    t0 = time.time()
    s, best, history = coordinate_ascent(
        initial(kind, start_n), _coordinates, lambda sch, coord: _variants(sch, coord, grid), evaluate, rounds,
        key=key, describe=lambda sch: sch.to_json(), progress=progress, label=f"speed schedule {kind} on {tier}")
    meta.update(mean_return=best, history=history,
                wall_s=evaluate.seconds if isinstance(evaluate, Journal) else time.time() - t0)
    return s, meta


def candidates() -> dict[str, list[float]]:
    """Where the ascent may put the switches and the table's knots (its start is its history's first record)."""
    return {"threshold_candidates_rpm": list(THRESHOLD_CANDIDATES_RPM), "table_knots_rpm": list(TABLE_KNOTS_RPM)}


def schedule_path(tier: str, kind: str, data_dir: Path = DATA_DIR) -> Path:
    return data_dir / f"speed_schedule_{tier}_{kind}.json"


def journal_path(out: Path) -> Path:
    """Where the fit writing ``out`` keeps its evaluated batches until it is written."""
    return out.with_name(out.stem + ".partial.jsonl")


def _start_n(tier: str, store: Path | None, grid_step_n: float) -> float:
    """The fit's starting level: the tier's stored validation constant by protocol v2's rule, on the grid."""
    from agents.references.store import STORE_PATH, load_choice
    start = load_choice(tier, STORE_PATH if store is None else store).preload_for_rule(P.V2_VALIDATION_RULE)
    return min(P.preload_grid(grid_step_n), key=lambda p: abs(p - start))


def write_fit(tier: str, kind: str, out: Path | None = None, episodes: int | None = None,
              rounds: int = P.SCHEDULE_FIT_ROUNDS, episode_steps: int = EPISODE_STEPS, store: Path | None = None,
              progress: Callable[[str], None] | None = print, until: float | None = None) -> Path:
    """Fit ``kind`` on ``tier`` (the protocol's episodes by default), starting from the validation
    constant in ``store``, and write it with its record and the kernel's fingerprint; returns the
    path. Resumable through the journal beside it (:func:`journal_path`; removed once written);
    ``until``: as :func:`fit_schedule`'s."""
    from bearing_gym.envs.provenance import kernel_hash
    n = P.episodes_for_tier(tier, P.SCHEDULE_FIT_EPISODES) if episodes is None else episodes
    out = Path(out) if out is not None else schedule_path(tier, kind)
    s, meta = fit_schedule(tier, kind, episodes=n, rounds=rounds, episode_steps=episode_steps,
                           start_n=_start_n(tier, store, P.CONTEXTUAL_GRID_STEP_N), progress=progress,
                           journal=journal_path(out), until=until)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"schedule": s.to_json(), **meta, "kernel_hash": kernel_hash()}, indent=1) + "\n")
    journal_path(out).unlink(missing_ok=True)
    return out


def fit_problems(tier: str, kind: str, path: Path, episodes: int, rounds: int, episode_steps: int,
                 store: Path | None = None) -> list[str]:
    """What keeps the stored fit at ``path`` from being what fitting now would write (empty:
    nothing): absent, another kernel, other episodes, grid, rounds or switch candidates, or another
    start (its history's first record: the initial schedule at the validation constant)."""
    from bearing_gym.envs.provenance import kernel_hash
    grid = P.CONTEXTUAL_GRID_STEP_N
    want = {"kernel_hash": kernel_hash(), "tier": tier, "kind": kind,
            "seeds": [P.SCHEDULE_FIT_SEED, P.SCHEDULE_FIT_SEED + episodes - 1], "episode_steps": episode_steps,
            "grid_step_n": grid, "rounds": rounds, "candidates": candidates()}
    return record_problems(path, want, initial(kind, _start_n(tier, store, grid)).to_json())


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(prog="python -m agents.references.speed_schedule_fit", description=__doc__.split("\n\n")[0])
    ap.add_argument("--tier", choices=TIER_NAMES, default=DEFAULT_TIER)
    ap.add_argument("--kind", choices=KINDS, required=True)
    ap.add_argument("--out", help="output JSON (default agents/data/speed_schedule_<tier>_<kind>.json)")
    ap.add_argument("--until", metavar="HH:MM", help="start no batch that would not end by then (at the pace so far); "
                    "exit 0 with the journal kept, run the command again to resume")
    a = ap.parse_args(argv)
    until = None
    if a.until:
        from agents.clock import deadline
        until = deadline(a.until).timestamp()
    try:
        out = write_fit(a.tier, a.kind, Path(a.out) if a.out else None, until=until)
    except FitStopped as stop:
        print(f"{stop}; run the same command again to resume")
        return
    print(f"wrote {out}: {json.loads(out.read_text())['schedule']}")


if __name__ == "__main__":
    main()
