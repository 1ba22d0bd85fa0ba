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

from .actuator import PreloadActuator
from .common import check_actions, configure, initial_observation, reset_one, step_outputs
from .observation import ObservationModel
from .reward import RewardModel

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

    def __init__(self, num_envs: int = 2, scenario: Any = "randomized", control_dt_s: float = 0.02,
                 actuator: PreloadActuator | None = None, reward: RewardModel | None = None,
                 observation: ObservationModel | None = None, params: BearingParams | None = None,
                 episode_steps: int = 250, max_episode_steps: int | None = 250,
                 num_threads: int | None = None, obs_noise_std: float | None = None,
                 render_mode: str | None = None):
        if render_mode is not None:
            raise ValueError("the vector env does not render; render a single BearingPreloadEnv")
        if isinstance(num_envs, bool) or not isinstance(num_envs, (int, np.integer)) or num_envs < 1:
            raise ValueError(f"num_envs must be an integer >= 1, got {num_envs!r}")
        self.num_envs = int(num_envs)
        configure(self, scenario, control_dt_s, actuator, reward, observation, params,
                  episode_steps, obs_noise_std, num_envs=self.num_envs)
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
        for b in idx:
            reset_one(self._batch, int(b), self._rngs[b], self.scenario_dist,
                      self.episode_steps * self.control_dt_s, options)
            self._elapsed[b] = 0
        return initial_observation(self._batch, idx, self.observation_model, [self._rngs[b] for b in idx])

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
        obs, rew, term, infos = step_outputs(self._batch, idx, before, self.observation_model,
                                             self.reward_model, [self._rngs[b] for b in idx])
        self._elapsed[idx] += 1
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
