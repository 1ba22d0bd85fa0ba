"""Gymnasium environments: env = physics + scenario + actuator + sensor + reward.

The parts are swappable (:mod:`.parts`); the difficulty tiers are presets of them
(:mod:`.tiers`).
"""

from .actuator import Actuator, PreloadActuator
from .bearing_preload import BearingPreloadEnv
from .core import env_params
from .measurement import StepMeasurement
from .observation import FEATURE_NAMES, ObservationModel, Sensor
from .privileged import PRIVILEGED_FEATURE_NAMES, PrivilegedObservation, PrivilegedObservationVector
from .reward import REWARD_TERMS, Reward, VibrationFirstReward, constrained_reward
from .scenario import PAPER, FixedScenario, Scenario, ScenarioDistribution, ScenarioSampler
from .tiers import CONTROL_DT_S, DEFAULT_TIER, EPISODE_STEPS, TIERS
from .vector import BearingPreloadVectorEnv

__all__ = ["BearingPreloadEnv", "BearingPreloadVectorEnv", "BearingPreloadSB3VecEnv",
           "Actuator", "PreloadActuator", "Sensor", "ObservationModel", "Reward",
           "VibrationFirstReward", "StepMeasurement", "Scenario", "ScenarioDistribution",
           "FixedScenario", "ScenarioSampler", "PAPER", "TIERS", "DEFAULT_TIER", "EPISODE_STEPS",
           "CONTROL_DT_S", "FEATURE_NAMES", "REWARD_TERMS", "env_params", "constrained_reward",
           "PrivilegedObservation", "PrivilegedObservationVector", "PRIVILEGED_FEATURE_NAMES"]


def __getattr__(name):  # the SB3 adapter imports torch: load it only on demand
    if name == "BearingPreloadSB3VecEnv":
        from .sb3 import BearingPreloadSB3VecEnv
        return BearingPreloadSB3VecEnv
    raise AttributeError(name)
