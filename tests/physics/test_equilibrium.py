"""Quasi-static 5-DOF equilibrium: limit cases, symmetry and the reference numbers."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

import bearing_gym
from bearing_gym.physics import EquilibriumError, static_equilibrium
from bearing_gym.physics.hertz import hertz_constant, inner_rx, outer_rx


def test_pure_axial_load_at_low_speed_matches_independent_solution():
    """At ~0 rpm under pure axial load every ball carries Q = P / (N sin alpha) with
    alpha_i = alpha_o = alpha. Independent calculation: the groove centres are
    (L_i + L_o)(cos a0, sin a0) + (0, z) apart, the total deflection is that distance minus
    r_i + r_o - D_b, shared so that K_i d_i^1.5 = K_o d_o^1.5; z solves N Q sin(alpha) = P."""
    p = bearing_gym.default_params(shaft_speed_rpm=1e-3, axial_preload_n=1000.0)
    g, n = p.geometry, p.geometry.n_balls
    eq = static_equilibrium(p)
    e_eff = p.material.youngs_modulus_pa / (1 - p.material.poisson_ratio ** 2)
    db, dp, ri, ro = g.ball_diameter_m, g.pitch_diameter_m, g.inner_groove_radius_m, g.outer_groove_radius_m
    li0 = ri - db / 2 - g.clearance_inner_m
    lo0 = ro - db / 2 - g.clearance_outer_m
    a0 = g.contact_angle_rad

    def solve(z):
        sx, sz = (li0 + lo0) * math.cos(a0), (li0 + lo0) * math.sin(a0) + z
        s = math.hypot(sx, sz)
        alpha = math.atan2(sz, sx)
        total = s - (ri + ro - db)
        k_i = hertz_constant(inner_rx(db, dp, math.cos(alpha), math.sin(alpha))[0], ri / (2 * ri / db - 1), e_eff)[0]
        k_o = hertz_constant(outer_rx(db, dp, math.cos(alpha), math.sin(alpha))[0], ro / (2 * ro / db - 1), e_eff)[0]
        # K_i d_i^1.5 = K_o d_o^1.5, d_i + d_o = total
        d_i = total / (1 + (k_i / k_o) ** (2 / 3))
        q = k_i * max(d_i, 0.0) ** 1.5
        return q, alpha

    z = brentq(lambda z: n * solve(z)[0] * math.sin(solve(z)[1]) - 1000.0, 0.0, 1e-3, xtol=1e-16)
    q, alpha = solve(z)
    assert eq.U[2] == pytest.approx(z, rel=1e-6)
    np.testing.assert_allclose(eq.q_i, q, rtol=1e-6)
    np.testing.assert_allclose(eq.q_o, q, rtol=1e-5)
    np.testing.assert_allclose(eq.alpha_i, alpha, atol=1e-6)
    np.testing.assert_allclose(eq.alpha_o, alpha, atol=1e-6)
    assert eq.q_i[0] == pytest.approx(1000.0 / (n * math.sin(eq.alpha_i[0])), rel=1e-6)
    assert np.allclose(eq.U[[0, 1, 3, 4]], 0.0, atol=1e-12)


def test_radial_load_rotated_by_ball_pitch_rotates_the_solution():
    n = 18
    step = 2 * math.pi / n
    kw = dict(axial_preload_n=1000.0, shaft_speed_rpm=10000.0)
    eq0 = static_equilibrium(bearing_gym.default_params(radial_load_x_n=300.0, radial_load_y_n=0.0, **kw))
    eq1 = static_equilibrium(bearing_gym.default_params(radial_load_x_n=300.0 * math.cos(step),
                                                        radial_load_y_n=300.0 * math.sin(step), **kw))
    rot = np.array([[math.cos(step), -math.sin(step)], [math.sin(step), math.cos(step)]])
    np.testing.assert_allclose(eq1.U[:2], rot @ eq0.U[:2], rtol=0, atol=1e-11)
    np.testing.assert_allclose(eq1.U[3:], rot @ eq0.U[3:], rtol=0, atol=1e-10)
    assert eq1.U[2] == pytest.approx(eq0.U[2], abs=1e-11)
    # ball j under the rotated load carries what ball j-1 carried
    np.testing.assert_allclose(eq1.q_i, np.roll(eq0.q_i, 1), rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(eq1.alpha_o, np.roll(eq0.alpha_o, 1), atol=1e-8)


def test_stiffness_structure():
    """Axisymmetric bearing under pure axial load: K_xx = K_yy, K_x,ty = -K_y,tx, no
    radial-axial coupling; at low speed (no centrifugal/gyroscopic terms) K is symmetric to the
    small non-potential part of the alpha-dependent Hertz constant (< 1e-3)."""
    for rpm in (1.0, 20000.0):
        k = static_equilibrium(bearing_gym.default_params(shaft_speed_rpm=rpm)).stiffness
        scale = np.max(np.abs(k))
        assert k[0, 0] == pytest.approx(k[1, 1], rel=1e-6)
        assert k[0, 4] == pytest.approx(-k[1, 3], rel=1e-6)
        assert k[3, 3] == pytest.approx(k[4, 4], rel=1e-6)
        assert abs(k[0, 2]) < 1e-8 * scale and abs(k[2, 0]) < 1e-8 * scale
        assert k[0, 0] > 0 and k[2, 2] > 0 and k[3, 3] > 0
        if rpm < 10:
            assert np.max(np.abs(k - k.T)) < 1e-3 * scale


def test_contact_angles_move_with_speed():
    a_i, a_o = [], []
    for rpm in (2000.0, 10000.0, 20000.0):
        eq = static_equilibrium(bearing_gym.default_params(shaft_speed_rpm=rpm))
        a_i.append(eq.alpha_i[0])
        a_o.append(eq.alpha_o[0])
    assert a_i[0] < a_i[1] < a_i[2]
    assert a_o[0] > a_o[1] > a_o[2]


def test_reference_numbers_at_20000_rpm_800_n(default_equilibrium):
    """docs/model.md reference numbers (Jones-Harris, outer-race control, c = 4 um): alpha_i ~ 33.9 deg,
    alpha_o ~ 0.9 deg, Q_i ~ 80 N, Q_o ~ 2.10 kN, cage/shaft ~ 0.4825."""
    eq = default_equilibrium
    assert math.degrees(eq.alpha_i[0]) == pytest.approx(33.9, abs=0.2)
    assert math.degrees(eq.alpha_o[0]) == pytest.approx(0.9, abs=0.1)
    assert eq.q_i[0] == pytest.approx(80.0, rel=0.02)
    assert eq.q_o[0] == pytest.approx(2100.0, rel=0.01)
    assert eq.cage_speed_ratio == pytest.approx(0.4825, abs=5e-4)
    assert eq.residual < 1e-4


def test_reference_angles_at_2000_rpm():
    eq = static_equilibrium(bearing_gym.default_params(shaft_speed_rpm=2000.0))
    assert math.degrees(eq.alpha_i[0]) == pytest.approx(28.0, abs=0.2)
    assert math.degrees(eq.alpha_o[0]) == pytest.approx(22.5, abs=0.2)


@pytest.mark.parametrize("preload", [200.0, 800.0, 2000.0])
def test_low_speed_cage_speed_is_epicyclic(preload):
    p = bearing_gym.default_params(shaft_speed_rpm=10.0, axial_preload_n=preload)
    eq = static_equilibrium(p)
    alpha = eq.alpha_i[0]
    expected = 0.5 * (1 - p.geometry.diameter_ratio * math.cos(alpha))
    assert eq.cage_speed_ratio == pytest.approx(expected, rel=1e-3)


def test_kinematic_ratio_at_nominal_angle():
    """docs/model.md: low-speed kinematic cage/shaft ratio 0.4383 at alpha_0 = 25 deg."""
    p = bearing_gym.default_params()
    assert 0.5 * (1 - p.geometry.diameter_ratio * math.cos(p.geometry.contact_angle_rad)) == pytest.approx(0.4383, abs=1e-4)


def test_no_load_at_speed_balls_ride_on_outer_race():
    eq = static_equilibrium(bearing_gym.default_params(axial_preload_n=0.0))
    assert np.all(np.isfinite(eq.q_o)) and np.all(eq.q_i < 1e-3)
    # centrifugal force at the cage speed ~ 1.7-2.1 kN carried by the outer race
    assert np.all(eq.q_o > 1500.0) and np.all(eq.q_o < 2500.0)


def test_no_load_at_rest_is_the_origin():
    eq = static_equilibrium(bearing_gym.default_params(axial_preload_n=0.0, shaft_speed_rpm=0.0))
    assert np.all(eq.U == 0.0) and np.all(eq.q_i == 0.0) and np.all(eq.q_o == 0.0)


@pytest.mark.parametrize("control,rpm", [("inner", 2000.0), ("auto", 2000.0), ("auto", 20000.0)])
def test_other_race_controls_converge(control, rpm):
    eq = static_equilibrium(bearing_gym.default_params(race_control=control, shaft_speed_rpm=rpm))
    assert eq.residual < 1e-4
    assert 0.40 < eq.cage_speed_ratio < 0.5
    if control == "inner":
        assert eq.inner_race_control.all()
    if control == "auto" and rpm == 20000.0:
        # Jones/Harris at high speed: the outer race controls (the classic assumption)
        assert not eq.inner_race_control.any()


def test_unbalanced_radial_only_load_at_rest_raises_clear_error():
    with pytest.raises(EquilibriumError, match="equilibrium"):
        static_equilibrium(bearing_gym.default_params(radial_load_x_n=500.0, axial_preload_n=0.0,
                                                      shaft_speed_rpm=1.0), max_iter=30)
