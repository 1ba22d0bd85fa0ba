"""Where a learned policy wins and loses: its per-episode normalised scores on a tier's test
episodes against the scenario each episode ran, from a leaderboard's results.json and the
stored test references (no simulation).

    python -m agents.leaderboard.breakdown --tier transient --row SAC --out docs/score_breakdown_transient.md

For each scenario feature (start, end, lowest and highest shaft speed, highest radial load,
clearance, waviness, eccentricity, initial preload, and the mean preload the hindsight best
constant applied) it gives Spearman's rank correlation with the row's score (mean over training
seeds) and the interquartile mean (the leaderboard's aggregate, robust to the few episodes
whose scores run to -10 and below) of the row's and of the contextual constant's scores in the
feature's lower, middle and upper third of the episodes; and how often the row beats the
contextual constant and the validation constant on an episode. It is the "why" of a score interval: it reads the episodes the
leaderboard ran, it does not test a hypothesis chosen in advance (the p-values are uncorrected
over the features and are a guide, not evidence).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

import numpy as np

from bearing_gym.task import CONTROL_DT_S
from bearing_gym.envs.tiers import tier_parts

from agents.leaderboard import scoring
from agents.references.store import DATA_DIR, load_references


__all__ = ["episode_features", "episode_scores", "breakdown", "to_markdown"]


def episode_features(tier: str, seeds: list[int], episode_steps: int) -> dict[str, np.ndarray]:
    """The scenario of each test seed, drawn as the env draws it at ``reset(seed=s)`` (the
    scenario is the first draw of the episode's generator, ``np.random.default_rng(s)``)."""
    sampler = tier_parts(tier)["scenario"]
    rows = []
    for s in seeds:
        sc = sampler.sample(np.random.default_rng(s), episode_steps * CONTROL_DT_S)
        speeds = [v for _, v in sc.speed_profile]
        loads = [f for _, f in sc.radial_load_profile]
        rows.append({"start speed (rpm)": speeds[0], "end speed (rpm)": speeds[-1],
                     "lowest speed (rpm)": min(speeds), "highest speed (rpm)": max(speeds),
                     "highest radial load (N)": max(loads), "clearance (um)": sc.clearance_m * 1e6,
                     "waviness (um)": sc.waviness_amplitude_m * 1e6, "eccentricity (um)": sc.eccentricity_m * 1e6,
                     "initial preload (N)": sc.initial_preload_n})
    return {k: np.array([r[k] for r in rows]) for k in rows[0]}


def _row(policies: dict[str, Any], name: str) -> tuple[str, dict[str, Any]]:
    hits = [k for k in policies if k == name] or [k for k, r in policies.items()
                                                   if k.startswith(name) and r.get("kind") != "submitted"]
    if len(hits) != 1:
        raise KeyError(f"row {name!r}: {'no row' if not hits else 'several rows'} starts so; "
                       f"the rows: {', '.join(policies)}")
    return hits[0], policies[hits[0]]


def episode_scores(tier_result: dict[str, Any]) -> tuple[np.ndarray, np.ndarray, dict[str, np.ndarray]]:
    """R_0, R_1 and every row's normalised scores (runs x episodes) of one tier of results.json."""
    policies = tier_result["policies"]
    if "mpc_episodes" in tier_result:
        raise ValueError("this results.json is from before the planner (its upper reference is the MPC on a subset "
                         "of the episodes): regenerate it with `python -m agents.leaderboard` to break its scores down")
    r0 = np.asarray(_row(policies, "validation constant")[1]["episode_returns"][0])
    hindsight = np.asarray(_row(policies, "hindsight constant")[1]["episode_returns"][0])
    planner = (np.asarray(_row(policies, "planner")[1]["episode_returns"][0])
               if tier_result.get("planner_episodes", 0) else None)
    r1 = scoring.upper_reference(hindsight, planner)
    scores = {name: scoring.normalised_scores(np.asarray(row["episode_returns"]), r0, r1)
              for name, row in policies.items() if np.asarray(row["episode_returns"]).shape[-1] == r0.size}
    return r0, r1, scores


def breakdown(results: dict[str, Any], tier: str, row: str, data_dir: Path = DATA_DIR) -> dict[str, Any]:
    from scipy.stats import spearmanr, trim_mean
    t = results["tiers"][tier]
    name, _ = _row(t["policies"], row)
    _, _, scores = episode_scores(t)
    ctx_name, _ = _row(t["policies"], "contextual constant")
    own = scores[name].mean(axis=0)                     # mean over training seeds, per episode
    ctx = scores[ctx_name][0]
    seeds = list(range(t["seeds"][0], t["seeds"][1] + 1))
    feats = episode_features(tier, seeds, t["episode_steps"])
    try:
        refs = load_references(tier, data_dir).first(len(seeds))
        feats["hindsight best constant: mean applied preload (N)"] = np.asarray(refs.hindsight.mean_preload)
    except (FileNotFoundError, ValueError):          # none stored, or a store from before the planner
        pass
    merged: list[tuple[list[str], np.ndarray]] = []   # features equal on every episode share a row
    for f, x in feats.items():
        same = next((names for names, y in merged if np.array_equal(x, y)), None)
        if same is not None:
            same.append(f)
        else:
            merged.append(([f], np.asarray(x)))
    table = []
    for names, x in merged:
        if np.ptp(x) == 0:
            continue
        f = " = ".join(names)
        rho, p = spearmanr(x, own)
        order = np.argsort(x, kind="stable")
        thirds = np.array_split(order, 3)
        table.append({"feature": f, "spearman_rho": float(rho), "p_uncorrected": float(p),
                      "thirds": [[float(x[i].min()), float(x[i].max()), float(trim_mean(own[i], 0.25)), float(trim_mean(ctx[i], 0.25))]
                                 for i in thirds]})
    return {"tier": tier, "row": name, "episodes": len(seeds), "runs": int(scores[name].shape[0]),
            "iqm_score": float(trim_mean(own, 0.25)), "contextual_iqm_score": float(trim_mean(ctx, 0.25)),
            "mean_score": float(own.mean()), "contextual_mean_score": float(ctx.mean()),
            "episodes_above_contextual": int(np.sum(own > ctx)),
            "episodes_above_validation_constant": int(np.sum(own > 0)), "features": table}


def to_markdown(b: dict[str, Any]) -> str:
    lines = [f"## {b['row']} on `{b['tier']}`: per-episode scores against the scenario",
             "",
             f"{b['episodes']} test episodes, score = mean over {b['runs']} training run(s) per episode; "
             f"IQM {b['iqm_score']:.3f}, mean {b['mean_score']:.3f} of these per-episode scores (contextual constant: "
             f"{b['contextual_iqm_score']:.3f}, {b['contextual_mean_score']:.3f}); "
             f"above the contextual constant on {b['episodes_above_contextual']} episodes, above the validation "
             f"constant on {b['episodes_above_validation_constant']}.",
             "",
             "| feature | Spearman rho (p, uncorrected) | lower third: range, IQM score (contextual) "
             "| middle third | upper third |",
             "|---|---|---|---|---|"]
    for r in sorted(b["features"], key=lambda r: -abs(r["spearman_rho"])):
        cells = [f"{lo:.4g}-{hi:.4g}: {s:.2f} ({c:.2f})" for lo, hi, s, c in r["thirds"]]
        lines.append(f"| {r['feature']} | {r['spearman_rho']:+.2f} ({r['p_uncorrected']:.2g}) | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> dict[str, Any]:
    ap = argparse.ArgumentParser(description="A learned row's per-episode scores against the scenarios.")
    ap.add_argument("--results", default="docs/results.json")
    ap.add_argument("--tier", default="transient")
    ap.add_argument("--row", default="SAC", help="the row's name or its start (one row must match)")
    ap.add_argument("--out", default=None, help="markdown file (default: print)")
    ap.add_argument("--references-dir", default=str(DATA_DIR), help="where the stored test references are")
    args = ap.parse_args(argv)
    b = breakdown(json.loads(Path(args.results).read_text()), args.tier, args.row, Path(args.references_dir))
    md = to_markdown(b)
    if args.out:
        Path(args.out).write_text(md)
        Path(args.out).with_suffix(".json").write_text(json.dumps(b, indent=1))
    print(md)
    return b


if __name__ == "__main__":
    main()
