"""Operating scenarios of the preload-control problem: what the spindle does during an episode.

A :class:`Scenario` fixes one episode's operating conditions: shaft speed (constant or a linear
ramp), a radial-load step, the bearing clearance, race waviness and rotor unbalance. A
:class:`ScenarioDistribution` draws scenarios from ranges with the environment's ``np_random``;
``reset(options=...)`` can pin any field. Presets: ``"paper"`` (the paper's section 3.2 case)
and ``"randomized"`` (the default).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any, Mapping

import numpy as np

__all__ = ["Scenario", "ScenarioDistribution", "PRESETS", "scenario_distribution"]


@dataclass(frozen=True)
class Scenario:
    """One episode's operating conditions (SI units; speeds in rpm as engineers quote them).

    The speed ramps linearly from ``speed_start_rpm`` to ``speed_end_rpm`` between
    ``ramp_start_s`` and ``ramp_end_s`` (equal speeds: constant). The radial load is
    ``radial_load_before_n`` until ``radial_step_time_s`` and ``radial_load_after_n`` after, in
    the direction ``radial_load_angle_rad`` from x. ``waviness_amplitude_m`` is the radial
    waviness of both races, order ``waviness_order`` (eqs 9-10).
    """

    speed_start_rpm: float = 20000.0
    speed_end_rpm: float = 20000.0
    ramp_start_s: float = 0.0
    ramp_end_s: float = 0.0
    radial_load_before_n: float = 0.0
    radial_load_after_n: float = 0.0
    radial_step_time_s: float = 0.0
    radial_load_angle_rad: float = math.pi / 4
    clearance_m: float = 4e-6
    waviness_amplitude_m: float = 0.0
    waviness_order: int = 18
    eccentricity_m: float = 1e-5
    initial_preload_n: float = 1000.0

    def __post_init__(self) -> None:
        from bearing_gym.params import _check_int, _check_real
        for name, lo, hi in (("speed_start_rpm", 1000.0, 60000.0), ("speed_end_rpm", 1000.0, 60000.0),
                             ("ramp_start_s", 0.0, 1e4), ("ramp_end_s", 0.0, 1e4),
                             ("radial_load_before_n", 0.0, 5000.0), ("radial_load_after_n", 0.0, 5000.0),
                             ("radial_step_time_s", 0.0, 1e4), ("radial_load_angle_rad", -10.0, 10.0),
                             ("clearance_m", 0.0, 1e-4), ("waviness_amplitude_m", 0.0, 1e-5),
                             ("eccentricity_m", 0.0, 1e-3), ("initial_preload_n", 0.0, 1e5)):
            object.__setattr__(self, name, _check_real(f"scenario {name}", getattr(self, name), lo, hi))
        object.__setattr__(self, "waviness_order", _check_int("scenario waviness_order", self.waviness_order, 1, 1000))
        if self.ramp_end_s < self.ramp_start_s:
            raise ValueError(f"scenario ramp_end_s ({self.ramp_end_s}) must be >= ramp_start_s ({self.ramp_start_s})")

    def shaft_speed_rpm_at(self, t: float) -> float:
        if t <= self.ramp_start_s or self.ramp_end_s <= self.ramp_start_s:
            return self.speed_start_rpm if t <= self.ramp_start_s else self.speed_end_rpm
        if t >= self.ramp_end_s:
            return self.speed_end_rpm
        f = (t - self.ramp_start_s) / (self.ramp_end_s - self.ramp_start_s)
        return self.speed_start_rpm + f * (self.speed_end_rpm - self.speed_start_rpm)

    def schedule_array(self) -> np.ndarray:
        """The operating-point schedule as the float64 row the step kernel reads (see kernel.py)."""
        c, s = math.cos(self.radial_load_angle_rad), math.sin(self.radial_load_angle_rad)
        rpm2rad = math.pi / 30.0
        return np.array([self.speed_start_rpm * rpm2rad, self.speed_end_rpm * rpm2rad,
                         self.ramp_start_s, self.ramp_end_s,
                         self.radial_load_before_n * c, self.radial_load_before_n * s,
                         self.radial_load_after_n * c, self.radial_load_after_n * s,
                         self.radial_step_time_s])


# ranges for ScenarioDistribution: (low, high) draws uniformly, a number is fixed
_Range = tuple[float, float] | float


@dataclass(frozen=True)
class ScenarioDistribution:
    """Ranges from which :meth:`sample` draws a :class:`Scenario`.

    ``speed_rpm``: start and end speeds are drawn independently in this range; with probability
    ``ramp_probability`` the episode ramps between them (over a random part of the episode),
    otherwise the start speed holds. ``radial_load_n``: the load after the step (before the step
    it is zero with probability 1/2, else the same draw); the step time is uniform over the
    episode. Clearance, waviness amplitude, eccentricity and initial preload are uniform.
    """

    speed_rpm: _Range = (10000.0, 25000.0)
    ramp_probability: float = 0.5
    radial_load_n: _Range = (0.0, 500.0)
    clearance_m: _Range = (4e-6, 30e-6)
    waviness_amplitude_m: _Range = (0.0, 1e-6)
    eccentricity_m: _Range = (0.5e-5, 2e-5)
    initial_preload_n: _Range = (800.0, 2000.0)

    def sample(self, rng: np.random.Generator, episode_s: float,
               pinned: Mapping[str, Any] | None = None) -> Scenario:
        def draw(r: _Range) -> float:
            if isinstance(r, (int, float)):
                return float(r)
            return float(rng.uniform(r[0], r[1]))

        v0, v1 = draw(self.speed_rpm), draw(self.speed_rpm)
        ramp = rng.uniform() < self.ramp_probability
        a, b = sorted(rng.uniform(0.0, episode_s, size=2))
        fr = draw(self.radial_load_n)
        before = 0.0 if rng.uniform() < 0.5 else fr
        fields = dict(
            speed_start_rpm=v0, speed_end_rpm=v1 if ramp else v0,
            ramp_start_s=float(a) if ramp else 0.0, ramp_end_s=float(b) if ramp else 0.0,
            radial_load_before_n=before, radial_load_after_n=fr,
            radial_step_time_s=float(rng.uniform(0.0, episode_s)),
            radial_load_angle_rad=float(rng.uniform(0.0, 2.0 * math.pi)),
            clearance_m=draw(self.clearance_m), waviness_amplitude_m=draw(self.waviness_amplitude_m),
            eccentricity_m=draw(self.eccentricity_m), initial_preload_n=draw(self.initial_preload_n))
        if pinned:
            fields.update(_check_pinned(pinned))
        return Scenario(**fields)


PAPER = Scenario(speed_start_rpm=20000.0, speed_end_rpm=20000.0, clearance_m=4e-6,
                 radial_load_before_n=0.0, radial_load_after_n=0.0, eccentricity_m=1e-5,
                 waviness_amplitude_m=0.0, initial_preload_n=1000.0)


@dataclass(frozen=True)
class FixedScenario:
    """A 'distribution' that always returns the same scenario (plus pinned fields)."""

    scenario: Scenario

    def sample(self, rng: np.random.Generator, episode_s: float,
               pinned: Mapping[str, Any] | None = None) -> Scenario:
        if not pinned:
            return self.scenario
        return dataclasses.replace(self.scenario, **_check_pinned(pinned))


PRESETS: dict[str, ScenarioDistribution | FixedScenario] = {
    "paper": FixedScenario(PAPER),
    "randomized": ScenarioDistribution(),
}

_SCENARIO_FIELDS = {f.name for f in dataclasses.fields(Scenario)}
# convenient aliases accepted in reset(options=...)
_ALIASES = {"shaft_speed_rpm": ("speed_start_rpm", "speed_end_rpm"),
            "radial_load_n": ("radial_load_before_n", "radial_load_after_n")}


def _check_pinned(pinned: Mapping[str, Any]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, value in pinned.items():
        if key in _ALIASES:
            for f in _ALIASES[key]:
                out[f] = value
        elif key in _SCENARIO_FIELDS:
            out[key] = value
        else:
            raise ValueError(f"unknown scenario option {key!r}; valid: "
                             f"{', '.join(sorted(_SCENARIO_FIELDS | set(_ALIASES)))}")
    return out


def scenario_distribution(scenario: str | Scenario | ScenarioDistribution | FixedScenario):
    """Resolve the env's ``scenario`` argument to an object with ``sample``."""
    if isinstance(scenario, str):
        if scenario not in PRESETS:
            raise ValueError(f"unknown scenario preset {scenario!r}; valid: {sorted(PRESETS)}")
        return PRESETS[scenario]
    if isinstance(scenario, Scenario):
        return FixedScenario(scenario)
    if hasattr(scenario, "sample"):
        return scenario
    raise ValueError(f"scenario must be a preset name, a Scenario or a ScenarioDistribution, got {scenario!r}")
