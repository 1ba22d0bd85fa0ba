"""Re-score a results.json against the stored test references of today, without running a policy:

    python -m agents.leaderboard.rescore                    # docs/results.json, every tier in it

The board (:mod:`agents.leaderboard.board`) stores every row's per-episode returns
(``episode_returns``, runs x episodes). When the upper reference changes - the planner runs on a
tier where it had not, or with a wider search, and ``reference_parts --merge`` writes it into
``agents/data/test_references_<tier>.json`` - nothing a policy did changes, only the score's 1.
This recomputes, for every row of every tier, the fields that depend on it
(:func:`agents.leaderboard.tables.score_fields`: normalised IQM and intervals, the share above 1,
the probabilities of improvement), puts the planner's row (from the store) where it belongs, and
rewrites the tier's upper-reference fields and deviations (:mod:`agents.leaderboard.upper`) and
the file's protocol header (the planner's settings are part of the protocol).

Refused (nothing written) where the stored returns are not the ones the board scored: a
results.json made by another kernel, a store of another kernel, or a store whose validation
constant or hindsight constant does not equal the row the board wrote bit for bit; and, as the
board refuses it, a stored planner that searched with other settings than the run's (the
protocol's; a smoke results.json: the smoke planner's). Minutes at the protocol's 50,000
bootstrap replications (every row's intervals are drawn again).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

import numpy as np

from bearing_gym.envs.provenance import kernel_hash

from agents.leaderboard.results_file import protocol_summary, write
from agents.leaderboard.settings import FULL, SMOKE
from agents.leaderboard.tables import score_fields
from agents.leaderboard.upper import (PLANNER_ROW, is_upper_deviation, planner_row, require_planner_settings,
                                     score_bounds, upper_fields)
from agents.paths import DATA_DIR, require_checkout
from agents.references.store import StoredReferences, load_references

__all__ = ["rescore_tier", "rescore", "check_same_returns", "row_named", "main"]


def row_named(rows: dict[str, Any], start: str, tier: str) -> tuple[str, dict[str, Any]]:
    """The one row of ``rows`` whose name starts with ``start``, submitted rows left out (their
    names are the submitters')."""
    found = [(n, r) for n, r in rows.items() if n.startswith(start) and r.get("kind") != "submitted"]
    if len(found) != 1:
        raise ValueError(f"tier {tier}: {len(found)} rows named {start!r}...; a board's results.json has one")
    return found[0]


def check_same_returns(tier: str, name: str, row: dict[str, Any], stored: np.ndarray) -> None:
    written = np.asarray(row["episode_returns"], dtype=np.float64)
    if written.shape != (1, stored.size) or not np.array_equal(written[0], stored):
        raise ValueError(f"tier {tier}: the row {name!r} of results.json does not hold the stored references' returns "
                         "bit for bit: the store is not the one this board was scored against; run the board again "
                         f"(`python -m agents.leaderboard --tier {tier} ... --stored-references`)")


def _with_upper_deviations(old: list[str], upper: list[str]) -> list[str]:
    """``old`` with its upper-reference deviations replaced by ``upper``, where the board puts
    them (before an episode-length deviation)."""
    at = next((k for k, d in enumerate(old) if is_upper_deviation(d)),
              next((k for k, d in enumerate(old) if "-step episodes (the benchmark" in d), None))
    kept = [d for d in old if not is_upper_deviation(d)]
    at = len(kept) if at is None else sum(1 for d in old[:at] if not is_upper_deviation(d))
    return kept[:at] + upper + kept[at:]


def rescore_tier(tier: str, t: dict[str, Any], refs: StoredReferences, bootstrap_reps: int, poi_reps: int,
                 command: str, smoke: bool = False) -> dict[str, Any]:
    """The tier object ``t`` of results.json scored against ``refs`` (its own test episodes)."""
    refs.check_kernel(f"python -m agents.leaderboard --tier {tier}")
    require_planner_settings(refs, (SMOKE if smoke else FULL).planner_settings())
    refs = refs.first(t["episodes"])
    if [refs.seeds[0], refs.seeds[-1]] != list(t["seeds"]) or refs.episode_steps != t["episode_steps"]:
        raise ValueError(f"tier {tier}: the stored references are for seeds {refs.seeds[0]}..{refs.seeds[-1]} of "
                         f"{refs.episode_steps} steps, the board's for {t['seeds'][0]}..{t['seeds'][1]} of "
                         f"{t['episode_steps']}")
    rows = t["policies"]
    check_same_returns(tier, *row_named(rows, "validation constant", tier), refs.validation_constant.returns)
    check_same_returns(tier, *row_named(rows, "hindsight constant", tier), refs.hindsight.returns)
    r0, r1 = score_bounds(refs)
    scored = []
    for name, row in rows.items():
        if name == PLANNER_ROW:
            continue                                  # rebuilt from the store below
        versus = {k: np.atleast_2d(np.asarray(rows[k]["episode_returns"], dtype=np.float64))
                  for k in row.get("poi_over", {})}
        scored.append((name, {**row, **score_fields(np.asarray(row["episode_returns"], dtype=np.float64), r0, r1,
                                                    bootstrap_reps, poi_reps, versus or None)}))
    if refs.planner is not None:                      # where the board puts it: before the learned rows
        at = next((k for k, (_, row) in enumerate(scored) if row["kind"] == "learned"), len(scored))
        scored.insert(at, (PLANNER_ROW, planner_row(refs, r0, r1, bootstrap_reps, poi_reps)))
    new_rows = dict(scored)
    fields, upper_deviations = upper_fields(refs, r0, r1, FULL.planner_settings())
    deviations = _with_upper_deviations(t["protocol_deviations"], upper_deviations)
    return {**t, "protocol": not deviations, "protocol_deviations": deviations,
            "references": "stored (agents/data); the scores re-computed against them by rescore (no policy ran again)",
            **fields, "policies": new_rows, "rescored_by": command}


def rescore(results: dict[str, Any], references_dir: Path, command: str) -> dict[str, Any]:
    """Every tier of ``results`` re-scored against the stored references in ``references_dir``;
    the protocol header becomes today's (the planner's settings are part of it)."""
    here = kernel_hash()
    if results.get("kernel_hash") != here:
        raise ValueError(f"results.json was made by kernel {results.get('kernel_hash')}, this is {here}: its returns "
                         "are another kernel's; run the board again")
    stats = results["statistics"]
    tiers = {tier: rescore_tier(tier, t, load_references(tier, references_dir), stats["bootstrap_reps"],
                                stats["poi_reps"], command, smoke=results.get("mode") == "smoke")
             for tier, t in results["tiers"].items()}
    return {**results, "protocol": protocol_summary(), "tiers": tiers}


def main(argv: list[str] | None = None) -> dict[str, Any]:
    ap = argparse.ArgumentParser(prog="python -m agents.leaderboard.rescore",
                                 description="Re-score results.json against today's stored test references "
                                             "(no policy runs).")
    ap.add_argument("--results", help="the results.json to re-score in place (default: docs/results.json of the checkout)")
    ap.add_argument("--references-dir", default=str(DATA_DIR))
    a = ap.parse_args(argv)
    try:
        path = Path(a.results) if a.results else require_checkout("docs/results.json", "--results") / "docs" / "results.json"
    except ValueError as err:
        raise SystemExit(f"rescore: {err}") from None
    command = "python -m agents.leaderboard.rescore " + " ".join(argv if argv is not None else sys.argv[1:])
    try:
        out = rescore(json.loads(path.read_text()), Path(a.references_dir), command.strip())
    except KeyError as err:
        raise SystemExit(f"rescore: {path} has no {err} where a board's results.json has one (an older format?): "
                         "run the board again") from None
    except (ValueError, RuntimeError, FileNotFoundError) as err:
        raise SystemExit(f"rescore: {err}") from None
    write(out, path, None)
    print(f"re-scored {', '.join(out['tiers'])} in {path} (and its table)")
    return out


if __name__ == "__main__":
    main()
