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
(d) The MPC with the true simulator (:mod:`agents.policies.mpc`) on the first
    ``agents.protocol.MPC_EPISODES`` test scenarios (:func:`run_mpc`): about
    9 candidates x 10 intervals / 5 = 18 simulated intervals per real one; measured at the
    env's 25 us step, 42 s per 150-step episode (two episodes in parallel on 2 cores).

The oracle (:class:`agents.policies.oracle.MapOracle`) is the fifth reference; it needs no fitting here.
"""

from __future__ import annotations

import argparse
import time
from multiprocessing import get_context
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from bearing_gym.task import EPISODE_STEPS
from bearing_gym.envs.reward import REWARD_TERMS
from bearing_gym.envs.provenance import kernel_hash

from agents.policies.contextual import ContextualConstant
from agents.evaluation.result import EvalResult
from agents.evaluation.episodes import constant_sweep, hindsight_constant
from agents.policies.mpc import RecedingHorizonMPC
from agents.references.sweep_cli import parse_sweep, sweep_parser
from agents.protocol import HINDSIGHT_GRID_STEP_N, VALIDATION, VALIDATION_CONSTANT_EPISODES, VALIDATION_GRID_STEP_N, preload_grid, validation_seeds
from agents.references.store import STORE_PATH, ValidationChoice, save_choice, validation_episodes


__all__ = ["choose_validation_constant", "hindsight_reference", "run_mpc", "ContextualConstant", "main"]


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
    return ValidationChoice(tier=tier, preload_n=grid[int(np.argmax(means))], seeds=tuple(seeds),
                            grid_step_n=float(grid_step_n), grid_n=grid, mean_returns=tuple(means),
                            episode_steps=episode_steps, wall_s=time.time() - t0,
                            episode_returns=tuple(tuple(float(x) for x in r.returns) for r in sweep),
                            kernel_hash=kernel_hash())


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


# -- (d) the MPC reference ------------------------------------------------------------------------
def _mpc_episode(job: tuple) -> dict:
    """One MPC episode (a worker: module level, so a spawned process can run it)."""
    tier, seed, episode_steps, candidates, horizon, replan_every, single_thread = job
    if single_thread:
        import numba
        numba.set_num_threads(1)                 # one process per core
    from bearing_gym.envs import BearingPreloadEnv
    env = BearingPreloadEnv(tier=tier, episode_steps=episode_steps)
    mpc = RecedingHorizonMPC(candidates_n=tuple(candidates), horizon=horizon, replan_every=replan_every)
    t0 = time.time()
    out = mpc.run_episode(env, seed=seed)
    return {"seed": seed, "return": out.episode_return, "terms": out.terms, "qp": out.quasi_periodic_fraction,
            "terminated": out.terminated, "preload": float(np.mean(out.preload_n)) if out.preload_n else np.nan,
            "vibration_um": out.vibration_um, "wall_s": time.time() - t0}


def run_mpc(tier: str, seeds: Sequence[int], episode_steps: int = EPISODE_STEPS,
            mpc: RecedingHorizonMPC | None = None, processes: int = 1,
            progress: str | None = None) -> tuple[EvalResult, list[float]]:
    """(the MPC reference's results on the scenarios of ``seeds``, each episode's wall time).
    With ``processes`` > 1 the episodes run in that many spawned processes, one numba thread
    each."""
    mpc = mpc or RecedingHorizonMPC()
    if processes < 1:
        raise ValueError(f"processes must be >= 1, got {processes}")
    jobs = [(tier, int(s), episode_steps, mpc.candidates_n, mpc.horizon, mpc.replan_every, processes > 1)
            for s in seeds]
    rows: list[dict] = []

    def report(row: dict) -> None:
        rows.append(row)
        if progress:
            print(f"{progress}: episode {len(rows)}/{len(jobs)} (seed {row['seed']}) return "
                  f"{row['return']:.2f}, {row['wall_s']:.0f} s", flush=True)
    if processes == 1:
        for job in jobs:
            report(_mpc_episode(job))
    else:
        with get_context("spawn").Pool(processes) as pool:
            for row in pool.imap(_mpc_episode, jobs):
                report(row)
    terms = {k: np.array([r["terms"].get(k, 0.0) for r in rows]) for k in REWARD_TERMS}
    result = EvalResult(f"MPC (true simulator, horizon {mpc.horizon}, {len(mpc.candidates_n)} candidates)",
                        np.array([r["return"] for r in rows]), terms, np.array([r["qp"] for r in rows]),
                        np.array([r["preload"] for r in rows]), terminated=np.array([r["terminated"] for r in rows]),
                        vibration_um=np.array([r["vibration_um"] for r in rows]))
    return result, [r["wall_s"] for r in rows]


# -- the command that rebuilds the stored validation choice ----------------------------------------
def build_parser() -> argparse.ArgumentParser:
    ap = sweep_parser("python -m agents.references", "Choose a tier's best constant preload on validation seeds and store it in "
                      "agents/data/reference_constants.json.",
                      episodes_help=f"validation episodes (default: the protocol's {VALIDATION_CONSTANT_EPISODES}; "
                                    "1 on a deterministic tier, where every seed gives the same episode)",
                      seed=VALIDATION.start, seed_help="first validation seed", grid_step_n=VALIDATION_GRID_STEP_N)
    ap.add_argument("--store", default=str(STORE_PATH), help="the JSON store (default: %(default)s)")
    return ap


def main(argv: list[str] | None = None) -> None:
    a, grid = parse_sweep(build_parser(), argv, validation_episodes, "validation constant", "validation")
    choice = choose_validation_constant(a.tier, a.episodes, a.seed, a.episode_steps, a.grid_step,
                                        progress=f"validation sweep: {len(grid)} constants x {a.episodes} episodes")
    save_choice(choice, Path(a.store))
    problems = choice.protocol_problems()
    print(f"{a.store}: tier {a.tier} -> {choice.describe()}, {choice.wall_s / 60:.1f} min"
          + (f"; not the protocol's: {'; '.join(problems)}" if problems else ""))


if __name__ == "__main__":
    main()
