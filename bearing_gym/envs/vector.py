"""Native vector environment (one batched numba kernel, prange over envs)."""

from __future__ import annotations

from typing import Any, Sequence

import gymnasium as gym
import numba
import numpy as np
from gymnasium import spaces
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv

from bearing_gym.params import BearingParams

from .common import (DEFAULTS, check_actions, configure, measurement, observe, reset_envs,
                     step_outputs)

__all__ = ["BearingPreloadVectorEnv"]


class BearingPreloadVectorEnv(VectorEnv):
    """``num_envs`` copies of :class:`~bearing_gym.envs.BearingPreloadEnv` stepped together by
    one numba kernel (``prange`` over environments, ``num_threads`` worker threads).

    Same arguments as the single env, plus ``num_envs``, ``max_episode_steps`` (truncation; the
    single env gets it from its TimeLimit) and ``num_threads`` (default: numba's). Autoreset mode
    ``NEXT_STEP``: the step after an episode ends resets that env and returns its first
    observation with reward 0. ``reset(seed=s)`` seeds env i with ``s + i``, so the batch is
    identical step by step to ``num_envs`` single envs reset with those seeds.
    """

    metadata = {"render_modes": [], "autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(self, num_envs: int = 2, tier: str = DEFAULTS["tier"], scenario: Any = None,
                 actuator: Any = None, observation: Any = None, reward: Any = None,
                 params: BearingParams | None = None, control_dt_s: float = DEFAULTS["control_dt_s"],
                 episode_steps: int = DEFAULTS["episode_steps"],
                 max_episode_steps: int | None = DEFAULTS["episode_steps"],
                 num_threads: int | None = None, render_mode: str | None = None):
        if render_mode is not None:
            raise ValueError("the vector env does not render; render a single BearingPreloadEnv")
        if isinstance(num_envs, bool) or not isinstance(num_envs, (int, np.integer)) or num_envs < 1:
            raise ValueError(f"num_envs must be an integer >= 1, got {num_envs!r}")
        self.num_envs = int(num_envs)
        configure(self, tier, scenario, actuator, observation, reward, params, control_dt_s,
                  episode_steps, num_envs=self.num_envs)
        self.max_episode_steps = max_episode_steps
        if num_threads is not None and not (1 <= num_threads <= numba.config.NUMBA_NUM_THREADS):
            raise ValueError(f"num_threads must be in [1, {numba.config.NUMBA_NUM_THREADS}], got {num_threads}")
        self.num_threads = num_threads
        self.single_action_space = spaces.Box(-1.0, 1.0, shape=(1,), dtype=np.float32)
        self.single_observation_space = self.observation_model.space
        self.action_space = gym.vector.utils.batch_space(self.single_action_space, self.num_envs)
        self.observation_space = gym.vector.utils.batch_space(self.single_observation_space, self.num_envs)
        self.render_mode = None
        self._rngs: list[np.random.Generator | None] = [None] * self.num_envs
        self._elapsed = np.zeros(self.num_envs, dtype=np.int64)
        self._autoreset = np.zeros(self.num_envs, dtype=bool)
        self._started = False

    # --- building blocks (also used by the SB3 adapter) ----------------------------------------
    def _seed(self, seed: int | Sequence[int | None] | None) -> None:
        if seed is None:
            seeds: list[int | None] = [None] * self.num_envs
        elif isinstance(seed, (int, np.integer)):
            seeds = [int(seed) + i for i in range(self.num_envs)]
        else:
            seeds = list(seed)
            if len(seeds) != self.num_envs:
                raise ValueError(f"seed list must have num_envs = {self.num_envs} entries, got {len(seeds)}")
        for i, s in enumerate(seeds):
            if s is not None or self._rngs[i] is None:
                self._rngs[i], _ = seeding.np_random(s)

    def _reset_envs(self, idx: np.ndarray, options: dict | None) -> np.ndarray:
        rngs = [self._rngs[b] for b in idx]
        reset_envs(self, idx, rngs, options)
        self._elapsed[idx] = 0
        b = self._batch
        m = measurement(b, idx, b.preload[idx].copy(), np.full(len(idx), self.episode_steps),
                        b.start_failed[idx].copy())
        return observe(self, m, idx, rngs)

    def _step_envs(self, actions: np.ndarray, idx: np.ndarray):
        """Step envs ``idx`` with their actions; returns obs, reward, terminated, truncated, infos."""
        active = np.zeros(self.num_envs, dtype=bool)
        active[idx] = True
        setpoints = np.zeros(self.num_envs)
        setpoints[idx] = self.actuator.setpoint_n(actions[idx])
        before = self._batch.preload[idx].copy()
        if self.num_threads is not None:
            numba.set_num_threads(self.num_threads)
        self._batch.step(setpoints, active)
        self._elapsed[idx] += 1
        steps_left = np.maximum(self.episode_steps - self._elapsed[idx], 0)
        obs, rew, term, infos = step_outputs(self, idx, before, steps_left, [self._rngs[b] for b in idx])
        if self.max_episode_steps is None:
            trunc = np.zeros(len(idx), dtype=bool)
        else:
            trunc = (self._elapsed[idx] >= self.max_episode_steps) & ~term
        return obs, rew, term, trunc, infos

    # --- gymnasium VectorEnv API -------------------------------------------------------------
    def reset(self, *, seed: int | Sequence[int | None] | None = None, options: dict | None = None):
        self._seed(seed)
        opts = dict(options or {})
        mask = opts.pop("reset_mask", None)
        idx = np.arange(self.num_envs) if mask is None else np.flatnonzero(np.asarray(mask, dtype=bool))
        obs_part = self._reset_envs(idx, opts)
        if not self._started:
            self._obs = np.zeros((self.num_envs,) + self.single_observation_space.shape, dtype=np.float32)
            self._started = True
        self._obs[idx] = obs_part
        self._autoreset[idx] = False
        infos: dict[str, Any] = {}
        for i, b in enumerate(idx):
            infos = self._add_info(infos, {"preload_n": float(self._batch.preload[b])}, int(b))
        return self._obs.copy(), infos

    def step(self, actions):
        if not self._started:
            raise RuntimeError("call reset() before step()")
        a = check_actions(actions, self.num_envs)
        rewards = np.zeros(self.num_envs)
        terminations = np.zeros(self.num_envs, dtype=bool)
        truncations = np.zeros(self.num_envs, dtype=bool)
        infos: dict[str, Any] = {}
        reset_idx = np.flatnonzero(self._autoreset)
        step_idx = np.flatnonzero(~self._autoreset)
        if len(reset_idx):
            self._obs[reset_idx] = self._reset_envs(reset_idx, None)
        if len(step_idx):
            obs, rew, term, trunc, env_infos = self._step_envs(a, step_idx)
            self._obs[step_idx] = obs
            rewards[step_idx] = rew
            terminations[step_idx] = term
            truncations[step_idx] = trunc
            for i, b in enumerate(step_idx):
                infos = self._add_info(infos, env_infos[i], int(b))
        self._autoreset = terminations | truncations
        return self._obs.copy(), rewards, terminations, truncations, infos
