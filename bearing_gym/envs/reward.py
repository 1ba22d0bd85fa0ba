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
``heat``              h = s_h (P / P_max)^1.33 (n / n_max). Palmgren: the load-dependent friction
                      torque is M_1 = f_1 P d_m with f_1 = z (P_0 / C_0)^0.33 for ball bearings,
                      so M_1 ~ P^1.33, and its heat M_1 omega ~ P^1.33 n.
``fatigue``           C(s_f u / u_ref, s_h + s_f - h): the fraction u of the bearing's L10
                      rating life the interval used per second (Lundberg-Palmgren, below),
                      relative to u_ref, the same at the costliest corner of the envelope; C a
                      smooth cap that keeps heat + fatigue below s_h + s_f (below).
``actuation``         w_a |Delta P| / (P_max - P_min): the preload moved in the interval.
``termination``       on termination only (the other terms are then 0): the worst cost of
                      one interval times (1 + the intervals left in the episode).
====================  ===================================================================

P is the actual axial preload, n the shaft speed (heat: at the interval's end; fatigue: its
mean over the interval), F_r the radial load.
P_max, P_min, n_max, F_r,max and c_max are the envelope of the task (the actuator's range,
25,000 rpm, 500 N, the tiers' largest clearance 30 um).

Fatigue: Lundberg-Palmgren, the basic form ISO/TS 16281 builds its reference rating life on
(Harris & Kotzalas, *Rolling Bearing Analysis* 5th ed., vol. 2, ch. 8; equations and source in
:mod:`bearing_gym.physics.rating`). The loads are the model's own contact loads Q_ij (inner) and
Q_oj (outer race) of every ball j at every Newmark step k of the interval (``ball_out`` of
:func:`bearing_gym.physics.rotor.integrate`: each ball in quasi-static equilibrium with its
centrifugal force, so the outer contacts carry it; the unbalance, the vibration and the radial
load are in them too), accumulated by the integrator (:mod:`.contact`). Over the interval's K
steps and the Z balls (Palmgren-Miner: the mean of Q^w over time and balls):

    Q_ei^3      = 1/(K Z) sum_k sum_j Q_ij^3           (rotating inner race, w = 3)
    Q_eo^(10/3) = 1/(K Z) sum_k sum_j Q_oj^(10/3)      (stationary outer race, w = 10/3)
    L_i = (Q_ci / Q_ei)^3,  L_o = (Q_co / Q_eo)^3       (10^6 revolutions)
    L_10 = (L_i^(-10/9) + L_o^(-10/9))^(-9/10)
    u = (n / 60 s) / (L_10 10^6)                        (life used per second, 1/s)

with n (rpm) the interval's mean shaft speed, the revolutions it turned over its duration (a
ramp's, not its end speed's).

with the races' basic dynamic capacities (N, D in mm; upper signs inner, lower outer)
Q_c = 98.1 (2f / (2f - 1))^0.41 (1 -+ gamma)^1.39 / (1 +- gamma)^(1/3) (gamma / cos alpha)^0.3
D^1.8 Z^(-1/3), f = groove radius / D, gamma = D cos alpha / d_m: Q_ci = 9646 N and
Q_co = 19345 N for the default bearing. u_ref is u at the static (quasi-static) equilibrium
(:func:`bearing_gym.physics.static_equilibrium`) of the default bearing (the paper's, whatever
bearing the env simulates: an env built with another bearing's ``params`` is charged against
this one's corner) at the costliest corner
of the envelope: P_max = 2000 N, n_max = 25,000 rpm, F_r,max = 500 N and the largest clearance
c_max = 30 um (L_10 = 96.5 h there; the clearance matters: with 4 um it is 124 h). At high speed
the outer race's centrifugal load dominates: at 25,000 rpm a ball presses on it with 2.6 kN
before any preload, so the preload moves the life little and the speed much (u ~ n^7 where the
centrifugal force dominates: the loads ~ n^2, cubed, times the revolutions); under radial load
with a large clearance a light preload can even cost more life than a firmer one (fewer balls
carry the load).

**The constrained variant** (safe RL: "stay out of quasi-periodic vibration" as a constraint, not
a penalty): :func:`constrained_reward` is this reward with ``vibration_weight=0`` (heat, fatigue
and actuation; a termination still costs the worst interval, now without vibration, times the
intervals left), and the vibration is the env's cost channel ``info["cost"]`` (1 per
quasi-periodic interval; :func:`bearing_gym.envs.composition.interval_cost`) under the budget
``bearing_gym.task.COST_BUDGET_PER_EPISODE`` per episode (docs/benchmark.md).

Why these weights (nothing here is fitted to a policy):

* heat and fatigue share the secondary cost equally (s_h = s_f = 0.5) and are scaled so that
  each would cost its share at the costliest corner of the envelope (P_max, n_max, F_r,max,
  c_max, static loads; the fatigue's cap below bends its 0.5 there to 0.475). Both follow the physical law of their term, so ratios between
  operating points are physical (twice the preload, 2.5 times the heat; the fatigue term is
  today's fraction of the L10 life used per second). The unbalance and the vibration load the
  contacts beyond the static corner, so the fatigue term has room b = s_h + s_f - h (times
  n / n_max beyond the envelope's speed) and is capped smoothly below it: C(x, b) = x for
  x <= 0.9 b, else 0.9 b + 0.1 b y / (1 + y), y = (x - 0.9 b) / (0.1 b) (continuous with its
  slope, strictly increasing, < b). So vibration stays first and the termination penalty a
  bound, and where the cap acts the reward still ranks the preloads by the life they use,
  if weakly (a hard min(x, b) would make every such preload cost exactly 1). At the static
  corner itself x = b = 0.5, so heat + fatigue = 0.5 + 0.45 + 0.025 = 0.975 there. The cap acts in
  quasi-periodic motion (where the vibration term dominates anyway) and in period-1 motion
  beyond the reward map's unbalances: at 20,000-25,000 rpm with the ``field`` tier's 30 um the
  synchronous orbit reaches outer loads of 7-11 kN and u of 2-10 u_ref (at 20,000-25,000 rpm /
  250 N / 17 um with 10-20 um, u stayed below 0.9 u_ref).
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

import functools
from dataclasses import dataclass, field
from typing import Protocol, runtime_checkable

import numpy as np

from bearing_gym.physics.portable_math import pow_array
from bearing_gym.physics.rating import static_life_used_per_s
from bearing_gym.units import rpm_to_rad_s
from bearing_gym.validation import check_real

from .measurement import StepMeasurement
from .parts import part_entry_point

__all__ = ["Reward", "VibrationFirstReward", "REWARD_TERMS", "corner_life_used_per_s", "smooth_cap",
           "constrained_reward"]

REWARD_TERMS = ("vibration", "heat", "fatigue", "actuation", "termination")
HEAT_LOAD_EXPONENT = 1.33      # Palmgren: M_1 = f_1 P d_m, f_1 ~ (P_0 / C_0)^0.33


@functools.lru_cache(maxsize=8)
def corner_life_used_per_s(preload_n: float, speed_rpm: float, radial_load_n: float, clearance_m: float) -> float:
    """u (1/s) at the static equilibrium of the default bearing at an operating point
    (:func:`bearing_gym.physics.rating.static_life_used_per_s`): the reward's u_ref at the
    envelope's costliest corner, computed once per process and envelope."""
    from bearing_gym.params import default_params
    return static_life_used_per_s(default_params(
        shaft_speed_rpm=speed_rpm, axial_preload_n=preload_n, radial_load_x_n=radial_load_n,
        clearance_inner_m=clearance_m, clearance_outer_m=clearance_m))


#: Where the fatigue term's smooth cap starts to bend, as a share of its room (module docstring).
CAP_KNEE = 0.9


def smooth_cap(x, room) -> np.ndarray:
    """C(x, b) = x for x <= k b, else k b + s y / (1 + y) with s = (1 - k) b, y = (x - k b) / s,
    k = ``CAP_KNEE``: continuous with its first derivative (1 at the knee), strictly increasing
    in x (algebraically, so in floating point too, where an exponential tail would round to b),
    below b; 0 where b = 0. IEEE operations only."""
    x, room = np.broadcast_arrays(np.asarray(x, dtype=np.float64), np.asarray(room, dtype=np.float64))
    knee = CAP_KNEE * room
    soft = (1.0 - CAP_KNEE) * room
    over = (x > knee) & (soft > 0.0)
    y = np.where(over, (x - knee) / np.where(soft > 0.0, soft, 1.0), 0.0)
    return np.where(over, knee + soft * y / (1.0 + y), np.minimum(x, knee + soft))


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
    #: 1: the benchmark's reward; 0: the constrained variant's (vibration is then the cost
    #: channel ``info["cost"]`` under a budget per episode, not a term of the reward)
    vibration_weight: float = 1.0
    min_preload_n: float = 300.0
    max_preload_n: float = 2000.0
    max_speed_rpm: float = 25000.0
    max_radial_load_n: float = 500.0
    max_clearance_m: float = 30e-6
    term_names: tuple[str, ...] = field(default=REWARD_TERMS, init=False)
    entry_point: str = field(default="", init=False)

    def __post_init__(self) -> None:
        check_real("amplitude_scale_um", self.amplitude_scale_um, 0.0, 1e6, low_open=True)
        check_real("amplitude_cap_um", self.amplitude_cap_um, 0.0, 1e6, low_open=True)
        for name in ("heat_share", "fatigue_share", "actuation_weight", "vibration_weight"):
            check_real(name, getattr(self, name), 0.0, 1e6)
        lo = check_real("min_preload_n", self.min_preload_n, 0.0, 1e5)
        check_real("max_preload_n", self.max_preload_n, lo, 1e5, low_open=True)
        check_real("max_speed_rpm", self.max_speed_rpm, 0.0, 1e6, low_open=True)
        check_real("max_radial_load_n", self.max_radial_load_n, 0.0, 1e6)
        check_real("max_clearance_m", self.max_clearance_m, 0.0, 1e-4)
        part_entry_point(self)

    # -- the terms -------------------------------------------------------------------------
    @property
    def reference_life_used_per_s(self) -> float:
        """u_ref (1/s): the life used per second at the envelope's costliest corner (module
        docstring), from the default bearing's static equilibrium there (cached per process)."""
        return corner_life_used_per_s(self.max_preload_n, self.max_speed_rpm, self.max_radial_load_n,
                                      self.max_clearance_m)

    def _speed_ratio(self, shaft_speed_rad_s) -> np.ndarray:
        return np.asarray(shaft_speed_rad_s, dtype=np.float64) / rpm_to_rad_s(self.max_speed_rpm)

    def heat_cost(self, preload_n, shaft_speed_rad_s) -> np.ndarray:
        """s_h (P / P_max)^1.33 (n / n_max) (>= 0)."""
        # the portable pow: NumPy's ** dispatches by CPU feature
        load = np.asarray(preload_n, dtype=np.float64) / self.max_preload_n
        return (self.heat_share * pow_array(np.atleast_1d(load), HEAT_LOAD_EXPONENT).reshape(load.shape)
                * self._speed_ratio(shaft_speed_rad_s))

    def secondary_costs(self, preload_n, shaft_speed_rad_s, life_used_per_s) -> tuple[np.ndarray, np.ndarray]:
        """(heat, fatigue) costs (>= 0) of an interval: the heat at its preload and speed, the
        fatigue from the fraction of the L10 life it used per second (1/s), capped smoothly
        (:func:`smooth_cap`) so that heat + fatigue stay below s_h + s_f (times n / n_max beyond
        the envelope's speed)."""
        heat = self.heat_cost(preload_n, shaft_speed_rad_s)
        fatigue = self.fatigue_share * np.asarray(life_used_per_s, dtype=np.float64) / self.reference_life_used_per_s
        room = (self.heat_share + self.fatigue_share) * np.maximum(self._speed_ratio(shaft_speed_rad_s), 1.0) - heat
        return heat, smooth_cap(fatigue, np.maximum(room, 0.0))

    def vibration_cost(self, quasi_periodic, nonsync_rms_m) -> np.ndarray:
        amp_um = np.minimum(np.asarray(nonsync_rms_m) * 1e6, self.amplitude_cap_um)
        return self.vibration_weight * np.where(quasi_periodic, 1.0 + amp_um / self.amplitude_scale_um, 0.0)

    def worst_step_cost(self, shaft_speed_rad_s, radial_load_n) -> np.ndarray:
        """An upper bound of one interval's cost at (and anywhere inside the envelope beyond)
        the given operating point: the termination penalty per interval left. Heat + fatigue
        never exceed max(heat at P_max, (s_h + s_f) max(1, n / n_max)), whatever the radial load
        (kept in the signature: a reward's bound may depend on it)."""
        vib = self.vibration_weight * (1.0 + self.amplitude_cap_um / self.amplitude_scale_um)
        speed = np.maximum(np.asarray(shaft_speed_rad_s, dtype=float), rpm_to_rad_s(self.max_speed_rpm))
        heat = self.heat_cost(self.max_preload_n, speed)
        secondary = np.maximum(heat, (self.heat_share + self.fatigue_share) * self._speed_ratio(speed))
        return vib + secondary + self.actuation_weight

    def __call__(self, m: StepMeasurement) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        heat, fatigue = self.secondary_costs(m.preload_n, m.shaft_speed_rad_s, m.life_used_per_s)
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


def constrained_reward() -> VibrationFirstReward:
    """The constrained variant's reward: :class:`VibrationFirstReward` without its vibration term
    (``vibration_weight=0``); the vibration is charged through ``info["cost"]`` against
    ``bearing_gym.task.COST_BUDGET_PER_EPISODE`` (module docstring)::

        gymnasium.make("BearingPreload-v0", reward=constrained_reward())
    """
    return VibrationFirstReward(vibration_weight=0.0)
