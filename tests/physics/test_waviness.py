"""Waviness (corrected eqs 9-14)."""

import math

import numpy as np

import bearing_gym
from bearing_gym import BallWaviness, RaceWaviness, Waviness
from bearing_gym.physics import Simulator
from bearing_gym.physics.bearing import ball_angle
from bearing_gym.physics.waviness import ball_waviness, race_waviness


def test_zero_amplitudes_reproduce_the_waviness_free_run_bit_for_bit():
    zero = Waviness(inner=RaceWaviness(orders=(18,), radial_amplitudes_m=(0.0,), axial_amplitudes_m=(0.0,)),
                    outer=RaceWaviness(orders=(18, 5), radial_amplitudes_m=(0.0, 0.0)),
                    balls=BallWaviness(orders=(2,), amplitudes_m=(0.0,)))
    a = Simulator(bearing_gym.default_params()).advance(0.005)
    b = Simulator(bearing_gym.default_params(waviness=zero)).advance(0.005)
    np.testing.assert_array_equal(a.data, b.data)


def test_outer_race_order_n_equal_to_ball_count_gives_every_ball_the_same_phase():
    n = 18
    race_wav = np.array([[1.0, 0.0, float(n), 1e-6, 0.3], [1.0, 1.0, float(n), 2e-6, 1.1]])
    vals = []
    for cage in (0.0, 0.123):
        vals = np.array([race_waviness(race_wav, ball_angle(j, n, cage, 0.0), 0.7) for j in range(n)])
        np.testing.assert_allclose(vals, np.broadcast_to(vals[0], vals.shape), rtol=0, atol=1e-18)
    # and with a different order the balls see different phases
    race_wav[:, 2] = 5.0
    vals = np.array([race_waviness(race_wav, ball_angle(j, n, 0.0, 0.0), 0.0) for j in range(n)])
    assert np.ptp(vals[:, 2]) > 1e-6


def test_inner_race_waviness_turns_with_the_shaft():
    race_wav = np.array([[0.0, 0.0, 3.0, 1e-6, 0.0]])
    # ball at angle phi and shaft at theta see the ring angle phi - theta
    assert race_waviness(race_wav, 1.0, 0.4)[0] == race_waviness(race_wav, 0.6, 0.0)[0]
    assert race_waviness(race_wav, 0.5, 0.0)[0] == 1e-6 * math.cos(1.5)


def test_ball_waviness_opposite_contacts_are_half_a_turn_apart():
    bw = np.array([[2.0, 1e-6], [3.0, 5e-7]])
    ph = np.array([[0.2, 0.4]])
    w_i, w_o = ball_waviness(bw, ph, 0, 0.9)
    assert w_i == 1e-6 * math.cos(2 * 0.9 + 0.2) + 5e-7 * math.cos(3 * 0.9 + 0.4)
    assert math.isclose(w_o, 1e-6 * math.cos(2 * (0.9 + math.pi) + 0.2)
                        + 5e-7 * math.cos(3 * (0.9 + math.pi) + 0.4), rel_tol=1e-14)


def test_outer_waviness_of_order_n_keeps_the_rotor_centred():
    """Order N on the outer race loads all balls alike: with no unbalance and no radial load the
    rotor moves only axially (x, y, tilts stay at round-off), at the ball-pass frequency."""
    wav = Waviness(outer=RaceWaviness(orders=(18,), radial_amplitudes_m=(1e-6,)))
    sim = Simulator(bearing_gym.default_params(waviness=wav, eccentricity_m=0.0))
    rec = sim.advance(0.01)
    assert np.max(np.abs(rec.x)) < 1e-12 and np.max(np.abs(rec.y)) < 1e-12
    assert np.max(np.abs(rec.theta_x)) < 1e-10 and np.max(np.abs(rec.theta_y)) < 1e-10
    assert np.ptp(rec.z[len(rec) // 2:]) > 1e-8


def test_waviness_of_all_balls_by_rotation_equals_the_per_ball_sums():
    """bearing.ball_geometry advances each ball's angle and each waviness term by the fixed ball
    spacing (a rotation) instead of evaluating eqs 6 and 9-12 per ball: the same values up to
    the rounding of the angles (independent: race_waviness evaluates every ball's cosine
    directly). A cosine's argument n (phi - theta) + xi is rounded to ~|argument| eps in either
    way, and the rotation adds about one ulp per ball: the bound is the amplitude times that."""
    from bearing_gym.physics.bearing import G_COS, G_PI, G_SIN, N_GEO, ball_geometry
    from bearing_gym.physics.layout import pack_params
    wav = Waviness(inner=RaceWaviness(orders=(18, 3), radial_amplitudes_m=(0.5e-6, 0.2e-6),
                                      axial_amplitudes_m=(0.1e-6, 0.0), radial_phases_rad=(0.3, 2.0)),
                   outer=RaceWaviness(orders=(18, 25), radial_amplitudes_m=(0.4e-6, 1e-7),
                                      axial_amplitudes_m=(0.0, 3e-7)))
    packed = pack_params(bearing_gym.default_params(waviness=wav, initial_cage_angle_rad=0.4))
    n = int(packed.prm[0])
    for cage, shaft in ((0.0, 0.0), (12.345, 98.7), (-3.0, 1e3)):
        geo = np.zeros((n, N_GEO))
        ball_geometry(cage, shaft, np.zeros(n), packed.prm, packed.race_wav, packed.ball_wav,
                      packed.ball_phase, geo)
        for j in range(n):
            phi = ball_angle(j, n, cage, 0.4)
            assert abs(geo[j, G_COS] - math.cos(phi)) < 1e-14 and abs(geo[j, G_SIN] - math.sin(phi)) < 1e-14
            expected = race_waviness(packed.race_wav, phi, shaft)
            argument = 25 * (abs(cage) + abs(shaft) + 2 * math.pi) + 2 * math.pi   # largest order 25
            bound = 1.3e-6 * (4 * argument + 4 * n) * np.finfo(float).eps           # sum of amplitudes 1.3 um
            np.testing.assert_allclose(geo[j, G_PI:G_PI + 4], expected, rtol=0, atol=bound)
