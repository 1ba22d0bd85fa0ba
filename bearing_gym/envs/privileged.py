"""The privileged observation: the hidden scenario parameters beside the sensor's features, for
asymmetric actor-critic (a critic that sees them) and system-identification research.

    env = PrivilegedObservation(gymnasium.make("BearingPreload-v0"))           # 15 + 5 features
    venv = PrivilegedObservationVector(BearingPreloadVectorEnv(num_envs=8))

What a real spindle does not measure, per control interval (after the sensor's 15 features,
:data:`PRIVILEGED_FEATURE_NAMES`, scaled to about [-1, 1] like them):

==  ===================  =============================================================  =========
#   name                 what                                                           scaling
==  ===================  =============================================================  =========
15  ``unbalance``        rotor mass eccentricity (the scenario's ``eccentricity_m``)    / 30 um
16  ``clearance``        the bearing's radial clearance (``clearance_m``)               / 30 um
17  ``waviness``         race waviness amplitude (``waviness_amplitude_m``)             / 2 um
18  ``radial_load``      the radial load acting now (the scenario's load profile)       / 500 N
19  ``speed_setpoint``   the speed the shaft is heading to: the speed profile's next    / 25,000 rpm
                         knot after now (its last once past every knot)
==  ===================  =============================================================  =========

The scales are the tiers' envelope (unbalance 5-30 um, clearance 4-30 um, waviness 0-2 um, radial
load 0-500 N, 10,000-25,000 rpm). **Never in a board's main rows**: the benchmark's policies read
the sensor's observation alone (docs/benchmark.md, the rules); the scoring API
(:mod:`agents.submit`) feeds a policy the plain observation, so a policy that needs these cannot
be scored there. The env's ``info`` has the radial load and the true quasi-periodicity index too:
privileged in the same sense.
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces
from gymnasium.vector import VectorEnv, VectorObservationWrapper

from .scenario import Scenario

__all__ = ["PRIVILEGED_FEATURE_NAMES", "PRIVILEGED_SCALES", "privileged_features", "PrivilegedObservation",
           "PrivilegedObservationVector"]

PRIVILEGED_FEATURE_NAMES = ("unbalance", "clearance", "waviness", "radial_load", "speed_setpoint")
#: what each privileged feature is divided by (SI units: m, m, m, N, rpm)
PRIVILEGED_SCALES = (30e-6, 30e-6, 2e-6, 500.0, 25000.0)


def speed_setpoint_rpm(scenario: Scenario, t_s: float) -> float:
    """The speed the shaft is heading to at ``t_s`` (s into the episode): the speed profile's
    first knot after ``t_s``, else its last knot's speed."""
    for t_k, rpm in scenario.speed_profile:
        if t_k > t_s:
            return float(rpm)
    return float(scenario.speed_profile[-1][1])


def privileged_features(scenario: Scenario, t_s: float, radial_load_n: float) -> np.ndarray:
    """The five privileged features (module docstring) of ``scenario`` at ``t_s`` with the
    radial load acting now, scaled, float32."""
    raw = (scenario.eccentricity_m, scenario.clearance_m, scenario.waviness_amplitude_m, radial_load_n,
           speed_setpoint_rpm(scenario, t_s))
    return np.array([v / s for v, s in zip(raw, PRIVILEGED_SCALES)], dtype=np.float32)


def _space(base: spaces.Box) -> spaces.Box:
    n = base.shape[0] + len(PRIVILEGED_FEATURE_NAMES)
    return spaces.Box(float(np.min(base.low)), float(np.max(base.high)), shape=(n,), dtype=base.dtype)


def _check_base(env: Any, what: str) -> None:
    u = env.unwrapped
    if not (hasattr(u, "batch") and hasattr(u, "task")):
        raise TypeError(f"{what} wraps a BearingPreload env (gymnasium.make('BearingPreload-v0') or "
                        f"BearingPreloadVectorEnv), got {type(u).__name__}")


class PrivilegedObservation(gym.ObservationWrapper):
    """The single env's observation with the five privileged features appended (module
    docstring); ``Box(-10, 10, (20,), float32)`` on the default observation model."""

    def __init__(self, env: gym.Env):
        _check_base(env, "PrivilegedObservation")
        super().__init__(env)
        self.observation_space = _space(env.observation_space)

    def observation(self, observation: np.ndarray) -> np.ndarray:
        u = self.env.unwrapped
        extra = privileged_features(u.scenario, float(u.batch.t_episode[0]), float(u.batch.radial_load_n()[0]))
        return np.concatenate([np.asarray(observation, dtype=np.float32), extra])


class PrivilegedObservationVector(VectorObservationWrapper):
    """:class:`PrivilegedObservation` for :class:`~bearing_gym.envs.BearingPreloadVectorEnv`:
    every env's row gets its own scenario's features."""

    def __init__(self, env: VectorEnv):
        _check_base(env, "PrivilegedObservationVector")
        super().__init__(env)
        self.single_observation_space = _space(env.single_observation_space)
        self.observation_space = gym.vector.utils.batch_space(self.single_observation_space, env.num_envs)

    def observations(self, observations: np.ndarray) -> np.ndarray:
        b = self.env.unwrapped.batch
        t, radial = b.t_episode, b.radial_load_n()
        extra = np.stack([privileged_features(sc, float(t[i]), float(radial[i]))
                          for i, sc in enumerate(b.scenarios)])
        return np.concatenate([np.asarray(observations, dtype=np.float32), extra], axis=1)
