"""Floquet machinery validated on systems with known multipliers, then on the bearing through
Liouville's formula."""

import math

import numpy as np
import pytest

import bearing_gym
from bearing_gym.analysis.floquet import (fd_monodromy, multipliers, ode_flow_map,
                                          simulator_floquet, variational_monodromy)
from bearing_gym.physics import Simulator


def _sorted(mu):
    mu = np.asarray(mu, dtype=complex)
    return mu[np.lexsort((mu.imag, mu.real))]


def test_constant_coefficient_gyroscopic_oscillator_multipliers_are_exp_lambda_t():
    # x'' + (C + G) x' + K x = 0, two DOF, skew gyroscopic coupling: a time-invariant system is
    # periodic with any period T and its multipliers are exactly exp(lambda T), lambda the
    # eigenvalues of the first-order matrix A.
    K = np.array([[40.0, 5.0], [5.0, 25.0]])
    C = np.diag([0.4, 0.7])
    G = np.array([[0.0, 1.5], [-1.5, 0.0]])
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [-K, -(C + G)]])
    T = 0.83
    flow = ode_flow_map(lambda t, x: A @ x, T)
    res = multipliers(fd_monodromy(flow, np.zeros(4), 1e-4), period_s=T)
    exact = np.exp(np.linalg.eigvals(A) * T)
    np.testing.assert_allclose(_sorted(res.multipliers), _sorted(exact), atol=1e-3)
    # much better than the 1e-3 asked for: the flow is linear, so central differences are exact
    np.testing.assert_allclose(_sorted(res.multipliers), _sorted(exact), atol=1e-8)
    # rates and folded frequencies of the modes
    lam = np.linalg.eigvals(A)
    rates = sorted(m["rate_per_s"] for m in res.modes())
    np.testing.assert_allclose(rates, sorted(lam.real), atol=1e-7)


@pytest.mark.parametrize("delta, eps, zeta", [(1.3, 0.5, 0.05), (0.25, 0.4, 0.02)])
def test_damped_mathieu_matches_variational_equations_and_liouville(delta, eps, zeta):
    # x'' + 2 zeta x' + (delta + eps cos t) x = 0, period 2 pi. The second case sits in the first
    # (period-doubling) instability tongue: a real multiplier below -1.
    T = 2 * math.pi

    def rhs(t, y):
        return np.array([y[1], -2 * zeta * y[1] - (delta + eps * math.cos(t)) * y[0]])

    def jac(t, y):
        return np.array([[0.0, 1.0], [-(delta + eps * math.cos(t)), -2 * zeta]])

    res = multipliers(fd_monodromy(ode_flow_map(rhs, T), np.zeros(2), 1e-3), period_s=T)
    ref = np.linalg.eigvals(variational_monodromy(rhs, jac, np.zeros(2), T))
    np.testing.assert_allclose(_sorted(res.multipliers), _sorted(ref), atol=1e-3)
    np.testing.assert_allclose(_sorted(res.multipliers), _sorted(ref), atol=1e-8)
    # Liouville: det M = exp(integral of the trace) = exp(-2 zeta T), in closed form
    assert np.prod(res.multipliers).real == pytest.approx(math.exp(-2 * zeta * T), rel=1e-8)
    if delta == 0.25:
        assert res.leading_modulus > 1.0 and res.multipliers[0].real < 0 and not res.stable


def test_trivial_multiplier_is_dropped_along_the_requested_coordinate():
    # a damped oscillator plus a neutral phase theta' = 1 + 0.1 x: the phase direction has
    # multiplier exactly 1 and must be the one dropped.
    w, zeta, T = 3.0, 0.1, 1.7

    def rhs(t, y):
        return np.array([y[1], -2 * zeta * w * y[1] - w * w * y[0], 1.0 + 0.1 * y[0]])

    res = multipliers(fd_monodromy(ode_flow_map(rhs, T), np.zeros(3), 1e-4), period_s=T,
                      drop_along=2)
    assert res.dropped == pytest.approx(1.0, abs=1e-8)
    lam = -zeta * w + 1j * w * math.sqrt(1 - zeta ** 2)
    np.testing.assert_allclose(np.abs(res.multipliers), abs(np.exp(lam * T)), atol=1e-8)


@pytest.fixture(scope="module")
def bearing_800():
    # 0.3 s from the static equilibrium: on the period-1 orbit to a few 1e-3 (index 0.02)
    sim = Simulator(bearing_gym.default_params(axial_preload_n=800.0))
    sim.advance(0.3)
    return sim


def test_bearing_monodromy_satisfies_liouville_and_keeps_the_state(bearing_800):
    sim = bearing_800
    before = sim.state
    res = simulator_floquet(sim)
    after = sim.state
    np.testing.assert_array_equal(before.X, after.X)
    assert after.t == before.t
    assert res.multipliers.shape == (10,) and res.dropped is None
    # det M = exp(-T sum c_k / M_kk) for eq 35 (trace of the Jacobian); Newmark average
    # acceleration and the finite differences agree to ~1e-3 (measured 1.2e-3 at 800 N)
    det = np.prod(res.multipliers).real
    assert det == pytest.approx(res.info["liouville_det"], rel=5e-3)
    assert res.stable and res.leading_modulus > 0.95   # the slow, weakly damped rocking mode


def test_bearing_cage_angle_adds_only_a_trivial_multiplier(bearing_800):
    res10 = simulator_floquet(bearing_800)
    res11 = simulator_floquet(bearing_800, include_cage_angle=True)
    assert res11.dropped is not None and abs(res11.dropped - 1.0) < 1e-2
    np.testing.assert_allclose(np.sort(np.abs(res11.multipliers)),
                               np.sort(np.abs(res10.multipliers)), atol=2e-3)
