"""Learning curves: the validation score of every checkpoint train.py validated, per algorithm,
IQM and 95 % interval over training seeds and validation episodes (rliable).

    python -m agents.leaderboard.learning_curves agents/trained/*/seed_* --out docs/learning_curves.png

Each run directory (train.py's ``--out``, or its collected copy under ``agents/trained``) has
``eval/validation_returns.npz``: the return of each validation episode (env i on the scenario of
seed ``val_seed + i``) at every validation. Each return becomes a normalised score on its own
scenario with the references stored for the tier's validation episodes
(``agents/data/reference_constants.json``, :meth:`~agents.references.store.ValidationChoice.validation_references`):
0 = the validation-chosen constant, 1 = the hindsight best constant of the 50 N grid on that
episode (no planner on validation episodes), with the denominator floor of :mod:`agents.leaderboard.scoring`.
The curve of an algorithm is, at each validation step, rliable's IQM over (seeds x episodes)
with a 95 % stratified-bootstrap interval.
"""

from __future__ import annotations

import argparse
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from bearing_gym.task import DEFAULT_TIER, EPISODE_STEPS

from agents import protocol as P
from agents.leaderboard import scoring
from agents.references.store import STORE_PATH, load_choice


__all__ = ["RunCurve", "read_run", "algorithm_curves", "plot", "main"]

CURVE_BOOTSTRAP_REPS = 2_000


@dataclass
class RunCurve:
    """One training run's validation history as normalised scores."""

    algo: str
    seed: int
    tier: str
    timesteps: np.ndarray          # (validations,)
    scores: np.ndarray             # (validations, episodes)


def read_run(run_dir: str | Path, store: Path = STORE_PATH) -> RunCurve:
    """The normalised validation scores of one train.py run directory."""
    d = Path(run_dir)
    cfg = json.loads((d / "config.json").read_text())
    path = d / "eval" / "validation_returns.npz"
    if not path.exists():
        raise FileNotFoundError(f"{path}: no per-episode validation returns (train.py writes them when it runs "
                                "one validation episode per eval env, its default)")
    with np.load(path) as log:
        timesteps, seeds, returns = log["timesteps"], [int(s) for s in log["seeds"]], log["returns"]
    tier = cfg.get("tier", DEFAULT_TIER)
    choice = load_choice(tier, store)
    steps = cfg.get("episode_steps", EPISODE_STEPS)
    if steps != choice.episode_steps:
        raise ValueError(f"{d}: {steps}-step episodes, the stored validation references are of {choice.episode_steps}")
    r0, r1 = choice.validation_references(seeds)
    return RunCurve(cfg["algo"], int(cfg["seed"]), tier, np.asarray(timesteps),
                    scoring.normalised_scores(returns, r0, r1))


def algorithm_curves(runs: list[RunCurve], reps: int = CURVE_BOOTSTRAP_REPS) -> dict[str, dict]:
    """Per algorithm: the validation steps every one of its runs has, and at each the IQM and
    95 % interval over (seeds x episodes)."""
    out: dict[str, dict] = {}
    for algo in sorted({r.algo for r in runs}):
        mine = [r for r in runs if r.algo == algo]
        steps = sorted(set.intersection(*(set(int(t) for t in r.timesteps) for r in mine)))
        if not steps:
            raise ValueError(f"{algo}: its runs share no validation step (train them with the same --eval-freq)")
        if len({r.scores.shape[1] for r in mine}) != 1:
            raise ValueError(f"{algo}: its runs have different numbers of validation episodes")
        iqm, lo, hi = [], [], []
        for t in steps:
            s = np.array([r.scores[list(r.timesteps).index(t)] for r in mine])     # (seeds, episodes)
            p, a, b = scoring.iqm_interval(s, reps=reps)
            iqm.append(p)
            lo.append(a)
            hi.append(b)
        out[algo] = {"timesteps": steps, "iqm": iqm, "ci_low": lo, "ci_high": hi,
                     "seeds": sorted(r.seed for r in mine), "episodes": int(mine[0].scores.shape[1])}
    return out


def plot(curves: dict[str, dict], path: str | Path, title: str = "") -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4.2))
    for algo, c in curves.items():
        t = np.array(c["timesteps"]) / 1000.0
        line, = ax.plot(t, c["iqm"], marker="o", ms=3, label=f"{algo.upper()} ({len(c['seeds'])} seed{'s' if len(c['seeds']) > 1 else ''})")
        ax.fill_between(t, c["ci_low"], c["ci_high"], color=line.get_color(), alpha=0.2)
    ax.axhline(0.0, color="k", lw=0.8, ls="--")
    ax.axhline(1.0, color="k", lw=0.8, ls=":")
    last = max((c["timesteps"][-1] for c in curves.values()), default=0)
    if P.PROTOCOL_VERSION >= 2 and last > P.V2_EARLY_ROW_STEPS:     # the early rows' budget
        ax.axvline(P.V2_EARLY_ROW_STEPS / 1000.0, color="0.5", lw=0.8, ls="-.")
        ax.text(P.V2_EARLY_ROW_STEPS / 1000.0, 1.0, " early rows", fontsize=7, color="0.4", va="bottom")
    ax.set_xlabel("environment steps (thousands)")
    ax.set_ylabel("validation score (IQM, 95 % CI)")
    ax.set_title(title or "0 = validation-chosen constant, 1 = hindsight best constant", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description="Learning curves (validation score vs steps) of train.py runs.")
    ap.add_argument("runs", nargs="+", help="train.py run directories")
    ap.add_argument("--store", default=str(STORE_PATH))
    ap.add_argument("--out", default="docs/learning_curves.png", help="figure (a JSON beside it)")
    a = ap.parse_args(argv)
    runs = [read_run(d, Path(a.store)) for d in a.runs]
    tiers = {r.tier for r in runs}
    if len(tiers) != 1:
        raise SystemExit(f"runs of several tiers ({', '.join(sorted(tiers))}): draw one tier at a time")
    curves = algorithm_curves(runs)
    out = Path(a.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    plot(curves, out, title=f"tier {tiers.pop()}: 0 = validation-chosen constant, 1 = hindsight best constant")
    out.with_suffix(".json").write_text(json.dumps(curves, indent=1) + "\n")
    for algo, c in curves.items():
        print(f"{algo}: {len(c['seeds'])} seeds; last validation ({c['timesteps'][-1]:,} steps) IQM "
              f"{c['iqm'][-1]:.3f} [{c['ci_low'][-1]:.3f}, {c['ci_high'][-1]:.3f}]")
    print(f"wrote {out} and {out.with_suffix('.json')}")
    return curves


if __name__ == "__main__":
    main()
