"""How chaotic the score is: the test set run again with the settled start nudged by 1e-15.

On a quasi-periodic orbit a difference in the last bit grows into another trajectory within an
episode, so an episode's return is a sample, not a number: two CPUs that differ in one bit
(torch's kernels do) would give two samples. This tool measures how far such samples spread.
For each policy it runs the test episodes ``replicas + 1`` times: once as the board does
(replica 0) and ``replicas`` times with every displacement of the settled initial state
multiplied by 1 + 1e-15 s_k (s_k = +-1 drawn from the episode's seed and the replica: 4-5 ulp,
far below any physical meaning). It reports, per policy,

* the per-episode spread: the standard deviation of an episode's return over the replicas
  (median and 90th percentile over the episodes, the share of episodes whose return moves by
  more than 1, one quasi-periodic interval's cost);
* the spread of the policy's IQM of returns over the replicas (its standard deviation and
  range), and, given per-episode references r0 (the validation constant) and r1 (the upper
  reference), of its IQM of normalised scores.

    python -m agents.leaderboard.chaos --tier transient --replicas 5 --out docs/chaos_transient.json

Every replica is written as it finishes (``<out stem>_parts/replica_<r>.json``), so a run
survives an interruption and continues where it stopped. The policies are the
validation-chosen constant and the shipped policies through the portable float64 path.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from bearing_gym.task import DEFAULT_TIER, EPISODE_STEPS, TIER_NAMES
from bearing_gym.envs.provenance import kernel_hash

from agents.evaluation.trained import PRETRAINED_DIR, load_trained, shipped_dirs
from agents.evaluation.episodes import run_policies
from agents.policies.scripted import ConstantPreload
from agents.leaderboard.upper import score_bounds
from agents.protocol import held_out_seeds
from agents.references.store import DATA_DIR, STORE_PATH, load_choice, load_references


__all__ = ["perturbation", "replica_returns", "summarise", "default_policies", "replica_path", "run_replica",
           "write_summary", "main", "RELATIVE_PERTURBATION"]

RELATIVE_PERTURBATION = 1e-15


def perturbation(replica: int):
    """The ``perturb`` hook of :func:`agents.evaluation.episodes.run_policies` for one replica (0: none)."""
    def apply(venv, seeds: list[int]) -> None:
        if replica == 0:
            return
        X = venv.batch.X
        for b, seed in enumerate(seeds):
            signs = np.random.default_rng([int(seed), int(replica)]).choice([-1.0, 1.0], size=X.shape[1])
            X[b] = X[b] * (1.0 + RELATIVE_PERTURBATION * signs)
    return apply


def replica_returns(policies: list, tier: str, episodes: int, replica: int,
                    episode_steps: int = EPISODE_STEPS, progress: bool = True) -> dict[str, list[float]]:
    """Each policy's returns on the first ``episodes`` test episodes of ``tier`` in one replica."""
    seeds = held_out_seeds(episodes)
    res = run_policies(policies, episodes, seeds.start, episode_steps, env_kwargs={"tier": tier},
                       progress=f"replica {replica}" if progress else None, perturb=perturbation(replica))
    return {r.name: [float(x) for x in r.returns] for r in res}


def _iqm(x: np.ndarray) -> float:
    from agents.leaderboard.scoring import iqm
    return iqm(np.asarray(x, dtype=float))


def summarise(returns: dict[str, np.ndarray], r0: np.ndarray | None = None,
              r1: np.ndarray | None = None) -> dict[str, Any]:
    """Per policy, from its (replicas, episodes) returns: the per-episode spread and the spread
    of its IQM over the replicas (of returns; of normalised scores with ``r0``, ``r1``)."""
    from agents.leaderboard.scoring import normalised_scores
    out: dict[str, Any] = {}
    for name, R in returns.items():
        R = np.asarray(R, dtype=float)
        sd = R.std(axis=0, ddof=1)
        moved = np.max(R, axis=0) - np.min(R, axis=0)
        iqms = np.array([_iqm(row) for row in R])
        row: dict[str, Any] = {
            "replicas": int(R.shape[0]), "episodes": int(R.shape[1]),
            "episode_sd_median": float(np.median(sd)), "episode_sd_p90": float(np.percentile(sd, 90)),
            "episodes_moving_more_than_1": float(np.mean(moved > 1.0)),
            "episodes_bit_identical": float(np.mean(moved == 0.0)),
            "return_iqm_per_replica": [float(v) for v in iqms],
            "return_iqm_sd": float(iqms.std(ddof=1)), "return_iqm_range": float(iqms.max() - iqms.min())}
        if r0 is not None and r1 is not None:
            s_iqm = np.array([_iqm(normalised_scores(rr, r0, r1)) for rr in R])
            row.update({"score_iqm_per_replica": [float(v) for v in s_iqm],
                        "score_iqm_sd": float(s_iqm.std(ddof=1)),
                        "score_iqm_range": float(s_iqm.max() - s_iqm.min())})
        out[name] = row
    return out


def _score_bounds(tier: str, episodes: int, constant_n: float, constant_returns: np.ndarray,
                  references_dir: Path = DATA_DIR) -> tuple[np.ndarray | None, np.ndarray | None, str]:
    """The score's 0 and 1 on the first ``episodes`` test episodes from the tier's stored test
    references (:func:`agents.leaderboard.upper.score_bounds`), if they were made by this kernel
    for the constant this run used (``constant_n``, whose unperturbed returns must be the stored
    ones bit for bit); else (None, None, why not)."""
    try:
        refs = load_references(tier, references_dir)
        refs.check_kernel(f"python -m agents.leaderboard --tier {tier}")
        refs = refs.first(episodes)
        if refs.validation_preload_n != constant_n:
            raise ValueError(f"the store scores {refs.validation_preload_n:.0f} N, this run {constant_n:.0f} N")
        refs.check_fresh(constant_returns, f"python -m agents.leaderboard --tier {tier}")
        r0, r1 = score_bounds(refs)
    except (FileNotFoundError, RuntimeError, ValueError) as err:
        return None, None, f"none (no normalised scores: {str(err).splitlines()[0]})"
    upper = "the hindsight constant" if refs.planner is None else f"the planner {refs.planner_settings}"
    return r0, r1, (f"the stored test references: 0 = the validation constant ({refs.validation_preload_n:.0f} N), "
                    f"1 = {upper}")


def default_policies(tier: str, pretrained_dir: Path = PRETRAINED_DIR, store: Path = STORE_PATH) -> list:
    """The validation-chosen constant of ``tier`` (from ``store``), then the shipped policies
    through the portable float64 path (``load_trained(portable="auto")``, as the board loads them:
    torch, with a warning, only for an architecture that path does not cover)."""
    choice = load_choice(tier, store)
    return [ConstantPreload(choice.preload_n)] + [load_trained(d, portable="auto") for d in shipped_dirs(pretrained_dir)]


def replica_path(out: Path, replica: int) -> Path:
    """Where replica ``replica`` of the summary ``out`` is kept (``<out stem>_parts/replica_<r>.json``)."""
    return out.with_name(out.stem + "_parts") / f"replica_{replica}.json"


def run_replica(policies: list, tier: str, episodes: int, replica: int, out: Path,
                episode_steps: int = EPISODE_STEPS) -> Path:
    """Replica ``replica`` of the summary ``out``, written to :func:`replica_path` - unless a
    file made for this tier, episode count, kernel and policy set is there already."""
    path = replica_path(out, replica)
    if path.exists():
        done = json.loads(path.read_text())
        if (done.get("tier"), done.get("episodes"), done.get("kernel_hash"), sorted(done["returns"])) == \
                (tier, episodes, kernel_hash(), sorted(p.name for p in policies)):
            print(f"replica {replica}: done before ({path})", flush=True)
            return path
        print(f"replica {replica}: {path} was made for another tier, episode count, kernel or policy set: "
              "computing it again", flush=True)
    t = time.time()
    rows = replica_returns(policies, tier, episodes, replica, episode_steps)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps({"tier": tier, "replica": replica, "episodes": episodes, "kernel_hash": kernel_hash(),
                               "relative_perturbation": RELATIVE_PERTURBATION if replica else 0.0,
                               "wall_s": time.time() - t, "returns": rows}) + "\n")
    tmp.replace(path)
    print(f"replica {replica}: wrote {path} ({time.time() - t:.0f} s)", flush=True)
    return path


def write_summary(out: Path, tier: str, episodes: int, replicas: int, constant_name: str, constant_n: float,
                  command: str, references_dir: Path = DATA_DIR) -> dict[str, Any]:
    """The summary of replicas 0..``replicas`` (every one written by :func:`run_replica`), scored
    against the stored test references in ``references_dir`` when they fit the validation
    constant (``constant_name``: its row, ``constant_n`` N), written to ``out``."""
    reps = [json.loads(replica_path(out, r).read_text()) for r in range(replicas + 1)]
    names = list(reps[0]["returns"])
    returns = {n: np.array([rep["returns"][n] for rep in reps]) for n in names}
    r0, r1, scored_against = _score_bounds(tier, episodes, constant_n, returns[constant_name][0], references_dir)
    summary = {"about": __doc__.split("\n\n")[0], "tier": tier, "episodes": episodes, "kernel_hash": kernel_hash(),
               "replicas": replicas, "relative_perturbation": RELATIVE_PERTURBATION, "command": command,
               "wall_s": sum(rep["wall_s"] for rep in reps), "scores_against": scored_against,
               "policies": summarise(returns, r0, r1)}
    out.write_text(json.dumps(summary, indent=1) + "\n")
    return summary


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="Replicas of the test set under a 1e-15 perturbation of the "
                                             "settled start: how much of a score is chaos.")
    ap.add_argument("--tier", choices=TIER_NAMES, default=DEFAULT_TIER)
    ap.add_argument("--replicas", type=int, default=5, help="perturbed replicas besides the unperturbed one")
    ap.add_argument("--episodes", type=int, default=100, help="first N test episodes")
    ap.add_argument("--out", default=None, help="summary JSON (default docs/chaos_<tier>.json)")
    ap.add_argument("--store", default=str(STORE_PATH), help="the stored validation-chosen constants")
    ap.add_argument("--references-dir", default=str(DATA_DIR), help="where the stored test references are")
    a = ap.parse_args(argv)
    if a.replicas < 2:
        ap.error("--replicas must be at least 2 (a spread needs two perturbed runs)")
    out = Path(a.out or f"docs/chaos_{a.tier}.json")
    policies = default_policies(a.tier, store=Path(a.store))
    t0 = time.time()
    for r in range(a.replicas + 1):
        run_replica(policies, a.tier, a.episodes, r, out)
    constant = policies[0]                     # default_policies: the validation constant first
    summary = write_summary(out, a.tier, a.episodes, a.replicas, constant.name, constant.preload_n,
                            "python -m agents.leaderboard.chaos " + " ".join(sys.argv[1:] if argv is None else argv),
                            Path(a.references_dir))
    print(f"wrote {out} ({time.time() - t0:.0f} s this run)")
    for n, row in summary["policies"].items():
        print(f"{n:45s} episode sd median {row['episode_sd_median']:7.3f}  moved>1 {row['episodes_moving_more_than_1']:.0%}"
              f"  IQM(return) sd {row['return_iqm_sd']:.3f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
