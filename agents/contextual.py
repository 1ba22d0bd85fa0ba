"""The contextual constant: one preload per episode, predicted from its first observation.

If a learned closed-loop policy does no better than this, the task is not closed-loop. From the
first observation of an episode (the settled start: vibration features, speed, the offsets that
carry the radial load and the clearance) a ridge regression (:mod:`agents.ridge`) predicts the
return of every constant preload of a 100 N grid over the actuator's whole range
(``agents.protocol.CONTEXTUAL_GRID_STEP_N``); the policy holds the constant with the highest
predicted return for the whole episode. Features: the observation standardised with the fit
data's mean and spread, optionally with the squares of those standardised values
(``squares="auto"`` keeps whichever form has the smaller leave-one-out error).

It is fitted on training-range scenarios only (``agents.protocol.CONTEXTUAL_FIT_SEED`` on, in
TRAIN): every grid constant runs every fit episode, one batch.

    python -m agents.contextual --tier transient --episodes 100    # -> agents/data/contextual_transient.json

Cost: (grid size) x episodes x episode length environment steps: 18 x 100 x 150 = 270,000 for
the protocol's fit (``CONTEXTUAL_FIT_EPISODES``): 26 min on the 2-core development machine for
the ``transient`` tier (``meta.wall_s`` of agents/data/contextual_transient.json). The fit itself
takes milliseconds.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path
from typing import Any

import numpy as np

from bearing_gym.benchmark import DEFAULT_TIER, EPISODE_STEPS, TIER_NAMES

from .evaluate import constant_sweep
from .policies import Policy
from .protocol import (CONTEXTUAL_FIT_EPISODES, CONTEXTUAL_FIT_SEED, CONTEXTUAL_GRID_STEP_N, TRAIN, episodes_for_tier,
                       preload_grid)
from .ridge import RidgeRegression

__all__ = ["ContextualConstant", "contextual_path", "fit_episodes", "collect_fit_data", "fit_contextual", "main"]

DATA_DIR = Path(__file__).with_name("data")
#: the fewest fit episodes (the ridge's leave-one-out choice of penalty needs a few rows); also
#: what a deterministic tier's fit runs (its episodes are copies of one)
MIN_FIT_EPISODES = 3


def contextual_path(tier: str, directory: str | Path = DATA_DIR) -> Path:
    """Where the fitted contextual constant of ``tier`` is stored."""
    return Path(directory) / f"contextual_{tier}.json"


def fit_episodes(tier: str) -> int:
    """The protocol's number of fit episodes on ``tier`` (MIN_FIT_EPISODES on a deterministic tier)."""
    return episodes_for_tier(tier, CONTEXTUAL_FIT_EPISODES, minimum=MIN_FIT_EPISODES)


def fit_command(tier: str, episodes: int | None = None) -> str:
    """The command that fits ``tier``'s contextual constant (by default on the protocol's episodes)."""
    if episodes is None:
        episodes = fit_episodes(tier)
    return f"python -m agents.contextual --tier {tier} --episodes {episodes}"


class ContextualConstant(Policy):
    """Holds, for each episode, the grid constant whose return the ridge map predicts highest
    from the episode's first observation (SB3 ``predict`` interface; the state is the held
    preload per env, chosen again where ``episode_start`` is True or the state is None)."""

    def __init__(self, ridge: RidgeRegression, grid_n: tuple[float, ...], obs_mean: np.ndarray,
                 obs_scale: np.ndarray, squares: bool, meta: dict[str, Any] | None = None, actuator=None):
        super().__init__(actuator)
        if ridge.coef.shape[1] != len(grid_n):
            raise ValueError(f"the ridge map predicts {ridge.coef.shape[1]} returns for {len(grid_n)} grid preloads")
        self.ridge, self.grid_n = ridge, tuple(float(p) for p in grid_n)
        self.obs_mean = np.asarray(obs_mean, dtype=np.float64)
        self.obs_scale = np.asarray(obs_scale, dtype=np.float64)
        self.squares = bool(squares)
        self.meta = dict(meta or {})
        self.name = "contextual constant (first observation)"

    @staticmethod
    def _features(obs: np.ndarray, mean: np.ndarray, scale: np.ndarray, squares: bool) -> np.ndarray:
        z = (np.asarray(obs, dtype=np.float64) - mean) / scale
        return np.hstack([z, z * z]) if squares else z

    def predict_returns(self, obs: np.ndarray) -> np.ndarray:
        """Predicted return (n, grid) of every grid constant for first observations (n, obs)."""
        return self.ridge.predict(self._features(self._batch(obs), self.obs_mean, self.obs_scale, self.squares))

    def choose(self, obs: np.ndarray) -> np.ndarray:
        """The preload (N) to hold for episodes starting with these observations."""
        return np.asarray(self.grid_n)[np.argmax(self.predict_returns(obs), axis=1)]

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        o = self._batch(obs)
        n = o.shape[0]
        held = np.full(n, np.nan) if state is None else np.array(state, dtype=np.float64).reshape(n)
        new = np.isnan(held)
        if episode_start is not None:
            new |= np.asarray(episode_start, dtype=bool).reshape(n)
        if new.any():
            held[new] = self.choose(o[new])
        return self.preload_to_action(held), held

    # -- fitting and storage ---------------------------------------------------------------------
    @classmethod
    def fit(cls, first_obs: np.ndarray, returns: np.ndarray, grid_n: tuple[float, ...],
            squares: bool | str = "auto", meta: dict[str, Any] | None = None) -> "ContextualConstant":
        """Fit on first observations (episodes, obs) and the return of every grid constant in
        each episode (episodes, grid). ``squares``: True, False or "auto" (the smaller
        leave-one-out error decides)."""
        first_obs = np.asarray(first_obs, dtype=np.float64)
        returns = np.asarray(returns, dtype=np.float64)
        if returns.ndim != 2 or returns.shape != (first_obs.shape[0], len(grid_n)):
            raise ValueError(f"returns must be (episodes, grid) = ({first_obs.shape[0]}, {len(grid_n)}), "
                             f"got {returns.shape}")
        mean = first_obs.mean(axis=0)
        spread = first_obs.std(axis=0)
        scale = np.where(spread > 1e-12, spread, 1.0)
        if squares not in (True, False, "auto"):
            raise ValueError(f"squares must be True, False or 'auto', got {squares!r}")
        forms = (False, True) if squares == "auto" else (bool(squares),)
        fits = {sq: RidgeRegression.fit(cls._features(first_obs, mean, scale, sq), returns) for sq in forms}
        chosen = min(fits, key=lambda sq: fits[sq].loo_rmse)
        info = dict(meta or {})
        info["loo_rmse"] = {("squares" if sq else "linear"): f.loo_rmse for sq, f in fits.items()}
        info["fit_episodes"] = int(first_obs.shape[0])
        return cls(fits[chosen], tuple(grid_n), mean, scale, chosen, info)

    def to_json(self) -> dict:
        """Everything :meth:`load` needs, as JSON types."""
        return {"grid_n": list(self.grid_n), "squares": self.squares, "obs_mean": self.obs_mean.tolist(),
                "obs_scale": self.obs_scale.tolist(), "ridge": self.ridge.to_json(), "meta": self.meta}

    def save(self, path: str | Path) -> None:
        """Write the fitted policy to ``path`` (JSON)."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(self.to_json(), indent=1) + "\n")

    @classmethod
    def load(cls, path: str | Path) -> "ContextualConstant":
        """A fitted contextual constant; raises FileNotFoundError with the command that fits it."""
        path = Path(path)
        if not path.exists():
            tier = path.stem.removeprefix("contextual_")
            raise FileNotFoundError(f"no fitted contextual constant at {path}; fit it with `{fit_command(tier)}`")
        d = json.loads(path.read_text())
        return cls(RidgeRegression.from_json(d["ridge"]), tuple(d["grid_n"]), np.array(d["obs_mean"]),
                   np.array(d["obs_scale"]), bool(d["squares"]), d.get("meta"))


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
            "grid_step_n": grid_step_n, "wall_s": time.time() - t0}
    return ContextualConstant.fit(first_obs, returns, grid, squares=squares, meta=meta)


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(description="Fit the contextual constant preload on training-range scenarios.")
    ap.add_argument("--tier", choices=TIER_NAMES, default=DEFAULT_TIER)
    ap.add_argument("--episodes", type=int,
                    help=f"training-range fit episodes (default: the protocol's {CONTEXTUAL_FIT_EPISODES}; "
                         f"{MIN_FIT_EPISODES} on a deterministic tier, where every seed gives the same episode)")
    ap.add_argument("--seed", type=int, default=CONTEXTUAL_FIT_SEED, help="first fit seed (in TRAIN)")
    ap.add_argument("--episode-steps", type=int, default=EPISODE_STEPS)
    ap.add_argument("--grid-step", type=float, default=CONTEXTUAL_GRID_STEP_N, help="grid of constants (N)")
    ap.add_argument("--squares", choices=("auto", "yes", "no"), default="auto",
                    help="add the squared standardised observation to the features (auto: by leave-one-out error)")
    ap.add_argument("--out", help="output JSON (default agents/data/contextual_<tier>.json)")
    return ap


def main(argv: list[str] | None = None) -> None:
    a = build_parser().parse_args(argv)
    if a.episodes is None:
        a.episodes = fit_episodes(a.tier)
    grid = preload_grid(a.grid_step)
    print(f"contextual fit, tier {a.tier}: {len(grid)} constants x {a.episodes} training-range episodes "
          f"(seeds {a.seed}..{a.seed + a.episodes - 1}) x {a.episode_steps} steps = "
          f"{len(grid) * a.episodes * a.episode_steps:,} env steps", flush=True)
    squares = {"auto": "auto", "yes": True, "no": False}[a.squares]
    pol = fit_contextual(a.tier, a.episodes, a.seed, a.episode_steps, a.grid_step, squares,
                         progress=f"contextual fit: {len(grid)} constants x {a.episodes} episodes")
    out = Path(a.out) if a.out else contextual_path(a.tier)
    pol.save(out)
    print(f"wrote {out}: {'squares' if pol.squares else 'linear'} features, leave-one-out RMSE "
          f"{pol.ridge.loo_rmse:.2f} (return units), {pol.meta['wall_s'] / 60:.1f} min")


if __name__ == "__main__":
    main()
