"""The feedback rule (:class:`agents.policies.scripted.FeedbackRule`: raise the preload when the
quasi-periodicity index crosses the benchmark's threshold, lower it slowly after quiet intervals)
tuned on validation seeds: coordinate ascent of its mean return (:mod:`agents.references.ascent`).

    python -m agents.references.feedback_fit --tier transient     # agents/data/feedback_rule_<tier>.json

Protocol v2 (agents.protocol ``V2_FEEDBACK_TUNE_*``): the first ``V2_FEEDBACK_TUNE_EPISODES``
validation episodes, ``V2_FEEDBACK_TUNE_ROUNDS`` rounds over the coordinates below, from the
rule's defaults. The index thresholds stay the benchmark's (``high`` = ``QPI_THRESHOLD``, ``low``
a third of it): one threshold for the concept. Cost: (18 + 5 + 5 + 5) candidates x rounds x
episodes x 150 env steps (~500k env steps, about 20 min of one core on `transient`).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
from pathlib import Path
from typing import Any, Callable

import numpy as np

from bearing_gym.task import DEFAULT_TIER, EPISODE_STEPS, TIER_NAMES

from agents import protocol as P
from agents.paths import DATA_DIR
from agents.policies.scripted import FeedbackRule
from agents.references.ascent import coordinate_ascent, mean_returns, record_problems

__all__ = ["CANDIDATES", "fit_feedback", "feedback_path", "load_feedback", "write_fit", "fit_problems", "fixed_settings", "main"]

#: each tuned setting's candidates, in the order the ascent sets them
CANDIDATES: dict[str, tuple] = {
    "start_n": P.preload_grid(P.CONTEXTUAL_GRID_STEP_N),
    "raise_n": (50.0, 100.0, 250.0, 500.0, 1000.0),
    "lower_n": (0.0, 5.0, 10.0, 25.0, 50.0),
    "hold_steps": (3, 5, 10, 20, 40),
}


def _setting(rule: FeedbackRule) -> dict[str, Any]:
    return {k: getattr(rule, k) for k in CANDIDATES}


def fixed_settings() -> dict[str, Any]:
    """What the ascent does not tune but the fitted rule runs with: the index thresholds (and
    the start of the ascent, the rule's defaults, is its history's first record)."""
    r = FeedbackRule()
    return {"high": r.high, "low": r.low}


def fit_feedback(tier: str, episodes: int = P.V2_FEEDBACK_TUNE_EPISODES, seed: int = P.VALIDATION.start,
                 episode_steps: int = EPISODE_STEPS, rounds: int = P.V2_FEEDBACK_TUNE_ROUNDS,
                 progress: Callable[[str], None] | None = print,
                 evaluate: Callable[[list[FeedbackRule]], np.ndarray] | None = None,
                 **run_kw: Any) -> tuple[FeedbackRule, dict[str, Any]]:
    """The tuned rule on ``tier`` and its record (module docstring). ``evaluate``: the mean return
    of each rule (default: run them on the validation episodes)."""
    if not (P.VALIDATION.start <= seed and seed + episodes <= P.VALIDATION.stop):
        raise ValueError(f"tuning seeds {seed}..{seed + episodes - 1} must be validation seeds "
                         f"({P.VALIDATION.start}..{P.VALIDATION.stop - 1}): the test seeds tune nothing")
    if evaluate is None:
        evaluate = mean_returns(tier, episodes, seed, episode_steps, **run_kw)
    rule, best, history = coordinate_ascent(
        FeedbackRule(), lambda r: list(CANDIDATES),
        lambda r, name: [dataclasses.replace(r, **{name: v}) for v in CANDIDATES[name]], evaluate, rounds,
        key=lambda r: tuple(_setting(r).values()), describe=_setting, progress=progress,
        label=f"feedback rule on {tier}")
    meta = {"tier": tier, "seeds": [seed, seed + episodes - 1], "episode_steps": episode_steps, "rounds": rounds,
            "candidates": {k: list(v) for k, v in CANDIDATES.items()}, "fixed": fixed_settings(), "mean_return": best,
            "history": history}
    return rule, meta


def feedback_path(tier: str, data_dir: Path = DATA_DIR) -> Path:
    return Path(data_dir) / f"feedback_rule_{tier}.json"


def load_feedback(tier: str, data_dir: Path = DATA_DIR) -> FeedbackRule:
    """The stored tuned rule of ``tier`` (LookupError naming the command if there is none)."""
    path = feedback_path(tier, data_dir)
    if not path.exists():
        raise LookupError(f"no tuned feedback rule for {tier}: python -m agents.references.feedback_fit --tier {tier}")
    rule = FeedbackRule(**json.loads(path.read_text())["rule"])
    rule.name = "feedback rule (tuned on validation seeds)"
    return rule


def write_fit(tier: str, out: Path | None = None, episodes: int | None = None,
              rounds: int = P.V2_FEEDBACK_TUNE_ROUNDS, episode_steps: int = EPISODE_STEPS,
              progress: Callable[[str], None] | None = print) -> Path:
    """Tune the rule on ``tier`` (the protocol's episodes by default) and write it with its record
    and the kernel's fingerprint; returns the path."""
    from bearing_gym.envs.provenance import kernel_hash
    import time
    t0 = time.time()
    n = P.episodes_for_tier(tier, P.V2_FEEDBACK_TUNE_EPISODES) if episodes is None else episodes
    rule, meta = fit_feedback(tier, episodes=n, rounds=rounds, episode_steps=episode_steps, progress=progress)
    out = Path(out) if out is not None else feedback_path(tier)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"rule": _setting(rule), **meta, "wall_s": time.time() - t0,
                               "kernel_hash": kernel_hash()}, indent=1) + "\n")
    return out


def fit_problems(tier: str, path: Path, episodes: int, rounds: int, episode_steps: int) -> list[str]:
    """What keeps the stored fit at ``path`` from being what fitting now would write (empty:
    nothing): absent, another kernel, other episodes, rounds, candidates or fixed thresholds, or
    another start (its history's first record: the rule's defaults)."""
    from bearing_gym.envs.provenance import kernel_hash
    want = {"kernel_hash": kernel_hash(), "tier": tier, "seeds": [P.VALIDATION.start, P.VALIDATION.start + episodes - 1],
            "episode_steps": episode_steps, "rounds": rounds,
            "candidates": {k: list(v) for k, v in CANDIDATES.items()}, "fixed": fixed_settings()}
    return record_problems(path, want, _setting(FeedbackRule()))


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(prog="python -m agents.references.feedback_fit", description=__doc__.split("\n\n")[0])
    ap.add_argument("--tier", choices=TIER_NAMES, default=DEFAULT_TIER)
    ap.add_argument("--out", help="output JSON (default agents/data/feedback_rule_<tier>.json)")
    a = ap.parse_args(argv)
    out = write_fit(a.tier, Path(a.out) if a.out else None)
    d = json.loads(out.read_text())
    print(f"wrote {out}: {d['rule']}, mean validation return {d['mean_return']:.2f}")


if __name__ == "__main__":
    main()
