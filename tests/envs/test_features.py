"""The numba window features agree with the NumPy definitions in analysis.signals."""

import numpy as np
import pytest

import bearing_gym
from bearing_gym.analysis import quasi_periodicity_index
from bearing_gym.envs.features import F_MEAN_X, F_QPI, N_FEATURES, window_features
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
    assert out[F_QPI] == pytest.approx(ref, rel=1e-6, abs=1e-9)


def test_short_window_reports_false():
    sim = Simulator(bearing_gym.default_params())
    rec = sim.advance(0.004)
    out = np.ones(N_FEATURES)
    assert not window_features(rec.data, len(rec), out)
    assert out[F_QPI] == 0.0


def _synthetic_record(turns, rpm=20000.0, dt=1e-5):
    from bearing_gym.physics.rotor import N_REC, R_SHAFT, R_T
    omega = rpm * np.pi / 30.0
    t = np.arange(int(turns * 2 * np.pi / omega / dt)) * dt
    rec = np.zeros((len(t), N_REC))
    rec[:, R_T] = t
    rec[:, R_SHAFT] = 0.3 + omega * t
    return rec, omega * t, t


def test_nonsync_rms_removes_the_synchronous_series_exactly():
    from bearing_gym.envs.features import nonsynchronous_rms
    from bearing_gym.physics.rotor import R_X
    rec, th, _ = _synthetic_record(6.7)
    rec[:, R_X] = 3e-6 + 40e-6 * np.cos(th + 0.2) + 5e-6 * np.sin(2 * th) + 1e-6 * np.cos(3 * th)
    rec[:, R_X + 2] = -20e-6 + 8e-6 * np.sin(th)
    assert nonsynchronous_rms(rec, len(rec)) < 1e-9 * 40e-6


def test_nonsync_rms_of_a_non_synchronous_tone_is_its_rms():
    # over a long window a tone at 0.44 x shaft speed (a Neimark-Sacker frequency) is orthogonal
    # to the synchronous series: its RMS A / sqrt(2) remains (1 % over 60 turns)
    from bearing_gym.envs.features import nonsynchronous_rms
    from bearing_gym.physics.rotor import R_X
    rec, th, _ = _synthetic_record(60)
    a = 10e-6
    rec[:, R_X] = 50e-6 * np.cos(th) + a * np.cos(0.44 * th + 1.0)
    assert nonsynchronous_rms(rec, len(rec)) == pytest.approx(a / np.sqrt(2), rel=0.01)


def test_nonsync_rms_matches_an_independent_least_squares_fit():
    from bearing_gym.envs.features import SYNC_HARMONICS, nonsynchronous_rms
    from bearing_gym.physics.rotor import R_SHAFT, R_X
    sim = Simulator(bearing_gym.default_params(axial_preload_n=500.0))      # quasi-periodic
    sim.advance(0.1)
    rec = sim.advance(0.02)
    th = rec.data[:, R_SHAFT] - rec.data[0, R_SHAFT]
    basis = np.column_stack([np.ones_like(th)] + [f(k * th) for k in range(1, SYNC_HARMONICS + 1)
                                                   for f in (np.cos, np.sin)])
    xyz = rec.data[:, R_X:R_X + 3]
    resid = xyz - basis @ np.linalg.lstsq(basis, xyz, rcond=None)[0]
    ref = np.sqrt(np.sum(np.mean(resid ** 2, axis=0)))
    assert ref > 1e-6                                          # a real non-synchronous motion
    assert nonsynchronous_rms(rec.data, len(rec)) == pytest.approx(ref, rel=1e-8)
