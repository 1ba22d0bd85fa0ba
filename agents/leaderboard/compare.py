"""Evaluate preload controllers side by side on the same held-out scenarios.

    python -m agents.evaluate --model DIR [DIR ...] [--episodes 20] [--tier transient] [--seed 300000]
    python -m agents.evaluate --pretrained [--episodes 20]      # the shipped policies of agents/pretrained/

Runs the trained policy in each DIR (``model.zip`` + ``vec_normalize.pkl`` from ``train.py``, or a
shipped directory's ``portable_policy.npz``; through the portable float64 path where it covers the
architecture; several DIRs put PPO and SAC side by side) and every scripted baseline on the same seeds (env i
of the batch is seeded ``seed + i``, so every policy meets the same scenarios): among them the
best constant preload chosen on the validation seeds (read from
``agents/data/reference_constants.json``, never chosen on these episodes) and, per scenario, the
best constant of a 50 N grid over the actuator's whole range with hindsight. It writes
``DIR/evaluation.md``, ``DIR/evaluation.csv``, ``DIR/evaluation_episodes.csv`` (every episode's
return per policy) and ``DIR/evaluation_traces.png``. Per policy: mean return with a 95 % confidence interval
(Student t over episodes), the mean of each reward term, the fraction of control intervals spent
quasi-periodic (index > QPI_THRESHOLD = 0.1), the mean preload and the number of episodes that terminated early
(the integrator diverged: the episode ends there, its return holds the termination penalty).
The report is :mod:`agents.leaderboard.compare_report`; a policy's results, :class:`agents.evaluation.result.EvalResult`.
"""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

from bearing_gym.task import DEFAULT_TIER, EPISODE_STEPS, TIER_NAMES

from agents.leaderboard.compare_report import write_report
from agents.evaluation.result import EvalResult
from agents.policies.oracle import TABLE_PATH as ORACLE_TABLE, MapOracle
from agents.policies.scripted import FeedbackRule, Policy, SpeedScheduledPreload
from agents.protocol import HINDSIGHT_GRID_STEP_N, preload_grid
from agents.references.store import STORE_PATH, ValidationChoice, load_choice, rebuild_command
from agents.paths import runs_dir
from agents.policies.stability_table import StabilityTable
from agents.evaluation.episodes import TEST_SEED, constant_sweep, hindsight_constant, run_policies, sweep_row
from agents.evaluation.trained import load_trained, shipped_dirs


def baselines(table: StabilityTable | None, oracle_table: str | Path = ORACLE_TABLE) -> list[Policy]:
    """The scripted controllers besides the constant preloads (those come from the sweep); the
    oracle reads its table from ``oracle_table``."""
    pols: list[Policy] = [FeedbackRule()]
    if table is not None:
        pols += [SpeedScheduledPreload(table)]
    pols.append(MapOracle(oracle_table))
    return pols


def stored_choice(tier: str, store_path: str | Path = STORE_PATH, verbose: bool = True) -> ValidationChoice | None:
    """The validation-chosen constant of ``tier`` from the store, or None (with a warning that
    says how to build it) if the store has none."""
    try:
        return load_choice(tier, store_path)
    except LookupError as err:
        if verbose:
            print(f"warning: {err}; the report has no validation-chosen constant row", flush=True)
        return None


def evaluate(model_dir: str | Path | list[str | Path] | None, episodes: int = 20, seed: int = TEST_SEED,
             episode_steps: int = EPISODE_STEPS, out_dir: str | Path | None = None,
             table_path: str | Path | None = None, verbose: bool = True,
             progress_every_s: float = 30.0, tier: str = DEFAULT_TIER,
             store_path: str | Path = STORE_PATH, grid_step_n: float = HINDSIGHT_GRID_STEP_N,
             oracle_table: str | Path = ORACLE_TABLE) -> list[EvalResult]:
    """Every policy (the trained ones in ``model_dir``, the scripted baselines, the constant
    preloads) on the same held-out scenarios; writes the report files to ``out_dir`` (default:
    the first model directory, else ``evaluation/``). With ``verbose``, progress lines (at most
    one per ``progress_every_s`` seconds per phase) and the table are printed.

    The best constant preload is the one stored for ``tier`` in ``store_path`` (chosen on
    validation seeds by ``python -m agents.references``), never chosen on these episodes; the
    hindsight reference is the best constant per scenario of a ``grid_step_n`` grid over the
    actuator's whole range (the stored constant's row is that sweep's run of it). The oracle
    baseline reads the reward map's best preloads from ``oracle_table``."""
    try:
        table = StabilityTable.load(table_path) if table_path else StabilityTable.load()
    except FileNotFoundError as err:
        print(f"warning: {err}; speed-schedule and oracle baselines skipped")
        table = None
    if model_dir is None:
        model_dirs = []
    elif isinstance(model_dir, (str, Path)):
        model_dirs = [model_dir]
    else:
        model_dirs = list(model_dir)
    policies: list[Policy] = [load_trained(d, portable="auto") for d in model_dirs]
    policies += baselines(table, oracle_table)
    choice = stored_choice(tier, store_path, verbose)
    grid = preload_grid(grid_step_n)
    if choice is not None and choice.preload_n not in grid:     # a store built on another grid
        grid = tuple(sorted(set(grid) | {choice.preload_n}))
    shape = f"{episodes} held-out episodes of {episode_steps} steps, stepped together"
    kw = {"env_kwargs": {"tier": tier}, "progress_every_s": progress_every_s}
    sweep = constant_sweep(grid, episodes, seed, episode_steps, **kw,
                           progress=f"evaluation 1/2: {len(grid)} constant preloads x {shape}" if verbose else None)
    results = run_policies(policies, episodes, seed, episode_steps, **kw,
                           progress=f"evaluation 2/2: {len(policies)} policies x {shape}" if verbose else None)
    hindsight = hindsight_constant(sweep)
    # the stored constant's row is its sweep run (same scenarios, deterministic): no second run
    chosen = []
    if choice is not None:
        chosen = [dataclasses.replace(sweep_row(sweep, choice.preload_n),
                                      name=f"constant {choice.preload_n:.0f} N (validation choice)")]
    results = results[:len(model_dirs)] + chosen + results[len(model_dirs):] + [hindsight]
    out = Path(out_dir or (model_dirs[0] if model_dirs else "evaluation"))
    definition = (" (the registered BearingPreload-v0)" if tier == DEFAULT_TIER and episode_steps == EPISODE_STEPS
                  else " (not the benchmark definition)")
    if choice is None:
        best = f"no validation-chosen constant is stored for tier {tier} (`{rebuild_command(tier)}` builds it)"
    else:
        problems = choice.protocol_problems()
        best = (f"best constant preload chosen on the validation seeds, not on these: {choice.describe()}"
                + (f" (provisional: {'; '.join(problems)})" if problems else ""))
    header = (f"Held-out seeds {seed}..{seed + episodes - 1}, {episodes} episodes of {episode_steps} control "
              f"intervals (20 ms) each, tier {tier}{definition}; {best}. The last row picks, for each scenario, "
              f"the best constant of a {grid_step_n:g} N grid over {grid[0]:.0f}-{grid[-1]:.0f} N "
              f"({len(grid)} preloads) with hindsight.")
    reference = chosen[0].name if chosen else hindsight.name
    written = write_report(results, out, header, reference=reference, first_seed=seed)
    if verbose:
        print((out / "evaluation.md").read_text())
        print(f"wrote {', '.join(p.name for p in written)} in {out.resolve()}", flush=True)
    return results


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="python -m agents.evaluate", description=__doc__.splitlines()[0])
    ap.add_argument("--model", nargs="+", help="directories written by train.py, evaluated side by side "
                    "(omit to evaluate the baselines only)")
    ap.add_argument("--pretrained", action="store_true",
                    help="add the shipped policies of agents/pretrained/<algo>/ (written to runs/evaluation_pretrained/ "
                         "unless --out or --model says where); their normalised scores against the stored references: "
                         "python -m agents.leaderboard --pretrained --stored-references")
    ap.add_argument("--episodes", type=int, default=20)
    ap.add_argument("--episode-steps", type=int, default=EPISODE_STEPS,
                    help="control intervals per episode (default: the benchmark's horizon)")
    ap.add_argument("--seed", type=int, default=TEST_SEED)
    ap.add_argument("--tier", choices=TIER_NAMES, default=DEFAULT_TIER)
    ap.add_argument("--out", help="output directory (default: the first model directory; with --pretrained alone "
                                  "runs/evaluation_pretrained/; with neither, evaluation/)")
    return ap


def main(argv: list[str] | None = None) -> None:
    ap = build_parser()
    args = ap.parse_args(argv)
    if args.episodes < 2:
        ap.error("--episodes must be >= 2 (a confidence interval needs two episodes)")
    models: list[str | Path] = list(args.model or [])
    out = args.out
    if args.pretrained:
        models += shipped_dirs()
        if out is None and not args.model:      # never write reports into the shipped policies' directories
            out = runs_dir("evaluation_pretrained")
    evaluate(models or None, args.episodes, args.seed, args.episode_steps, out, tier=args.tier)


if __name__ == "__main__":
    main()
