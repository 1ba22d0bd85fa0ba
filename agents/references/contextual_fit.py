"""Fitting the contextual constant (:class:`agents.policies.contextual.ContextualConstant`): every
constant of its grid runs every fit episode (training-range scenarios from
``agents.protocol.CONTEXTUAL_FIT_SEED`` on, one batch), and a ridge regression learns each
constant's return from the episode's first observation.

    python -m agents.references.contextual_fit --tier transient --episodes 100    # -> agents/data/contextual_transient.json

Cost: (grid size) x episodes x episode length environment steps: 18 x 100 x 150 = 270,000 for
the protocol's fit (``CONTEXTUAL_FIT_EPISODES``): 26 min on the 2-core development machine for
the ``transient`` tier (``meta.wall_s`` of agents/data/contextual_transient.json). The fit itself
takes milliseconds.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from bearing_gym.task import EPISODE_STEPS
from bearing_gym.envs.provenance import kernel_hash

from agents.evaluation.episodes import constant_sweep
from agents.references.sweep_cli import parse_sweep, sweep_parser
from agents.protocol import CONTEXTUAL_FIT_EPISODES, CONTEXTUAL_FIT_SEED, CONTEXTUAL_GRID_STEP_N, TRAIN, preload_grid
from agents.policies.contextual import ContextualConstant, MIN_FIT_EPISODES, contextual_path, fit_episodes


def collect_fit_data(tier: str, episodes: int, seed: int = CONTEXTUAL_FIT_SEED, episode_steps: int = EPISODE_STEPS,
                     grid_step_n: float = CONTEXTUAL_GRID_STEP_N, progress: str | None = None,
                     **run_kw) -> tuple[np.ndarray, np.ndarray, tuple[float, ...]]:
    """(first observations (episodes, obs), returns (episodes, grid), grid) of every grid constant
    on the training-range scenarios seed .. seed+episodes-1 (raises before running anything if
    one is outside agents.protocol.TRAIN)."""
    if episodes < MIN_FIT_EPISODES:
        raise ValueError(f"the contextual fit needs at least {MIN_FIT_EPISODES} episodes, got {episodes}")
    if seed not in TRAIN or seed + episodes - 1 not in TRAIN:
        raise ValueError(f"the contextual fit must use training seeds [{TRAIN.start}, {TRAIN.stop}); "
                         f"got {seed}..{seed + episodes - 1}")
    grid = preload_grid(grid_step_n)
    sweep = constant_sweep(grid, episodes, seed, episode_steps, env_kwargs={"tier": tier}, progress=progress, **run_kw)
    return sweep[0].first_obs.astype(np.float64), np.array([r.returns for r in sweep]).T, grid


def fit_contextual(tier: str, episodes: int = CONTEXTUAL_FIT_EPISODES, seed: int = CONTEXTUAL_FIT_SEED,
                   episode_steps: int = EPISODE_STEPS, grid_step_n: float = CONTEXTUAL_GRID_STEP_N,
                   squares: bool | str = "auto", progress: str | None = None, **run_kw) -> ContextualConstant:
    """Collect the fit data of ``tier`` and fit the contextual constant (not saved)."""
    t0 = time.time()
    first_obs, returns, grid = collect_fit_data(tier, episodes, seed, episode_steps, grid_step_n, progress, **run_kw)
    meta = {"tier": tier, "seeds": [seed, seed + episodes - 1], "episode_steps": episode_steps,
            "grid_step_n": grid_step_n, "wall_s": time.time() - t0, "kernel_hash": kernel_hash()}
    return ContextualConstant.fit(first_obs, returns, grid, squares=squares, meta=meta)


def build_parser() -> argparse.ArgumentParser:
    ap = sweep_parser("python -m agents.references.contextual_fit", "Fit the contextual constant preload on training-range scenarios.",
                      episodes_help=f"training-range fit episodes (default: the protocol's {CONTEXTUAL_FIT_EPISODES}; "
                                    f"{MIN_FIT_EPISODES} on a deterministic tier, where every seed gives the same episode)",
                      seed=CONTEXTUAL_FIT_SEED, seed_help="first fit seed (in TRAIN)", grid_step_n=CONTEXTUAL_GRID_STEP_N)
    ap.add_argument("--squares", choices=("auto", "yes", "no"), default="auto",
                    help="add the squared standardised observation to the features (auto: by leave-one-out error)")
    ap.add_argument("--out", help="output JSON (default agents/data/contextual_<tier>.json)")
    return ap


def main(argv: list[str] | None = None) -> None:
    a, grid = parse_sweep(build_parser(), argv, fit_episodes, "contextual fit", "training-range")
    squares = {"auto": "auto", "yes": True, "no": False}[a.squares]
    pol = fit_contextual(a.tier, a.episodes, a.seed, a.episode_steps, a.grid_step, squares,
                         progress=f"contextual fit: {len(grid)} constants x {a.episodes} episodes")
    out = Path(a.out) if a.out else contextual_path(a.tier)
    pol.save(out)
    print(f"wrote {out}: {'squares' if pol.squares else 'linear'} features, leave-one-out RMSE "
          f"{pol.ridge.loo_rmse:.2f} (return units), {pol.meta['wall_s'] / 60:.1f} min")


if __name__ == "__main__":
    main()
