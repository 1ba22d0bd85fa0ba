"""Operating scenarios of the preload-control problem: what the spindle does during an episode.

A :class:`Scenario` fixes one episode's operating conditions: a shaft-speed profile (piecewise
linear through knots), a radial-load profile (piecewise constant, stepping at given times), the
bearing clearance, race waviness, rotor unbalance and the initial preload. A scenario
distribution is any object with ``sample(rng, episode_s, pinned) -> Scenario`` drawing from the
environment's ``np_random``; ``reset(options=...)`` pins fields. Two are provided:
:class:`ScenarioDistribution` (a random operating point held for the whole episode, optionally
with random events) and :class:`FixedScenario` (always the same scenario). The difficulty tiers
(:mod:`.tiers`) are presets of them.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any, Mapping, Protocol, runtime_checkable

import numpy as np

from bearing_gym.physics.portable_math import sincos
from bearing_gym.units import rpm_to_rad_s

from .parts import part_entry_point

__all__ = ["Scenario", "ScenarioDistribution", "FixedScenario", "ScenarioSampler", "PAPER",
           "MAX_EVENTS", "SCHEDULE_SIZE"]

MAX_EVENTS = 8                              # knots of the speed profile, steps of the load profile
SCHEDULE_SIZE = 2 + 2 * MAX_EVENTS + 3 * MAX_EVENTS


@runtime_checkable
class ScenarioSampler(Protocol):
    """What the env needs of a scenario distribution."""

    def sample(self, rng: np.random.Generator, episode_s: float,
               pinned: Mapping[str, Any] | None = None) -> "Scenario": ...


def _pairs(name: str, value: Any, width: int) -> tuple[tuple[float, ...], ...]:
    try:
        rows = tuple(tuple(float(x) for x in row) for row in value)
    except (TypeError, ValueError):
        raise ValueError(f"scenario {name} must be a sequence of ({', '.join(['t_s'] + ['value'] * (width - 1))}) "
                         f"tuples, got {value!r}") from None
    if not 1 <= len(rows) <= MAX_EVENTS or any(len(r) != width for r in rows):
        raise ValueError(f"scenario {name} must hold 1 to {MAX_EVENTS} tuples of {width} numbers, got {value!r}")
    times = [r[0] for r in rows]
    if times[0] != 0.0 or any(b <= a for a, b in zip(times, times[1:])):
        raise ValueError(f"scenario {name}: times must start at 0 and increase strictly, got {times}")
    return rows


@dataclass(frozen=True)
class Scenario:
    """One episode's operating conditions (SI units; speeds in rpm as engineers quote them).

    ``speed_profile``: ``((0, rpm_0), (t_1, rpm_1), ...)``: the shaft speed runs linearly from
    knot to knot and holds after the last. ``radial_load_profile``: ``((0, F_0), (t_1, F_1),
    ...)``: the radial load (N) is F_j from t_j on, in the direction ``radial_load_angle_rad``
    from x. ``waviness_amplitude_m`` is the radial waviness of both races, order
    ``waviness_order`` (eqs 9-10). At most ``MAX_EVENTS`` entries each.
    """

    speed_profile: tuple[tuple[float, float], ...] = ((0.0, 20000.0),)
    radial_load_profile: tuple[tuple[float, float], ...] = ((0.0, 0.0),)
    radial_load_angle_rad: float = math.pi / 4
    clearance_m: float = 4e-6
    waviness_amplitude_m: float = 0.0
    waviness_order: int = 18
    eccentricity_m: float = 1e-5
    initial_preload_n: float = 1000.0
    entry_point: str = field(default="", init=False)

    def __post_init__(self) -> None:
        from bearing_gym.validation import check_int, check_real
        speed = _pairs("speed_profile", self.speed_profile, 2)
        for t, v in speed:
            check_real("scenario speed_profile rpm", v, 1000.0, 60000.0)
        load = _pairs("radial_load_profile", self.radial_load_profile, 2)
        for t, f in load:
            check_real("scenario radial_load_profile load (N)", f, 0.0, 5000.0)
        object.__setattr__(self, "speed_profile", speed)
        object.__setattr__(self, "radial_load_profile", load)
        for name, lo, hi in (("radial_load_angle_rad", -10.0, 10.0), ("clearance_m", 0.0, 1e-4),
                             ("waviness_amplitude_m", 0.0, 1e-5), ("eccentricity_m", 0.0, 1e-3),
                             ("initial_preload_n", 0.0, 1e5)):
            object.__setattr__(self, name, check_real(f"scenario {name}", getattr(self, name), lo, hi))
        object.__setattr__(self, "waviness_order", check_int("scenario waviness_order", self.waviness_order, 1, 1000))
        part_entry_point(self)

    @property
    def initial_speed_rpm(self) -> float:
        return self.speed_profile[0][1]

    @property
    def initial_radial_load_n(self) -> float:
        return self.radial_load_profile[0][1]

    def operating_key(self) -> tuple:
        """What fixes the motion at t = 0 (the settled start depends on nothing else)."""
        return (self.initial_speed_rpm, self.initial_radial_load_n, self.radial_load_angle_rad,
                self.clearance_m, self.waviness_amplitude_m, self.waviness_order,
                self.eccentricity_m, self.initial_preload_n)

    def schedule_array(self) -> np.ndarray:
        """The profiles as the float64 row the step kernel reads (``kernel.operating_point``):
        [n_speed, (t, omega rad/s) * MAX_EVENTS, n_load, (t, F_x, F_y) * MAX_EVENTS]."""
        row = np.zeros(SCHEDULE_SIZE)
        row[0] = len(self.speed_profile)
        for k, (t, rpm) in enumerate(self.speed_profile):
            row[1 + 2 * k], row[2 + 2 * k] = t, rpm_to_rad_s(rpm)
        base = 1 + 2 * MAX_EVENTS
        row[base] = len(self.radial_load_profile)
        s, c = sincos(self.radial_load_angle_rad)
        for k, (t, f) in enumerate(self.radial_load_profile):
            row[base + 1 + 3 * k: base + 4 + 3 * k] = (t, f * c, f * s)
        return row


# ranges for ScenarioDistribution: (low, high) draws uniformly, a number is fixed
_Range = tuple[float, float] | float


def _draw(rng: np.random.Generator, r: _Range) -> float:
    if isinstance(r, (int, float)):
        return float(r)
    return float(rng.uniform(r[0], r[1]))


@dataclass(frozen=True)
class ScenarioDistribution:
    """Ranges from which :meth:`sample` draws a :class:`Scenario` (uniform draws).

    The operating point (speed, radial load, clearance, waviness, unbalance, initial preload) is
    drawn once. With ``events`` > 0 the episode then holds that many events at random times in
    [``event_window[0]``, ``event_window[1]``] x the episode length, at least
    ``min_event_spacing_s`` apart: each is, with equal chance, a speed ramp to a new speed
    drawn from ``speed_rpm`` (lasting ``ramp_duration_s``) or a radial-load step to a new load
    drawn from ``radial_load_n``. New levels differ from the current one by at least
    ``min_speed_change_rpm`` / ``min_load_change_n``, up or down with equal chance where the
    range allows both.
    """

    speed_rpm: _Range = (10000.0, 25000.0)
    radial_load_n: _Range = (0.0, 500.0)
    clearance_m: _Range = (4e-6, 30e-6)
    waviness_amplitude_m: _Range = (0.0, 1e-6)
    eccentricity_m: _Range = (0.5e-5, 2e-5)
    initial_preload_n: _Range = (300.0, 2000.0)
    events: int = 0
    event_window: tuple[float, float] = (0.2, 0.85)
    min_event_spacing_s: float = 0.5
    ramp_duration_s: _Range = (0.1, 0.4)
    min_speed_change_rpm: float = 4000.0
    min_load_change_n: float = 200.0
    entry_point: str = field(default="", init=False)

    def __post_init__(self) -> None:
        from bearing_gym.validation import check_int, check_real
        check_int("events", self.events, 0, (MAX_EVENTS - 1) // 2)
        lo = check_real("event_window[0]", self.event_window[0], 0.0, 1.0)
        check_real("event_window[1]", self.event_window[1], lo, 1.0)
        longest_ramp = self.ramp_duration_s if isinstance(self.ramp_duration_s, (int, float)) else max(self.ramp_duration_s)
        check_real("min_event_spacing_s", self.min_event_spacing_s, float(longest_ramp), 1e4, low_open=True)
        part_entry_point(self)

    @property
    def deterministic(self) -> bool:
        """True if every draw is the same scenario: no events, every range a single value and no
        radial load (its direction is drawn at random whatever its size)."""
        fixed = all(isinstance(r, (int, float)) or r[0] == r[1]
                    for r in (self.speed_rpm, self.radial_load_n, self.clearance_m, self.waviness_amplitude_m,
                              self.eccentricity_m, self.initial_preload_n))
        no_load = (self.radial_load_n if isinstance(self.radial_load_n, (int, float)) else max(self.radial_load_n)) == 0
        return fixed and no_load and self.events == 0

    def _new_level(self, rng: np.random.Generator, r: _Range, current: float, min_change: float) -> float:
        if isinstance(r, (int, float)):
            return float(r)
        lo, hi = float(r[0]), float(r[1])
        up = (current + min_change, hi) if current + min_change <= hi else None
        down = (lo, current - min_change) if current - min_change >= lo else None
        options = [o for o in (up, down) if o is not None]
        if not options:
            return _draw(rng, r)
        a, b = options[int(rng.integers(len(options)))]
        return float(rng.uniform(a, b))

    def _event_times(self, rng: np.random.Generator, episode_s: float) -> list[float]:
        a, b = self.event_window[0] * episode_s, self.event_window[1] * episode_s
        for _ in range(100):      # rejection sampling of well-separated times
            times = sorted(float(t) for t in rng.uniform(a, b, size=self.events))
            if all(t2 - t1 >= self.min_event_spacing_s for t1, t2 in zip(times, times[1:])):
                return times
        step = (b - a) / max(self.events, 1)
        return [a + step * (k + 0.5) for k in range(self.events)]   # evenly spread instead

    def sample(self, rng: np.random.Generator, episode_s: float,
               pinned: Mapping[str, Any] | None = None) -> Scenario:
        v0 = _draw(rng, self.speed_rpm)
        f0 = _draw(rng, self.radial_load_n)
        fields: dict[str, Any] = dict(
            radial_load_angle_rad=float(rng.uniform(0.0, 2.0 * math.pi)),
            clearance_m=_draw(rng, self.clearance_m),
            waviness_amplitude_m=_draw(rng, self.waviness_amplitude_m),
            eccentricity_m=_draw(rng, self.eccentricity_m),
            initial_preload_n=_draw(rng, self.initial_preload_n))
        speed = [(0.0, v0)]
        load = [(0.0, f0)]
        if self.events:
            for t in self._event_times(rng, episode_s):
                if rng.uniform() < 0.5:
                    v_new = self._new_level(rng, self.speed_rpm, speed[-1][1], self.min_speed_change_rpm)
                    start = max(t, speed[-1][0] + 1e-3)     # after the previous ramp (short episodes)
                    speed += [(start, speed[-1][1]), (start + _draw(rng, self.ramp_duration_s), v_new)]
                else:
                    load.append((t, self._new_level(rng, self.radial_load_n, load[-1][1], self.min_load_change_n)))
        fields["speed_profile"] = tuple(speed)
        fields["radial_load_profile"] = tuple(load)
        if pinned:
            fields.update(check_pinned(pinned))
        return Scenario(**fields)


PAPER = Scenario(speed_profile=((0.0, 20000.0),), radial_load_profile=((0.0, 0.0),),
                 clearance_m=4e-6, eccentricity_m=1e-5, waviness_amplitude_m=0.0,
                 initial_preload_n=1000.0)


@dataclass(frozen=True)
class FixedScenario:
    """A 'distribution' that always returns the same scenario (plus pinned fields)."""

    scenario: Scenario = PAPER
    entry_point: str = field(default="", init=False)

    def __post_init__(self) -> None:
        if isinstance(self.scenario, Mapping):          # rebuilt from a spec's JSON
            object.__setattr__(self, "scenario", Scenario(**{k: v for k, v in self.scenario.items()
                                                             if k != "entry_point"}))
        part_entry_point(self)

    #: every draw is the same scenario (the generator is not used)
    deterministic = True

    def sample(self, rng: np.random.Generator, episode_s: float,
               pinned: Mapping[str, Any] | None = None) -> Scenario:
        if not pinned:
            return self.scenario
        return dataclasses.replace(self.scenario, **check_pinned(pinned))


_SCENARIO_FIELDS = {f.name for f in dataclasses.fields(Scenario) if f.init}


def check_pinned(pinned: Mapping[str, Any]) -> dict[str, Any]:
    """Scenario fields from ``reset(options=...)``: field names, plus ``shaft_speed_rpm`` (a
    constant speed) and ``radial_load_n`` (a constant radial load). Unknown keys raise."""
    out: dict[str, Any] = {}
    for key, value in pinned.items():
        if key == "shaft_speed_rpm":
            out["speed_profile"] = ((0.0, value),)
        elif key == "radial_load_n":
            out["radial_load_profile"] = ((0.0, value),)
        elif key in _SCENARIO_FIELDS:
            out[key] = value
        else:
            raise ValueError(f"unknown scenario option {key!r}; valid: "
                             f"{', '.join(sorted(_SCENARIO_FIELDS | {'shaft_speed_rpm', 'radial_load_n'}))}")
    return out
