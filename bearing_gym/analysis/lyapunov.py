"""Largest Lyapunov exponent by Benettin's two-trajectory method (Benettin et al., Meccanica 15,
1980; Wolf et al., Physica D 16, 1985).

A reference trajectory and a neighbour at distance d0 are advanced together for a time τ;
after each interval the separation d is measured, ln(d / d0) accumulated, and the neighbour put
back at distance d0 along the current separation. The exponent is

    λ1 = (1 / (K τ)) Σ_k ln(d_k / d0)           (1/s)

over K intervals after a discarded transient. It stays meaningful for quasi-periodic forcing
(unbalance at ω and ball passage at N ω_c, paper section 3.2), where a monodromy matrix does not
strictly exist: λ1 < 0 for a stable period-1 response (it then equals ln|μ_max| / T of the
Floquet multipliers), λ1 ≈ 0 on a quasi-periodic torus, λ1 > 0 for chaos.

* :func:`benettin` works on any flow ``flow(x, tau) -> x`` of a state vector;
  :func:`rk4_flow` makes one from an ODE (fixed-step classical Runge-Kutta), used by the tests on
  the Lorenz system (λ1 ≈ 0.906 for σ = 10, ρ = 28, β = 8/3) and a damped oscillator
  (λ1 = −ζ ω_n exactly for an underdamped linear oscillator).
* :func:`simulator_lyapunov` runs the same iteration on the bearing Simulator with the (X, V) coordinates of
  :mod:`.simstate`; distances are measured in the scaled units of
  :func:`.simstate.state_scale`, and at each renormalisation the neighbour takes the reference's
  cage angle, shaft angle and ball states (the cage phase is treated as a forcing phase, as in
  :func:`.floquet.simulator_floquet`), with a consistent acceleration.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from bearing_gym.physics import SimulatorState

from .simstate import StatePerturber, shaft_period_steps, state_scale, state_vector

__all__ = ["LyapunovResult", "benettin", "rk4_flow", "simulator_lyapunov"]


@dataclass
class LyapunovResult:
    """``exponent`` (1/time unit of the flow) and the running estimate after each interval."""

    exponent: float
    running: np.ndarray
    times: np.ndarray
    tau: float
    d0: float

    def spread(self, fraction: float = 0.5) -> float:
        """Range of the running estimate over its last ``fraction``: a convergence indicator."""
        tail = self.running[int(len(self.running) * (1 - fraction)):]
        return float(np.ptp(tail)) if tail.size else math.nan


def rk4_flow(rhs: Callable[[float, np.ndarray], np.ndarray], dt: float) -> Callable[[np.ndarray, float], np.ndarray]:
    """Flow map of the autonomous ODE dx/dt = rhs(t, x) by classical RK4 with step ``dt``
    (tau is rounded to a whole number of steps)."""
    if not dt > 0:
        raise ValueError(f"dt must be positive, got {dt!r}")

    def flow(x: np.ndarray, tau: float) -> np.ndarray:
        n = max(1, int(round(tau / dt)))
        h = tau / n
        y = np.array(x, dtype=float)
        for _ in range(n):
            k1 = rhs(0.0, y)
            k2 = rhs(0.0, y + 0.5 * h * k1)
            k3 = rhs(0.0, y + 0.5 * h * k2)
            k4 = rhs(0.0, y + h * k3)
            y = y + (h / 6.0) * (k1 + 2 * k2 + 2 * k3 + k4)
        return y

    return flow


def benettin(flow: Callable[[np.ndarray, float], np.ndarray], x0: np.ndarray, *, tau: float,
             n_intervals: int, d0: float = 1e-8, n_transient: int = 0,
             weights: np.ndarray | None = None, direction: np.ndarray | None = None) -> LyapunovResult:
    """Largest Lyapunov exponent of ``flow`` from ``x0`` (see the module docstring).

    ``weights``: distances are |weights * (x_b − x_a)| (to make coordinates comparable);
    ``n_transient`` intervals are run first and not counted (the neighbour aligns with the
    most unstable direction); ``direction``: initial separation (default: all ones).
    """
    result, _ = _benettin(flow, np.array(x0, dtype=float), _as_vector, _displaced, tau=tau,
                          n_intervals=n_intervals, d0=d0, n_transient=n_transient,
                          weights=weights, direction=direction)
    return result


def _as_vector(x: np.ndarray) -> np.ndarray:
    return x


def _displaced(_base: np.ndarray, vector: np.ndarray) -> np.ndarray:
    return vector


def _benettin(flow: Callable[[Any, float], Any], x0: Any, vector: Callable[[Any], np.ndarray],
              displaced: Callable[[Any, np.ndarray], Any], *, tau: float, n_intervals: int,
              d0: float, n_transient: int, weights: np.ndarray | None,
              direction: np.ndarray | None) -> tuple[LyapunovResult, Any]:
    """Benettin's iteration on states of any kind: ``vector(state)`` is the phase-space vector
    the distance is measured on and ``displaced(base, vector)`` the state ``base`` moved to
    ``vector`` (the identity for plain vectors; for the Simulator it keeps the reference's
    forcing phase and ball states). Returns the result and the reference's end state."""
    if n_intervals < 1:
        raise ValueError(f"n_intervals must be >= 1, got {n_intervals}")
    xa = x0
    va = vector(xa)
    w = np.ones_like(va) if weights is None else np.asarray(weights, dtype=float)
    u = np.ones_like(va) if direction is None else np.asarray(direction, dtype=float)
    u = u / np.linalg.norm(w * u)
    xb = displaced(xa, va + d0 * u)
    total = 0.0
    running = []
    for k in range(n_transient + n_intervals):
        xa = flow(xa, tau)
        xb = flow(xb, tau)
        va = vector(xa)
        sep = vector(xb) - va
        d = float(np.linalg.norm(w * sep))
        if not (d > 0 and math.isfinite(d)):
            raise FloatingPointError("the two trajectories coincided or diverged; change d0 or tau")
        if k >= n_transient:
            total += math.log(d / d0)
            running.append(total / ((k - n_transient + 1) * tau))
        xb = displaced(xa, va + sep * (d0 / d))
    running_arr = np.array(running)
    return (LyapunovResult(float(running_arr[-1]), running_arr,
                           tau * np.arange(1, n_intervals + 1), float(tau), float(d0)), xa)


def simulator_lyapunov(sim, duration_s: float, *, tau_s: float | None = None, d0_m: float = 1e-8,
                       transient_s: float = 0.0) -> LyapunovResult:
    """Largest Lyapunov exponent (1/s) of the Simulator's motion from its current state over
    ``duration_s`` (after ``transient_s`` not counted): :func:`benettin`'s iteration on
    Simulator states. ``tau_s``: renormalisation interval (default: one shaft period, rounded
    to whole steps); ``d0_m``: separation in scaled units (metres at the groove radius). The
    Simulator ends at the reference trajectory's end state. Cost: twice the simulated time."""
    if tau_s is None:
        _, tau_s = shaft_period_steps(sim)
    n = max(1, int(round(duration_s / tau_s)))
    n_tr = int(round(transient_s / tau_s))
    weights = 1.0 / state_scale(sim)
    perturber = StatePerturber(sim)

    def flow(state: SimulatorState, tau: float) -> SimulatorState:
        sim.state = state
        sim.advance(tau)
        return sim.state

    result, end = _benettin(flow, sim.state, state_vector, perturber.make, tau=tau_s,
                            n_intervals=n, d0=d0_m, n_transient=n_tr, weights=weights,
                            direction=np.ones(10) / weights)
    sim.state = end
    return result
