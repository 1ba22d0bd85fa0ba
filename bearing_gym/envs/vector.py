"""Native vector environment (one batched numba kernel, prange over envs)."""

from __future__ import annotations

import copy

from collections import deque
from typing import Any, Sequence

import gymnasium as gym
import numba
import numpy as np
from gymnasium import spaces
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv

from bearing_gym.params import BearingParams
from bearing_gym.units import rad_s_to_rpm

from .bearing_preload import BearingPreloadEnv
from .composition import DEFAULTS, PreloadTask, TaskParts, check_actions
from .start_bank import env_scenario, install_for
from .rendering import HISTORY_LENGTH, POINCARE_LENGTH, record_interval, rgb_frame

__all__ = ["BearingPreloadVectorEnv", "ResetMaskError"]


class ResetMaskError(ValueError, TypeError):
    """A bad ``options["reset_mask"]``. A ``ValueError``, and also a ``TypeError`` because
    Gymnasium's own vector envs raise that for a mask of the wrong type or dtype: code written
    for either catches it."""


def check_action_batch(actions, num_envs: int) -> np.ndarray:
    """Validate a batch of actions (see ``check_actions``); a scalar is a ``TypeError``, as in
    Gymnasium's vector envs (they cannot iterate over it)."""
    if np.ndim(actions) == 0:
        raise TypeError(f"actions must be a batch, one action per env (shape ({num_envs}, 1)); "
                        f"got the scalar {actions!r}")
    return check_actions(actions, num_envs)


class BearingPreloadVectorEnv(TaskParts, VectorEnv):
    """``num_envs`` copies of :class:`~bearing_gym.envs.BearingPreloadEnv` stepped together by
    one numba kernel (``prange`` over environments, ``num_threads`` worker threads).

    Same arguments as the single env, plus ``num_envs``, ``max_episode_steps`` (truncation; the
    single env gets it from its TimeLimit) and ``num_threads`` (default: numba's; applied only
    around the kernel call, the caller's numba thread count is restored). Autoreset mode
    ``NEXT_STEP``: the step after an episode ends resets that env and returns its first
    observation with reward 0 and its reset info. ``reset(seed=s)`` seeds env i with ``s + i``,
    so the batch is identical step by step to ``num_envs`` single envs reset with those seeds
    (and to ``gym.make_vec(..., vectorization_mode="sync")``); ``reset(seed=[s0, s1, ...])``
    seeds each env, ``None`` entries keep an env's generator; ``np_random_seed`` is the tuple of
    the envs' seeds. ``reset(options={"reset_mask": mask})`` resets only the envs where the
    boolean array ``mask`` (shape ``(num_envs,)``) is True, and only those take their seed.
    ``render_mode="rgb_array"``: ``render()`` returns a tuple of the envs' frames, each what the
    single env's ``render()`` returns.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": BearingPreloadEnv.metadata["render_fps"],
                "autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(self, num_envs: int = 2, tier: str = DEFAULTS["tier"], scenario: Any = None,
                 actuator: Any = None, observation: Any = None, reward: Any = None,
                 params: BearingParams | None = None, control_dt_s: float = DEFAULTS["control_dt_s"],
                 episode_steps: int = DEFAULTS["episode_steps"],
                 max_episode_steps: int | None = DEFAULTS["episode_steps"],
                 num_threads: int | None = None, render_mode: str | None = None, start_bank: Any = None):
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(
                f"render_mode must be None or 'rgb_array' (a tuple of the envs' frames), got "
                f"{render_mode!r}; for a window render a single BearingPreloadEnv, use "
                "vectorization_mode='sync', or wrap this env in gymnasium.wrappers.vector.HumanRendering")
        if isinstance(num_envs, bool) or not isinstance(num_envs, (int, np.integer)) or num_envs < 1:
            raise ValueError(f"num_envs must be an integer >= 1, got {num_envs!r}")
        self.num_envs = int(num_envs)
        scenario, bank = env_scenario(start_bank, scenario, tier)
        self.task = PreloadTask.build(tier, scenario, actuator, observation, reward, params, control_dt_s,
                                      episode_steps, num_envs=self.num_envs)
        install_for(bank, self.task)
        self.max_episode_steps = max_episode_steps
        if num_threads is not None and not (1 <= num_threads <= numba.config.NUMBA_NUM_THREADS):
            raise ValueError(f"num_threads must be in [1, {numba.config.NUMBA_NUM_THREADS}], got {num_threads}")
        self.num_threads = num_threads
        self.single_action_space = spaces.Box(-1.0, 1.0, shape=(1,), dtype=np.float32)
        self.single_observation_space = self.observation_model.space
        self.action_space = gym.vector.utils.batch_space(self.single_action_space, self.num_envs)
        self.observation_space = gym.vector.utils.batch_space(self.single_observation_space, self.num_envs)
        self.render_mode = render_mode
        self._rngs: list[np.random.Generator | None] = [None] * self.num_envs
        self._rng_seeds: list[int | None] = [None] * self.num_envs
        self._elapsed = np.zeros(self.num_envs, dtype=np.int64)
        self._autoreset = np.zeros(self.num_envs, dtype=bool)
        self._started = False
        # what each env's frame shows (render_mode="rgb_array"); see bearing_gym.envs.rendering
        self._frame_history = [deque(maxlen=HISTORY_LENGTH) for _ in range(self.num_envs)]
        self._frame_poincare = [deque(maxlen=POINCARE_LENGTH) for _ in range(self.num_envs)]
        self._frame_orbit: list[np.ndarray | None] = [None] * self.num_envs

    # --- seeding -------------------------------------------------------------------------------
    @property
    def np_random(self) -> tuple[np.random.Generator, ...]:
        """The envs' random generators (an unseeded env gets a random seed on first use)."""
        return tuple(self._rng(b) for b in range(self.num_envs))

    @property
    def np_random_seed(self) -> tuple[int, ...]:
        """The envs' seeds, as ``SyncVectorEnv.np_random_seed``: after ``reset(seed=s)``
        ``(s, s + 1, ...)``; an env never seeded reports the random seed it drew."""
        for b in range(self.num_envs):
            self._rng(b)
        return tuple(self._rng_seeds)

    def _rng(self, b: int) -> np.random.Generator:
        if self._rngs[b] is None:
            self._rngs[b], self._rng_seeds[b] = seeding.np_random(None)
        return self._rngs[b]

    # --- building blocks (also used by the SB3 adapter) ----------------------------------------
    def seed_some(self, seed: int | Sequence[int | None] | None, idx: np.ndarray | None = None) -> None:
        """Seed envs ``idx`` (default all) from ``seed``: None, an int (env i gets seed + i) or
        one entry per env (None keeps that env's generator). Envs outside ``idx`` keep theirs."""
        if seed is None:
            seeds: list[int | None] = [None] * self.num_envs
        elif isinstance(seed, (int, np.integer)):
            seeds = [int(seed) + i for i in range(self.num_envs)]
        else:
            seeds = [int(s) if isinstance(s, np.integer) else s for s in seed]
            if len(seeds) != self.num_envs:
                raise ValueError(f"seed list must have num_envs = {self.num_envs} entries, got {len(seeds)}")
        for b in (range(self.num_envs) if idx is None else idx):
            if seeds[b] is not None or self._rngs[b] is None:
                self._rngs[b], self._rng_seeds[b] = seeding.np_random(seeds[b])

    def reset_some(self, idx: np.ndarray, options: dict | None) -> tuple[np.ndarray, list[dict]]:
        """Reset envs ``idx`` (their settled starts run together); returns their first
        observations and reset infos."""
        rngs = [self._rng(b) for b in idx]
        self._with_threads(self.task.reset, idx, rngs, options)
        for b in idx:
            self._elapsed[b] = 0
            self._frame_history[b].clear()
            self._frame_poincare[b].clear()
            self._frame_orbit[b] = None
        return self.task.reset_outputs(idx, rngs)

    def copy_env(self, src: int, dst) -> None:
        """Make env(s) ``dst`` exact copies of env ``src`` mid-episode: the physics
        (:meth:`PreloadBatch.copy_env`), the steps taken, the sensor model's state and the random
        generator, so that a copy stepped with the same actions gives the same observations,
        rewards and ends, bit for bit. A planner's branch point: roll copies forward under other
        actions while env ``src`` keeps its own course."""
        if not 0 <= int(src) < self.num_envs:
            raise ValueError(f"src must be an env index in [0, {self.num_envs}), got {src!r}")
        dst = np.atleast_1d(np.asarray(dst, dtype=np.int64))
        if dst.size and (dst.min() < 0 or dst.max() >= self.num_envs or np.any(dst == src)):
            raise ValueError(f"dst must be env indices in [0, {self.num_envs}) other than src = {src}, got {dst.tolist()}")
        src = int(src)
        self.batch.copy_env(src, dst)
        state = self.task.sensor_state
        for arr in (state.values() if isinstance(state, dict) else [state]):
            if isinstance(arr, np.ndarray) and arr.shape[:1] == (self.num_envs,):
                arr[dst] = arr[src]
        for d in dst:
            d = int(d)
            self._elapsed[d] = self._elapsed[src]
            self._autoreset[d] = self._autoreset[src]
            self._rng(src)
            self._rngs[d] = copy.deepcopy(self._rngs[src])
            self._rng_seeds[d] = self._rng_seeds[src]
            self._frame_history[d] = copy.deepcopy(self._frame_history[src])
            self._frame_poincare[d] = copy.deepcopy(self._frame_poincare[src])
            self._frame_orbit[d] = self._frame_orbit[src]

    def hold_operating_point(self, idx) -> None:
        """Env(s) ``idx`` hold, from now on, the shaft speed and radial load of their present
        time (:meth:`PreloadBatch.hold_operating_point`): branches of a controller that does not
        know the scenario's future (copy them with :meth:`copy_env` first)."""
        idx = np.atleast_1d(np.asarray(idx, dtype=np.int64))
        if idx.size and (idx.min() < 0 or idx.max() >= self.num_envs):
            raise ValueError(f"idx must be env indices in [0, {self.num_envs}), got {idx.tolist()}")
        self.batch.hold_operating_point(idx)

    @property
    def scenarios(self) -> tuple:
        """The scenario each env is running (None before its first reset)."""
        return tuple(self.batch.scenarios)

    def operating_points(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(shaft speed rpm, radial load N, clearance m, rotor eccentricity m) of every env now:
        what an oracle is told (the reward map's axes)."""
        b = self.batch
        clearance = np.array([np.nan if sc is None else sc.clearance_m for sc in b.scenarios])
        eccentricity = np.array([np.nan if sc is None else sc.eccentricity_m for sc in b.scenarios])
        return rad_s_to_rpm(b.omega()), b.radial_load_n(), clearance, eccentricity

    def _with_threads(self, fn, *args):
        """``fn(*args)`` with numba's thread count set to ``num_threads`` for this call only (the
        count is per calling thread; the caller's is restored)."""
        if self.num_threads is None:
            return fn(*args)
        previous = numba.get_num_threads()
        numba.set_num_threads(self.num_threads)
        try:
            return fn(*args)
        finally:
            numba.set_num_threads(previous)

    def step_some(self, actions: np.ndarray, idx: np.ndarray):
        """Step envs ``idx`` with their actions; returns obs, reward, terminated, truncated, infos."""
        active = np.zeros(self.num_envs, dtype=bool)
        active[idx] = True
        setpoints = np.zeros(self.num_envs)
        setpoints[idx] = self.actuator.setpoint_n(actions[idx])
        before = self.batch.preload[idx].copy()
        self._with_threads(self.batch.step, setpoints, active)
        if self.render_mode is not None:
            for b in idx:
                orbit = record_interval(self.batch, int(b), self._frame_history[b], self._frame_poincare[b])
                if orbit is not None:
                    self._frame_orbit[b] = orbit
        self._elapsed[idx] += 1
        steps_left = np.maximum(self.episode_steps - self._elapsed[idx], 0)
        obs, rew, term, infos = self.task.step_outputs(idx, before, steps_left, [self._rngs[b] for b in idx])
        if self.max_episode_steps is None:
            trunc = np.zeros(len(idx), dtype=bool)
        else:
            trunc = (self._elapsed[idx] >= self.max_episode_steps) & ~term
        return obs, rew, term, trunc, infos

    def _mask_indices(self, mask: Any) -> np.ndarray:
        """The envs a ``reset_mask`` selects; raises ResetMaskError naming what is wrong."""
        m = np.asarray(mask)
        if m.shape != (self.num_envs,):
            raise ResetMaskError(f"options['reset_mask'] must have shape ({self.num_envs},) (one "
                                 f"bool per env), got shape {m.shape}")
        if m.dtype != np.bool_:
            raise ResetMaskError(f"options['reset_mask'] must have dtype bool, got {m.dtype}")
        if not m.any():
            raise ResetMaskError("options['reset_mask'] is all False: it must select at least one env")
        if not self._started and not m.all():
            raise ResetMaskError("the first reset must reset every env; options['reset_mask'] "
                                 f"leaves out envs {np.flatnonzero(~m).tolist()}")
        return np.flatnonzero(m)

    # --- gymnasium VectorEnv API -------------------------------------------------------------
    def reset(self, *, seed: int | Sequence[int | None] | None = None, options: dict | None = None):
        opts = dict(options or {})
        mask = opts.pop("reset_mask", None)
        idx = np.arange(self.num_envs) if mask is None else self._mask_indices(mask)
        self.seed_some(seed, idx)
        obs_part, env_infos = self.reset_some(idx, opts)
        if not self._started:
            self._obs = np.zeros((self.num_envs,) + self.single_observation_space.shape, dtype=np.float32)
            self._started = True
        self._obs[idx] = obs_part
        self._autoreset[idx] = False
        infos: dict[str, Any] = {}
        for b, info in zip(idx, env_infos):
            infos = self._add_info(infos, info, int(b))
        return self._obs.copy(), infos

    def step(self, actions):
        if not self._started:
            raise RuntimeError("call reset() before step()")
        a = check_action_batch(actions, self.num_envs)
        rewards = np.zeros(self.num_envs)
        terminations = np.zeros(self.num_envs, dtype=bool)
        truncations = np.zeros(self.num_envs, dtype=bool)
        infos: dict[str, Any] = {}
        reset_idx = np.flatnonzero(self._autoreset)
        step_idx = np.flatnonzero(~self._autoreset)
        if len(reset_idx):
            self._obs[reset_idx], env_infos = self.reset_some(reset_idx, None)
            for b, info in zip(reset_idx, env_infos):
                infos = self._add_info(infos, info, int(b))
        if len(step_idx):
            obs, rew, term, trunc, env_infos = self.step_some(a, step_idx)
            self._obs[step_idx] = obs
            rewards[step_idx] = rew
            terminations[step_idx] = term
            truncations[step_idx] = trunc
            for b, info in zip(step_idx, env_infos):
                infos = self._add_info(infos, info, int(b))
        self._autoreset = terminations | truncations
        return self._obs.copy(), rewards, terminations, truncations, infos

    def render(self) -> tuple[np.ndarray | None, ...]:
        """The envs' frames (``render_mode="rgb_array"``), as ``SyncVectorEnv.render``: a tuple,
        one (H, W, 3) uint8 frame per env; a tuple of None without a render mode."""
        if self.render_mode != "rgb_array":
            return (None,) * self.num_envs
        return tuple(rgb_frame(self._frame_orbit[b], self._frame_poincare[b], self._frame_history[b])
                     for b in range(self.num_envs))
