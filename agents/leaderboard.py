"""The leaderboard: every learned policy and every reference on the protocol's test episodes,
as normalised scores with rliable statistics.

    python -m agents.leaderboard --smoke                 # the pipeline at a tiny budget (CI; ~1-2 min)
    python -m agents.leaderboard --pretrained            # shipped policies (agents/pretrained/<algo>/)
    python -m agents.leaderboard --model runs/sac_s0 runs/sac_s1000 ... --tier transient

Per tier (``--tier``, default the benchmark's), on ``agents.protocol.TEST_EPISODES`` test
scenarios (seeds ``TEST.start`` on), one batch per phase:

1. the validation-chosen constant, read from ``agents/data/reference_constants.json``
   (``python -m agents.references`` builds it on validation seeds), and the hindsight best
   constant per episode of the 50 N grid (one sweep of the grid; the chosen constant's row is
   its run in that sweep);
2. the contextual constant (``agents/data/contextual_<tier>.json``, ``python -m agents.contextual``),
   the oracle (reward map, nearest cell) and the learned policies: ``--model`` directories
   written by train.py (grouped by algorithm: one directory per training seed) and, with
   ``--pretrained``, the shipped policy of each algorithm in ``agents/pretrained/<algo>/``
   (``model.zip`` + ``vec_normalize.pkl``, as :func:`agents.evaluate.load_trained` loads them);
3. the MPC reference on the first ``MPC_EPISODES`` test scenarios (``--processes`` in parallel).

Scores and statistics: :mod:`agents.scoring` (0 = the validation-chosen constant, 1 = the better
of MPC and hindsight on the episode - the hindsight alone where the MPC did not run - a
denominator floor of one quasi-periodic interval's cost, IQM with stratified-bootstrap 95 %
intervals and the probability of improvement over the validation constant, with rliable). It
writes ``results.json`` (per tier and per policy: ``normalised_score_iqm``, ``ci_low``,
``ci_high``, ``n_seeds``, ``n_episodes`` and the raw metrics) and a markdown table beside it;
the full mode writes ``docs/results.json`` and ``docs/results_table.md``. Every departure from the
protocol (fewer episodes, a provisional stored constant, no MPC) is listed in
``protocol_deviations`` and the tier is marked ``"protocol": false``.

``--smoke`` runs the same code on 2 test episodes of 3 intervals, with the validation constant
and the contextual fit computed on the spot at that size on coarse grids (written to the output
directory, not to agents/data), a 1-episode MPC and few bootstrap replications: it checks the
pipeline, its numbers mean nothing.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from bearing_gym.benchmark import DEFAULT_TIER, EPISODE_STEPS, TIER_NAMES

from . import protocol as P
from . import scoring
from .contextual import DATA_DIR, ContextualConstant, contextual_path, fit_contextual
from .evaluate import EvalResult, SB3Policy, load_trained, run_policies, sweep_row
from .mpc import RecedingHorizonMPC
from .oracle import MapOracle
from .reference_store import STORE_PATH, ValidationChoice, load_choice, save_choice
from .references import choose_validation_constant, hindsight_reference, run_mpc

__all__ = ["Settings", "FULL", "SMOKE", "LearnedGroup", "learned_groups", "run_tier", "summarise",
           "to_markdown", "main"]

ROOT = Path(__file__).resolve().parent.parent
PRETRAINED_DIR = Path(__file__).with_name("pretrained")


@dataclass(frozen=True)
class Settings:
    """How large a leaderboard run is. FULL is the protocol; SMOKE checks the pipeline."""

    smoke: bool
    episodes: int
    episode_steps: int
    mpc_episodes: int
    hindsight_grid_step_n: float
    mpc: RecedingHorizonMPC
    bootstrap_reps: int
    poi_reps: int
    # smoke only: the validation constant and the contextual fit are computed at this size
    validation_episodes: int = 0
    contextual_episodes: int = 0
    contextual_grid_step_n: float = P.CONTEXTUAL_GRID_STEP_N


FULL = Settings(smoke=False, episodes=P.TEST_EPISODES, episode_steps=EPISODE_STEPS, mpc_episodes=P.MPC_EPISODES,
                hindsight_grid_step_n=P.HINDSIGHT_GRID_STEP_N, mpc=RecedingHorizonMPC(),
                bootstrap_reps=scoring.BOOTSTRAP_REPS, poi_reps=scoring.POI_REPS)
_COARSE_N = 850.0       # smoke grids: 300, 1150, 2000 N
SMOKE = Settings(smoke=True, episodes=2, episode_steps=3, mpc_episodes=1, hindsight_grid_step_n=_COARSE_N,
                 mpc=RecedingHorizonMPC(candidates_n=(300.0, 2000.0), horizon=2, replan_every=2),
                 bootstrap_reps=200, poi_reps=50, validation_episodes=2, contextual_episodes=3,
                 contextual_grid_step_n=_COARSE_N)


@dataclass
class LearnedGroup:
    """One learned row: an algorithm's runs (one policy per training seed) on one tier."""

    name: str
    algo: str
    tier: str
    policies: list[SB3Policy]
    seeds: list[int | None]
    timesteps: list[int | None]
    dirs: list[str] = field(default_factory=list)


def _config(d: Path) -> dict:
    cfg = d / "config.json"
    return json.loads(cfg.read_text()) if cfg.exists() else {}


def learned_groups(model_dirs: list[str | Path], pretrained: bool,
                   pretrained_dir: Path = PRETRAINED_DIR) -> list[LearnedGroup]:
    """The learned rows: ``model_dirs`` grouped by (algorithm, tier) from their config.json
    (one directory per training seed), then one row per shipped policy in
    ``pretrained_dir/<algo>/`` if ``pretrained``."""
    groups: dict[tuple[str, str, bool], LearnedGroup] = {}

    def add(d: Path, algo: str | None, shipped: bool) -> None:
        cfg = _config(d)
        algo = algo or cfg.get("algo")
        if algo is None:
            raise ValueError(f"{d}: no config.json names the algorithm; train it with train.py or put the "
                             "model in agents/pretrained/<algo>/")
        tier = cfg.get("tier", DEFAULT_TIER)
        key = (algo, tier, shipped)
        if key not in groups:
            groups[key] = LearnedGroup(f"{algo.upper()} ({'shipped' if shipped else 'trained'})", algo, tier, [], [], [])
        g = groups[key]
        g.policies.append(load_trained(d, algo=algo))
        g.seeds.append(cfg.get("seed"))
        g.timesteps.append(cfg.get("selected_timesteps", cfg.get("num_timesteps")))
        g.dirs.append(str(d))

    for d in model_dirs:
        add(Path(d), None, False)
    if pretrained:
        shipped = sorted(p for p in pretrained_dir.glob("*") if (p / "model.zip").exists()) if pretrained_dir.exists() else []
        if not shipped:
            raise FileNotFoundError(f"--pretrained: no shipped policy in {pretrained_dir}/<algo>/ (each needs model.zip "
                                    "and vec_normalize.pkl, as train.py writes them); copy the best run of each "
                                    "algorithm there, or leave out --pretrained")
        for d in shipped:
            add(d, d.name, True)
    return list(groups.values())


# -- one tier --------------------------------------------------------------------------------------
def _validation_choice(tier: str, s: Settings, store: Path, out_dir: Path, progress: bool) -> ValidationChoice:
    if not s.smoke:
        return load_choice(tier, store)
    choice = choose_validation_constant(tier, s.validation_episodes, P.VALIDATION.start, s.episode_steps,
                                        s.hindsight_grid_step_n,
                                        progress="smoke: validation constant" if progress else None)
    save_choice(choice, out_dir / "reference_constants.json")
    return choice


def _contextual(tier: str, s: Settings, contextual_dir: Path, out_dir: Path, progress: bool) -> ContextualConstant:
    if not s.smoke:
        return ContextualConstant.load(contextual_path(tier, contextual_dir))
    pol = fit_contextual(tier, s.contextual_episodes, P.CONTEXTUAL_FIT_SEED, s.episode_steps, s.contextual_grid_step_n,
                         progress="smoke: contextual fit" if progress else None)
    pol.save(contextual_path(tier, out_dir))
    return pol


def _metrics(results: list[EvalResult]) -> dict[str, Any]:
    """Raw metrics over every run and episode of a row (costs per episode, positive)."""
    def mean(get) -> float:
        return float(np.mean(np.concatenate([np.atleast_1d(get(r)) for r in results])))
    out = {"mean_return": mean(lambda r: r.returns),
           "quasi_periodic_fraction": mean(lambda r: r.qp_fraction),
           "vibration_amplitude_um": (None if any(r.vibration_um is None for r in results)
                                      else mean(lambda r: r.vibration_um)),
           "vibration_cost": -mean(lambda r: r.terms["vibration"]),
           "heat_cost": -mean(lambda r: r.terms["heat"]),
           "fatigue_cost": -mean(lambda r: r.terms["fatigue"]),
           "mean_preload_n": mean(lambda r: r.mean_preload),
           "terminated_episodes": int(sum(r.terminated_count for r in results))}
    return out


def summarise(kind: str, results: list[EvalResult], r0: np.ndarray, r1: np.ndarray,
              s: Settings, **extra: Any) -> dict[str, Any]:
    """One row of results.json: the normalised scores of ``results`` (one EvalResult per run,
    all on the episodes of ``r0``/``r1``) aggregated with rliable, and the raw metrics."""
    returns = np.array([r.returns for r in results])                     # (runs, episodes)
    scores = scoring.normalised_scores(returns, r0, r1)
    point, lo, hi = scoring.iqm_interval(scores, reps=s.bootstrap_reps)
    poi, poi_lo, poi_hi = scoring.probability_of_improvement(scores, np.zeros((1, scores.shape[1])), reps=s.poi_reps)
    row: dict[str, Any] = {
        "kind": kind, "normalised_score_iqm": point, "ci_low": lo, "ci_high": hi,
        "ci_method": ("stratified bootstrap over training seeds and episodes (rliable, task_bootstrap=True)"
                      if scores.shape[0] > 1 else "bootstrap over episodes (single run; rliable, task_bootstrap=True)"),
        "n_seeds": int(scores.shape[0]), "n_episodes": int(scores.shape[1]),
        "normalised_score_mean": float(np.mean(scores)),
        "probability_of_improvement": poi, "poi_ci_low": poi_lo, "poi_ci_high": poi_hi}
    if scores.shape[0] > 1:
        _, row["seed_ci_low"], row["seed_ci_high"] = scoring.seed_interval(scores, reps=s.bootstrap_reps)
    row.update(_metrics(results))
    row.update(extra)
    return row


def run_tier(tier: str, s: Settings, groups: list[LearnedGroup], store: Path = STORE_PATH,
             contextual_dir: Path = DATA_DIR, out_dir: Path = Path("."),
             processes: int = 1, progress: bool = True) -> dict[str, Any]:
    """Every reference and learned row of ``tier``, as the tier's object of results.json."""
    t0 = time.time()
    deviations: list[str] = []
    choice = _validation_choice(tier, s, store, out_dir, progress)
    deviations += [f"validation constant: {p}" for p in choice.protocol_problems()]
    contextual = _contextual(tier, s, contextual_dir, out_dir, progress)
    seeds = P.held_out_seeds(s.episodes)
    shape = f"{s.episodes} test episodes of {s.episode_steps} steps"
    hindsight, sweep = hindsight_reference(tier, s.episodes, seeds.start, s.episode_steps, s.hindsight_grid_step_n,
                                           extra_n=(choice.preload_n,),
                                           progress=f"{tier} 1/3: constant sweep x {shape}" if progress else None)
    r0_result = sweep_row(sweep, choice.preload_n)
    mine = [g for g in groups if g.tier == tier]
    policies = [contextual, MapOracle()] + [p for g in mine for p in g.policies]
    ran = run_policies(policies, s.episodes, seeds.start, s.episode_steps, env_kwargs={"tier": tier},
                       progress=f"{tier} 2/3: {len(policies)} policies x {shape}" if progress else None)
    contextual_res, oracle_res, learned_res = ran[0], ran[1], ran[2:]
    m = min(s.mpc_episodes, s.episodes)
    mpc_res, mpc_wall = (None, [])
    if m > 0:
        mpc_res, mpc_wall = run_mpc(tier, seeds[:m], s.episode_steps, s.mpc, processes,
                                    progress=f"{tier} 3/3: MPC" if progress else None)
    r0 = r0_result.returns
    mpc_full = np.full(s.episodes, np.nan)
    if mpc_res is not None:
        mpc_full[:m] = mpc_res.returns
    r1 = scoring.upper_reference(hindsight.returns, mpc_full)

    rows: dict[str, dict] = {}
    rows[f"validation constant ({choice.preload_n:.0f} N)"] = summarise(
        "reference", [r0_result], r0, r1, s, preload_n=choice.preload_n)
    rows[f"hindsight constant ({s.hindsight_grid_step_n:g} N grid)"] = summarise(
        "reference", [hindsight], r0, r1, s)
    rows["contextual constant"] = summarise("reference", [contextual_res], r0, r1, s,
                                            features="squares" if contextual.squares else "linear",
                                            fit=contextual.meta)
    rows["oracle (reward map, nearest cell)"] = summarise("reference", [oracle_res], r0, r1, s)
    if mpc_res is not None:
        rows[f"MPC (true simulator, first {m} episodes)"] = summarise(
            "reference", [mpc_res], r0[:m], r1[:m], s, horizon=s.mpc.horizon,
            replan_every=s.mpc.replan_every, candidates_n=list(s.mpc.candidates_n),
            wall_s_per_episode=float(np.mean(mpc_wall)))
    k = 0
    for g in mine:
        runs = learned_res[k:k + len(g.policies)]
        k += len(g.policies)
        headline = g.algo == P.HEADLINE_ALGORITHM and "shipped" not in g.name
        rows[g.name] = summarise("learned", runs, r0, r1, s, algo=g.algo, training_seeds=g.seeds,
                                 timesteps=g.timesteps, model_dirs=g.dirs, headline=headline)
        want = len(P.training_seeds(g.algo)) if g.algo in P.ALGORITHMS else None
        if "shipped" not in g.name and want is not None and len(g.policies) < want:
            deviations.append(f"{g.name}: {len(g.policies)} training seeds (the protocol: {want})")
    if s.episodes < P.TEST_EPISODES:
        deviations.append(f"{s.episodes} test episodes (the protocol: {P.TEST_EPISODES})")
    if m < min(P.MPC_EPISODES, s.episodes):
        deviations.append(f"MPC on {m} episodes (the protocol: {P.MPC_EPISODES})")
    if s.episode_steps != EPISODE_STEPS:
        deviations.append(f"{s.episode_steps}-step episodes (the benchmark: {EPISODE_STEPS})")
    if s.smoke:
        deviations.insert(0, "smoke run: tiny budget, the numbers mean nothing")
    upper = (f"the better of the MPC and the hindsight constant on the first {m} episodes (the MPC subset); "
             f"the hindsight constant alone on the other {s.episodes - m}" if m else
             "the hindsight constant alone (the MPC did not run)")
    return {"episodes": s.episodes, "seeds": [seeds.start, seeds[-1]], "episode_steps": s.episode_steps,
            "protocol": not deviations, "protocol_deviations": deviations,
            "validation_constant": {"preload_n": choice.preload_n, "episodes": choice.episodes,
                                    "seeds": [choice.seeds[0], choice.seeds[-1]], "grid_step_n": choice.grid_step_n,
                                    "episode_steps": choice.episode_steps},
            "upper_reference": upper, "mpc_episodes": m, "mpc_seeds": [seeds.start, seeds.start + m - 1] if m else [],
            "hindsight_grid_step_n": s.hindsight_grid_step_n, "hindsight_preloads": len(sweep),
            "denominator_floor": scoring.DENOMINATOR_FLOOR,
            "floored_episodes": scoring.floored_episodes(r0, r1),
            "policies": rows, "wall_s": time.time() - t0}


# -- output ----------------------------------------------------------------------------------------
def _fmt(x: float | None, spec: str = ".2f") -> str:
    return "-" if x is None else format(x, spec)


def to_markdown(results: dict[str, Any]) -> str:
    """The leaderboard table of each tier, with the notes a reader needs to read it."""
    lines = [f"# Leaderboard ({results['mode']})", "",
             f"Generated by `{results['command']}`. Normalised score: 0 = the validation-chosen constant "
             "preload, 1 = the better of the MPC reference and the hindsight best constant on the episode; "
             "IQM with 95 % stratified-bootstrap intervals (rliable; over training seeds and episodes, over "
             "episodes for single-run rows); P(improvement) over the validation constant.", ""]
    for tier, t in results["tiers"].items():
        lines += [f"## Tier `{tier}`", "",
                  f"{t['episodes']} test episodes (seeds {t['seeds'][0]}..{t['seeds'][1]}) of {t['episode_steps']} "
                  f"intervals; upper reference: {t['upper_reference']}; denominator floor "
                  f"{t['denominator_floor']:g} reward units, reached on {t['floored_episodes']} episodes.", ""]
        if not t["protocol"]:
            lines += ["**Not the protocol:** " + "; ".join(t["protocol_deviations"]) + ".", ""]
        lines += ["| policy | seeds | episodes | normalised score IQM [95 % CI] | P(improvement) | mean return "
                  "| time quasi-periodic | vibration (um) | heat cost | fatigue cost | terminated |",
                  "|---|---|---|---|---|---|---|---|---|---|---|"]
        for name, r in t["policies"].items():
            lines.append(f"| {name} | {r['n_seeds']} | {r['n_episodes']} | {r['normalised_score_iqm']:.3f} "
                         f"[{r['ci_low']:.3f}, {r['ci_high']:.3f}] | {r['probability_of_improvement']:.2f} "
                         f"| {r['mean_return']:.2f} | {100 * r['quasi_periodic_fraction']:.1f} % "
                         f"| {_fmt(r['vibration_amplitude_um'])} | {r['heat_cost']:.2f} | {r['fatigue_cost']:.2f} "
                         f"| {r['terminated_episodes']} |")
        lines.append("")
    return "\n".join(lines)


def _protocol_summary() -> dict[str, Any]:
    return {"test_episodes": P.TEST_EPISODES, "mpc_episodes": P.MPC_EPISODES,
            "validation_constant_episodes": P.VALIDATION_CONSTANT_EPISODES,
            "contextual_fit_episodes": P.CONTEXTUAL_FIT_EPISODES, "headline_algorithm": P.HEADLINE_ALGORITHM,
            "training_seeds": {a: list(P.training_seeds(a)) for a in P.ALGORITHMS},
            "step_budget_per_run": P.STEP_BUDGET_PER_RUN,
            "step_budget_chosen_from_throughput": P.STEP_BUDGET_CHOSEN_FROM_THROUGHPUT,
            "denominator_floor": scoring.DENOMINATOR_FLOOR}


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(description="The leaderboard: learned policies and references as normalised scores.")
    ap.add_argument("--smoke", action="store_true", help="the pipeline at a tiny budget (2 episodes); for CI")
    ap.add_argument("--tier", nargs="+", choices=TIER_NAMES, default=[DEFAULT_TIER])
    ap.add_argument("--model", nargs="+", default=[], help="train.py run directories (one per training seed)")
    ap.add_argument("--pretrained", action="store_true", help="add the shipped policies of agents/pretrained/<algo>/")
    ap.add_argument("--pretrained-dir", default=str(PRETRAINED_DIR))
    ap.add_argument("--episodes", type=int, help=f"test episodes (default: the protocol's {P.TEST_EPISODES}; "
                                                 "fewer is recorded as a deviation)")
    ap.add_argument("--mpc-episodes", type=int, help=f"MPC subset (default {P.MPC_EPISODES}; 0 skips the MPC)")
    ap.add_argument("--processes", type=int, default=2, help="parallel MPC episodes (default %(default)d)")
    ap.add_argument("--store", default=str(STORE_PATH), help="stored validation-chosen constants")
    ap.add_argument("--contextual-dir", default=str(DATA_DIR), help="fitted contextual constants")
    ap.add_argument("--out", help="results.json path (default: docs/results.json; with --smoke "
                                  "runs/leaderboard_smoke/results.json); the markdown table goes beside it")
    return ap


def main(argv: list[str] | None = None) -> dict[str, Any]:
    a = build_parser().parse_args(argv)
    s = SMOKE if a.smoke else FULL
    if a.episodes is not None:
        if a.episodes < 2:
            raise SystemExit("--episodes must be >= 2 (an interval needs two episodes)")
        s = dataclasses.replace(s, episodes=a.episodes)
    if a.mpc_episodes is not None:
        if a.mpc_episodes < 0:
            raise SystemExit("--mpc-episodes must be >= 0")
        s = dataclasses.replace(s, mpc_episodes=a.mpc_episodes)
    out = Path(a.out) if a.out else (ROOT / "runs" / "leaderboard_smoke" / "results.json" if a.smoke
                                     else ROOT / "docs" / "results.json")
    md = out.with_name("results_table.md") if out.name == "results.json" else out.with_suffix(".md")
    out.parent.mkdir(parents=True, exist_ok=True)
    t0 = time.time()
    groups = learned_groups(a.model, a.pretrained, Path(a.pretrained_dir))
    command = "python -m agents.leaderboard " + " ".join(argv if argv is not None else sys.argv[1:])
    results: dict[str, Any] = {"benchmark": "BearingPreload-v0", "mode": "smoke" if s.smoke else "full",
                               "command": command.strip(), "protocol": _protocol_summary(),
                               "statistics": {"bootstrap_reps": s.bootstrap_reps, "poi_reps": s.poi_reps,
                                              "iqm": "rliable.metrics.aggregate_iqm",
                                              "intervals": "rliable.library.get_interval_estimates, 95 %, percentile"},
                               "tiers": {}}
    for tier in a.tier:
        results["tiers"][tier] = run_tier(tier, s, groups, Path(a.store), Path(a.contextual_dir), out.parent,
                                          processes=1 if s.smoke else a.processes)
    unused = [g.name for g in groups if g.tier not in a.tier]
    if unused:
        print(f"note: not evaluated (trained on another tier): {', '.join(unused)}", flush=True)
    results["wall_s"] = time.time() - t0
    out.write_text(json.dumps(results, indent=1) + "\n")
    text = to_markdown(results)
    md.write_text(text)
    print(text)
    print(f"wrote {out} and {md} ({results['wall_s'] / 60:.1f} min)")
    return results


if __name__ == "__main__":
    main()
