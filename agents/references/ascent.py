"""Coordinate ascent of a mean return: how the industry baselines are fitted (the speed schedules on
training seeds, the feedback rule on validation seeds) - one setting at a time, as a practitioner
tuning one knob at a time on recorded cycles would.

Each round sets every coordinate in turn to the candidate with the best value, the others held;
ties keep the current setting, then the first candidate. Every candidate of a coordinate is
evaluated in one batch.
"""

from __future__ import annotations

import time
from typing import Any, Callable, Sequence, TypeVar

import numpy as np

__all__ = ["coordinate_ascent", "mean_returns", "record_problems"]

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
