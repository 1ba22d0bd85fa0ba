"""The contextual constant: one preload per episode, predicted from its first observation.

If a learned closed-loop policy does no better than this, the task is not closed-loop. From the
first observation of an episode (the settled start: vibration features, speed, the offsets that
carry the radial load and the clearance) a ridge regression (:mod:`agents.policies.ridge`) predicts the
return of every constant preload of a 100 N grid over the actuator's whole range
(``agents.protocol.CONTEXTUAL_GRID_STEP_N``); the policy holds the constant with the highest
predicted return for the whole episode. Features: the observation standardised with the fit
data's mean and spread, optionally with the squares of those standardised values
(``squares="auto"`` keeps whichever form has the smaller leave-one-out error). It is fitted on
training-range scenarios only (:mod:`agents.references.contextual_fit`) and stored in
``agents/data/contextual_<tier>.json``.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from agents.policies.scripted import Policy
from agents.protocol import CONTEXTUAL_FIT_EPISODES, episodes_for_tier
from agents.policies.ridge import RidgeRegression
from agents.paths import DATA_DIR


__all__ = ["ContextualConstant", "contextual_path", "fit_episodes", "fit_command", "MIN_FIT_EPISODES"]




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
    return f"python -m agents.references.contextual_fit --tier {tier} --episodes {episodes}"


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
