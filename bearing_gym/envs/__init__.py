"""Gymnasium environments: env = physics + scenario + actuator + observation + reward."""

from .actuator import PreloadActuator
from .bearing_preload import BearingPreloadEnv
from .observation import FEATURE_NAMES, ObservationModel
from .reward import REWARD_TERMS, RewardModel
from .scenario import PRESETS, Scenario, ScenarioDistribution
from .vector import BearingPreloadVectorEnv

__all__ = ["BearingPreloadEnv", "BearingPreloadVectorEnv", "BearingPreloadSB3VecEnv", "PreloadActuator", "ObservationModel", "RewardModel", "Scenario",
           "ScenarioDistribution", "PRESETS", "FEATURE_NAMES", "REWARD_TERMS"]


def __getattr__(name):  # the SB3 adapter imports torch: load it only on demand
    if name == "BearingPreloadSB3VecEnv":
        from .sb3 import BearingPreloadSB3VecEnv
        return BearingPreloadSB3VecEnv
    raise AttributeError(name)
