"""Logic shared by the single and the vector environment (one place, so both behave alike)."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from bearing_gym.physics.status import ST_OK, status_text
from bearing_gym.units import rad_s_to_rpm

from .core import PreloadBatch
from .measurement import StepMeasurement
from .parts import rebuild_dataclass, resolve_part
from .scenario import FixedScenario, Scenario, check_pinned
from .tiers import CONTROL_DT_S, DEFAULT_TIER, EPISODE_STEPS, TIERS, tier_parts

_REQUIRED = {
    "scenario": ("sample",),
    "actuator": ("min_preload_n", "max_preload_n", "update_interval_s", "setpoint_n", "action_for", "as_array"),
    "observation": ("space", "make_state", "reset_state", "__call__"),
    "reward": ("term_names", "__call__"),
}


def _scenario_part(value: Any, default: Any) -> Any:
    if isinstance(value, Mapping):                # from a spec's JSON: rebuild first
        value = resolve_part("scenario", value, default, ())
    if isinstance(value, str):
        if value not in TIERS:
            raise ValueError(f"unknown scenario preset {value!r}; valid: {', '.join(TIERS)} (the tiers' scenarios)")
        return TIERS[value]["scenario"]
    if isinstance(value, Scenario):
        return FixedScenario(value)
    return resolve_part("scenario", value, default, _REQUIRED["scenario"])


def configure(env, tier: str, scenario, actuator, observation, reward, params,
              control_dt_s: float, episode_steps: int, num_envs: int) -> None:
    """Set the parts every preload env has (single or vector) on ``env``: the tier's parts,
    replaced by any given explicitly, the physics batch and the single-env spaces."""
    from bearing_gym.params import BearingParams
    from bearing_gym.validation import check_real
    if not isinstance(tier, str):
        raise ValueError(f"tier must be one of {', '.join(TIERS)}, got {tier!r}")
    parts = tier_parts(tier)
    check_real("control_dt_s", control_dt_s, 1e-3, 1.0)
    if isinstance(episode_steps, bool) or not isinstance(episode_steps, (int, np.integer)) or episode_steps < 1:
        raise ValueError(f"episode_steps must be an integer >= 1, got {episode_steps!r}")
    if isinstance(params, Mapping):                # from a spec's JSON
        params = rebuild_dataclass(BearingParams, params)
    if params is not None and not isinstance(params, BearingParams):
        raise TypeError(f"params must be a bearing_gym.BearingParams (default_params(...)), got {type(params).__name__}")
    env.tier = tier
    env.scenario_dist = _scenario_part(scenario, parts["scenario"])
    env.actuator = resolve_part("actuator", actuator, parts["actuator"], _REQUIRED["actuator"])
    env.observation_model = resolve_part("observation", observation, parts["observation"], _REQUIRED["observation"])
    env.reward_model = resolve_part("reward", reward, parts["reward"], _REQUIRED["reward"])
    env.episode_steps = int(episode_steps)
    env.batch = PreloadBatch(num_envs, params, control_dt_s, env.actuator)
    env.control_dt_s = env.batch.control_dt_s
    env._sensor_state = env.observation_model.make_state(num_envs)


DEFAULTS = {"tier": DEFAULT_TIER, "control_dt_s": CONTROL_DT_S, "episode_steps": EPISODE_STEPS}


def check_actions(actions: Any, n: int) -> np.ndarray:
    """Validate a batch of actions (n, 1) in [-1, 1]; raise naming the problem."""
    if isinstance(actions, (str, bytes)) or actions is None:
        raise TypeError(f"action must be a number or an array of numbers in [-1, 1], got {actions!r}")
    try:
        a = np.asarray(actions, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"action must be a number or an array of numbers in [-1, 1], got {actions!r}") from None
    if a.size != n:
        raise ValueError(f"action must have {n} element(s) (shape ({n}, 1) or ({n},) for a batch), got shape {a.shape}")
    a = a.reshape(n)
    if not np.all(np.isfinite(a)):
        raise ValueError(f"action contains NaN or infinity: {a.tolist()}; actions must be finite numbers in [-1, 1]")
    if np.any(a < -1.0) or np.any(a > 1.0):
        raise ValueError(f"action {a.tolist()} is outside the action space [-1, 1]; scale it (the env does not clip)")
    return a


def reset_envs(env, idx: Sequence[int], rngs: Sequence[np.random.Generator],
               options: Mapping[str, Any] | None) -> list[Scenario]:
    """Draw (or take from options) the scenarios of envs ``idx``, load them and settle them
    together (one batched warm-up)."""
    batch: PreloadBatch = env.batch
    episode_s = env.episode_steps * env.control_dt_s
    scenarios = []
    for b, rng in zip(idx, rngs):
        opts = dict(options or {})
        if "scenario" in opts:
            sc = opts.pop("scenario")
            if not isinstance(sc, Scenario):
                raise ValueError(f"options['scenario'] must be a Scenario, got {type(sc).__name__}")
            scenario = dataclasses.replace(sc, **check_pinned(opts)) if opts else sc
        else:
            scenario = env.scenario_dist.sample(rng, episode_s, opts or None)
        batch.load(int(b), scenario)
        env.observation_model.reset_state(env._sensor_state, int(b), rng)
        scenarios.append(scenario)
    batch.settle(np.asarray(idx, dtype=np.int64))
    return scenarios


def measurement(batch: PreloadBatch, idx: np.ndarray, preload_before: np.ndarray,
                steps_left: np.ndarray, terminated: np.ndarray) -> StepMeasurement:
    """The :class:`StepMeasurement` of envs ``idx`` after their last kernel step (or settle)."""
    a = batch.actuator
    omega = batch.omega()[idx]
    return StepMeasurement(
        features=batch.feats[idx].copy(), preload_n=batch.preload[idx].copy(),
        preload_before_n=np.asarray(preload_before, dtype=float), setpoint_n=batch.setpoint[idx].copy(),
        shaft_speed_rad_s=omega, radial_load_n=batch.radial_load_n()[idx],
        kinematic_cage_speed_rad_s=0.5 * omega * (1.0 - batch.gamma_cos_a0),
        t_s=batch.t_episode[idx].copy(), steps_left=np.asarray(steps_left),
        terminated=np.asarray(terminated, dtype=bool),
        preload_range_n=(float(a.min_preload_n), float(a.max_preload_n)))


def observe(env, m: StepMeasurement, idx: np.ndarray, rngs) -> np.ndarray:
    return env.observation_model(m, env._sensor_state, np.asarray(idx), rngs)


def reset_info(batch: PreloadBatch, b: int, m: StepMeasurement, i: int) -> dict[str, Any]:
    """The info of a reset: the operating point, the preload and the settled motion."""
    return {"preload_n": float(batch.preload[b]), "setpoint_n": float(batch.setpoint[b]),
            "shaft_speed_rpm": float(rad_s_to_rpm(m.shaft_speed_rad_s[i])),
            "radial_load_n": float(m.radial_load_n[i]), "qpi": float(m.qpi[i]),
            "quasi_periodic": bool(m.quasi_periodic[i]), "nonsync_rms_um": float(m.nonsync_rms_m[i] * 1e6),
            "t": 0.0}


def step_outputs(env, idx: np.ndarray, preload_before: np.ndarray, steps_left: np.ndarray, rngs):
    """Observations, rewards, terminations and infos of envs ``idx`` after a kernel step."""
    batch: PreloadBatch = env.batch
    status = batch.status[idx]
    terminated = (status != ST_OK) | batch.start_failed[idx]
    m = measurement(batch, idx, preload_before, steps_left, terminated)
    obs = observe(env, m, idx, rngs)
    reward, terms = env.reward_model(m)
    infos = []
    for i, b in enumerate(idx):
        info = {f"reward_{k}": float(terms[k][i]) for k in env.reward_model.term_names}
        info.update(reset_info(batch, int(b), m, i))
        info["t"] = float(batch.t_episode[b])
        if terminated[i]:
            code = int(status[i])
            info["termination_reason"] = ("the start diverged at this operating point" if batch.start_failed[b]
                                          else status_text(code))
        infos.append(info)
    return obs, np.asarray(reward, dtype=np.float64), terminated, infos
