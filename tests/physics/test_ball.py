"""Per-ball equilibrium (eqs 16-31): analytic Jacobian (App. C, corrected) and contact loss."""

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import bearing_gym
from bearing_gym.physics import static_equilibrium
from bearing_gym.physics.ball import N_BALL_OUT, ball_residual, solve_ball
from bearing_gym.physics.layout import I_NT_TOL as NT_TOL
from bearing_gym.physics.layout import pack_params

RPM_CASES = (2000.0, 20000.0)
_BASE = {}


def base_state(rpm):
    if rpm not in _BASE:
        p = bearing_gym.default_params(shaft_speed_rpm=rpm)
        eq = static_equilibrium(p)
        prm = pack_params(p).prm
        g = p.geometry
        _BASE[rpm] = dict(prm=prm, u=(0.0, eq.U[2]),
                          v=(eq.ball_displacement_r[0], eq.ball_displacement_z[0]),
                          dist=(g.inner_groove_radius_m - g.ball_diameter_m / 2,
                                g.outer_groove_radius_m - g.ball_diameter_m / 2),
                          omega=p.shaft_speed_rad_s)
    return _BASE[rpm]


@settings(max_examples=60, deadline=None)
@given(rpm=st.sampled_from(RPM_CASES), inner=st.booleans(),
       d=st.lists(st.floats(-4e-6, 4e-6), min_size=4, max_size=4))
def test_analytic_jacobian_matches_central_differences(rpm, inner, d):
    b = base_state(rpm)
    ur, uz = b["u"][0] + d[0], b["u"][1] + d[1]
    vr, vz = b["v"][0] + d[2], b["v"][1] + d[3]
    args = (ur, uz, b["dist"][0], b["dist"][1], b["omega"], inner, b["prm"])
    r = ball_residual(vr, vz, *args)
    assume(r[15] > 2e-7 and r[16] > 2e-7)   # both contacts loaded, away from the Hertz kink
    h = 1e-10
    rp_r, rm_r = ball_residual(vr + h, vz, *args), ball_residual(vr - h, vz, *args)
    rp_z, rm_z = ball_residual(vr, vz + h, *args), ball_residual(vr, vz - h, *args)
    fd = np.array([[(rp_r[0] - rm_r[0]) / (2 * h), (rp_z[0] - rm_z[0]) / (2 * h)],
                   [(rp_r[1] - rm_r[1]) / (2 * h), (rp_z[1] - rm_z[1]) / (2 * h)]])
    jac = np.array([[r[2], r[3]], [r[4], r[5]]])
    scale = np.max(np.abs(jac))
    np.testing.assert_allclose(jac, fd, rtol=0, atol=2e-6 * scale)


@pytest.mark.parametrize("inner", [False, True])
def test_newton_converges_from_cold_start_to_equilibrium(inner):
    b = base_state(20000.0)
    out = np.zeros((1, N_BALL_OUT))
    vr, vz, status = solve_ball(0.0, 0.0, b["u"][0], b["u"][1], b["dist"][0], b["dist"][1],
                                b["omega"], inner, b["prm"], out, 0)
    assert status == 0
    r = ball_residual(vr, vz, b["u"][0], b["u"][1], b["dist"][0], b["dist"][1], b["omega"], inner,
                      b["prm"])
    # the iteration stops once the Newton step is below newton_tol_m (1 nm) and takes that last
    # step: in the quadratic regime the remaining error is ~ step^2 / delta (1e-13 m here), so the
    # residual of eq 28 is below 1e-6 of the contact loads
    assert abs(r[0]) < 1e-6 * max(r[6], r[7]) and abs(r[1]) < 1e-6 * max(r[6], r[7])
    # and the contact state written by the solver is that of the returned point
    np.testing.assert_allclose(out[0, :2], [r[6], r[7]], rtol=1e-9)


def test_free_ball_at_speed_is_held_against_outer_race_by_centrifugal_force():
    """Inner race pulled away (no inner contact): zero inner load, the outer load balances the
    centrifugal force m_b (D_p/2 + v_r) omega_m^2 (eq 29) and the ball sits at alpha_o ~ 0."""
    p = bearing_gym.default_params()
    prm = pack_params(p).prm
    g = p.geometry
    out = np.zeros((1, N_BALL_OUT))
    vr, vz, status = solve_ball(0.0, 0.0, -50e-6, -20e-6, g.inner_groove_radius_m - g.ball_diameter_m / 2,
                                g.outer_groove_radius_m - g.ball_diameter_m / 2,
                                p.shaft_speed_rad_s, False, prm, out, 0)
    assert status == 0
    q_i, q_o, ci, si, co, so, wm = out[0, :7]
    assert q_i == 0.0
    assert np.all(np.isfinite(out))
    fe = p.ball_mass_kg * (g.pitch_diameter_m / 2 + vr) * wm ** 2
    # radial balance: Q_o cos a_o = F_e - (2 M_g / D_b) sin a_o (outer-race control friction)
    mg = out[0, 8]
    assert q_o * co == pytest.approx(fe - 2 * mg / g.ball_diameter_m * so, rel=1e-9)
    assert abs(math.atan2(so, co)) < math.radians(1.0)


def test_unloaded_ball_at_rest_carries_nothing():
    p = bearing_gym.default_params(shaft_speed_rpm=0.0)
    prm = pack_params(p).prm
    g = p.geometry
    out = np.zeros((1, N_BALL_OUT))
    vr, vz, status = solve_ball(0.0, 0.0, 0.0, 0.0, g.inner_groove_radius_m - g.ball_diameter_m / 2,
                                g.outer_groove_radius_m - g.ball_diameter_m / 2, 0.0, False, prm, out, 0)
    assert status == 0 and vr == 0.0 and vz == 0.0
    assert out[0, 0] == 0.0 and out[0, 1] == 0.0
    assert np.all(np.isfinite(out))


@pytest.mark.parametrize("rpm", RPM_CASES)
@pytest.mark.parametrize("miss_m", [5e-9, 2e-8, 6e-8])
def test_the_quadratic_stop_is_within_the_rotor_tolerance_of_the_solution(rpm, miss_m):
    """The ball Newton stops once its error estimate step^2 / delta_min is below the rotor's
    newmark_tol_m (the env's 1e-10 m): the point it returns must then lie within that tolerance
    of the converged solution (an independent solve from it with the step rule alone, to
    1e-15 m), for warm starts that miss by 5-60 nm in every direction; it never needs more
    residuals than the step rule, and where the miss is within sqrt(tol delta_min) (5 nm here,
    with deflections of a few um) it stops after one residual where the step rule (1 nm) needs
    two."""
    b = base_state(rpm)
    env_prm = b["prm"].copy()
    from bearing_gym.physics.layout import I_NM_TOL
    from bearing_gym.physics.ball import B_NITER
    env_prm[I_NM_TOL] = 1e-10
    tight = env_prm.copy()
    tight[NT_TOL] = 1e-15
    tight[I_NM_TOL] = 1e-30                         # the step rule alone
    args = (b["u"][0] + 1e-6, b["u"][1] - 2e-6, b["dist"][0], b["dist"][1], b["omega"], False)
    out = np.zeros((1, N_BALL_OUT))
    v_star = solve_ball(0.0, 0.0, *args, tight, out, 0)[:2]
    single = 0
    for angle in np.linspace(0.0, 2 * math.pi, 8, endpoint=False):
        start = (v_star[0] + miss_m * math.cos(angle), v_star[1] + miss_m * math.sin(angle))
        out = np.zeros((1, N_BALL_OUT))
        vr, vz, status = solve_ball(*start, *args, env_prm, out, 0)
        assert status == 0
        assert math.hypot(vr - v_star[0], vz - v_star[1]) < 1e-10
        single += out[0, B_NITER] == 1.0
        out_step = np.zeros((1, N_BALL_OUT))
        solve_ball(*start, *args, tight, out_step, 0)
        assert out_step[0, B_NITER] >= out[0, B_NITER]
    if miss_m <= 5e-9:
        assert single == 8
