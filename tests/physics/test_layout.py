"""Packing of the parameters into the flat arrays of the numba kernels (physics/layout.py)."""

import numpy as np
import pytest

import bearing_gym
from bearing_gym import BallWaviness, RaceWaviness, Waviness
from bearing_gym.physics import static_equilibrium
from bearing_gym.physics.layout import I_IB, I_MB, N_PRM, pack_params


def test_same_parameters_give_identical_arrays():
    wav = Waviness(inner=RaceWaviness(orders=(18,), radial_amplitudes_m=(1e-6,)),
                   balls=BallWaviness(orders=(2,), amplitudes_m=(1e-6,), phases_rad=(0.5,)))
    a = pack_params(bearing_gym.default_params(waviness=wav))
    b = pack_params(bearing_gym.default_params(waviness=wav))
    for x, y in zip(a, b):
        np.testing.assert_array_equal(x, y)
    assert a.race_wav.shape == (1, 5) and a.ball_wav.shape == (1, 2) and a.ball_phase.shape == (18, 1)


@pytest.mark.parametrize("centrifugal, gyroscopic", [(False, True), (True, False), (False, False)])
def test_switched_off_high_speed_terms_zero_only_the_ball_mass_or_inertia(centrifugal, gyroscopic):
    p = bearing_gym.default_params()
    full = pack_params(p).prm
    part = pack_params(p.replace(include_centrifugal=centrifugal, include_gyroscopic=gyroscopic)).prm
    assert full[I_MB] == pytest.approx(p.ball_mass_kg) and full[I_IB] == pytest.approx(p.ball_inertia_kg_m2)
    assert part[I_MB] == (full[I_MB] if centrifugal else 0.0)
    assert part[I_IB] == (full[I_IB] if gyroscopic else 0.0)
    others = np.setdiff1d(np.arange(N_PRM), [I_MB, I_IB])
    np.testing.assert_array_equal(part[others], full[others])


def test_without_high_speed_terms_the_contact_angles_are_equal():
    # with no centrifugal force and no gyroscopic moment a ball is held by its two contact
    # forces only, so they are collinear: alpha_i = alpha_o (and the cage runs at the
    # epicyclic speed of that angle, w/2 (1 - gamma cos a))
    import math

    p = bearing_gym.default_params(shaft_speed_rpm=2000.0)
    eq = static_equilibrium(p.replace(include_centrifugal=False, include_gyroscopic=False))
    np.testing.assert_allclose(eq.alpha_i, eq.alpha_o, atol=1e-9)
    gamma = p.geometry.diameter_ratio
    assert eq.cage_speed_ratio == pytest.approx(0.5 * (1 - gamma * math.cos(eq.alpha_i[0])), rel=1e-9)
    # and the full model is different: the centrifugal force opens the angles apart
    full = static_equilibrium(p)
    assert full.alpha_i[0] - full.alpha_o[0] > math.radians(1)
