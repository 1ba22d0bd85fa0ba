"""Observation model: normalised features of the last control interval.

Index, feature and scale (all float32, clipped to the Box [-10, 10]):

==  =====================  ===============================================================
0   ``ptp_x``              peak-to-peak x over the interval / 100 um
1   ``ptp_y``              peak-to-peak y / 100 um
2   ``ptp_z``              peak-to-peak z / 100 um
3   ``rms_x``              RMS of x about its mean / 50 um
4   ``rms_y``              RMS of y / 50 um
5   ``rms_z``              RMS of z / 50 um
6   ``cage_speed_ratio``   10 * (mean cage speed / kinematic cage speed - 1); the kinematic
                           value is omega/2 (1 - gamma cos alpha_0) (0.4383 omega here)
7   ``cage_speed_ptp``     10 * peak-to-peak cage speed / kinematic cage speed
8   ``qpi``                quasi-periodicity index (analysis.signals): ~0.01-0.05 periodic,
                           0.5-1.4 quasi-periodic or chaotic
9   ``preload``            actual preload mapped to [-1, 1] over [min_preload_n, max_preload_n]
10  ``setpoint``           last set-point, same mapping (= the last action)
11  ``shaft_speed``        shaft speed / 25,000 rpm
12  ``radial_offset``      mean radial displacement sqrt(mean x^2 + mean y^2) / 100 um: the
                           static offset a displacement probe reads; it carries the radial
                           load (about 50-130 um at 500 N, 0 without), the strongest factor
                           of the critical preload
13  ``axial_offset``       mean axial displacement z / 100 um: carries the clearance (axial
                           play: about -50 um at 4 um clearance, +40 um at 30 um) and preload
==  =====================  ===============================================================

At reset the rotor sits at its static equilibrium, so the offsets are its x, y, z there and the
interval features 0-8 are zero (no motion yet).

Optional sensor noise: Gaussian, standard deviation ``noise_std`` (in observation units) added
to the measured features (0-8, 12, 13), drawn from the environment's ``np_random``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from gymnasium import spaces

from bearing_gym.analysis.window import (F_CAGE_MEAN, F_CAGE_PTP, F_MEAN_X, F_PTP_X, F_QPI,
                                       F_RMS_X)

__all__ = ["ObservationModel", "FEATURE_NAMES"]

FEATURE_NAMES = ("ptp_x", "ptp_y", "ptp_z", "rms_x", "rms_y", "rms_z", "cage_speed_ratio",
                 "cage_speed_ptp", "qpi", "preload", "setpoint", "shaft_speed", "radial_offset",
                 "axial_offset")
OBS_BOUND = 10.0
_MEASURED = np.r_[0:9, 12:14]    # sensor features (noise applies); 9-11 are commands/known


@dataclass(frozen=True)
class ObservationModel:
    noise_std: float = 0.0
    displacement_scale_m: float = 100e-6
    rms_scale_m: float = 50e-6
    speed_scale_rpm: float = 25000.0
    offset_scale_m: float = 100e-6

    @property
    def space(self) -> spaces.Box:
        return spaces.Box(-OBS_BOUND, OBS_BOUND, shape=(len(FEATURE_NAMES),), dtype=np.float32)

    def build(self, feats: np.ndarray, preload_n: np.ndarray, setpoint_n: np.ndarray,
              omega_rad_s: np.ndarray, gamma_cos_a0: float, p_min: float, p_max: float,
              rngs=None) -> np.ndarray:
        """Observations (B, 14) for feature rows ``feats`` (B, N_FEATURES)."""
        b = feats.shape[0]
        obs = np.zeros((b, len(FEATURE_NAMES)))
        obs[:, 0:3] = feats[:, F_PTP_X:F_PTP_X + 3] / self.displacement_scale_m
        obs[:, 3:6] = feats[:, F_RMS_X:F_RMS_X + 3] / self.rms_scale_m
        kin = np.maximum(0.5 * omega_rad_s * (1.0 - gamma_cos_a0), 1e-9)
        obs[:, 6] = 10.0 * (feats[:, F_CAGE_MEAN] / kin - 1.0)
        obs[:, 7] = 10.0 * feats[:, F_CAGE_PTP] / kin
        obs[:, 8] = feats[:, F_QPI]
        obs[:, 9] = 2.0 * (preload_n - p_min) / (p_max - p_min) - 1.0
        obs[:, 10] = 2.0 * (setpoint_n - p_min) / (p_max - p_min) - 1.0
        obs[:, 11] = omega_rad_s * 30.0 / math.pi / self.speed_scale_rpm
        obs[:, 12] = np.hypot(feats[:, F_MEAN_X], feats[:, F_MEAN_X + 1]) / self.offset_scale_m
        obs[:, 13] = feats[:, F_MEAN_X + 2] / self.offset_scale_m
        if self.noise_std > 0.0 and rngs is not None:
            for i, rng in enumerate(rngs):
                obs[i, _MEASURED] += rng.normal(0.0, self.noise_std, size=len(_MEASURED))
        obs = np.nan_to_num(obs, nan=0.0, posinf=OBS_BOUND, neginf=-OBS_BOUND)
        return np.clip(obs, -OBS_BOUND, OBS_BOUND).astype(np.float32)
