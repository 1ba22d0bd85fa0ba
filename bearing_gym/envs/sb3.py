"""Stable-Baselines3 ``VecEnv`` adapter of the native batched env.

Kept in its own module, imported only when asked for, because importing SB3 imports torch
(about 1.5 s): ``import bearing_gym.envs`` stays light.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .vector import BearingPreloadVectorEnv, check_action_batch

__all__ = ["BearingPreloadSB3VecEnv"]

from stable_baselines3.common.vec_env.base_vec_env import VecEnv as _SB3VecEnv


class BearingPreloadSB3VecEnv(_SB3VecEnv):
    """Stable-Baselines3 ``VecEnv`` over the native batched env (SB3 does not take a gymnasium
    ``VectorEnv``). SB3 semantics, as its ``DummyVecEnv``: an env that ends is reset in the same
    step, its last observation goes to ``infos[i]["terminal_observation"]``,
    ``infos[i]["TimeLimit.truncated"]`` says whether it was truncated, and ``reset_infos[i]``
    holds env i's latest reset info. ``render_mode="rgb_array"`` gives ``get_images()`` and
    SB3's tiled ``render()``. Takes the :class:`BearingPreloadVectorEnv` arguments."""

    def __init__(self, num_envs: int = 2, **kwargs: Any):
        self.venv = BearingPreloadVectorEnv(num_envs=num_envs, **kwargs)
        super().__init__(num_envs, self.venv.single_observation_space, self.venv.single_action_space)
        self._actions: np.ndarray | None = None
        self._started = False

    def reset(self):
        self.venv.seed_some(list(self._seeds))
        obs = np.zeros((self.num_envs,) + self.observation_space.shape, dtype=np.float32)
        # envs without options settle together (one batched warm-up on all threads); an env
        # with its own options is reset on its own
        plain = [b for b in range(self.num_envs) if not self._options[b]]
        groups = ([np.array(plain)] if plain else []) + [
            np.array([b]) for b in range(self.num_envs) if self._options[b]]
        for idx in groups:
            o, infos = self.venv.reset_some(idx, self._options[int(idx[0])] or None)
            obs[idx] = o
            for b, info in zip(idx, infos):
                self.reset_infos[int(b)] = info
        self._reset_seeds()        # seeds and options are used once, as in SB3's own VecEnvs
        self._reset_options()
        self._started = True
        return obs

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = actions

    def step_wait(self):
        if not self._started:
            raise RuntimeError("call reset() before step()")
        a = check_action_batch(self._actions, self.num_envs)
        idx = np.arange(self.num_envs)
        obs, rew, term, trunc, infos = self.venv.step_some(a, idx)
        dones = term | trunc
        for b in idx:
            infos[b]["TimeLimit.truncated"] = bool(trunc[b] and not term[b])
        ended = np.flatnonzero(dones)
        if len(ended):
            for b in ended:
                infos[b]["terminal_observation"] = obs[b].copy()
            # the envs that ended in this step settle together (with equal-length episodes they
            # all end in the same step): one batched warm-up on all threads, not one per env
            o, reset_infos = self.venv.reset_some(ended, None)
            obs[ended] = o
            for b, info in zip(ended, reset_infos):
                self.reset_infos[int(b)] = info
        return obs, rew.astype(np.float32), dones, infos

    def get_images(self):
        if self.render_mode != "rgb_array":
            return [None] * self.num_envs
        return list(self.venv.render())

    def close(self) -> None:
        self.venv.close()

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
