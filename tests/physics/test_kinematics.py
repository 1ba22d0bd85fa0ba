"""Race-control kinematics (App. B) checked against rigid-body rolling kinematics."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bearing_gym.physics.kinematics import race_control_kinematics, spin_axis_angle

DB, DP = 19.05e-3, 140e-3
GAMMA = DB / DP


def contact_velocities(alpha_i, alpha_o, omega, inner_control):
    """Slip velocity (rolling direction) and spin about the contact normal at both contacts.

    Frame (r, phi, z) at the ball centre; ball angular velocity = omega_m e_z + omega_b a with the
    spin axis a = (-sin beta, 0, cos beta) (beta from the bearing axis, App. B); the inner race
    turns at omega about the bearing axis, the outer race is fixed.
    """
    ci, si, co, so = math.cos(alpha_i), math.sin(alpha_i), math.cos(alpha_o), math.sin(alpha_o)
    wm, _, _, _, _, _, wb = race_control_kinematics(ci, si, co, so, omega, GAMMA, 1.0, inner_control)
    beta = spin_axis_angle(ci, si, co, so, GAMMA, inner_control)
    spin_axis = np.array([-math.sin(beta), 0.0, math.cos(beta)])
    w_ball = np.array([0.0, 0.0, wm]) + wb * spin_axis
    centre = np.array([DP / 2, 0.0, 0.0])
    out = {}
    for name, alpha, side, race_speed in (("inner", alpha_i, -1.0, omega), ("outer", alpha_o, 1.0, 0.0)):
        normal = np.array([math.cos(alpha), 0.0, math.sin(alpha)])
        point = centre + side * DB / 2 * normal
        v_ball = np.cross(w_ball, point - centre) + np.cross([0.0, 0.0, wm], centre)
        v_race = np.cross([0.0, 0.0, race_speed], point)
        slip = (v_ball - v_race)[1]
        spin = (w_ball - np.array([0.0, 0.0, race_speed])) @ normal
        out[name] = (slip, spin)
    return wm, wb, out


@settings(max_examples=60, deadline=None)
@given(alpha_i=st.floats(0.0, 1.2), alpha_o=st.floats(0.0, 1.2), inner=st.booleans())
def test_pure_rolling_and_no_spin_at_controlling_race(alpha_i, alpha_o, inner):
    omega = 2000.0
    wm, wb, c = contact_velocities(alpha_i, alpha_o, omega, inner)
    scale = omega * DP / 2
    # rolling without slip at both contacts (tol: 1e-12 of the surface speed)
    assert abs(c["inner"][0]) < 1e-12 * scale
    assert abs(c["outer"][0]) < 1e-12 * scale
    # no spin at the controlling race
    controlling = "inner" if inner else "outer"
    assert abs(c[controlling][1]) < 1e-12 * omega
    assert wb < 0.0  # App. B sign kept (docs/model.md, errata)


@pytest.mark.parametrize("alpha_deg", [0.0, 15.0, 25.0, 40.0])
@pytest.mark.parametrize("inner", [False, True])
def test_equal_angles_give_epicyclic_cage_speed(alpha_deg, inner):
    a = math.radians(alpha_deg)
    omega = 1234.5
    wm = race_control_kinematics(math.cos(a), math.sin(a), math.cos(a), math.sin(a), omega, GAMMA,
                                 1.0, inner)[0]
    assert wm == pytest.approx(omega / 2 * (1 - GAMMA * math.cos(a)), rel=1e-14)


@settings(max_examples=40, deadline=None)
@given(alpha_i=st.floats(0.05, 1.2), alpha_o=st.floats(0.0, 1.2), inner=st.booleans())
def test_angle_derivatives_match_central_differences(alpha_i, alpha_o, inner):
    omega, ib = 2000.0, 1.03e-6

    def f(ai, ao):
        r = race_control_kinematics(math.cos(ai), math.sin(ai), math.cos(ao), math.sin(ao), omega,
                                    GAMMA, ib, inner)
        return np.array([r[0], r[3]])

    r = race_control_kinematics(math.cos(alpha_i), math.sin(alpha_i), math.cos(alpha_o),
                                math.sin(alpha_o), omega, GAMMA, ib, inner)
    h = 1e-6
    d_ai = (f(alpha_i + h, alpha_o) - f(alpha_i - h, alpha_o)) / (2 * h)
    d_ao = (f(alpha_i, alpha_o + h) - f(alpha_i, alpha_o - h)) / (2 * h)
    scale_w, scale_m = omega, ib * omega ** 2 / GAMMA
    assert abs(r[1] - d_ai[0]) < 1e-7 * scale_w
    assert abs(r[2] - d_ao[0]) < 1e-7 * scale_w
    assert abs(r[4] - d_ai[1]) < 1e-7 * scale_m
    assert abs(r[5] - d_ao[1]) < 1e-7 * scale_m
