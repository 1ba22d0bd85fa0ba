"""Parameter dataclasses: Table 1 defaults, validation with the field name, flat overrides."""

import dataclasses
import math

import pytest

import bearing_gym
from bearing_gym import BallWaviness, BearingGeometry, RaceWaviness, Waviness


def test_table_1_defaults():
    p = bearing_gym.default_params()
    g = p.geometry
    assert g.n_balls == 18
    assert (g.ball_diameter_m, g.pitch_diameter_m) == (19.05e-3, 140e-3)
    assert (g.inner_groove_radius_m, g.outer_groove_radius_m) == (10.287e-3, 9.906e-3)
    assert g.contact_angle_rad == pytest.approx(math.radians(25))
    assert (g.clearance_inner_m, g.clearance_outer_m) == (4e-6, 4e-6)
    assert (p.rotor.mass_kg, p.rotor.inertia_radial_kg_m2, p.rotor.inertia_polar_kg_m2) == (12.17, 0.0330, 0.0609)
    assert p.material.youngs_modulus_pa == 208e9 and p.material.poisson_ratio == 0.3
    # docs/model.md: m_b ~ 28.4 g, I_b = m_b D_b^2 / 10
    assert p.ball_mass_kg == pytest.approx(0.0284, abs=1e-4)
    assert p.ball_inertia_kg_m2 == pytest.approx(p.ball_mass_kg * 19.05e-3 ** 2 / 10)


def test_flat_overrides():
    p = bearing_gym.default_params(shaft_speed_rpm=12000, axial_preload_n=950.0, radial_load_x_n=10.0,
                                   radial_load_y_n=-5.0, clearance_inner_m=1e-5, clearance_outer_m=2e-5,
                                   eccentricity_m=2e-5, damping_ratio=0.05, race_control="auto", dt_s=2e-6)
    assert p.shaft_speed_rpm == 12000 and p.loads.axial_preload_n == 950.0
    assert p.loads.radial_load_x_n == 10.0 and p.loads.radial_load_y_n == -5.0
    assert p.geometry.clearance_inner_m == 1e-5 and p.geometry.clearance_outer_m == 2e-5
    assert p.rotor.eccentricity_m == 2e-5 and p.damping.damping_ratio == 0.05
    assert p.race_control == "auto" and p.integrator.dt_s == 2e-6
    assert p.replace(axial_preload_n=10.0).loads.axial_preload_n == 10.0


def test_unknown_keyword_is_a_type_error_naming_it():
    with pytest.raises(TypeError, match="preload_newtons"):
        bearing_gym.default_params(preload_newtons=800)


INVALID = [
    ("axial_preload_n", -1.0),
    ("axial_preload_n", float("nan")),
    ("shaft_speed_rpm", -10.0),
    ("shaft_speed_rpm", float("inf")),
    ("n_balls", 0),
    ("n_balls", 2.5),
    ("n_balls", 40),                      # 40 balls of 19 mm do not fit on a 140 mm pitch circle
    ("ball_diameter_m", -1e-3),
    ("pitch_diameter_m", 10e-3),          # smaller than the ball
    ("inner_groove_radius_m", 9.0e-3),    # groove smaller than the ball
    ("outer_groove_radius_m", 9.525e-3),  # no room for the clearance
    ("clearance_inner_m", -1e-6),
    ("contact_angle_rad", math.radians(85)),
    ("youngs_modulus_pa", 0.0),
    ("poisson_ratio", 0.6),
    ("density_kg_m3", -1.0),
    ("mass_kg", 0.0),
    ("inertia_radial_kg_m2", -0.1),
    ("inertia_polar_kg_m2", float("nan")),
    ("eccentricity_m", -1e-6),
    ("radial_load_x_n", float("nan")),
    ("damping_ratio", -0.1),
    ("damping_ratio", 2.0),
    ("dt_s", 0.0),
    ("dt_s", -1e-6),
    ("newmark_beta", 0.0),
    ("newmark_gamma", 0.4),
    ("newton_tol_m", 0.0),
    ("newton_max_iter", 0),
    ("newmark_max_iter", 1.5),
    ("race_control", "middle"),
]


@pytest.mark.parametrize("field,value", INVALID)
def test_invalid_value_raises_value_error_naming_the_field(field, value):
    with pytest.raises(ValueError, match=field):
        bearing_gym.default_params(**{field: value})


def test_error_message_states_the_allowed_range():
    with pytest.raises(ValueError, match=r"axial_preload_n must be in \[0, 1e\+06\], got -5"):
        bearing_gym.default_params(axial_preload_n=-5.0)


def test_waviness_validation():
    with pytest.raises(ValueError, match="radial_amplitudes_m"):
        RaceWaviness(orders=(18, 2), radial_amplitudes_m=(1e-6,))
    with pytest.raises(ValueError, match="orders"):
        RaceWaviness(orders=(0,))
    with pytest.raises(ValueError, match="amplitudes_m"):
        BallWaviness(orders=(2,), amplitudes_m=(-1e-6,))
    with pytest.raises(ValueError, match="oversize_m"):
        bearing_gym.default_params(waviness=Waviness(balls=BallWaviness(oversize_m=(1e-6,) * 5)))
    with pytest.raises(ValueError, match="geometry"):
        bearing_gym.default_params(geometry="Table 1")


def test_frozen():
    g = BearingGeometry()
    with pytest.raises(dataclasses.FrozenInstanceError):
        g.n_balls = 3


def test_high_speed_term_switches_are_validated_booleans():
    p = bearing_gym.default_params()
    assert p.include_centrifugal is True and p.include_gyroscopic is True
    q = p.replace(include_centrifugal=False)
    assert q.include_centrifugal is False and q.include_gyroscopic is True
    for bad in (0, 1, "no", None, 0.0):
        with pytest.raises(ValueError, match="include_gyroscopic must be True or False"):
            p.replace(include_gyroscopic=bad)


def test_params_imports_no_physics():
    """params.py is below the physics: importing it loads no bearing_gym.physics module."""
    import subprocess
    import sys

    code = ("import sys, bearing_gym.params; "
            "print(sorted(m for m in sys.modules if m.startswith('bearing_gym.physics')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
