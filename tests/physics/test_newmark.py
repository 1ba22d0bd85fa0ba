"""Newmark-beta (section 2.4) as run by ``rotor.integrate`` itself, on motions with exact
discrete solutions.

With a clearance much larger than the motion no ball touches a race, and with the balls'
centrifugal force and gyroscopic moment switched off nothing pushes them against one, so the
bearing force is exactly zero and eq 35 is linear: translations under a constant force, and the tilts
of the spinning rotor, whose angular velocity u = theta_x' + i theta_y' obeys
I_r u' = (i I_z omega - c) u, an oscillator at the precession frequency W = I_z omega / I_r.
The average-acceleration rule (beta = 1/4, gamma = 1/2) is the trapezoidal rule there, so the
discrete solution is known in closed form: u_n = u_0 ((1 + h lam / 2) / (1 - h lam / 2))^n.
"""

import math

import numpy as np
import pytest

import bearing_gym
from bearing_gym.physics.ball import N_BALL_OUT
from bearing_gym.physics.layout import pack_params
from bearing_gym.physics.rotor import (N_REC, N_SCAL, R_F, R_N_INNER, R_T, R_V, R_X, S_A_PREV,
                                       S_A_PREV2, integrate)
from bearing_gym.physics.status import ST_OK

CLEARANCE = 300e-6        # the rotor moves < 1 um here: never in contact with the inner race


def _free_rotor(damping, *, preload=0.0, radial=0.0, rpm=20000.0):
    p = bearing_gym.default_params(clearance_inner_m=CLEARANCE, clearance_outer_m=CLEARANCE,
                                   axial_preload_n=preload, radial_load_x_n=radial,
                                   shaft_speed_rpm=rpm, eccentricity_m=0.0,
                                   damping_coefficients=damping, include_centrifugal=False,
                                   include_gyroscopic=False)
    return p, pack_params(p)


def _run(packed, V0, A0, n_steps):
    """integrate() from X = 0 with velocity V0 and acceleration A0; returns the record."""
    n = packed.ball_size.shape[0]
    X, V, A = np.zeros(5), np.array(V0, dtype=float), np.array(A0, dtype=float)
    scal = np.zeros(N_SCAL)
    scal[S_A_PREV:S_A_PREV + 5] = A
    scal[S_A_PREV2:S_A_PREV2 + 5] = A
    rec = np.empty((n_steps, N_REC))
    status, done, rows = integrate(packed.prm, packed.op, packed.race_wav, packed.ball_wav, packed.ball_phase,
                                   packed.ball_size, X, V, A, scal, np.zeros(n), np.zeros((n, 2)),
                                   np.zeros((n, N_BALL_OUT)), n_steps, 1, rec)
    assert (status, done, rows) == (ST_OK, n_steps, n_steps)
    assert np.all(rec[:, R_N_INNER] == 0) and np.all(rec[:, R_F:R_F + 5] == 0.0)   # free rotor
    return rec


def test_constant_force_gives_the_exact_parabola():
    """Average acceleration integrates a constant acceleration exactly: x = a t^2 / 2 + v0 t."""
    p, packed = _free_rotor((0.0,) * 5, preload=0.5, radial=-0.3)     # < 10 um in 20 ms
    m = p.rotor.mass_kg
    a = np.array([-0.3 / m, 0.0, 0.5 / m, 0.0, 0.0])
    v0 = np.array([1e-4, -2e-4, 0.0, 0.0, 0.0])
    n = 2000
    rec = _run(packed, v0, a, n)
    t = rec[:, R_T]
    np.testing.assert_allclose(t, p.integrator.dt_s * np.arange(1, n + 1), rtol=1e-12)
    for k in (0, 1, 2):
        exact = v0[k] * t + 0.5 * a[k] * t * t
        np.testing.assert_allclose(rec[:, R_X + k], exact, rtol=1e-9, atol=1e-18)
        np.testing.assert_allclose(rec[:, R_V + k], v0[k] + a[k] * t, rtol=1e-9, atol=1e-15)


def _precession(c_tilt):
    p, packed = _free_rotor((0.0, 0.0, 0.0, c_tilt, c_tilt))
    r = p.rotor
    w_shaft = p.shaft_speed_rad_s
    lam = complex(-c_tilt, r.inertia_polar_kg_m2 * w_shaft) / r.inertia_radial_kg_m2
    u0 = complex(1e-3, 0.0)                                   # rad/s
    du0 = lam * u0
    V0 = [0.0, 0.0, 0.0, u0.real, u0.imag]
    A0 = [0.0, 0.0, 0.0, du0.real, du0.imag]
    return p, packed, lam, u0, V0, A0


def test_undamped_precession_matches_the_exact_discrete_solution_and_keeps_its_speed():
    p, packed, lam, u0, V0, A0 = _precession(0.0)
    h = p.integrator.dt_s
    n = 3000                                      # about 18 precession periods
    rec = _run(packed, V0, A0, n)
    u = rec[:, R_V + 3] + 1j * rec[:, R_V + 4]
    steps = np.arange(1, n + 1)
    discrete = u0 * ((1 + h * lam / 2) / (1 - h * lam / 2)) ** steps
    np.testing.assert_allclose(u, discrete, rtol=0, atol=1e-12 * abs(u0))
    np.testing.assert_allclose(np.abs(u), abs(u0), rtol=1e-12)     # the rule conserves |u|
    # and follows the continuous precession with a phase lag of about (W h)^3 / 12 per step
    w = lam.imag
    lag = n * (w * h) ** 3 / 12
    assert np.max(np.abs(u - u0 * np.exp(lam * h * steps))) == pytest.approx(abs(u0) * lag, rel=0.05)


def test_damped_precession_matches_closed_form():
    # c chosen for a decay rate of 0.05 W: several e-foldings over the run
    p0, _, lam0, *_ = _precession(0.0)
    c = 0.05 * lam0.imag * p0.rotor.inertia_radial_kg_m2
    p, packed, lam, u0, V0, A0 = _precession(c)
    h = p.integrator.dt_s
    n = 3000
    rec = _run(packed, V0, A0, n)
    u = rec[:, R_V + 3] + 1j * rec[:, R_V + 4]
    steps = np.arange(1, n + 1)
    np.testing.assert_allclose(u, u0 * ((1 + h * lam / 2) / (1 - h * lam / 2)) ** steps,
                               rtol=0, atol=1e-12 * abs(u0))
    exact = u0 * np.exp(lam * h * steps)
    assert abs(u[-1]) < 0.5 * abs(u0)                        # it did decay
    assert np.max(np.abs(u - exact)) < 2e-3 * abs(u0)
    # the tilt angles are the integral of u (trapezoidal): theta_n = h sum (u_k + u_{k-1}) / 2
    theta = rec[:, R_X + 3] + 1j * rec[:, R_X + 4]
    trap = h * np.cumsum((u + np.concatenate([[u0], u[:-1]])) / 2)
    np.testing.assert_allclose(theta, trap, rtol=0, atol=1e-12 * abs(u0) * h * n)
    assert math.isfinite(abs(theta[-1]))


@pytest.mark.parametrize("waviness_m", [0.0, 0.5e-6])
def test_each_accepted_step_is_within_the_tolerance_of_the_converged_iteration(waviness_m):
    """The a-posteriori stop (rotor module docstring; Hairer & Wanner IV.8) accepts an iterate
    whose estimated distance to the fixed point, eta |dX|, is below ``newmark_tol_m``. Check the
    estimate against the fixed point itself: from 40 states along a contact-loaded orbit (with
    and without order-18 race waviness, whose fast forcing is where most steps now stop after one
    pass), one step at the env's tolerance and one iterated to a 1e-8 times tighter tolerance
    give displacements within that tolerance (max norm, rotations at the groove radius)."""
    from bearing_gym.params import RaceWaviness, Waviness
    from bearing_gym.physics.rotor import S_ETA, S_N_EVAL
    from bearing_gym.physics.simulator import Simulator

    wav = Waviness()
    if waviness_m:
        race = RaceWaviness(orders=(18,), radial_amplitudes_m=(waviness_m,))
        wav = Waviness(inner=race, outer=race)
    params = bearing_gym.default_params(shaft_speed_rpm=20000.0, axial_preload_n=1200.0, waviness=wav)
    tol = params.integrator.newmark_tol_m
    sim = Simulator(params)
    sim.reset()
    sim.advance(0.01)
    tight = Simulator(params.replace(newmark_tol_m=tol * 1e-8))
    from bearing_gym.physics.layout import I_RP
    r_p = sim.packed_params.prm[I_RP]             # rotations compared at the groove radius
    scale = np.array([1.0, 1.0, 1.0, r_p, r_p])
    one_pass = 0
    worst = 0.0
    for _ in range(40):
        sim.advance(5 * sim.dt_s)
        start = sim.state
        assert 0.0 < start.scal[S_ETA] < 1.0          # a contraction has been measured
        evals = start.scal[S_N_EVAL]
        sim.advance(sim.dt_s)
        one_pass += sim.state.scal[S_N_EVAL] - evals == 1.0
        tight.reset(start)
        tight.advance(tight.dt_s)
        worst = max(worst, float(np.max(np.abs(sim.state.X - tight.state.X) * scale)))
    assert worst < tol
    assert one_pass > 0      # the estimate is used, not the plain |dX| < tol
