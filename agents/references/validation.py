"""The leaderboard's references, each computed on the seeds the protocol gives it.

(a) The validation-chosen best constant: the constant preload (50 N grid over the actuator's
    whole range) with the best mean return on the *validation* seeds of a tier
    (:func:`choose_validation_constant`), stored in ``agents/data/reference_constants.json``
    (:mod:`agents.references.store`). Evaluation reads the stored choice; nothing chooses on test
    episodes. Rebuild a tier's entry:

        python -m agents.references --tier transient --episodes 50

    The store keeps every candidate's return on every validation episode too: the chosen
    constant and the hindsight best constant per validation episode are 0 and 1 of the
    validation score of train.py's learning curves.
    Cost: 35 constants x episodes x 150 steps (262,500 env steps for the protocol's 50
    episodes).
(b) The hindsight best constant per episode on the same 50 N grid (:func:`hindsight_reference`:
    :func:`agents.evaluation.episodes.constant_sweep` + :func:`agents.evaluation.episodes.hindsight_constant`).
(c) The contextual constant, one preload per episode from its first observation
    (:class:`agents.policies.contextual.ContextualConstant`, fitted on training-range scenarios).
(d) The upper reference, the full-horizon planner with the true simulator
    (:mod:`agents.policies.planner`), run per test episode by :mod:`agents.references.planner_runs`.

The oracle (:class:`agents.policies.oracle.MapOracle`) is the fifth reference; it needs no fitting here.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from bearing_gym.task import EPISODE_STEPS
from bearing_gym.envs.provenance import kernel_hash

from agents.policies.contextual import ContextualConstant
from agents.evaluation.result import EvalResult
from agents.evaluation.episodes import constant_sweep, hindsight_constant
from agents.references.sweep_cli import parse_sweep, sweep_parser
from agents.protocol import (HINDSIGHT_GRID_STEP_N, VALIDATION, VALIDATION_CONSTANT_EPISODES, VALIDATION_GRID_STEP_N,
                             VALIDATION_RULE, preload_grid, validation_seeds)
from agents.references.store import STORE_PATH, ValidationChoice, rule_choice, save_choice, validation_episodes


__all__ = ["choose_validation_constant", "repicked", "rechoose", "hindsight_grid", "hindsight_reference", "ContextualConstant", "main"]


def choose_validation_constant(tier: str, episodes: int = VALIDATION_CONSTANT_EPISODES,
                               seed: int = VALIDATION.start, episode_steps: int = EPISODE_STEPS,
                               grid_step_n: float = VALIDATION_GRID_STEP_N, progress: str | None = None,
                               **run_kw: Any) -> ValidationChoice:
    """The grid constant with the best mean return on validation episodes seed ..
    seed+episodes-1 of ``tier`` (raises before running anything if a seed is not a validation
    seed). ``run_kw`` go to :func:`agents.evaluation.episodes.run_policies`."""
    seeds = validation_seeds(episodes, seed)
    grid = preload_grid(grid_step_n)
    t0 = time.time()
    sweep = constant_sweep(grid, episodes, seeds.start, episode_steps,
                           env_kwargs={"tier": tier}, progress=progress, **run_kw)
    means = [float(np.mean(r.returns)) for r in sweep]
    returns = tuple(tuple(float(x) for x in r.returns) for r in sweep)
    return ValidationChoice(tier=tier, preload_n=grid[rule_choice(VALIDATION_RULE, grid, means, returns, tier)],
                            rule=VALIDATION_RULE, seeds=tuple(seeds),
                            grid_step_n=float(grid_step_n), grid_n=grid, mean_returns=tuple(means),
                            episode_steps=episode_steps, wall_s=time.time() - t0,
                            episode_returns=returns,
                            kernel_hash=kernel_hash())


def repicked(choice: ValidationChoice, rule: str = VALIDATION_RULE) -> ValidationChoice:
    """``choice`` picked again by ``rule`` (default: the protocol's) from its stored per-episode
    validation returns, nothing run: a new protocol's rule on the same validation sweep."""
    import dataclasses
    return dataclasses.replace(choice, preload_n=choice.preload_for_rule(rule), rule=rule)


def rechoose(tier: str, store: Path = STORE_PATH, rule: str = VALIDATION_RULE) -> ValidationChoice:
    """The stored choice of ``tier`` :func:`repicked` by ``rule`` and stored; returns it."""
    from agents.references.store import load_choice
    new = repicked(load_choice(tier, store), rule)
    save_choice(new, store)
    return new


def hindsight_grid(grid_step_n: float = HINDSIGHT_GRID_STEP_N, extra_n: Sequence[float] = ()) -> tuple[float, ...]:
    """The constants :func:`hindsight_reference` sweeps, in its order."""
    return tuple(sorted(set(preload_grid(grid_step_n)) | {float(p) for p in extra_n}))


def hindsight_reference(tier: str, episodes: int, seed: int, episode_steps: int = EPISODE_STEPS,
                        grid_step_n: float = HINDSIGHT_GRID_STEP_N, extra_n: Sequence[float] = (),
                        progress: str | None = None, **run_kw: Any) -> tuple[EvalResult, list[EvalResult]]:
    """(the hindsight best constant per episode, the whole sweep) on episodes seed ..
    seed+episodes-1: every constant of the grid (plus ``extra_n``, e.g. a stored choice made on
    another grid) on every episode, one batch."""
    grid = hindsight_grid(grid_step_n, extra_n)
    sweep = constant_sweep(grid, episodes, seed, episode_steps, env_kwargs={"tier": tier},
                           progress=progress, **run_kw)
    return hindsight_constant(sweep), sweep


# -- the command that rebuilds the stored validation choice ----------------------------------------
def build_parser() -> argparse.ArgumentParser:
    ap = sweep_parser("python -m agents.references", "Choose a tier's best constant preload on validation seeds and store it in "
                      "agents/data/reference_constants.json.",
                      episodes_help=f"validation episodes (default: the protocol's {VALIDATION_CONSTANT_EPISODES}; "
                                    "1 on a deterministic tier, where every seed gives the same episode)",
                      seed=VALIDATION.start, seed_help="first validation seed", grid_step_n=VALIDATION_GRID_STEP_N)
    ap.add_argument("--store", default=str(STORE_PATH), help="the JSON store (default: %(default)s)")
    ap.add_argument("--rechoose", action="store_true",
                    help=f"pick the stored choice again by the protocol's rule ({VALIDATION_RULE}) from its stored "
                         "per-episode returns; runs nothing")
    return ap


def main(argv: list[str] | None = None) -> None:
    a, grid = parse_sweep(build_parser(), argv, validation_episodes, "validation constant", "validation")
    if a.rechoose:
        choice = rechoose(a.tier, Path(a.store))
        print(f"{a.store}: tier {a.tier} -> {choice.describe()} (rule {choice.rule}, from the stored returns)")
        return
    choice = choose_validation_constant(a.tier, a.episodes, a.seed, a.episode_steps, a.grid_step,
                                        progress=f"validation sweep: {len(grid)} constants x {a.episodes} episodes")
    save_choice(choice, Path(a.store))
    problems = choice.protocol_problems()
    print(f"{a.store}: tier {a.tier} -> {choice.describe()}, {choice.wall_s / 60:.1f} min"
          + (f"; not the protocol's: {'; '.join(problems)}" if problems else ""))


if __name__ == "__main__":
    main()
