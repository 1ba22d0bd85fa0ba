"""Performance profiles of a board (rliable): per row, the fraction of its (seed, episode)
normalised scores above each threshold tau, with 95 % stratified-bootstrap bands. The IQM
summarises the middle of a row; the profile shows its whole distribution, tails included (a row
whose profile lies above another's everywhere is better at every level; rliable's paper,
Agarwal et al. 2021, section 4).

    python -m agents.leaderboard.profiles                       # docs/performance_profiles.png from docs/results.json

The scores are the board's (:mod:`agents.leaderboard.scoring`): every row's stored per-episode
returns, 0 the validation constant's and 1 the upper reference's on each episode.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

import numpy as np

from agents.leaderboard import scoring

__all__ = ["tier_scores", "plotted", "profiles", "plot", "main", "TAUS"]

#: the thresholds of the profiles: from a score of -1 (one gap below the validation constant) to
#: 1.2 (past the upper reference)
TAUS = np.linspace(-1.0, 1.2, 89)


def _row(policies: dict[str, Any], prefix: str) -> dict[str, Any]:
    hits = [v for k, v in policies.items() if k.startswith(prefix)]
    if len(hits) != 1:
        raise ValueError(f"the board's tier must hold one row named {prefix!r}..., found {len(hits)}")
    return hits[0]


def tier_scores(results: dict[str, Any], tier: str,
                kinds: tuple[str, ...] = ("learned", "submitted", "reference", "industry", "model-based"),
                ) -> dict[str, np.ndarray]:
    """Name -> normalised scores (runs x episodes) of every row of ``tier`` whose kind is in
    ``kinds`` (the upper reference's own row, 1 by definition, left out)."""
    t = results["tiers"][tier]
    pol = t["policies"]
    r0 = np.asarray(_row(pol, "validation constant")["episode_returns"], dtype=float)[0]
    hindsight = np.asarray(_row(pol, "hindsight constant")["episode_returns"], dtype=float)[0]
    planner_rows = [v for k, v in pol.items() if k.startswith("planner")]
    r1 = scoring.upper_reference(hindsight, np.asarray(planner_rows[0]["episode_returns"], dtype=float)[0]
                                 if planner_rows else None)
    floor = float(t.get("denominator_floor", scoring.DENOMINATOR_FLOOR))
    return {name: scoring.normalised_scores(np.asarray(row["episode_returns"], dtype=float), r0, r1, floor)
            for name, row in pol.items() if row.get("kind") in kinds and not name.startswith("planner")}


def plotted(results: dict[str, Any], tier: str) -> dict[str, np.ndarray]:
    """The rows the figure shows of ``tier`` (:func:`tier_scores`): every learned row at its
    selected checkpoint (a protocol-v2 run's early row, ``early_row_steps``, stays in the table),
    the best industry row by IQM, the model-based rows and the references but the validation
    constant (0 by definition); submitted rows stay in the table too. Ten curves, not twenty."""
    from agents.leaderboard.tables import best_of_kind
    pol = results["tiers"][tier]["policies"]
    best_industry = best_of_kind(pol, "industry")
    keep = {name for name, row in pol.items()
            if (row["kind"] == "learned" and row.get("early_row_steps") is None)
            or row["kind"] in ("model-based", "reference") or name == best_industry}
    return {k: v for k, v in tier_scores(results, tier).items()
            if k in keep and not k.startswith("validation constant")}


def profiles(scores: dict[str, np.ndarray], taus: np.ndarray = TAUS, reps: int = 2000,
             seed: int = scoring.BOOTSTRAP_SEED) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """(name -> fraction of scores above each tau, name -> (2, len(taus)) 95 % band): rliable's
    ``create_performance_profile`` over the (runs x episodes) matrices, its stratified bootstrap
    seeded."""
    from rliable import library
    with scoring.seeded_global_rng(seed):
        return library.create_performance_profile({k: np.atleast_2d(v) for k, v in scores.items()}, taus, reps=reps)


def plot(results: dict[str, Any], out: Path, tiers: list[str] | None = None, reps: int = 2000) -> Path:
    """One panel per tier (default: the board's random tiers, the benchmark's main tier first),
    the profile and band of each row :func:`plotted` picks; a row keeps its colour across the panels."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from bearing_gym.task import DEFAULT_TIER
    tiers = tiers or sorted((t for t, v in results["tiers"].items() if not v.get("deterministic")),
                            key=lambda t: (t != DEFAULT_TIER, t))
    per_tier = {t: plotted(results, t) for t in tiers}
    names = list(dict.fromkeys(k.split(" - trained on")[0] for sc in per_tier.values() for k in sc))
    colours = {k: plt.get_cmap("tab10" if len(names) <= 10 else "tab20")(i) for i, k in enumerate(names)}
    fig, axes = plt.subplots(1, len(tiers), figsize=(5.2 * len(tiers), 4.6), squeeze=False, sharey=True)
    for ax, tier in zip(axes[0], tiers):
        point, band = profiles(per_tier[tier], reps=reps)
        for name, y in point.items():
            c = colours[name.split(" - trained on")[0]]
            ax.plot(TAUS, y, color=c, lw=1.4, label=name.split(" - trained on")[0])
            ax.fill_between(TAUS, band[name][0], band[name][1], color=c, alpha=0.15, lw=0)
        for x in (0.0, 1.0):
            ax.axvline(x, color="0.6", lw=0.8, ls=":")
        ax.set_title(f"{tier} ({results['tiers'][tier]['episodes']} test episodes)")
        ax.set_xlabel("normalised score tau (0: validation constant, 1: upper reference)")
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("fraction of (seed, episode) scores > tau")
    handles = {h.get_label(): h for ax in axes[0] for h in ax.get_lines() if not h.get_label().startswith("_")}
    fig.legend(list(handles.values()), list(handles), loc="lower center", ncol=min(len(handles), 5), fontsize=8)
    fig.tight_layout(rect=(0, 0.1, 1, 1))
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=120)
    plt.close(fig)
    return out


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(prog="python -m agents.leaderboard.profiles", description=__doc__.split("\n\n")[0])
    ap.add_argument("--results", default="docs/results.json")
    ap.add_argument("--out", default="docs/performance_profiles.png")
    ap.add_argument("--tier", nargs="*", help="tiers (default: the board's random tiers)")
    ap.add_argument("--reps", type=int, default=2000, help="bootstrap replications of the bands")
    a = ap.parse_args(argv)
    print(f"wrote {plot(json.loads(Path(a.results).read_text()), Path(a.out), a.tier, a.reps)}")


if __name__ == "__main__":
    main()
