"""Spectra and Poincare sections on signals with known answers."""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from bearing_gym.analysis.poincare import angle_section, cage_section, section_spread, shaft_section
from bearing_gym.analysis.spectra import (ball_pass_frequency, ball_pass_frequency_inner,
                                          power_spectrum, principal_frequency, spectral_peaks)
from bearing_gym.units import rpm_to_rad_s


@pytest.mark.parametrize("method", ["welch", "periodogram"])
def test_pure_sinusoid_peaks_at_its_frequency(method):
    fs, f0 = 10000.0, 123.4
    t = np.arange(0, 1.0, 1 / fs)
    s = 3.0 * np.sin(2 * math.pi * f0 * t + 0.3) + 7.0
    f, p = power_spectrum(t, s, method=method)
    df = f[1] - f[0]
    # the bin of the maximum is the one nearest f0; the refined peak is within a tenth of a bin
    assert abs(f[np.argmax(p)] - f0) <= df / 2 + 1e-9
    assert principal_frequency(t, s, method=method) == pytest.approx(f0, abs=0.1 * df)
    # Parseval: the PSD integrates to the variance A^2 / 2 (Hann window, within 2 %)
    assert np.sum(p) * df == pytest.approx(4.5, rel=0.02)


def test_two_tones_are_ranked_by_power():
    t = np.arange(0, 2.0, 1e-4)
    s = np.cos(2 * math.pi * 50 * t) + 0.3 * np.cos(2 * math.pi * 333.3 * t)
    peaks = spectral_peaks(t, s, 2)
    assert [round(f) for f, _ in peaks] == [50, 333]
    # power ratio 0.3^2 = 0.09, up to the Hann scalloping loss (1.42 dB in amplitude, a power
    # factor 0.72) of the off-bin 333.3 Hz tone
    assert 0.09 * 0.72 <= peaks[1][1] / peaks[0][1] <= 0.09 / 0.72
    assert principal_frequency(t, s, fmin_hz=100) == pytest.approx(333.3, abs=0.2)


def test_ball_pass_frequencies():
    # 18 balls, cage at 0.4825 of 20,000 rpm: N w_c / 2 pi and N (w - w_c) / 2 pi
    w = rpm_to_rad_s(20000)
    assert ball_pass_frequency(0.4825 * w, 18) == pytest.approx(18 * 0.4825 * 20000 / 60)
    assert ball_pass_frequency_inner(w, 0.4825 * w, 18) == pytest.approx(18 * 0.5175 * 20000 / 60)


def test_non_uniform_time_is_rejected():
    t = np.cumsum(np.random.default_rng(0).uniform(0.5, 1.5, 100))
    with pytest.raises(ValueError, match="uniformly sampled"):
        power_spectrum(t, np.sin(t))


def _record(t, w, signals, cage_ratio=0.45):
    x, y, z = signals
    return SimpleNamespace(t=t, shaft_angle=w * t, cage_angle=cage_ratio * w * t, x=x, y=y, z=z)


def test_period_one_motion_gives_one_stroboscopic_point_and_quasi_periodic_a_closed_curve():
    w = 2 * math.pi * 100.0
    t = np.arange(0, 0.5, 1e-5)
    per = _record(t, w, (np.cos(w * t), np.sin(w * t), 0.1 * np.cos(2 * w * t)))
    pts = shaft_section(per)
    assert pts.shape == (50, 3)                   # 50 revolutions in 0.5 s at 100 Hz
    assert section_spread(pts) < 1e-6
    w2 = w * (math.sqrt(5) - 1) / 2
    qp = _record(t, w, (np.cos(w * t) + 0.5 * np.cos(w2 * t), np.sin(w * t) + 0.5 * np.sin(w2 * t),
                        np.zeros_like(t)))
    pts = shaft_section(qp)
    # points on a circle of radius 0.5 about (1, 0): spread = 0.5 (x and y variances 1/8 each)
    assert section_spread(pts) == pytest.approx(0.5, rel=0.05)
    np.testing.assert_allclose(np.hypot(pts[:, 0] - 1, pts[:, 1]), 0.5, atol=2e-3)


def test_cage_section_samples_at_ball_passage():
    w = 2 * math.pi * 100.0
    t = np.arange(0, 0.2, 1e-5)
    ratio = 0.45
    wc = ratio * w
    rec = _record(t, w, (np.cos(18 * wc * t), np.zeros_like(t), np.zeros_like(t)), ratio)
    pts = cage_section(rec, names=("x",), divisions=18)
    assert pts.shape[0] == int(np.floor(wc * t[-1] / (2 * math.pi / 18) + 1e-9)) + 1
    # every ball passage sees the same phase of the ball-pass signal; linear interpolation at a
    # peak of a tone with 40 samples per period errs by at most (2 pi / 40)^2 / 8 = 3.1e-3
    np.testing.assert_allclose(pts[:, 0], 1.0, atol=3.1e-3)
    with pytest.raises(ValueError, match="non-decreasing"):
        angle_section(-t, t)
