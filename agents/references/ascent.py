"""Coordinate ascent of a mean return: how the industry baselines are fitted (the speed schedules on
training seeds, the feedback rule on validation seeds) - one setting at a time, as a practitioner
tuning one knob at a time on recorded cycles would.

Each round sets every coordinate in turn to the candidate with the best value, the others held;
ties keep the current setting, then the first candidate. Every candidate of a coordinate is
evaluated in one batch.

A fit can take longer than a sitting (a speed table on the slower tiers: one to two hours of a
core). :class:`Journal` keeps every evaluated batch on disk, so a stopped fit run again replays the
ascent from the journal - the ascent is deterministic, so it asks for the same batches in the same
order - and evaluates only what is left; ``until`` stops it cleanly before a batch that would not
finish in time (:class:`FitStopped`).
"""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Any, Callable, Sequence, TypeVar

import numpy as np

__all__ = ["coordinate_ascent", "mean_returns", "record_problems", "Journal", "FitStopped"]

S = TypeVar("S")


def coordinate_ascent(start: S, coordinates: Callable[[S], Sequence[str]],
                      candidates: Callable[[S, str], list[S]], evaluate: Callable[[list[S]], np.ndarray],
                      rounds: int, key: Callable[[S], Any], describe: Callable[[S], Any],
                      progress: Callable[[str], None] | None = None, label: str = "") -> tuple[S, float, list[dict]]:
    """(the best setting, its value, the history: one record per coordinate set). ``coordinates(s)``:
    the names in the order they are set; ``candidates(s, name)``: ``s`` with that coordinate at each
    of its candidates; ``key(s)``: what makes two settings the same; ``describe(s)``: its record."""
    s = start
    best = float(evaluate([s])[0])
    history: list[dict] = [{"setting": describe(s), "mean_return": best}]
    t0 = time.time()
    for r in range(rounds):
        for coord in coordinates(s):
            cands = candidates(s, coord)
            if not cands:
                continue
            values = np.asarray(evaluate(cands), dtype=float)
            k = int(np.argmax(values))
            current = next((i for i, c in enumerate(cands) if key(c) == key(s)), None)
            if current is not None and values[current] >= values[k]:
                k = current
            s, best = cands[k], float(values[k])
            history.append({"round": r, "coordinate": coord, "setting": describe(s), "mean_return": best})
            if progress:
                progress(f"{label}: round {r + 1}/{rounds}, {coord}: {describe(s)}, mean return {best:.2f} "
                         f"({(time.time() - t0) / 60:.1f} min)")
    return s, best, history


def mean_returns(tier: str, episodes: int, seed: int, episode_steps: int, **run_kw: Any):
    """The ascent's default ``evaluate``: each policy's mean return over episodes ``seed`` ..
    ``seed + episodes - 1`` of ``tier``, all in one batch."""
    from agents.evaluation.episodes import run_policies

    def evaluate(policies: list) -> np.ndarray:
        ran = run_policies(policies, episodes, seed, episode_steps, env_kwargs={"tier": tier}, **run_kw)
        return np.array([float(np.mean(r.returns)) for r in ran])
    return evaluate


def record_problems(path, want: dict[str, Any], start: Any) -> list[str]:
    """What keeps a stored fit at ``path`` (a JSON record with the ascent's history) from being
    what fitting now would write: absent, a field of ``want`` (kernel, seeds, rounds,
    candidates, ...) stored with another value, or another start (the history's first record)."""
    import json
    from pathlib import Path
    try:
        d = json.loads(Path(path).read_text())
    except (OSError, ValueError):
        return [f"no fit in {path}"]
    out = [f"{k}: stored {str(d.get(k))[:40]}, today's {str(v)[:40]}" for k, v in want.items() if d.get(k) != v]
    stored = (d.get("history") or [{}])[0].get("setting")
    if stored != start:
        out.append(f"start: stored {str(stored)[:60]}, today's {start}")
    return out


class FitStopped(Exception):
    """A journaled fit stopped before a batch that would not finish by its deadline; its journal keeps
    what is done (run the same command again to resume)."""


class Journal:
    """``evaluate`` with its batches kept in a JSON-lines file: the first line the fit's ``context``
    (its inputs: kernel, tier, episodes, grid, ...), then one line per evaluated batch (the
    candidates' keys, their values, the seconds it took). A batch already in the journal - the same
    keys in the same order - is answered from it, not run; a journal written for another context is
    set aside (started afresh, with a message). ``until`` (a ``time.time()`` deadline): before a
    batch, :class:`FitStopped` if it would not end in time at the pace measured so far (seconds per
    candidate). ``seconds``: the fit's evaluation time so far, the journaled batches' included."""

    def __init__(self, evaluate: Callable[[list], np.ndarray], path: Path, context: dict[str, Any],
                 key: Callable[[Any], Any], until: float | None = None,
                 progress: Callable[[str], None] | None = None):
        self.evaluate, self.path, self.key, self.until, self.progress = evaluate, Path(path), key, until, progress
        self.context = json.loads(json.dumps(context))            # as it reads back from the file
        self.done: dict[str, tuple[list[float], float]] = {}
        self.seconds = 0.0
        self._pace: float | None = None                           # seconds per candidate, measured
        lines = self._read()
        if lines and lines[0].get("context") == self.context:
            for rec in lines[1:]:
                self.done[json.dumps(rec["keys"])] = (rec["values"], rec["seconds"])
                self._pace = rec["seconds"] / max(len(rec["keys"]), 1)
            if progress and self.done:
                progress(f"resuming from {self.path}: {len(self.done)} batches already evaluated")
        else:
            if lines and progress:
                progress(f"{self.path} holds a fit of other inputs; starting afresh")
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self.path.write_text(json.dumps({"context": self.context}) + "\n")

    def _read(self) -> list[dict]:
        try:
            text = self.path.read_text()
        except OSError:
            return []
        out = []
        for line in text.splitlines():
            try:
                out.append(json.loads(line))
            except ValueError:                                    # a line cut short by a kill: the batch reruns
                break
        return out

    def __call__(self, candidates: list) -> np.ndarray:
        keys = [self.key(c) for c in candidates]
        name = json.dumps(keys)
        if name in self.done:
            values, seconds = self.done[name]
            self.seconds += seconds
            return np.asarray(values, dtype=float)
        if self.until is not None and self._pace is not None and time.time() + self._pace * len(keys) > self.until:
            raise FitStopped(f"stopped before a batch of {len(keys)} candidates (~{self._pace * len(keys) / 60:.1f} min) "
                             f"that would end after the deadline; {len(self.done)} batches kept in {self.path}")
        t0 = time.time()
        values = np.asarray(self.evaluate(candidates), dtype=float)
        seconds = time.time() - t0
        self.seconds += seconds
        self._pace = seconds / max(len(keys), 1)
        self.done[name] = (values.tolist(), seconds)
        with self.path.open("a") as f:
            f.write(json.dumps({"keys": keys, "values": values.tolist(), "seconds": seconds}) + "\n")
        return values
