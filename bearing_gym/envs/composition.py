"""What both preload envs (single and vector) are made of, composed once: the tier's scenario
distribution, actuator, observation model and reward - each replaceable by the user's own
object (:mod:`.parts`) - the physics batch they drive and the observation model's state.

The envs hold one :class:`PreloadTask` and do only the Gymnasium bookkeeping around it (spaces,
seeding, time limit, rendering), so the two behave alike by construction.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from bearing_gym.physics.portable_math import TWO_PI
from bearing_gym.physics.rating import friction_torque_n_m, life_used_per_revolution
from bearing_gym.physics.status import ST_OK, status_text
from bearing_gym.units import rad_s_to_rpm

from .contact import C_INNER_Q3_MEAN, C_OUTER_Q10_3_MEAN, C_SHAFT_SPEED_MEAN
from .core import PreloadBatch
from .measurement import StepMeasurement
from .parts import rebuild_dataclass, resolve_part
from .scenario import FixedScenario, Scenario, check_pinned
from .tiers import CONTROL_DT_S, DEFAULT_TIER, EPISODE_STEPS, TIERS, tier_parts

__all__ = ["PreloadTask", "TaskParts", "DEFAULTS", "check_actions", "measurement", "interval_cost"]

_REQUIRED = {
    "scenario": ("sample",),
    "actuator": ("min_preload_n", "max_preload_n", "update_interval_s", "setpoint_n", "action_for", "as_array"),
    "observation": ("space", "make_state", "reset_state", "__call__"),
    "reward": ("term_names", "__call__"),
}

DEFAULTS = {"tier": DEFAULT_TIER, "control_dt_s": CONTROL_DT_S, "episode_steps": EPISODE_STEPS}


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


def check_actions(actions: Any, n: int, single: bool = False) -> np.ndarray:
    """Validate ``n`` actions in [-1, 1] (a batch (n, 1) or (n,); with ``single``, the one action of
    the single env: shape (1,) or a scalar); raise naming the problem."""
    if isinstance(actions, (str, bytes)) or actions is None:
        raise TypeError(f"action must be a number or an array of numbers in [-1, 1], got {actions!r}")
    try:
        a = np.asarray(actions, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"action must be a number or an array of numbers in [-1, 1], got {actions!r}") from None
    if a.size != n:
        expected = "one element (shape (1,), the env's action space)" if single else \
            f"{n} element(s) (shape ({n}, 1) or ({n},), one per env)"
        raise ValueError(f"action must have {expected}, got shape {a.shape}")
    a = a.reshape(n)
    if not np.all(np.isfinite(a)):
        raise ValueError(f"action contains NaN or infinity: {a.tolist()}; actions must be finite numbers in [-1, 1]")
    if np.any(a < -1.0) or np.any(a > 1.0):
        raise ValueError(f"action {a.tolist()} is outside the action space [-1, 1]; scale it (the env does not clip)")
    return a


def measurement(batch: PreloadBatch, idx: np.ndarray, preload_before: np.ndarray, steps_left: np.ndarray,
                terminated: np.ndarray) -> StepMeasurement:
    """The :class:`StepMeasurement` of ``batch``'s envs ``idx`` after their last kernel step (or
    settle): what the observation model and the reward read. The life used per second is
    Lundberg-Palmgren's 1 / L_10 of the interval's contact loads (the bearing's capacities,
    ``batch.dynamic_capacities_n``) times the shaft's revolutions per second over the interval
    (its mean speed: a ramp's revolutions, not its end speed's); the friction torque Palmgren's M_1 at its preload and radial load
    (:mod:`bearing_gym.physics.rating`)."""
    a = batch.actuator
    omega = batch.omega()[idx]
    contact = batch.contact[idx].copy()
    radial = batch.radial_load_n()[idx]
    preload = batch.preload[idx].copy()
    life = life_used_per_revolution(contact[:, C_INNER_Q3_MEAN], contact[:, C_OUTER_Q10_3_MEAN],
                                    batch.dynamic_capacities_n) * (contact[:, C_SHAFT_SPEED_MEAN] / TWO_PI)
    return StepMeasurement(
        features=batch.feats[idx].copy(), preload_n=preload,
        preload_before_n=np.asarray(preload_before, dtype=float), setpoint_n=batch.setpoint[idx].copy(),
        shaft_speed_rad_s=omega, radial_load_n=radial,
        kinematic_cage_speed_rad_s=0.5 * omega * (1.0 - batch.gamma_cos_a0),
        t_s=batch.t_episode[idx].copy(), steps_left=np.asarray(steps_left),
        terminated=np.asarray(terminated, dtype=bool), contact=contact, life_used_per_s=life,
        friction_torque_n_m=friction_torque_n_m(batch.base.geometry, radial, preload),
        preload_range_n=(float(a.min_preload_n), float(a.max_preload_n)))


def interval_cost(quasi_periodic: bool, terminated: bool, steps_left: int) -> float:
    """``info["cost"]`` of an interval, the safe-RL cost channel: 1.0 if the interval was
    quasi-periodic, else 0.0; on termination (the integrator failed) 1 + the intervals left, as if
    every one of them were quasi-periodic (a crash never pays, as in the reward's termination
    term). The env's reset info has 0.0. Summed over an episode: the quasi-periodic intervals,
    against ``bearing_gym.task.COST_BUDGET_PER_EPISODE`` in the constrained variant."""
    if terminated:
        return 1.0 + float(steps_left)
    return 1.0 if quasi_periodic else 0.0


@dataclass
class PreloadTask:
    """The composed parts of a preload env (module docstring); :meth:`build` makes one."""

    tier: str
    scenario_dist: Any
    actuator: Any
    observation_model: Any
    reward_model: Any
    episode_steps: int
    batch: PreloadBatch
    sensor_state: Any

    @classmethod
    def build(cls, tier: str, scenario: Any, actuator: Any, observation: Any, reward: Any, params: Any,
              control_dt_s: float, episode_steps: int, num_envs: int) -> "PreloadTask":
        """The tier's parts, replaced by any given explicitly, the physics batch of ``num_envs``
        envs and the observation model's state."""
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
        act = resolve_part("actuator", actuator, parts["actuator"], _REQUIRED["actuator"])
        obs = resolve_part("observation", observation, parts["observation"], _REQUIRED["observation"])
        return cls(tier=tier, scenario_dist=_scenario_part(scenario, parts["scenario"]), actuator=act,
                   observation_model=obs,
                   reward_model=resolve_part("reward", reward, parts["reward"], _REQUIRED["reward"]),
                   episode_steps=int(episode_steps), batch=PreloadBatch(num_envs, params, control_dt_s, act),
                   sensor_state=obs.make_state(num_envs))

    @property
    def control_dt_s(self) -> float:
        return self.batch.control_dt_s

    def reset(self, idx: Sequence[int], rngs: Sequence[np.random.Generator],
              options: Mapping[str, Any] | None) -> list[Scenario]:
        """Draw (or take from options) the scenarios of envs ``idx``, load them and settle them
        together (one batched warm-up)."""
        episode_s = self.episode_steps * self.control_dt_s
        scenarios = []
        for b, rng in zip(idx, rngs):
            opts = dict(options or {})
            if "scenario" in opts:
                sc = opts.pop("scenario")
                if not isinstance(sc, Scenario):
                    raise ValueError(f"options['scenario'] must be a Scenario, got {type(sc).__name__}")
                scenario = dataclasses.replace(sc, **check_pinned(opts)) if opts else sc
            else:
                scenario = self.scenario_dist.sample(rng, episode_s, opts or None)
            self.batch.load(int(b), scenario)
            self.observation_model.reset_state(self.sensor_state, int(b), rng)
            scenarios.append(scenario)
        self.batch.settle(np.asarray(idx, dtype=np.int64))
        return scenarios

    def measurement(self, idx: np.ndarray, preload_before: np.ndarray, steps_left: np.ndarray,
                    terminated: np.ndarray) -> StepMeasurement:
        """The :class:`StepMeasurement` of envs ``idx`` after their last kernel step (or settle)."""
        return measurement(self.batch, idx, preload_before, steps_left, terminated)

    def reset_outputs(self, idx: np.ndarray, rngs) -> tuple[np.ndarray, list[dict[str, Any]]]:
        """Observations and infos of envs ``idx`` just reset."""
        batch = self.batch
        m = self.measurement(idx, batch.preload[idx].copy(), np.full(len(idx), self.episode_steps),
                             batch.start_failed[idx].copy())
        obs = self.observation_model(m, self.sensor_state, np.asarray(idx), rngs)
        return obs, [{**self._info(int(b), m, i), "cost": 0.0} for i, b in enumerate(idx)]

    def _info(self, b: int, m: StepMeasurement, i: int) -> dict[str, Any]:
        """The operating point, the preload, the motion and the bearing's engineering quantities
        of env ``b`` (row ``i`` of ``m``; docs/environment.md has the table)."""
        batch = self.batch
        life = float(m.life_used_per_s[i])
        return {"preload_n": float(batch.preload[b]), "setpoint_n": float(batch.setpoint[b]),
                "shaft_speed_rpm": float(rad_s_to_rpm(m.shaft_speed_rad_s[i])),
                "radial_load_n": float(m.radial_load_n[i]), "qpi": float(m.qpi[i]),
                "quasi_periodic": bool(m.quasi_periodic[i]), "nonsync_rms_um": float(m.nonsync_rms_m[i] * 1e6),
                "t": float(batch.t_episode[b]),
                "radial_stiffness_n_per_m": float(m.radial_stiffness_n_per_m[i]),
                "axial_stiffness_n_per_m": float(m.axial_stiffness_n_per_m[i]),
                "max_inner_contact_load_n": float(m.max_inner_contact_load_n[i]),
                "max_outer_contact_load_n": float(m.max_outer_contact_load_n[i]),
                "life_used_per_s": life, "l10_life_h": 1.0 / (3600.0 * life) if life > 0.0 else float("inf"),
                "friction_torque_n_m": float(m.friction_torque_n_m[i])}

    def step_outputs(self, idx: np.ndarray, preload_before: np.ndarray, steps_left: np.ndarray, rngs):
        """Observations, rewards, terminations and infos of envs ``idx`` after a kernel step."""
        batch = self.batch
        status = batch.status[idx]
        terminated = (status != ST_OK) | batch.start_failed[idx]
        m = self.measurement(idx, preload_before, steps_left, terminated)
        obs = self.observation_model(m, self.sensor_state, np.asarray(idx), rngs)
        reward, terms = self.reward_model(m)
        infos = []
        for i, b in enumerate(idx):
            info = {f"reward_{k}": float(terms[k][i]) for k in self.reward_model.term_names}
            info.update(self._info(int(b), m, i))
            info["cost"] = interval_cost(bool(m.quasi_periodic[i]), bool(terminated[i]), int(steps_left[i]))
            if terminated[i]:
                code = int(status[i])
                info["termination_reason"] = ("the start diverged at this operating point" if batch.start_failed[b]
                                              else status_text(code))
            infos.append(info)
        return obs, np.asarray(reward, dtype=np.float64), terminated, infos


class TaskParts:
    """The parts of an env's :class:`PreloadTask` (``self.task``) as read-only attributes of the
    env, for users and wrappers: ``env.actuator``, ``env.reward_model``, ``env.batch``, ..."""

    task: PreloadTask

    tier = property(lambda self: self.task.tier, doc="the tier the env was made for")
    scenario_dist = property(lambda self: self.task.scenario_dist, doc="draws each episode's scenario")
    actuator = property(lambda self: self.task.actuator, doc="action -> preload set-point, and its lag")
    observation_model = property(lambda self: self.task.observation_model, doc="features -> observation")
    reward_model = property(lambda self: self.task.reward_model, doc="measurement -> reward and its terms")
    episode_steps = property(lambda self: self.task.episode_steps, doc="control intervals per episode")
    batch = property(lambda self: self.task.batch, doc="the physics of the env(s): a PreloadBatch")
    control_dt_s = property(lambda self: self.task.control_dt_s, doc="control interval (s)")
