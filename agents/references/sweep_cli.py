"""The command line the two sweeps share: the validation constant (:mod:`.validation`) and the
contextual fit (:mod:`.contextual_fit`) both run a grid of constant preloads on a tier's
episodes from a first seed, and say what that costs before they start."""

from __future__ import annotations

import argparse
from typing import Callable

import numpy as np

from bearing_gym.task import DEFAULT_TIER, EPISODE_STEPS, TIER_NAMES

from agents.protocol import preload_grid


def sweep_parser(prog: str, description: str, *, episodes_help: str, seed: int, seed_help: str,
                 grid_step_n: float) -> argparse.ArgumentParser:
    """--tier, --episodes, --seed, --episode-steps and --grid-step, with these defaults."""
    ap = argparse.ArgumentParser(prog=prog, description=description)
    ap.add_argument("--tier", choices=TIER_NAMES, default=DEFAULT_TIER)
    ap.add_argument("--episodes", type=int, help=episodes_help)
    ap.add_argument("--seed", type=int, default=seed, help=seed_help)
    ap.add_argument("--episode-steps", type=int, default=EPISODE_STEPS)
    ap.add_argument("--grid-step", type=float, default=grid_step_n, help="grid of constants (N)")
    return ap


def parse_sweep(ap: argparse.ArgumentParser, argv: list[str] | None, default_episodes: Callable[[str], int],
                what: str, episodes_kind: str) -> tuple[argparse.Namespace, np.ndarray]:
    """Parse, fill in the tier's default number of episodes, print the sweep's size; returns the
    arguments and the grid of constants."""
    a = ap.parse_args(argv)
    if a.episodes is None:
        a.episodes = default_episodes(a.tier)
    grid = preload_grid(a.grid_step)
    print(f"{what}, tier {a.tier}: {len(grid)} constants x {a.episodes} {episodes_kind} episodes "
          f"(seeds {a.seed}..{a.seed + a.episodes - 1}) x {a.episode_steps} steps = "
          f"{len(grid) * a.episodes * a.episode_steps:,} env steps", flush=True)
    return a, grid
