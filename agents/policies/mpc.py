"""Receding-horizon control with the true simulator as its model: the short-horizon controller of
the tier-design study (:mod:`agents.references.tier_gap`; the leaderboard's upper reference is
the full-horizon planner, :mod:`agents.policies.planner`).

At every ``replan_every``-th control interval the controller copies the env (its full state:
physics, actuator, scenario schedule, sensor and random generators; ``copy.deepcopy`` of a
:class:`~bearing_gym.envs.BearingPreloadEnv` mid-episode continues identically), holds each
candidate set-point for ``horizon`` intervals in a copy, and applies the candidate whose copy
earned the most reward. It sees the future of the scenario (the events to come), which no
policy can, and it is expensive: ``len(candidates_n) * horizon / replan_every`` simulated
intervals per real one.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field

import numpy as np


__all__ = ["RecedingHorizonMPC", "EpisodeOutcome", "run_episode", "run_constant", "DEFAULT_CANDIDATES_N"]

DEFAULT_CANDIDATES_N = tuple(float(p) for p in np.linspace(300.0, 2000.0, 9))


@dataclass
class EpisodeOutcome:
    """One episode of a controller: return, terms, the preload trace and the mean
    non-synchronous vibration amplitude (um) over the intervals it ran."""

    episode_return: float
    terms: dict[str, float]
    quasi_periodic_fraction: float
    terminated: bool
    preload_n: list[float] = field(default_factory=list)
    vibration_um: float = 0.0


def _hold(env, action: np.ndarray, steps: int) -> float:
    total = 0.0
    for _ in range(steps):
        _, r, term, trunc, _ = env.step(action)
        total += float(r)
        if term or trunc:
            break
    return total


@dataclass
class RecedingHorizonMPC:
    candidates_n: tuple[float, ...] = DEFAULT_CANDIDATES_N
    horizon: int = 10
    replan_every: int = 5

    def plan(self, env) -> np.ndarray:
        """The best candidate's action for the env (single BearingPreloadEnv, unwrapped) now."""
        best, best_action = -np.inf, None
        for p in self.candidates_n:
            action = np.array([env.actuator.action_for(p)], dtype=np.float32)
            look_ahead = min(self.horizon, max(env.episode_steps - env.steps_taken, 1))   # not past the end
            score = _hold(copy.deepcopy(env), action, look_ahead)
            if score > best:
                best, best_action = score, action
        return best_action

    def run_episode(self, env, seed: int | None = None, options: dict | None = None) -> EpisodeOutcome:
        """One episode of the env (single, unwrapped) under receding-horizon control."""
        chosen: list[np.ndarray] = []

        def action(k: int) -> np.ndarray:
            if k % self.replan_every == 0:
                chosen[:] = [self.plan(env)]
            return chosen[0]

        return run_episode(env, action, seed, options)


def run_episode(env, action_at, seed: int | None = None, options: dict | None = None) -> EpisodeOutcome:
    """One episode with the action ``action_at(k)`` at interval k (the env: single, unwrapped)."""
    env.reset(seed=seed, options=options)
    out = EpisodeOutcome(0.0, {}, 0.0, False)
    qp = 0
    vibration = 0.0
    for k in range(env.episode_steps):
        _, r, term, _, info = env.step(action_at(k))
        _accumulate(out, r, info)
        qp += info["quasi_periodic"]
        vibration += info["nonsync_rms_um"]
        if term:
            out.terminated = True
            break
    out.quasi_periodic_fraction = qp / env.episode_steps
    out.vibration_um = vibration / max(len(out.preload_n), 1)
    return out


def _accumulate(out: EpisodeOutcome, r: float, info: dict) -> None:
    out.episode_return += float(r)
    for k, v in info.items():
        if k.startswith("reward_"):
            out.terms[k[7:]] = out.terms.get(k[7:], 0.0) + float(v)
    out.preload_n.append(float(info["preload_n"]))


def run_constant(env, preload_n: float, seed: int | None = None, options: dict | None = None) -> EpisodeOutcome:
    """One episode at a constant set-point."""
    action = np.array([env.actuator.action_for(preload_n)], dtype=np.float32)
    return run_episode(env, lambda k: action, seed, options)
