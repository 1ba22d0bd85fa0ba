"""Does a tier need closed-loop control? MPC with the true simulator against the hindsight best
constant preload, paired on the same scenarios.

    python -m agents.references.tier_gap --tier transient --seed 200000 --episodes 20 --out docs/tier_gap_transient.json

For each scenario (env seeded ``seed + i``): every constant preload of a grid over the whole
action range (``--grid-step``, default 50 N) runs the episode in one batch (the native vector
env, every env on the same scenario) and the best is the hindsight constant; the receding-horizon
MPC (:mod:`agents.policies.mpc`) runs the same episode. Reports each mean and the paired difference MPC -
hindsight with a 95 % Student-t interval. The seeds 200000+ are the tier-design range: apart
from training, validation and test seeds (``agents.protocol``).
"""

from __future__ import annotations

import argparse
import json
import math
import time
from multiprocessing import get_context
from pathlib import Path

import numpy as np


__all__ = ["hindsight_constant", "scenario_gap", "scenario_kwargs", "main"]


def scenario_kwargs(tier: str, eccentricity_um: tuple[float, float] | None) -> dict:
    """The env's keyword arguments for ``tier``, its unbalance (the rotor's mass-centre
    eccentricity) drawn uniformly in ``eccentricity_um`` (um) instead if given, everything else as
    the tier draws it (the realistic-balance study: ``--eccentricity-um 0.2 2.5``)."""
    if eccentricity_um is None:
        return {"tier": tier}
    import dataclasses

    from bearing_gym.envs.tiers import tier_parts
    lo, hi = (float(x) for x in eccentricity_um)
    if not 0.0 < lo <= hi <= 1000.0:
        raise ValueError(f"--eccentricity-um takes 0 < LO <= HI <= 1000 (um), got {lo} {hi}")
    dist = tier_parts(tier)["scenario"]
    if not hasattr(dist, "eccentricity_m") or not dataclasses.is_dataclass(dist) or getattr(dist, "deterministic", False):
        raise ValueError(f"--eccentricity-um needs a tier that draws its scenarios (not {tier!r})")
    return {"tier": tier, "scenario": dataclasses.replace(dist, eccentricity_m=(lo * 1e-6, hi * 1e-6))}


def hindsight_constant(tier: str, seed: int, preloads_n: np.ndarray,
                       eccentricity_um: tuple[float, float] | None = None) -> tuple[float, float, np.ndarray]:
    """(best preload, its return, all returns) of the constants on the scenario of ``seed``."""
    from bearing_gym.envs import BearingPreloadEnv, BearingPreloadVectorEnv
    kw = scenario_kwargs(tier, eccentricity_um)
    probe = BearingPreloadEnv(**kw)
    probe.reset(seed=seed)
    scenario = probe.scenario
    venv = BearingPreloadVectorEnv(num_envs=len(preloads_n), max_episode_steps=None, **kw)
    venv.reset(seed=seed, options={"scenario": scenario})
    actions = np.array([[venv.actuator.action_for(p)] for p in preloads_n])
    total = np.zeros(len(preloads_n))
    alive = np.ones(len(preloads_n), dtype=bool)
    for _ in range(venv.episode_steps):
        _, r, term, _, _ = venv.step(actions)
        total += np.where(alive, r, 0.0)
        alive &= ~term
    best = int(np.argmax(total))
    return float(preloads_n[best]), float(total[best]), total


def scenario_gap(args: tuple) -> dict:
    tier, seed, grid_step, horizon, replan_every, *rest = args      # + (eccentricity_um, controller) if given
    eccentricity_um = rest[0] if rest else None
    controller = rest[1] if len(rest) > 1 else "mpc"
    import numba
    numba.set_num_threads(1)                     # one process per core
    from bearing_gym.envs import BearingPreloadEnv

    from agents.policies.mpc import RecedingHorizonMPC
    t0 = time.time()
    preloads = np.arange(300.0, 2000.0 + 1e-9, grid_step)
    best_p, best_r, _ = hindsight_constant(tier, seed, preloads, eccentricity_um)
    kw = scenario_kwargs(tier, eccentricity_um)
    env = BearingPreloadEnv(**kw)
    env.reset(seed=seed)
    sc = env.scenario
    if controller == "planner":                  # the full-horizon planner (the episode's future known)
        from agents.policies.planner import plan_episode
        res = plan_episode(tier, seed, env_kwargs={k: v for k, v in kw.items() if k != "tier"})
        return {"seed": seed, "hindsight_preload_n": best_p, "hindsight_return": best_r,
                "controller_return": res.return_, "planner_hindsight_return": res.hindsight_return,
                "clearance_um": sc.clearance_m * 1e6, "eccentricity_um": sc.eccentricity_m * 1e6,
                "wall_s": time.time() - t0}
    mpc = RecedingHorizonMPC(horizon=horizon, replan_every=replan_every)
    out = mpc.run_episode(env, seed=seed)
    return {"seed": seed, "hindsight_preload_n": best_p, "hindsight_return": best_r,
            "mpc_return": out.episode_return, "mpc_terms": out.terms,
            "mpc_quasi_periodic_fraction": out.quasi_periodic_fraction,
            "speed_profile": [list(k) for k in sc.speed_profile],
            "radial_load_profile": [list(k) for k in sc.radial_load_profile],
            "clearance_um": sc.clearance_m * 1e6, "eccentricity_um": sc.eccentricity_m * 1e6,
            "wall_s": time.time() - t0}


def _planner_settings() -> dict:
    from agents.policies.planner import PlannerSettings
    return PlannerSettings().as_dict()


def mpc_candidates() -> tuple[float, ...]:
    from agents.policies.mpc import DEFAULT_CANDIDATES_N
    return DEFAULT_CANDIDATES_N


def paired_ci(diff: np.ndarray) -> tuple[float, float, float]:
    from scipy import stats
    m = float(np.mean(diff))
    h = float(stats.t.ppf(0.975, len(diff) - 1) * np.std(diff, ddof=1) / math.sqrt(len(diff)))
    return m, m - h, m + h


def build_parser() -> argparse.ArgumentParser:
    from agents.protocol import TIER_DESIGN
    ap = argparse.ArgumentParser(description="MPC (true simulator) vs the hindsight best constant, paired")
    ap.add_argument("--tier", default="transient")
    ap.add_argument("--seed", type=int, default=TIER_DESIGN.start)
    ap.add_argument("--episodes", type=int, default=20)
    ap.add_argument("--grid-step", type=float, default=50.0)
    ap.add_argument("--horizon", type=int, default=10, help="MPC look-ahead (control intervals)")
    ap.add_argument("--replan-every", type=int, default=5)
    ap.add_argument("--processes", type=int, default=2)
    ap.add_argument("--out", default=None, help="JSON file for the per-scenario results")
    ap.add_argument("--controller", choices=("mpc", "planner"), default="mpc",
                    help="mpc: the receding-horizon MPC (0.2 s look-ahead, the true simulator); planner: the "
                         "full-horizon planner (the episode's whole future; the leaderboard's upper reference). The "
                         "paired statistic's keys keep the MPC's names (paired_mpc_minus_hindsight, mpc_wins)")
    ap.add_argument("--eccentricity-um", nargs=2, type=float, metavar=("LO", "HI"),
                    help="draw the rotor's unbalance (mass-centre eccentricity, um) uniformly in [LO, HI] instead of "
                         "the tier's range, everything else as the tier (e.g. 0.2 2.5: G0.2 at 10,000 rpm to G6.5 at 25,000 rpm)")
    return ap


def run_settings(a: argparse.Namespace) -> dict:
    """What a stored row depends on besides its seed (a resumed run keeps only rows made so)."""
    from bearing_gym.envs.provenance import kernel_hash, package_version
    return {"tier": a.tier, "grid_step_n": a.grid_step,
            **({"eccentricity_um": list(a.eccentricity_um)} if getattr(a, "eccentricity_um", None) else {}),
            **({"mpc": {"horizon": a.horizon, "replan_every": a.replan_every, "candidates": len(mpc_candidates())}}
               if getattr(a, "controller", "mpc") == "mpc" else {"planner": _planner_settings()}),
            "kernel_hash": kernel_hash(), "package_version": package_version()}


def stored_rows(path: str | None, settings: dict) -> dict[int, dict]:
    """The scenarios an earlier run with the same settings on the same kernel left in ``path``."""
    if not path or not Path(path).exists():
        return {}
    old = json.loads(Path(path).read_text())
    if any(old.get(k) != v for k, v in settings.items() if k != "package_version"):
        return {}
    return {int(r["seed"]): r for r in old.get("scenarios", [])}


def summarise(settings: dict, seeds: list[int], rows: list[dict]) -> dict:
    """The file's content; ``core_s`` sums the scenarios' wall times (one core each)."""
    done = sorted(rows, key=lambda r: r["seed"])
    summary = {**settings, "seeds": [seeds[0], seeds[-1]], "episodes": len(seeds),
               "complete": len(done) == len(seeds), "core_s": float(sum(r["wall_s"] for r in done)),
               "scenarios": done}
    if len(done) >= 2:
        key = "mpc_return" if "mpc_return" in done[0] else "controller_return"
        diff = np.array([r[key] - r["hindsight_return"] for r in done])
        m, lo, hi = paired_ci(diff)
        summary.update({"mean_mpc_return" if key == "mpc_return" else "mean_controller_return":
                        float(np.mean([r[key] for r in done])),
                        "mean_hindsight_return": float(np.mean([r["hindsight_return"] for r in done])),
                        "paired_mpc_minus_hindsight": m, "ci95_low": lo, "ci95_high": hi,
                        "mpc_wins": int(np.sum(diff > 0))})
    return summary


def main(argv: list[str] | None = None) -> None:
    a = build_parser().parse_args(argv)
    settings = run_settings(a)
    seeds = [a.seed + i for i in range(a.episodes)]
    done = stored_rows(a.out, settings)
    rows = [done[s] for s in seeds if s in done]
    if rows:
        print(f"resuming: {len(rows)} of {len(seeds)} scenarios already in {a.out}", flush=True)
    if a.controller == "planner" and a.grid_step != 50.0:
        raise SystemExit("--controller planner: the planner starts from the hindsight constant of its own 50 N grid; "
                         "leave --grid-step at 50 so both compare on the same grid")
    ecc = tuple(a.eccentricity_um) if a.eccentricity_um else None
    scenario_kwargs(a.tier, ecc)                  # a bad range or tier: refused before any process starts
    jobs = [(a.tier, s, a.grid_step, a.horizon, a.replan_every, ecc, a.controller) for s in seeds if s not in done]
    name = "MPC" if a.controller == "mpc" else "planner"
    key = "mpc_return" if a.controller == "mpc" else "controller_return"
    with get_context("spawn").Pool(a.processes) as pool:
        for row in pool.imap(scenario_gap, jobs):
            rows.append(row)
            print(f"[{len(rows)}/{len(seeds)}] seed {row['seed']}: {name} {row[key]:.2f}, hindsight "
                  f"{row['hindsight_preload_n']:.0f} N {row['hindsight_return']:.2f} ({row['wall_s']:.0f} s)", flush=True)
            if a.out:
                Path(a.out).write_text(json.dumps(summarise(settings, seeds, rows), indent=1))
    summary = summarise(settings, seeds, rows)
    mean = summary["mean_mpc_return" if a.controller == "mpc" else "mean_controller_return"]
    print(f"{a.tier}: {name} {mean:.2f}, hindsight constant "
          f"{summary['mean_hindsight_return']:.2f}, paired {summary['paired_mpc_minus_hindsight']:+.2f} "
          f"[{summary['ci95_low']:+.2f}, {summary['ci95_high']:+.2f}] ({name} better in {summary['mpc_wins']}/"
          f"{len(seeds)}), {summary['core_s'] / 3600:.2f} core-hours")
    if a.out:
        Path(a.out).write_text(json.dumps(summary, indent=1))


if __name__ == "__main__":
    main()
