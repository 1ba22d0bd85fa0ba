"""Scripted preload controllers: the ways spindle engineers set preload today.

* :class:`ConstantPreload`: one fixed preload (the best one is found by a sweep over the
  validation scenarios, :mod:`agents.references.validation`).
* :class:`SpeedScheduledPreload`: a preload-vs-speed table (spindle makers' speed-dependent
  preload), here the worst-case critical preload of the stability map at each speed plus a margin.
* :class:`FeedbackRule`: raise the preload when the observed quasi-periodicity index crosses a
  threshold, lower it slowly otherwise (hysteresis and rate limit).
* :class:`OraclePreload`: knows the true operating conditions (speed, radial load, clearance)
  and the stability map: critical preload + margin. It bounds what a controller can achieve.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from bearing_gym.analysis.signals import QPI_THRESHOLD
from bearing_gym.envs.actuator import PreloadActuator
from bearing_gym.envs.observation import FEATURE_NAMES

from agents.policies.stability_table import StabilityTable


__all__ = ["Policy", "ConstantPreload", "SpeedScheduledPreload", "FeedbackRule", "OraclePreload"]

_QPI = FEATURE_NAMES.index("qpi")
_SPEED = FEATURE_NAMES.index("shaft_speed")
_SETPOINT = FEATURE_NAMES.index("setpoint")


class Policy:
    """SB3-style interface over batched observations (n_envs, 14)."""

    name = "policy"

    def __init__(self, actuator: PreloadActuator | None = None):
        self.actuator = actuator or PreloadActuator()

    def preload_to_action(self, preload_n: np.ndarray) -> np.ndarray:
        a = self.actuator
        p = np.clip(np.asarray(preload_n, dtype=np.float64), a.min_preload_n, a.max_preload_n)
        return (2.0 * (p - a.min_preload_n) / (a.max_preload_n - a.min_preload_n) - 1.0).astype(np.float32)[:, None]

    def predict(self, obs: np.ndarray, state: Any = None, episode_start: np.ndarray | None = None,
                deterministic: bool = True):
        raise NotImplementedError

    @staticmethod
    def _batch(obs: np.ndarray) -> np.ndarray:
        obs = np.asarray(obs, dtype=np.float64)
        return obs[None, :] if obs.ndim == 1 else obs


class ConstantPreload(Policy):
    """Always the same set-point ``preload_n``."""

    def __init__(self, preload_n: float, actuator: PreloadActuator | None = None):
        super().__init__(actuator)
        a = self.actuator
        if not a.min_preload_n <= preload_n <= a.max_preload_n:
            raise ValueError(f"preload_n must be in [{a.min_preload_n}, {a.max_preload_n}] N, got {preload_n}")
        self.preload_n = float(preload_n)
        self.name = f"constant {self.preload_n:.0f} N"

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        n = self._batch(obs).shape[0]
        return self.preload_to_action(np.full(n, self.preload_n)), state


class SpeedScheduledPreload(Policy):
    """Preload from a speed table: the stability map's worst case over radial load and clearance
    at the observed shaft speed, plus ``margin_n``."""

    def __init__(self, table: StabilityTable, margin_n: float = 100.0,
                 actuator: PreloadActuator | None = None, speed_scale_rpm: float = 25000.0):
        super().__init__(actuator)
        self.table = table
        self.margin_n = float(margin_n)
        self.speed_scale_rpm = speed_scale_rpm
        self.name = f"speed schedule (+{self.margin_n:.0f} N)"

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        o = self._batch(obs)
        rpm = o[:, _SPEED] * self.speed_scale_rpm
        return self.preload_to_action(self.table.worst_case(rpm) + self.margin_n), state


@dataclass
class FeedbackRule(Policy):
    """Raise the set-point by ``raise_n`` when the quasi-periodicity index exceeds ``high``;
    after ``hold_steps`` quiet intervals (index below ``low``) lower it by ``lower_n`` per
    interval. The state is the per-env (set-point, quiet-interval count)."""

    high: float = QPI_THRESHOLD
    low: float = QPI_THRESHOLD / 3
    raise_n: float = 250.0
    lower_n: float = 10.0
    hold_steps: int = 10
    start_n: float = 1200.0
    actuator: PreloadActuator = field(default_factory=PreloadActuator)

    def __post_init__(self) -> None:
        self.name = "feedback rule"

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        o = self._batch(obs)
        n = o.shape[0]
        if state is None:
            state = np.column_stack([np.full(n, self.start_n), np.zeros(n)])
        state = np.array(state, dtype=np.float64)
        if episode_start is not None:
            starts = np.asarray(episode_start, dtype=bool)
            state[starts, 0] = self.start_n
            state[starts, 1] = 0.0
        qpi = o[:, _QPI]
        bad = qpi > self.high
        quiet = qpi < self.low
        state[bad, 0] += self.raise_n
        state[bad, 1] = 0.0
        state[quiet, 1] += 1.0
        lower = quiet & (state[:, 1] > self.hold_steps)
        state[lower, 0] -= self.lower_n
        a = self.actuator
        state[:, 0] = np.clip(state[:, 0], a.min_preload_n, a.max_preload_n)
        return self.preload_to_action(state[:, 0]), state


class OraclePreload(Policy):
    """Critical preload of the true operating point (from the stability map) plus ``margin_n``.

    The evaluation loop tells it the true conditions through :meth:`set_conditions` before each
    ``predict`` (it cannot be read from the observation: radial load and clearance are hidden).
    """

    def __init__(self, table: StabilityTable, margin_n: float = 100.0,
                 actuator: PreloadActuator | None = None):
        super().__init__(actuator)
        self.table = table
        self.margin_n = float(margin_n)
        self.name = f"oracle (+{self.margin_n:.0f} N)"
        self._conditions: np.ndarray | None = None

    def set_conditions(self, speed_rpm: np.ndarray, radial_load_n: np.ndarray, clearance_m: np.ndarray,
                       eccentricity_m: np.ndarray | None = None) -> None:
        """The true operating point; ``eccentricity_m`` is accepted (the evaluation loop tells every
        oracle the unbalance) and ignored: the stability table is at the paper's 10 um."""
        self._conditions = np.column_stack([speed_rpm, radial_load_n, clearance_m])

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        if self._conditions is None:
            raise RuntimeError("OraclePreload needs set_conditions(speed, radial_load, clearance) before predict")
        c = self._conditions
        return self.preload_to_action(self.table.critical(c[:, 0], c[:, 1], c[:, 2]) + self.margin_n), state
