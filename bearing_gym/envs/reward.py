"""Reward models: what a control interval costs.

A reward model is any object with

* ``term_names``: a tuple of names; the env puts each term into ``info["reward_<name>"]``;
* ``__call__(m: StepMeasurement) -> (reward, terms)``: the reward of each environment in the
  batch (array of length ``len(m)``) and a dict of its additive terms (same keys as
  ``term_names``). A termination (``m.terminated``) is the reward model's business too: it
  decides the penalty.

The default, :class:`VibrationFirstReward`, orders what a spindle user cares about: vibration
first, then friction heat and fatigue life, then actuation.

====================  ===================================================================
term                  cost per control interval (dimensionless; the reward is minus the sum)
====================  ===================================================================
``vibration``         q (1 + min(a, a_cap) / a_ref). q = 1 if the interval is quasi-periodic
                      (index > ``QPI_THRESHOLD``, :mod:`bearing_gym.analysis.signals`), else 0;
                      a = RMS of the non-synchronous displacement of x, y, z in um (what is
                      left after removing the once-per-revolution response and its harmonics,
                      :mod:`.features`); a_ref = 10 um, a_cap = 100 um.
``heat``              s_h (P / P_max)^1.33 (n / n_max). Palmgren: the load-dependent friction
                      torque is M_1 = f_1 P d_m with f_1 = z (P_0 / C_0)^0.33 for ball bearings,
                      so M_1 ~ P^1.33, and its heat M_1 omega ~ P^1.33 n.
``fatigue``           s_f (P_eq / P_eq,max)^3 (n / n_max). ISO 281: L10 = (C / P_eq)^3
                      revolutions, so the fraction of the rating life used per second is
                      proportional to P_eq^3 n; P_eq = max(F_r, 0.41 F_r + 0.87 F_a) (X, Y of a
                      25 deg angular-contact bearing, e = 0.68), F_a = P.
``actuation``         w_a |Delta P| / (P_max - P_min): the preload moved in the interval.
``termination``       on termination only (the other terms are then 0): the worst cost of
                      one interval times (1 + the intervals left in the episode).
====================  ===================================================================

P is the actual axial preload, n the shaft speed, F_r the radial load. P_max, P_min, n_max and
F_r,max are the envelope of the task (the actuator's range, 25,000 rpm, 500 N);
P_eq,max = max(F_r,max, 0.41 F_r,max + 0.87 P_max).

Why these weights (nothing here is fitted to a policy):

* heat and fatigue share the secondary cost equally (s_h = s_f = 0.5) and are scaled so that
  together they cost exactly 1 at the costliest corner of the envelope (P_max, n_max,
  F_r,max). Both follow the physical law of their term, so ratios between operating points are
  physical (twice the preload, 2.5 times the heat; twice the load, eight times the life used).
* vibration comes first: a quasi-periodic interval costs at least 1, as much as the most
  expensive preload anywhere in the envelope, so no saving of heat or life can pay for
  quasi-periodic motion. On top of that, every 10 um RMS of non-synchronous vibration costs as
  much again: the order of a finishing tolerance (IT6 over 30-50 mm is 13-16 um), so among
  quasi-periodic states the reward still ranks the smaller vibration higher (a gradient for a
  policy that cannot leave a quasi-periodic band at once). Period-1 motion costs no vibration:
  its synchronous part is balanced and compensated in practice, and its non-synchronous rest
  (ball-pass vibration, decaying transients) stays far below the amplitude scale.
  The cap (100 um, about a tenth of the integrator's divergence limit) bounds the worst cost.
* actuation comes last: moving the preload over the whole range costs w_a = 0.1, a tenth of
  the costliest steady secondary cost.
* termination (the integrator failed: the rotor left the bearing's working range) earns the
  worst per-interval cost for this interval and for every interval left in the episode, so an
  episode that crashes never earns more than any continuation without a crash.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol, runtime_checkable

import numpy as np

from bearing_gym.physics.portable_math import pow_array
from bearing_gym.units import rpm_to_rad_s
from bearing_gym.validation import check_real

from .measurement import StepMeasurement
from .parts import part_entry_point

__all__ = ["Reward", "VibrationFirstReward", "REWARD_TERMS"]

REWARD_TERMS = ("vibration", "heat", "fatigue", "actuation", "termination")
HEAT_LOAD_EXPONENT = 1.33      # Palmgren: M_1 = f_1 P d_m, f_1 ~ (P_0 / C_0)^0.33


@runtime_checkable
class Reward(Protocol):
    """What the env needs of a reward model (see the module docstring)."""

    term_names: tuple[str, ...]

    def __call__(self, m: StepMeasurement) -> tuple[np.ndarray, dict[str, np.ndarray]]: ...


@dataclass(frozen=True)
class VibrationFirstReward:
    """The default reward: vibration first, then heat and fatigue life, then actuation
    (module docstring: formula, units and the reason for every weight)."""

    amplitude_scale_um: float = 10.0
    amplitude_cap_um: float = 100.0
    heat_share: float = 0.5
    fatigue_share: float = 0.5
    actuation_weight: float = 0.1
    min_preload_n: float = 300.0
    max_preload_n: float = 2000.0
    max_speed_rpm: float = 25000.0
    max_radial_load_n: float = 500.0
    term_names: tuple[str, ...] = field(default=REWARD_TERMS, init=False)
    entry_point: str = field(default="", init=False)

    def __post_init__(self) -> None:
        check_real("amplitude_scale_um", self.amplitude_scale_um, 0.0, 1e6, low_open=True)
        check_real("amplitude_cap_um", self.amplitude_cap_um, 0.0, 1e6, low_open=True)
        for name in ("heat_share", "fatigue_share", "actuation_weight"):
            check_real(name, getattr(self, name), 0.0, 1e6)
        lo = check_real("min_preload_n", self.min_preload_n, 0.0, 1e5)
        check_real("max_preload_n", self.max_preload_n, lo, 1e5, low_open=True)
        check_real("max_speed_rpm", self.max_speed_rpm, 0.0, 1e6, low_open=True)
        check_real("max_radial_load_n", self.max_radial_load_n, 0.0, 1e6)
        part_entry_point(self)

    # -- the terms -------------------------------------------------------------------------
    @staticmethod
    def equivalent_load_n(radial_load_n, axial_load_n):
        """ISO 281 dynamic equivalent load of a 25 deg angular-contact ball bearing."""
        return np.maximum(radial_load_n, 0.41 * radial_load_n + 0.87 * axial_load_n)

    def secondary_costs(self, preload_n, shaft_speed_rad_s, radial_load_n) -> tuple[np.ndarray, np.ndarray]:
        """(heat, fatigue) costs (>= 0) at an operating point."""
        speed = np.asarray(shaft_speed_rad_s) / rpm_to_rad_s(self.max_speed_rpm)
        p_eq_max = self.equivalent_load_n(self.max_radial_load_n, self.max_preload_n)
        # the portable pow and a product for the cube: NumPy's ** dispatches by CPU feature
        load = np.asarray(preload_n, dtype=np.float64) / self.max_preload_n
        heat = self.heat_share * pow_array(np.atleast_1d(load), HEAT_LOAD_EXPONENT).reshape(load.shape) * speed
        eq = np.asarray(self.equivalent_load_n(radial_load_n, preload_n), dtype=np.float64) / p_eq_max
        fatigue = self.fatigue_share * (eq * eq * eq) * speed
        return heat, fatigue

    def vibration_cost(self, quasi_periodic, nonsync_rms_m) -> np.ndarray:
        amp_um = np.minimum(np.asarray(nonsync_rms_m) * 1e6, self.amplitude_cap_um)
        return np.where(quasi_periodic, 1.0 + amp_um / self.amplitude_scale_um, 0.0)

    def worst_step_cost(self, shaft_speed_rad_s, radial_load_n) -> np.ndarray:
        """An upper bound of one interval's cost at (and anywhere inside the envelope beyond)
        the given operating point: the termination penalty per interval left."""
        vib = 1.0 + self.amplitude_cap_um / self.amplitude_scale_um
        speed = np.maximum(np.asarray(shaft_speed_rad_s, dtype=float), rpm_to_rad_s(self.max_speed_rpm))
        fr = np.maximum(np.asarray(radial_load_n, dtype=float), self.max_radial_load_n)
        heat, fatigue = self.secondary_costs(self.max_preload_n, speed, fr)
        return vib + heat + fatigue + self.actuation_weight

    def __call__(self, m: StepMeasurement) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        heat, fatigue = self.secondary_costs(m.preload_n, m.shaft_speed_rad_s, m.radial_load_n)
        span = self.max_preload_n - self.min_preload_n
        terms = {
            "vibration": -self.vibration_cost(m.quasi_periodic, m.nonsync_rms_m),
            "heat": -heat,
            "fatigue": -fatigue,
            "actuation": -self.actuation_weight * np.abs(m.preload_n - m.preload_before_n) / span,
        }
        term = np.asarray(m.terminated, dtype=bool)
        for k in terms:                          # a failed interval's features mean nothing
            terms[k] = np.where(term, 0.0, terms[k])
        worst = self.worst_step_cost(m.shaft_speed_rad_s, m.radial_load_n)
        terms["termination"] = np.where(term, -worst * (np.asarray(m.steps_left) + 1.0), 0.0)
        reward = sum(terms[k] for k in REWARD_TERMS)
        return np.asarray(reward, dtype=np.float64), terms
