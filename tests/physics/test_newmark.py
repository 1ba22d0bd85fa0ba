"""Newmark-beta (section 2.4) on a linear oscillator, using the integrator's own update rules
and the same fixed-point equilibrium iteration as rotor.integrate."""

import math

import numpy as np
import pytest

from bearing_gym.physics.rotor import newmark_displacement, newmark_predictor, newmark_velocity


def integrate_sdof(m, c, k, x0, v0, dt, n_steps, beta=0.25, gamma=0.5, force=lambda t: 0.0):
    X, V = np.array([x0]), np.array([v0])
    A = np.array([(force(0.0) - c * v0 - k * x0) / m])
    base, vstar = np.zeros(1), np.zeros(1)
    xs, vs = [x0], [v0]
    t = 0.0
    for _ in range(n_steps):
        t += dt
        newmark_predictor(X, V, A, dt, beta, gamma, base, vstar)
        x = newmark_displacement(base[0], A[0], dt, beta)
        for _it in range(200):      # fixed-point iteration on the displacement, as in integrate()
            a = (force(t) - k * x - c * vstar[0]) / (m + gamma * dt * c)
            x_new = newmark_displacement(base[0], a, dt, beta)
            done = abs(x_new - x) < 1e-15
            x = x_new
            if done:
                break
        X[0], A[0], V[0] = x, a, newmark_velocity(vstar[0], a, dt, gamma)
        xs.append(X[0])
        vs.append(V[0])
    return np.array(xs), np.array(vs)


def test_undamped_matches_exact_discrete_solution_and_conserves_energy():
    """Average acceleration on x'' + w^2 x = 0 is exactly x_n = cos(n w_d dt) with
    w_d dt = 2 atan(w dt / 2), and conserves (k x^2 + m v^2) / 2 exactly."""
    m, k = 2.0, 2.0 * (2 * math.pi * 50.0) ** 2
    w = math.sqrt(k / m)
    dt = 1e-4
    n = 2000
    x, v = integrate_sdof(m, 0.0, k, 1.0, 0.0, dt, n)
    wd = 2 * math.atan(w * dt / 2) / dt
    steps = np.arange(n + 1)
    np.testing.assert_allclose(x, np.cos(wd * dt * steps), atol=1e-10)
    energy = 0.5 * k * x ** 2 + 0.5 * m * v ** 2
    np.testing.assert_allclose(energy, energy[0], rtol=1e-10)
    # and the discrete solution follows the continuous one: the phase lags by about
    # (w dt)^3 / 12 per step, 5e-3 rad after n steps here
    phase_error = n * (w * dt) ** 3 / 12
    np.testing.assert_allclose(x, np.cos(w * dt * steps), atol=1.1 * phase_error)


def test_damped_forced_oscillator_matches_closed_form():
    """m x'' + c x' + k x = F0 sin(W t) from rest: closed-form transient + steady state."""
    m, k = 1.5, 1.5 * (2 * math.pi * 40.0) ** 2
    wn = math.sqrt(k / m)
    zeta = 0.05
    c = 2 * zeta * wn * m
    f0, W = 100.0, 2 * math.pi * 25.0
    dt, n = 2e-5, 25000
    x, _ = integrate_sdof(m, c, k, 0.0, 0.0, dt, n, force=lambda t: f0 * math.sin(W * t))
    t = np.arange(n + 1) * dt
    # steady state X sin(W t - phi)
    amp = f0 / math.sqrt((k - m * W ** 2) ** 2 + (c * W) ** 2)
    phi = math.atan2(c * W, k - m * W ** 2)
    xp = amp * np.sin(W * t - phi)
    # homogeneous part fixed by x(0) = 0, v(0) = 0
    wd = wn * math.sqrt(1 - zeta ** 2)
    c1 = -amp * math.sin(-phi)
    vp0 = amp * W * math.cos(-phi)
    c2 = (-vp0 + zeta * wn * c1) / wd
    xh = np.exp(-zeta * wn * t) * (c1 * np.cos(wd * t) + c2 * np.sin(wd * t))
    exact = xp + xh
    assert np.max(np.abs(x - exact)) < 1e-3 * np.max(np.abs(exact))
