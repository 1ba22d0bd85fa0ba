"""Benettin's largest Lyapunov exponent on systems with known values."""

import math

import numpy as np
import pytest

from bearing_gym.analysis.lyapunov import benettin, rk4_flow


def lorenz(t, u, sigma=10.0, rho=28.0, beta=8.0 / 3.0):
    x, y, z = u
    return np.array([sigma * (y - x), x * (rho - z) - y, x * y - beta * z])


def test_lorenz_largest_exponent_is_positive_and_near_0_906():
    # literature value 0.9056 (Sprott, Chaos and Time-Series Analysis, 2003); 150 time units
    # give it to a few percent
    flow = rk4_flow(lorenz, 0.005)
    x0 = flow(np.array([1.0, 1.0, 20.0]), 10.0)              # onto the attractor
    res = benettin(flow, x0, tau=0.5, n_intervals=300, d0=1e-8, n_transient=10)
    assert res.exponent > 0
    assert res.exponent == pytest.approx(0.906, abs=0.1)


def test_damped_oscillator_exponent_is_minus_zeta_omega():
    # x'' + 2 zeta w x' + w^2 x = 0: both eigenvalues have real part -zeta w; the separation of
    # two trajectories decays exactly at that rate (up to a bounded oscillation)
    w, zeta = 2 * math.pi, 0.1
    flow = rk4_flow(lambda t, u: np.array([u[1], -2 * zeta * w * u[1] - w * w * u[0]]), 1e-3)
    res = benettin(flow, np.array([1.0, 0.0]), tau=0.25, n_intervals=200, d0=1e-6,
                   n_transient=4, weights=np.array([w, 1.0]))
    assert res.exponent < 0
    assert res.exponent == pytest.approx(-zeta * w, rel=0.02)
    assert res.running.shape == (200,) and res.times[-1] == pytest.approx(50.0)


def test_simulator_lyapunov_on_a_stable_orbit_is_negative_and_ends_on_the_reference():
    """On the period-1 orbit at 800 N a separation decays; the Simulator is left at the end of
    the unperturbed (reference) trajectory, as advancing a copy in the same steps gives."""
    import bearing_gym
    from bearing_gym.analysis.lyapunov import simulator_lyapunov
    from bearing_gym.analysis.simstate import shaft_period_steps
    from bearing_gym.physics import Simulator

    sim = Simulator(bearing_gym.default_params(axial_preload_n=800.0))
    sim.advance(0.05)
    start = sim.state
    res = simulator_lyapunov(sim, 0.03, transient_s=0.006)
    _, tau = shaft_period_steps(sim)
    n = int(round(0.03 / tau))
    assert res.tau == tau and res.running.shape == (n,) and res.exponent == res.running[-1]
    assert res.exponent < 0
    twin = Simulator(bearing_gym.default_params(axial_preload_n=800.0))
    twin.state = start
    for _ in range(n + int(round(0.006 / tau))):
        twin.advance(tau)
    np.testing.assert_array_equal(sim.state.X, twin.state.X)
    np.testing.assert_array_equal(sim.state.V, twin.state.V)
    assert sim.t == twin.t
