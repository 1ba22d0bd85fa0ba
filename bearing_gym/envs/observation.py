"""Sensor models: what the agent observes of a control interval.

A sensor model is any object with

* ``space``: the observation ``gymnasium.spaces.Box`` of one environment;
* ``make_state(num_envs)``: per-environment sensor state (anything deep-copyable, or None);
* ``reset_state(state, i, rng)``: start environment ``i``'s sensor afresh (a new episode);
* ``__call__(m, state, env_ids, rngs) -> np.ndarray``: observations (len(m), dim) for the
  :class:`~.measurement.StepMeasurement` ``m`` of environments ``env_ids``, drawing any noise
  from their ``rngs``.

The default, :class:`ObservationModel`, gives 15 features (float32, clipped to [-10, 10]):

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
8   ``qpi``                quasi-periodicity index (analysis.signals): ~0.001-0.03 period-1,
                           0.2-1.4 quasi-periodic or chaotic
9   ``preload``            actual preload mapped to [-1, 1] over the actuator's range
10  ``setpoint``           last set-point, same mapping (= the last action)
11  ``shaft_speed``        shaft speed / 25,000 rpm
12  ``radial_offset``      mean radial displacement sqrt(mean x^2 + mean y^2) / 100 um: the
                           static offset a displacement probe reads; it carries the radial
                           load (about 50-130 um at 500 N, 0 without)
13  ``axial_offset``       mean axial displacement z / 100 um: carries the clearance (axial
                           play) and the preload
14  ``nonsync_rms``        RMS of the non-synchronous displacement / 10 um (features.py): the
                           vibration amplitude the reward charges for
==  =====================  ===============================================================

What a real spindle measures, and how (the ``field`` tier models it):

* x, y, z: non-contact (eddy-current or capacitive) displacement probes against the shaft,
  sampled at tens of kHz; a once-per-revolution key (keyphasor) gives the shaft angle, so
  peak-to-peak, RMS, mean, the Poincare section (qpi) and the synchronous fit (nonsync_rms)
  are all computed from probe signals. Their errors: electrical noise (0.1-0.5 um RMS),
  a calibration offset and thermal drift of the zero (micrometres over an episode's scale),
  and target runout (form error and electrical runout of the shaft surface, 1-5 um at 1x),
  which a probe cannot tell from motion.
* shaft speed: the keyphasor or the drive encoder, accurate.
* preload and set-point: the actuator's own force sensor and command.
* cage speed: only instrumented test rigs carry a cage sensor (an optical or magnetic pick-up
  on the cage); production spindles do not. ``cage_speed_sensor=False`` reads 0 for features 6-7.

Sensor errors (all 0 by default, the ``field`` tier sets them), applied to the interval's
features as their expected effect on the computed quantity:

* ``displacement_noise_m`` sigma (white, independent per axis): rms' = sqrt(rms^2 + sigma^2),
  ptp' = ptp + 7 sigma (the expected range of ~2000 Gaussian samples), nonsync' =
  sqrt(nonsync^2 + 3 sigma^2), and the Poincare spread and the size of the qpi both grow by
  3 sigma^2 in quadrature;
* ``runout_max_m``: each episode draws a runout amplitude r uniform in [0, runout_max_m] for
  x and y (synchronous, so nonsync is unchanged): rms' = sqrt(rms^2 + r^2 / 2), ptp' = ptp + 2r,
  and the qpi's size grows by r^2 in quadrature;
* ``offset_bias_m``: each episode draws a calibration offset per axis uniform in
  [-offset_bias_m, offset_bias_m]; ``offset_drift_m_per_sqrt_s``: the offset then walks
  randomly (standard deviation drift * sqrt(t)): features 12-13 read the drifting offset.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Protocol, runtime_checkable

import numpy as np
from gymnasium import spaces

from bearing_gym.physics.portable_math import standard_normal
from bearing_gym.units import rad_s_to_rpm
from bearing_gym.validation import check_real

from .measurement import StepMeasurement
from .parts import part_entry_point

__all__ = ["Sensor", "ObservationModel", "FEATURE_NAMES", "OBS_BOUND"]

FEATURE_NAMES = ("ptp_x", "ptp_y", "ptp_z", "rms_x", "rms_y", "rms_z", "cage_speed_ratio",
                 "cage_speed_ptp", "qpi", "preload", "setpoint", "shaft_speed", "radial_offset",
                 "axial_offset", "nonsync_rms")
OBS_BOUND = 10.0


@runtime_checkable
class Sensor(Protocol):
    """What the env needs of a sensor model (see the module docstring)."""

    @property
    def space(self) -> spaces.Box: ...

    def make_state(self, num_envs: int) -> Any: ...

    def reset_state(self, state: Any, i: int, rng: np.random.Generator) -> None: ...

    def __call__(self, m: StepMeasurement, state: Any, env_ids: np.ndarray, rngs) -> np.ndarray: ...


@dataclass(frozen=True)
class ObservationModel:
    """The default sensor model (module docstring: features, scales, sensor errors)."""

    displacement_scale_m: float = 100e-6
    rms_scale_m: float = 50e-6
    nonsync_scale_m: float = 10e-6
    speed_scale_rpm: float = 25000.0
    offset_scale_m: float = 100e-6
    displacement_noise_m: float = 0.0
    runout_max_m: float = 0.0
    offset_bias_m: float = 0.0
    offset_drift_m_per_sqrt_s: float = 0.0
    cage_speed_sensor: bool = True
    entry_point: str = field(default="", init=False)

    def __post_init__(self) -> None:
        for name in ("displacement_scale_m", "rms_scale_m", "nonsync_scale_m", "speed_scale_rpm",
                     "offset_scale_m"):
            check_real(name, getattr(self, name), 0.0, 1e6, low_open=True)
        for name in ("displacement_noise_m", "runout_max_m", "offset_bias_m", "offset_drift_m_per_sqrt_s"):
            check_real(name, getattr(self, name), 0.0, 1e-3)
        if not isinstance(self.cage_speed_sensor, bool):
            raise ValueError(f"cage_speed_sensor must be True or False, got {self.cage_speed_sensor!r}")
        part_entry_point(self)

    @property
    def deterministic(self) -> bool:
        """True if the sensor adds nothing random: no probe noise, runout or offset."""
        return (self.displacement_noise_m == 0.0 and self.runout_max_m == 0.0 and self.offset_bias_m == 0.0
                and self.offset_drift_m_per_sqrt_s == 0.0)

    @property
    def space(self) -> spaces.Box:
        return spaces.Box(-OBS_BOUND, OBS_BOUND, shape=(len(FEATURE_NAMES),), dtype=np.float32)

    # -- per-episode sensor state: runout amplitude (x, y) and probe offsets (x, y, z) ----------
    def make_state(self, num_envs: int) -> dict[str, np.ndarray]:
        return {"runout_m": np.zeros(num_envs), "offset_m": np.zeros((num_envs, 3)),
                "t_s": np.zeros(num_envs)}

    def reset_state(self, state: dict[str, np.ndarray], i: int, rng: np.random.Generator) -> None:
        state["runout_m"][i] = rng.uniform(0.0, self.runout_max_m) if self.runout_max_m > 0 else 0.0
        state["offset_m"][i] = (rng.uniform(-self.offset_bias_m, self.offset_bias_m, size=3)
                                if self.offset_bias_m > 0 else 0.0)
        state["t_s"][i] = 0.0

    def __call__(self, m: StepMeasurement, state: dict[str, np.ndarray], env_ids: np.ndarray,
                 rngs) -> np.ndarray:
        ptp, rms = m.ptp_m.copy(), m.rms_m.copy()
        ns = m.nonsync_rms_m.copy()
        # products, not ** (NumPy's power dispatches by CPU) and sums in a fixed order
        size2 = rms[:, 0] * rms[:, 0] + rms[:, 1] * rms[:, 1] + rms[:, 2] * rms[:, 2]
        spread2 = (m.qpi * m.qpi) * size2
        sigma = self.displacement_noise_m
        if sigma > 0.0:
            var = sigma * sigma
            rms = np.sqrt(rms * rms + var)
            ptp = ptp + 7.0 * sigma
            ns = np.sqrt(ns * ns + 3.0 * var)
            spread2 = spread2 + 3.0 * var
            size2 = size2 + 3.0 * var
        r = state["runout_m"][env_ids]
        if np.any(r > 0.0):
            rms[:, :2] = np.sqrt(rms[:, :2] * rms[:, :2] + 0.5 * (r * r)[:, None])
            ptp[:, :2] = ptp[:, :2] + 2.0 * r[:, None]
            size2 = size2 + r * r
        qpi = np.where(size2 > 0.0, np.sqrt(spread2 / np.where(size2 > 0.0, size2, 1.0)), 0.0)
        offsets = m.mean_displacement_m + self._drifted_offsets(m, state, env_ids, rngs)
        p_min, p_max = m.preload_range_n
        span = p_max - p_min
        kin = np.maximum(m.kinematic_cage_speed_rad_s, 1e-9)
        obs = np.zeros((len(m), len(FEATURE_NAMES)))
        obs[:, 0:3] = ptp / self.displacement_scale_m
        obs[:, 3:6] = rms / self.rms_scale_m
        if self.cage_speed_sensor:
            obs[:, 6] = 10.0 * (m.cage_speed_mean_rad_s / kin - 1.0)
            obs[:, 7] = 10.0 * m.cage_speed_ptp_rad_s / kin
        obs[:, 8] = qpi
        obs[:, 9] = 2.0 * (m.preload_n - p_min) / span - 1.0
        obs[:, 10] = 2.0 * (m.setpoint_n - p_min) / span - 1.0
        obs[:, 11] = rad_s_to_rpm(m.shaft_speed_rad_s) / self.speed_scale_rpm
        obs[:, 12] = np.sqrt(offsets[:, 0] * offsets[:, 0] + offsets[:, 1] * offsets[:, 1]) / self.offset_scale_m
        obs[:, 13] = offsets[:, 2] / self.offset_scale_m
        obs[:, 14] = ns / self.nonsync_scale_m
        obs = np.nan_to_num(obs, nan=0.0, posinf=OBS_BOUND, neginf=-OBS_BOUND)
        return np.clip(obs, -OBS_BOUND, OBS_BOUND).astype(np.float32)

    def _drifted_offsets(self, m: StepMeasurement, state, env_ids: np.ndarray, rngs) -> np.ndarray:
        """Probe offsets (len(m), 3): the episode's bias plus a random walk in time."""
        if self.offset_drift_m_per_sqrt_s > 0.0:
            for k, i in enumerate(env_ids):
                dt = max(float(m.t_s[k]) - float(state["t_s"][i]), 0.0)
                state["offset_m"][i] += (self.offset_drift_m_per_sqrt_s * math.sqrt(dt)) * standard_normal(rngs[k], 3)
                state["t_s"][i] = float(m.t_s[k])
        return state["offset_m"][env_ids]
