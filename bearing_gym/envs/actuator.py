"""The preload actuator between the agent's set-point and the bearing.

An action a in [-1, 1] maps linearly to a set-point in [min_preload_n, max_preload_n]. The
actuator (a hydraulic or piezo preload unit) follows the set-point as a first-order lag with
time constant ``time_constant_s``, and its rate of change is limited to ``slew_rate_n_per_s``.
The step kernel applies it every ``update_interval_s`` (1 ms) inside the control interval.

An actuator model is any object with ``min_preload_n``, ``max_preload_n``,
``update_interval_s``, ``setpoint_n(action) -> N`` (any mapping: a dead band, quantisation,
a nonlinear valve characteristic), ``action_for(preload_n)`` (its inverse, for scripted
policies) and ``as_array() -> [time_constant_s, slew_rate_n_per_s]``: the lag and the rate
limit the kernel applies (the dynamics run inside the numba kernel, so their form is this
first-order lag with a rate limit; the numbers are the actuator's: time constant >= 0, slew rate
> 0). ``update_interval_s`` must be a whole multiple of the integrator step (25 us in the env)
and the env's control interval a whole multiple of ``update_interval_s``; the env refuses other
values with the nearest valid ones rather than round them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol, runtime_checkable

import numpy as np
from numba import njit

from bearing_gym.physics.portable_math import exp
from bearing_gym.validation import check_real

from .parts import part_entry_point

__all__ = ["Actuator", "PreloadActuator", "actuator_update"]


@runtime_checkable
class Actuator(Protocol):
    """What the env needs of an actuator model (see the module docstring)."""

    min_preload_n: float
    max_preload_n: float
    update_interval_s: float

    def setpoint_n(self, action: np.ndarray) -> np.ndarray: ...

    def action_for(self, preload_n: float) -> float: ...

    def as_array(self) -> np.ndarray: ...


@dataclass(frozen=True)
class PreloadActuator:
    min_preload_n: float = 300.0
    max_preload_n: float = 2000.0
    time_constant_s: float = 0.02
    slew_rate_n_per_s: float = 20000.0
    update_interval_s: float = 1e-3
    entry_point: str = field(default="", init=False)

    def __post_init__(self) -> None:
        lo = check_real("min_preload_n", self.min_preload_n, 0.0, 1e5)
        check_real("max_preload_n", self.max_preload_n, lo, 1e5, low_open=True)
        check_real("time_constant_s", self.time_constant_s, 0.0, 10.0)
        check_real("slew_rate_n_per_s", self.slew_rate_n_per_s, 0.0, 1e9, low_open=True)
        check_real("update_interval_s", self.update_interval_s, 0.0, 1.0, low_open=True)
        part_entry_point(self)

    def setpoint_n(self, action: np.ndarray) -> np.ndarray:
        """Set-point (N) for actions in [-1, 1] (already validated by the env)."""
        a = np.asarray(action, dtype=np.float64)
        return self.min_preload_n + 0.5 * (a + 1.0) * (self.max_preload_n - self.min_preload_n)

    def action_for(self, preload_n: float) -> float:
        """Inverse of :meth:`setpoint_n` (for scripted policies)."""
        return 2.0 * (preload_n - self.min_preload_n) / (self.max_preload_n - self.min_preload_n) - 1.0

    def as_array(self) -> np.ndarray:
        return np.array([self.time_constant_s, self.slew_rate_n_per_s], dtype=np.float64)


@njit(cache=True, inline="always")
def actuator_update(preload, setpoint, h, time_constant, slew_rate):
    """Preload after ``h`` seconds: first-order lag towards the set-point, rate-limited."""
    if time_constant > 0.0:
        change = (setpoint - preload) * (1.0 - exp(-h / time_constant))
    else:
        change = setpoint - preload
    limit = slew_rate * h
    if change > limit:
        change = limit
    elif change < -limit:
        change = -limit
    return preload + change
