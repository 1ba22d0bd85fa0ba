"""The numba window features agree with the NumPy definitions in analysis.signals."""

import numpy as np
import pytest

import bearing_gym
from bearing_gym.analysis import quasi_periodicity_index
from bearing_gym.analysis.window import F_MEAN_X, N_FEATURES, window_features
from bearing_gym.physics import Simulator


@pytest.mark.parametrize("preload", [600.0, 800.0])
def test_window_features_match_numpy(preload):
    sim = Simulator(bearing_gym.default_params(axial_preload_n=preload))
    sim.advance(0.05)
    rec = sim.advance(0.02)
    out = np.zeros(N_FEATURES)
    assert window_features(rec.data, len(rec), out)
    xyz = np.column_stack([rec.x, rec.y, rec.z])
    np.testing.assert_allclose(out[:3], np.ptp(xyz, axis=0), rtol=1e-12)
    np.testing.assert_allclose(out[3:6], np.std(xyz, axis=0), rtol=1e-9)
    assert out[6] == pytest.approx(np.mean(rec.cage_speed), rel=1e-12)
    assert out[7] == pytest.approx(np.ptp(rec.cage_speed), rel=1e-12)
    np.testing.assert_allclose(out[F_MEAN_X:F_MEAN_X + 3], np.mean(xyz, axis=0), rtol=1e-12, atol=1e-18)
    # at constant speed the shaft-angle section is the stroboscopic section of signals.py
    ref = quasi_periodicity_index(rec.t, xyz, 20000 * np.pi / 30)
    assert out[8] == pytest.approx(ref, rel=1e-6, abs=1e-9)


def test_short_window_reports_false():
    sim = Simulator(bearing_gym.default_params())
    rec = sim.advance(0.004)
    out = np.ones(N_FEATURES)
    assert not window_features(rec.data, len(rec), out)
    assert out[8] == 0.0
