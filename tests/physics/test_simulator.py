"""Simulator API, determinism, time-step convergence and contact loss in the dynamics."""

import numpy as np
import pytest

import bearing_gym
from bearing_gym.physics import SimulationError, Simulator
from bearing_gym.physics.layout import pack_params
from bearing_gym.units import rpm_to_rad_s


@pytest.fixture(scope="module")
def sim_800():
    return Simulator(bearing_gym.default_params())


def test_record_fields_and_shapes(sim_800):
    sim_800.reset()
    rec = sim_800.advance(0.002, record_every=10)
    n = round(0.002 / sim_800.dt_s) // 10
    assert len(rec) == n and rec.ok
    for name in ("t", "x", "y", "z", "theta_x", "theta_y", "x_dot", "y_dot", "z_dot",
                 "theta_x_dot", "theta_y_dot", "cage_speed", "cage_angle", "shaft_angle"):
        arr = getattr(rec, name)
        assert arr.shape == (n,) and np.all(np.isfinite(arr)), name
    assert rec.bearing_force.shape == (n, 5)
    assert rec.t[-1] == pytest.approx(0.002, rel=1e-12)
    np.testing.assert_allclose(np.diff(rec.t), 10 * sim_800.dt_s, rtol=1e-9)


def test_starts_at_static_equilibrium(sim_800):
    sim_800.reset()
    eq = sim_800.equilibrium
    np.testing.assert_array_equal(sim_800.state.X, eq.U)
    # cage speed at t = 0 is eq 7 at the equilibrium
    assert sim_800.state.scal[3] == pytest.approx(eq.cage_speed_ratio * rpm_to_rad_s(20000), rel=1e-12)


def test_same_parameters_give_identical_trajectories():
    p = bearing_gym.default_params(shaft_speed_rpm=15000.0)
    a = Simulator(p).advance(0.01)
    b = Simulator(p).advance(0.01)
    np.testing.assert_array_equal(a.data, b.data)
    pa, pb = pack_params(p), pack_params(bearing_gym.default_params(shaft_speed_rpm=15000.0))
    for x, y in zip(pa, pb):
        np.testing.assert_array_equal(x, y)


def test_state_restore_reproduces_continuation(sim_800):
    sim_800.reset()
    sim_800.advance(0.003)
    saved = sim_800.state
    first = sim_800.advance(0.002)
    sim_800.state = saved
    second = sim_800.advance(0.002)
    np.testing.assert_array_equal(first.data, second.data)


def test_split_advance_equals_one_advance(sim_800):
    sim_800.reset()
    whole = sim_800.advance(0.004)
    sim_800.reset()
    a = sim_800.advance(0.002)
    b = sim_800.advance(0.002)
    np.testing.assert_array_equal(whole.data, np.vstack([a.data, b.data]))


def test_loads_and_speed_settable_between_advances():
    sim = Simulator(bearing_gym.default_params())
    sim.advance(0.002)
    sim.axial_preload_n = 1200.0
    sim.radial_load_x_n = 100.0
    sim.radial_load_y_n = -50.0
    sim.shaft_speed_rpm = 18000.0
    rec = sim.advance(0.05)
    assert sim.axial_preload_n == 1200.0 and sim.shaft_speed_rpm == pytest.approx(18000.0)
    # a stiffer preload pushes the rotor further in +z: mean F_z settles near -1200 N
    assert np.mean(rec.bearing_force[-1000:, 2]) == pytest.approx(-1200.0, rel=0.02)
    with pytest.raises(ValueError, match="axial_preload_n"):
        sim.axial_preload_n = -1.0
    with pytest.raises(ValueError, match="shaft_speed_rpm"):
        sim.shaft_speed_rpm = float("nan")


def test_balanced_rotor_stays_at_equilibrium_with_the_static_cage_speed():
    """No unbalance, no waviness: the static equilibrium is a fixed point of eq 35, so the
    rotor stays there and the cage turns at the eq 7 speed of the static solution."""
    sim = Simulator(bearing_gym.default_params(eccentricity_m=0.0))
    rec = sim.advance(0.02)
    eq = sim.equilibrium
    np.testing.assert_allclose(rec.displacement, np.broadcast_to(eq.U, rec.displacement.shape),
                               rtol=0, atol=1e-12)
    omega = rpm_to_rad_s(20000)
    np.testing.assert_allclose(rec.cage_speed / omega, eq.cage_speed_ratio, rtol=1e-9)
    # eq 8: the cage angle integrates the cage speed
    np.testing.assert_allclose(np.diff(rec.cage_angle), rec.cage_speed[:-1] * sim.dt_s, rtol=1e-9)


def test_halving_dt_changes_steady_amplitudes_by_less_than_1_percent():
    """20,000 rpm, 800 N: peak-to-peak of x, z and cage speed over 0.10-0.15 s at the default
    dt and at dt/2 (same physical transient, so the difference is the discretisation error)."""
    dt = bearing_gym.default_params().integrator.dt_s
    amps = []
    for step in (dt, dt / 2):
        rec = Simulator(bearing_gym.default_params(dt_s=step)).advance(0.15)
        m = rec.t > 0.10
        amps.append(np.array([np.ptp(rec.x[m]), np.ptp(rec.z[m]), np.ptp(rec.cage_speed[m])]))
    rel = np.abs(amps[0] - amps[1]) / amps[1]
    assert np.all(rel < 0.01), rel


def test_balls_losing_inner_contact_give_finite_motion():
    """Light preload at 20,000 rpm: unbalance whirl unloads the inner contacts of many balls
    (some instants none at all); the motion stays finite and the integrator does not fail."""
    sim = Simulator(bearing_gym.default_params(axial_preload_n=300.0))
    rec = sim.advance(0.1)
    assert rec.ok and np.all(np.isfinite(rec.data))
    assert rec.n_inner_contacts.min() < 18


def test_zero_preload_zero_speed_is_at_rest():
    sim = Simulator(bearing_gym.default_params(axial_preload_n=0.0, shaft_speed_rpm=0.0,
                                               eccentricity_m=0.0))
    rec = sim.advance(0.001)
    assert rec.ok and np.all(rec.displacement == 0.0) and np.all(rec.bearing_force == 0.0)


def test_divergence_is_reported_not_nan():
    p = bearing_gym.default_params(divergence_limit_m=1e-6)
    sim = Simulator(p)
    with pytest.raises(SimulationError, match="diverged"):
        sim.advance(0.05)
    rec = Simulator(p).advance(0.05, raise_on_error=False)
    assert not rec.ok and "diverged" in rec.status and np.all(np.isfinite(rec.data))


def test_bad_advance_arguments(sim_800):
    with pytest.raises(ValueError, match="duration_s"):
        sim_800.advance(-1.0)
    with pytest.raises(ValueError, match="record_every"):
        sim_800.advance(0.001, record_every=0)
    with pytest.raises(TypeError, match="BearingParams"):
        Simulator({"shaft_speed_rpm": 1})
