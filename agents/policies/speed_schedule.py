"""The spindle makers' practice: preload switched by shaft speed.

A machine-tool spindle with a variable-preload unit (hydraulic or pneumatic) runs a high preload
at low speed (stiffness for roughing) and switches to a lower one above a speed threshold (less
heat and centrifugal contact load), sometimes in three steps, sometimes along a table. These are
those rules, reading only the observed shaft speed:

* :class:`SpeedSchedule` with ``interpolate=False``: level ``levels_n[k]`` while the speed is in
  ``[thresholds_rpm[k-1], thresholds_rpm[k])`` (2 levels: one threshold; 3 levels: two);
* with ``interpolate=True``: a table, the preload linear in the speed between
  ``(thresholds_rpm[k], levels_n[k])`` knots and held beyond the first and the last.

:mod:`agents.references.speed_schedule_fit` fits their levels (and thresholds) on training seeds.
"""

from __future__ import annotations

import numpy as np

from bearing_gym.envs.actuator import PreloadActuator
from bearing_gym.envs.observation import FEATURE_NAMES, ObservationModel

from agents.policies.scripted import Policy

__all__ = ["SpeedSchedule", "SPEED_SCALE_RPM"]

_SPEED = FEATURE_NAMES.index("shaft_speed")
#: the observation's shaft-speed scaling (the feature is the speed / this), the sensor model's
SPEED_SCALE_RPM = ObservationModel.speed_scale_rpm


class SpeedSchedule(Policy):
    """Preload by the observed shaft speed (module docstring). Switched: ``len(levels_n) ==
    len(thresholds_rpm) + 1``; a table (``interpolate``): one level per knot, at least two."""

    def __init__(self, thresholds_rpm, levels_n, interpolate: bool = False,
                 actuator: PreloadActuator | None = None):
        super().__init__(actuator)
        t = np.asarray(thresholds_rpm, dtype=float)
        if t.ndim != 1 or not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0):
            raise ValueError(f"thresholds_rpm must be increasing speeds (rpm), got {thresholds_rpm}")
        want = len(t) if interpolate else len(t) + 1
        if len(levels_n) != want or (interpolate and len(t) < 2):
            raise ValueError(("a table needs one level per knot, at least 2" if interpolate else
                              "a switch needs one level more than thresholds")
                             + f": got {len(t)} thresholds and {len(levels_n)} levels")
        a = self.actuator
        bad = [p for p in levels_n if not a.min_preload_n <= p <= a.max_preload_n]
        if bad:
            raise ValueError(f"levels_n must be in [{a.min_preload_n}, {a.max_preload_n}] N, got {bad}")
        self.thresholds_rpm = tuple(float(x) for x in t)
        self.levels_n = tuple(float(x) for x in levels_n)
        self.interpolate = bool(interpolate)
        self.name = "speed table" if self.interpolate else f"speed switch ({len(self.levels_n)} levels)"

    def preload_n(self, speed_rpm: np.ndarray) -> np.ndarray:
        """The schedule's preload (N) at each speed (rpm): arithmetic only (no libm), as
        everything that feeds the state."""
        s = np.asarray(speed_rpm, dtype=np.float64)
        t, lv = np.asarray(self.thresholds_rpm), np.asarray(self.levels_n)
        if self.interpolate:
            return np.interp(s, t, lv)
        return lv[np.searchsorted(t, s, side="right")]

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        o = self._batch(obs)
        return self.preload_to_action(self.preload_n(o[:, _SPEED] * SPEED_SCALE_RPM)), state

    def to_json(self) -> dict:
        return {"thresholds_rpm": list(self.thresholds_rpm), "levels_n": list(self.levels_n),
                "interpolate": self.interpolate}

    @classmethod
    def from_json(cls, d: dict) -> "SpeedSchedule":
        return cls(d["thresholds_rpm"], d["levels_n"], bool(d.get("interpolate", False)))
