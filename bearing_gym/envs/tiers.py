"""The benchmark's difficulty tiers: presets of the env's parts, and the one horizon.

``gym.make("BearingPreload-v0", tier=...)``; the default tier, ``"transient"``, is the main
benchmark. Every tier has the same horizon (``EPISODE_STEPS`` control intervals of
``CONTROL_DT_S``), actuator and reward; they differ in what happens during an episode and in
what the sensor sees.

==============  ==============================================================================
tier            what a good policy must do
==============  ==============================================================================
``paper``       The paper's operating point (20,000 rpm, c = 4 um, no radial load, e = 10 um,
                no waviness) from 1000 N: find the lowest preload of the periodic band and
                hold it. One scenario; a benchmark of optimisation, not of control.
``stationary``  A random operating point (speed 10,000-25,000 rpm, radial load 0-500 N,
                clearance 4-30 um, race waviness 0-1 um, unbalance 5-20 um), constant for the
                episode, from a random preload (300-2000 N): identify the operating point
                from the response and hold the best preload. The stability map has isolated
                windows, so "just above the critical preload" is not enough.
``transient``   As ``stationary``, plus three events per episode at random times between 20 %
                and 85 % of it, at least 0.5 s apart: speed ramps (0.1-0.4 s, by at least
                4000 rpm) and radial-load steps (by at least 200 N), up or down. The best
                preload before an event is often wrong after it: closed-loop tracking.
``field``       ``transient`` as a real spindle would present it: displacement-probe noise
                (0.3 um RMS), target runout (up to 3 um), an unknown calibration offset
                (+-5 um) drifting (2 um / sqrt(s)), no cage-speed sensor, and a wider spread of
                waviness (0-2 um) and unbalance (5-30 um) that the agent cannot observe directly.
==============  ==============================================================================
"""

from __future__ import annotations

from typing import Any

from bearing_gym.task import CONTROL_DT_S, DEFAULT_TIER, EPISODE_STEPS, TIER_NAMES

from .actuator import PreloadActuator
from .observation import ObservationModel
from .reward import VibrationFirstReward
from .scenario import PAPER, FixedScenario, ScenarioDistribution

__all__ = ["TIERS", "DEFAULT_TIER", "EPISODE_STEPS", "CONTROL_DT_S", "tier_parts", "tier_is_deterministic"]


_STATIONARY = ScenarioDistribution()
_TRANSIENT = ScenarioDistribution(events=3)
_FIELD = ScenarioDistribution(events=3, waviness_amplitude_m=(0.0, 2e-6), eccentricity_m=(0.5e-5, 3e-5))
_FIELD_SENSOR = ObservationModel(displacement_noise_m=0.3e-6, runout_max_m=3e-6, offset_bias_m=5e-6,
                                 offset_drift_m_per_sqrt_s=2e-6, cage_speed_sensor=False)

TIERS: dict[str, dict[str, Any]] = {
    "paper": {"scenario": FixedScenario(PAPER), "observation": ObservationModel()},
    "stationary": {"scenario": _STATIONARY, "observation": ObservationModel()},
    "transient": {"scenario": _TRANSIENT, "observation": ObservationModel()},
    "field": {"scenario": _FIELD, "observation": _FIELD_SENSOR},
}


assert tuple(TIERS) == TIER_NAMES, "bearing_gym.task.TIER_NAMES must name the tiers in order"


def tier_parts(tier: str) -> dict[str, Any]:
    """The parts of ``tier`` (scenario, observation, actuator, reward)."""
    if tier not in TIERS:
        raise ValueError(f"unknown tier {tier!r}; valid: {', '.join(TIERS)}")
    return dict(TIERS[tier], actuator=PreloadActuator(), reward=VibrationFirstReward())


def tier_is_deterministic(tier: str) -> bool:
    """True if every seed gives ``tier`` the same episode under a deterministic policy: its
    scenario distribution and its sensor draw nothing at random (their ``deterministic``; a part
    without that attribute counts as random). The actuator, reward and simulator are
    deterministic. Of the built-in tiers only ``paper`` is."""
    parts = tier_parts(tier)
    return all(bool(getattr(parts[name], "deterministic", False)) for name in ("scenario", "observation"))
