"""Stable-Baselines3 ``VecEnv`` adapter of the native batched env.

Kept in its own module, imported only when asked for, because importing SB3 imports torch
(about 1.5 s): ``import bearing_gym.envs`` stays light.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .common import check_actions
from .vector import BearingPreloadVectorEnv

__all__ = ["BearingPreloadSB3VecEnv"]

from stable_baselines3.common.vec_env.base_vec_env import VecEnv as _SB3VecEnv


class BearingPreloadSB3VecEnv(_SB3VecEnv):
    """Stable-Baselines3 ``VecEnv`` over the native batched env (SB3 does not take a gymnasium
    ``VectorEnv``). SB3 semantics: an env that ends is reset in the same step, its last
    observation goes to ``infos[i]["terminal_observation"]`` and ``"TimeLimit.truncated"`` marks
    truncation. Takes the :class:`BearingPreloadVectorEnv` arguments."""

    def __init__(self, num_envs: int = 2, **kwargs: Any):
        self.venv = BearingPreloadVectorEnv(num_envs=num_envs, **kwargs)
        super().__init__(num_envs, self.venv.single_observation_space, self.venv.single_action_space)
        self._actions: np.ndarray | None = None
        self._started = False

    def reset(self):
        seeds = getattr(self, "_seeds", [None] * self.num_envs)
        self.venv._seed(list(seeds))
        opts = getattr(self, "_options", [{}] * self.num_envs)
        obs = np.zeros((self.num_envs,) + self.observation_space.shape, dtype=np.float32)
        for b in range(self.num_envs):
            obs[b] = self.venv._reset_envs(np.array([b]), opts[b] or None)[0]
        if hasattr(self, "_reset_seeds"):
            self._reset_seeds()
        if hasattr(self, "_reset_options"):
            self._reset_options()
        self._started = True
        return obs

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = np.asarray(actions)

    def step_wait(self):
        if not self._started:
            raise RuntimeError("call reset() before step()")
        a = check_actions(self._actions, self.num_envs)
        idx = np.arange(self.num_envs)
        obs, rew, term, trunc, infos = self.venv._step_envs(a, idx)
        dones = term | trunc
        for b in np.flatnonzero(dones):
            infos[b]["terminal_observation"] = obs[b].copy()
            infos[b]["TimeLimit.truncated"] = bool(trunc[b] and not term[b])
            obs[b] = self.venv._reset_envs(np.array([b]), None)[0]
        return obs, rew.astype(np.float32), dones, infos

    def close(self) -> None:
        pass

    def _indices(self, indices) -> list[int]:
        if indices is None:
            return list(range(self.num_envs))
        if isinstance(indices, int):
            return [indices]
        return list(indices)

    def get_attr(self, attr_name: str, indices=None) -> list[Any]:
        return [getattr(self.venv, attr_name) for _ in self._indices(indices)]

    def set_attr(self, attr_name: str, value: Any, indices=None) -> None:
        setattr(self.venv, attr_name, value)

    def env_method(self, method_name: str, *method_args, indices=None, **method_kwargs) -> list[Any]:
        return [getattr(self.venv, method_name)(*method_args, **method_kwargs) for _ in self._indices(indices)]

    def env_is_wrapped(self, wrapper_class, indices=None) -> list[bool]:
        return [False for _ in self._indices(indices)]
