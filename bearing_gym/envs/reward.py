"""Reward model: minus a weighted sum of four costs per control interval.

==================  =====================================================================
term                cost (dimensionless, per control interval)
==================  =====================================================================
vibration           quasi-periodicity index of the interval (~0.02 periodic, ~1 quasi-periodic)
heat                preload-dependent friction heat relative to 1 kN at 20,000 rpm:
                    (P / 1000 N) (omega / omega_ref). Palmgren: the load-dependent friction
                    torque is M_1 = f_1 P d_m, and its heat M_1 omega.
fatigue             rate of fatigue-life consumption relative to 1 kN at 20,000 rpm (ISO 281,
                    L10 = (C / P_eq)^3 revolutions): (P_eq / 1000 N)^3 (omega / omega_ref), with
                    the equivalent load P_eq = 0.41 F_r + 0.87 F_a (X, Y for a 25 deg angular-
                    contact bearing, F_a / F_r > e).
preload_change      |change of the actual preload over the interval| / 1000 N
==================  =====================================================================

reward = -(w_vibration * vibration + w_heat * heat + w_fatigue * fatigue
           + w_preload_change * preload_change)

With the default weights a quasi-periodic interval (index ~0.8) costs ~1.6, while moving the
preload from 700 N to 1000 N costs ~0.1 in heat and fatigue: the best constant preload is the
lowest one that keeps the motion periodic (docs/environment.md shows the sweep).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from bearing_gym.params import _check_real

__all__ = ["RewardModel", "REWARD_TERMS"]

REWARD_TERMS = ("vibration", "heat", "fatigue", "preload_change")


@dataclass(frozen=True)
class RewardModel:
    w_vibration: float = 2.0
    w_heat: float = 0.3
    w_fatigue: float = 0.1
    w_preload_change: float = 0.1
    reference_speed_rpm: float = 20000.0
    reference_load_n: float = 1000.0
    termination_penalty: float = 10.0

    def __post_init__(self) -> None:
        for name in ("w_vibration", "w_heat", "w_fatigue", "w_preload_change", "termination_penalty"):
            _check_real(name, getattr(self, name), 0.0, 1e6)
        _check_real("reference_speed_rpm", self.reference_speed_rpm, 0.0, 1e6, low_open=True)
        _check_real("reference_load_n", self.reference_load_n, 0.0, 1e9, low_open=True)

    def terms(self, qpi: np.ndarray, preload_n: np.ndarray, preload_before_n: np.ndarray,
              omega_rad_s: np.ndarray, radial_load_n: np.ndarray) -> dict[str, np.ndarray]:
        """Weighted contributions to the reward (each <= 0), keyed by REWARD_TERMS."""
        speed = omega_rad_s / (self.reference_speed_rpm * math.pi / 30.0)
        p_eq = 0.41 * radial_load_n + 0.87 * preload_n
        return {
            "vibration": -self.w_vibration * qpi,
            "heat": -self.w_heat * preload_n / self.reference_load_n * speed,
            "fatigue": -self.w_fatigue * (p_eq / self.reference_load_n) ** 3 * speed,
            "preload_change": -self.w_preload_change * np.abs(preload_n - preload_before_n) / self.reference_load_n,
        }
