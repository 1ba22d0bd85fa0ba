"""Gymnasium environments: env = physics + scenario + actuator + observation + reward."""

from .actuator import PreloadActuator
from .bearing_preload import BearingPreloadEnv
from .observation import FEATURE_NAMES, ObservationModel
from .reward import REWARD_TERMS, RewardModel
from .scenario import PRESETS, Scenario, ScenarioDistribution
from .vector import BearingPreloadSB3VecEnv, BearingPreloadVectorEnv

__all__ = ["BearingPreloadEnv", "BearingPreloadVectorEnv", "BearingPreloadSB3VecEnv", "PreloadActuator", "ObservationModel", "RewardModel", "Scenario",
           "ScenarioDistribution", "PRESETS", "FEATURE_NAMES", "REWARD_TERMS"]
