"""What protocol v2's hyperparameter search found, from its committed logs (agents/tuning/<algo>.json,
written by ``python -m agents.training.tuning --export``): per algorithm the trials finished,
pruned and failed, the core time they took, the best trial and its settings, and how its
validation score moved over the trial (the evidence for the run budget).

    python -m agents.training.tuning_report                 # the markdown table
    python -m agents.training.tuning_report --json          # the same as JSON

Reads JSON only (no optuna, no torch): the numbers a reader of docs/training.md checks.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from agents import protocol as P
from agents.paths import PACKAGE_DIR
from agents.training.search_spaces import ALGORITHMS

__all__ = ["summarise", "report", "to_markdown", "main"]

TUNING_DIR = PACKAGE_DIR / "tuning"
#: the searched parameters shown in the table, in this order (others stay in the JSON)
SHOWN = ("gamma", "utd", "net_arch", "critic_width", "learning_rate", "batch_size", "n_steps", "n_epochs",
         "ent_coef", "lstm_hidden_size")


def summarise(log: dict[str, Any], trials: int = P.TUNING_TRIALS) -> dict[str, Any]:
    """One algorithm's search from its exported log: counts by state, core hours (the trials'
    recorded wall times, one core each), and the best finished trial (highest value, the first
    on a tie, as optuna's ``best_trial``) with its parameters and validation scores by step."""
    rows = log["trials"]
    count = {state: sum(t["state"] == state for t in rows) for state in ("COMPLETE", "PRUNED", "FAIL", "RUNNING")}
    finished = [t for t in rows if t["state"] in ("COMPLETE", "PRUNED") and t["value"] is not None]
    complete = [t for t in rows if t["state"] == "COMPLETE" and t["value"] is not None]
    best = max(complete, key=lambda t: t["value"]) if complete else None
    out: dict[str, Any] = {
        "study": log["study"], "trials_budget": trials, "finished": len(finished),
        "complete": count["COMPLETE"], "pruned": count["PRUNED"], "failed": count["FAIL"], "running": count["RUNNING"],
        "core_hours": sum(t.get("user_attrs", {}).get("wall_s") or 0.0 for t in rows) / 3600.0,
        "done": len(finished) >= trials}
    if best is not None:
        out.update(best_trial=best["number"], best_value=best["value"], best_params=best["params"],
                   best_scores={int(k): v for k, v in best["intermediate"].items()})
    return out


def report(tuning_dir: Path = TUNING_DIR) -> dict[str, dict[str, Any]]:
    """:func:`summarise` of every algorithm whose log is in ``tuning_dir`` (search-space order)."""
    return {algo: summarise(json.loads((Path(tuning_dir) / f"{algo}.json").read_text()))
            for algo in ALGORITHMS if (Path(tuning_dir) / f"{algo}.json").exists()}


def _value(v: Any) -> str:
    return f"{v:.2g}" if isinstance(v, float) and (abs(v) < 1e-2 or abs(v) >= 1e4) else str(v)


def to_markdown(rep: dict[str, dict[str, Any]]) -> str:
    """The table of :func:`report` with a note on how to read it."""
    lines = ["| algorithm | trials (complete / pruned / failed) | core hours | best trial | value | its scores at 20k / 40k / 60k | chosen |",
             "|---|---|---|---|---|---|---|"]
    for algo, r in rep.items():
        state = f"{r['finished']} of {r['trials_budget']} ({r['complete']} / {r['pruned']} / {r['failed']})"
        if not r["done"]:
            state += ", **in progress**"
        if "best_trial" not in r:
            lines.append(f"| {algo} | {state} | {r['core_hours']:.1f} | - | - | - | - |")
            continue
        scores = " / ".join(f"{r['best_scores'][s]:.2f}" if s in r["best_scores"] else "-"
                            for s in (20_000, 40_000, 60_000))
        chosen = ", ".join(f"{k} {_value(r['best_params'][k])}" for k in SHOWN if k in r["best_params"])
        lines.append(f"| {algo} | {state} | {r['core_hours']:.1f} | {r['best_trial']} | {r['best_value']:.3f} "
                     f"| {scores} | {chosen} |")
    lines += ["", f"Value: the mean of a trial's last {P.TUNING_LAST_VALIDATIONS} validation scores (the IQM of {P.TUNING_VALIDATION_EPISODES} validation episodes' "
              f"normalised scores; 0 the validation constant, 1 the hindsight constant). Core hours: the trials' "
              "wall times, one core each, on the 2-core machine with another job beside them. "
              "Failed: a trial whose worker was stopped; its slot is run again."]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m agents.training.tuning_report", description=__doc__.split("\n\n")[0])
    ap.add_argument("--dir", default=str(TUNING_DIR), help="the exported logs (default: agents/tuning/)")
    ap.add_argument("--json", action="store_true", help="print JSON instead of the markdown table")
    a = ap.parse_args(argv)
    rep = report(Path(a.dir))
    if not rep:
        raise SystemExit(f"no tuning log in {a.dir}: export one with python -m agents.training.tuning --algo A --export")
    print(json.dumps(rep, indent=1) if a.json else to_markdown(rep))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
