"""The fatigue term: Lundberg-Palmgren life from the model's contact loads (physics/rating.py,
envs/contact.py, the reward's fatigue term), checked against hand calculations of the textbook
formulas (Harris & Kotzalas vol. 2 ch. 8; ISO 76; Palmgren), written out here independently of
the code (plain ``math`` and NumPy ``**``)."""

import math

import numpy as np
import pytest

from bearing_gym.envs import BearingPreloadEnv, VibrationFirstReward
from bearing_gym.envs.contact import C_INNER_Q3_MEAN, C_MAX_INNER_N, C_MAX_OUTER_N, C_OUTER_Q10_3_MEAN
from bearing_gym.envs.core import env_params
from bearing_gym.params import default_params
from bearing_gym.physics import Simulator, static_equilibrium
from bearing_gym.physics.ball import B_QI, B_QO
from bearing_gym.physics.portable_math import cube_root_near
from bearing_gym.physics.rating import (dynamic_capacities_n, friction_torque_n_m,
                                        life_used_per_revolution, static_capacity_n)
from bearing_gym.physics.rotor import (N_REC, S_LOAD_STEPS, S_MAX_QI, S_MAX_QO, S_SUM_QI3, S_SUM_QO10_3, integrate)

RPM = math.pi / 30.0
GEOMETRY = default_params().geometry


def harris_capacities_by_hand():
    """Harris' Q_c for the default bearing (Table 1 of Bai & Xu: D = 19.05 mm, d_m = 140 mm,
    r_i = 10.287 mm, r_o = 9.906 mm, alpha = 25 deg, Z = 18), N with D in mm."""
    d, dm, z = 19.05, 140.0, 18
    fi, fo = 10.287 / d, 9.906 / d            # 0.54, 0.52
    g = d * math.cos(math.radians(25.0)) / dm
    common = 98.1 * (d / dm) ** 0.3 * d ** 1.8 * z ** (-1.0 / 3.0)
    qci = common * (2 * fi / (2 * fi - 1)) ** 0.41 * (1 - g) ** 1.39 / (1 + g) ** (1.0 / 3.0)
    qco = common * (2 * fo / (2 * fo - 1)) ** 0.41 * (1 + g) ** 1.39 / (1 - g) ** (1.0 / 3.0)
    return qci, qco


def l10_by_hand(qi, qo, qci, qco):
    """L_10 (10^6 revolutions) from per-ball loads, Lundberg-Palmgren as in Harris."""
    qei = np.mean(np.asarray(qi) ** 3) ** (1 / 3)
    qeo = np.mean(np.asarray(qo) ** (10 / 3)) ** (3 / 10)
    li, lo = (qci / qei) ** 3, (qco / qeo) ** 3
    return (li ** (-10 / 9) + lo ** (-10 / 9)) ** (-9 / 10)


# --- the formulas -----------------------------------------------------------------------------
def test_capacities_are_harris_formula_for_the_default_bearing():
    qci, qco = dynamic_capacities_n(GEOMETRY)
    hand_i, hand_o = harris_capacities_by_hand()
    # the same formula through the portable powers: agreement to rounding (1e-9 relative)
    assert qci == pytest.approx(hand_i, rel=1e-9) and qco == pytest.approx(hand_o, rel=1e-9)
    # and the numbers the docs quote (worked by hand: 98.1 x 2.907 x 0.8012 x 0.5497 x 201.3 x
    # 0.3816 for the inner race), to their 4-5 digits
    assert qci == pytest.approx(9646.0, rel=1e-4) and qco == pytest.approx(19345.0, rel=1e-4)
    # the outer race's conformity (0.52) and convex-concave geometry make it the stronger race
    assert qco > 2.0 * qci


def test_life_of_uniform_loads_is_the_race_law_exactly():
    qci, qco = dynamic_capacities_n(GEOMETRY)
    for q in (50.0, 800.0, 3000.0):
        # inner race alone: L_i = (Q_ci / Q)^3 (10^6 revolutions)
        per_rev = life_used_per_revolution(q ** 3, 0.0, (qci, qco))[0]
        assert 1.0 / (per_rev * 1e6) == pytest.approx((qci / q) ** 3, rel=1e-12)
        # outer race alone: the mean of Q^(10/3) of equal loads is Q^(10/3): L_o = (Q_co / Q)^3
        per_rev = life_used_per_revolution(0.0, q ** (10 / 3), (qci, qco))[0]
        assert 1.0 / (per_rev * 1e6) == pytest.approx((qco / q) ** 3, rel=1e-12)


def test_races_combine_with_the_10_9_law():
    qci, qco = dynamic_capacities_n(GEOMETRY)
    # two races of equal life L: L_10 = L 2^(-9/10)
    q_i = 1000.0
    q_o = qco / qci * q_i                     # (Q_co / Q_o)^3 = (Q_ci / Q_i)^3
    life = (qci / q_i) ** 3
    per_rev = life_used_per_revolution(q_i ** 3, q_o ** (10 / 3), (qci, qco))[0]
    assert 1.0 / (per_rev * 1e6) == pytest.approx(life * 2 ** (-0.9), rel=1e-12)
    # one race far weaker than the other: the bearing's life is that race's
    per_rev = life_used_per_revolution(q_i ** 3, (1e-3 * q_o) ** (10 / 3), (qci, qco))[0]
    assert 1.0 / (per_rev * 1e6) == pytest.approx(life, rel=1e-8)
    # unequal loads over the balls: the hand calculation of Harris' equivalent loads
    qi = np.linspace(0.0, 900.0, 18)
    qo = np.linspace(1500.0, 2600.0, 18)
    per_rev = life_used_per_revolution(np.mean(qi ** 3), np.mean(qo ** (10 / 3)), (qci, qco))[0]
    assert 1.0 / (per_rev * 1e6) == pytest.approx(l10_by_hand(qi, qo, qci, qco), rel=1e-12)


def test_cube_root_near_is_the_cube_root():
    rng = np.random.default_rng(0)
    for x in rng.uniform(1.0, 1e4, 200):
        exact = x ** (1 / 3)
        for guess in (exact * 1.02, exact * 0.97, exact * 1.5, exact * 0.1, 0.0):   # near: Halley, far: cbrt
            assert cube_root_near(x, guess) == pytest.approx(exact, rel=2e-14)


def test_friction_torque_is_palmgrens_load_term():
    # ISO 76: f_0 = 15.9 at D cos(alpha) / d_m = 0.12 and 15.6 at 0.13 (Table 2), C_0 = f_0 Z D^2 cos(alpha)
    g = 19.05 * math.cos(math.radians(25.0)) / 140.0
    f0 = 15.9 + (g - 0.12) / 0.01 * (15.6 - 15.9)
    c0 = f0 * 18 * 19.05 ** 2 * math.cos(math.radians(25.0))
    assert static_capacity_n(GEOMETRY) == pytest.approx(c0, rel=1e-12)
    assert 85e3 < c0 < 100e3          # a 100 mm bore, 25 deg spindle bearing's catalogue C_0
    for fr, fa in ((0.0, 800.0), (500.0, 2000.0), (500.0, 300.0)):
        p0 = max(fr, 0.5 * fr + 0.38 * fa)          # X_0 = 0.5, Y_0 = 0.38 at 25 deg
        p1 = max(fa - 0.1 * fr, fr)
        m1 = 0.001 * (p0 / c0) ** 0.33 * p1 * 0.140
        assert friction_torque_n_m(GEOMETRY, fr, fa)[0] == pytest.approx(m1, rel=1e-12)


# --- the model's loads ------------------------------------------------------------------------
def _static(rpm, preload, radial=0.0, clearance=4e-6):
    return static_equilibrium(default_params(shaft_speed_rpm=rpm, axial_preload_n=preload, radial_load_x_n=radial,
                                             clearance_inner_m=clearance, clearance_outer_m=clearance))


def test_more_preload_at_fixed_speed_uses_more_inner_race_life():
    qci, qco = dynamic_capacities_n(GEOMETRY)
    inner, bearing = [], []
    for p in (300.0, 1000.0, 2000.0):
        eq = _static(15000.0, p)
        inner.append(life_used_per_revolution(np.mean(eq.q_i ** 3), 0.0, (qci, qco))[0])
        bearing.append(life_used_per_revolution(np.mean(eq.q_i ** 3), np.mean(eq.q_o ** (10 / 3)), (qci, qco))[0])
    # and the bearing's life used follows (the outer contacts carry the preload too)
    assert bearing[0] < bearing[1] < bearing[2]
    assert inner[0] < inner[1] < inner[2]
    assert inner[2] / inner[0] > 10.0        # Q_i ~ P: (2000 / 300)^3 = 296 at equal angles


def test_speed_loads_the_outer_race_with_the_balls_centrifugal_force():
    p = default_params()
    m_b = p.material.density_kg_m3 * math.pi * 0.01905 ** 3 / 6
    gamma_cos = 19.05 / 140.0 * math.cos(math.radians(25.0))
    qci, qco = dynamic_capacities_n(GEOMETRY)
    qo_mean, per_rev = {}, {}
    for rpm in (10000.0, 25000.0):
        eq = _static(rpm, 800.0)
        qo_mean[rpm] = float(np.mean(eq.q_o))
        per_rev[rpm] = life_used_per_revolution(np.mean(eq.q_i ** 3), np.mean(eq.q_o ** (10 / 3)), (qci, qco))[0]
    # F_c = m_b (d_m / 2) omega_m^2 with the kinematic orbital speed omega_m = omega/2 (1 - gamma cos a)
    fc = {rpm: m_b * 0.07 * (0.5 * rpm * RPM * (1 - gamma_cos)) ** 2 for rpm in qo_mean}
    assert fc[25000.0] == pytest.approx(2.6e3, rel=0.05)
    # the outer loads grow by about the centrifugal force's growth (its radial part: cos(alpha_o) ~ 0.8-0.9)
    assert qo_mean[25000.0] - qo_mean[10000.0] == pytest.approx(fc[25000.0] - fc[10000.0], rel=0.25)
    # so a revolution at 25,000 rpm costs far more life than one at 10,000 rpm at the same preload
    assert per_rev[25000.0] > 50.0 * per_rev[10000.0]


def test_the_integrators_accumulators_are_the_sums_of_the_step_loads():
    sim = Simulator(env_params(shaft_speed_rpm=18000.0, axial_preload_n=700.0, radial_load_x_n=300.0,
                               clearance_inner_m=10e-6, clearance_outer_m=10e-6))
    s = sim.state
    X, V, A, scal, psi_b, ball_v, ball_out = (s.X.copy(), s.V.copy(), s.A.copy(), s.scal.copy(), s.psi_b.copy(),
                                              s.ball_v.copy(), s.ball_out.copy())
    p = sim.packed_params
    rec = np.zeros((2, N_REC))
    scal[S_SUM_QI3:S_MAX_QO + 1] = 0.0
    loads_i, loads_o = [], []
    ref = None
    for k in range(300):                    # one step per call: read each step's loads
        st, done, _ = integrate(p.prm, p.op, p.race_wav, p.ball_wav, p.ball_phase, p.ball_size, X, V, A, scal,
                                psi_b, ball_v, ball_out, 1, 1000, rec)
        assert st == 0 and done == 1
        loads_i.append(ball_out[:, B_QI].copy())
        loads_o.append(ball_out[:, B_QO].copy())
        if k == 0:
            ref = scal.copy()
    qi, qo = np.array(loads_i), np.array(loads_o)
    assert scal[S_LOAD_STEPS] == 300.0
    assert scal[S_SUM_QI3] == pytest.approx(np.sum(qi ** 3), rel=1e-12)
    assert scal[S_SUM_QO10_3] == pytest.approx(np.sum(qo ** (10 / 3)), rel=1e-12)
    assert scal[S_MAX_QI] == qi.max() and scal[S_MAX_QO] == qo.max()
    assert ref[S_LOAD_STEPS] == 1.0 and qo.max() > qo.min() > 0.0       # the loads did vary
    # one call of 300 steps (each outer root from the last step's by Halley) gives the same sums
    s2 = sim.state
    X, V, A, scal2, psi_b, ball_v, ball_out = (s2.X.copy(), s2.V.copy(), s2.A.copy(), s2.scal.copy(),
                                               s2.psi_b.copy(), s2.ball_v.copy(), s2.ball_out.copy())
    scal2[S_SUM_QI3:S_MAX_QO + 1] = 0.0
    integrate(p.prm, p.op, p.race_wav, p.ball_wav, p.ball_phase, p.ball_size, X, V, A, scal2, psi_b, ball_v,
              ball_out, 300, 1000, rec)
    assert scal2[S_SUM_QO10_3] == pytest.approx(scal[S_SUM_QO10_3], rel=1e-13)
    assert scal2[S_SUM_QI3] == scal[S_SUM_QI3]


def test_an_env_interval_reports_the_means_of_its_steps():
    env = BearingPreloadEnv(tier="stationary")
    env.reset(seed=0, options={"shaft_speed_rpm": 20000.0, "radial_load_n": 250.0, "clearance_m": 10e-6,
                               "initial_preload_n": 1000.0, "waviness_amplitude_m": 0.0})
    env.step(np.array([env.actuator.action_for(1000.0)], np.float32))
    b = env.batch
    steps = b.scal[0, S_LOAD_STEPS]
    assert steps == round(0.02 / b.dt_s)                 # every Newmark step of the interval, once
    n = b.base.geometry.n_balls
    assert b.contact[0, C_INNER_Q3_MEAN] == pytest.approx(b.scal[0, S_SUM_QI3] / (steps * n), rel=1e-15)
    assert b.contact[0, C_OUTER_Q10_3_MEAN] == pytest.approx(b.scal[0, S_SUM_QO10_3] / (steps * n), rel=1e-15)
    assert b.contact[0, C_MAX_INNER_N] >= b.ball_out[0, :, B_QI].max()
    assert b.contact[0, C_MAX_OUTER_N] >= b.ball_out[0, :, B_QO].max()


def test_period1_life_used_is_close_to_the_static_equilibriums():
    # what the docs' before/after table assumes (benchmarks/fatigue_map.py --dynamic checks more)
    env = BearingPreloadEnv(tier="stationary")
    env.reset(seed=0, options={"shaft_speed_rpm": 25000.0, "radial_load_n": 0.0, "clearance_m": 4e-6,
                               "eccentricity_m": 5e-6, "initial_preload_n": 1200.0, "waviness_amplitude_m": 0.0})
    lives = []
    for _ in range(3):
        *_, info = env.step(np.array([env.actuator.action_for(1200.0)], np.float32))
        assert not info["quasi_periodic"]
        lives.append(info["life_used_per_s"])
    eq = _static(25000.0, 1200.0)
    static = 25000.0 / 60.0 / (1e6 * l10_by_hand(eq.q_i, eq.q_o, *harris_capacities_by_hand()))
    assert np.mean(lives) == pytest.approx(static, rel=0.02)


# --- the reward's normalisation ---------------------------------------------------------------
def test_the_costliest_corner_costs_the_fatigue_share_bent_by_the_cap():
    r = VibrationFirstReward()
    eq = _static(25000.0, 2000.0, radial=500.0, clearance=30e-6)
    u = 25000.0 / 60.0 / (1e6 * l10_by_hand(eq.q_i, eq.q_o, *harris_capacities_by_hand()))
    assert r.reference_life_used_per_s == pytest.approx(u, rel=1e-12)
    heat, fatigue = r.secondary_costs(2000.0, 25000.0 * RPM, u)
    # there the fatigue's raw cost s_f u / u_ref = 0.5 meets its room 1 - heat = 0.5, where the
    # smooth cap bends it to 0.45 + 0.05 * 1 / (1 + 1) (reward docstring)
    assert heat == pytest.approx(r.heat_share, rel=1e-12)
    assert fatigue == pytest.approx(0.9 * 0.5 + 0.1 * 0.5 * 0.5, rel=1e-12)
    # and it is the costliest clearance of the envelope: the 4 um bearing uses less life there
    eq4 = _static(25000.0, 2000.0, radial=500.0, clearance=4e-6)
    assert l10_by_hand(eq4.q_i, eq4.q_o, *harris_capacities_by_hand()) > 1.2 * (25000.0 / 60.0 / u / 1e6)


def test_the_smooth_cap_is_the_identity_below_its_knee_continuous_increasing_and_bounded():
    """C(x, b): x itself up to 0.9 b; above, continuous in value and slope at the knee (one-sided
    differences agree to 1e-6), strictly increasing, below b, and 0 without room."""
    from bearing_gym.envs.reward import smooth_cap
    b = 0.37
    below = np.linspace(0.0, 0.9 * b, 50)
    np.testing.assert_array_equal(smooth_cap(below, b), below)
    x = np.linspace(0.0, 20.0 * b, 4001)             # up to 20 times the room: still ranked
    c = smooth_cap(x, b)
    assert np.all(np.diff(c) > 0.0) and np.all(c < b)
    k, h = 0.9 * b, 1e-7
    assert smooth_cap(k + h, b) == pytest.approx(k + h, abs=1e-12)
    slope_above = (smooth_cap(k + 2 * h, b) - smooth_cap(k + h, b)) / h
    assert slope_above == pytest.approx(1.0, abs=1e-5)
    assert float(smooth_cap(5.0, 0.0)) == 0.0
