import math

import numpy as np
import pytest

from bearing_gym.analysis import peak_to_peak, quasi_periodicity_index, rms

W = 2 * math.pi * 333.3


def test_period_one_signal_has_zero_index():
    t = np.arange(0, 0.05, 1e-5)
    sig = np.column_stack([np.cos(W * t) + 0.3 * np.cos(3 * W * t + 1), 0.5 * np.sin(2 * W * t)])
    assert quasi_periodicity_index(t, sig, W) < 1e-3


def test_two_frequency_quasi_periodic_signal_has_large_index():
    t = np.arange(0, 0.05, 1e-5)
    w2 = W * (math.sqrt(5) - 1) / 2 * 0.9          # incommensurate with W
    sig = np.cos(W * t) + np.cos(w2 * t)
    assert quasi_periodicity_index(t, sig, W) > 0.5


def test_index_grows_with_the_incommensurate_part():
    t = np.arange(0, 0.1, 1e-5)
    w2 = W * 0.4142
    vals = [quasi_periodicity_index(t, np.cos(W * t) + a * np.cos(w2 * t), W) for a in (0.0, 0.1, 0.3, 1.0)]
    assert vals[0] < 1e-3 and vals[0] < vals[1] < vals[2] < vals[3]
    # small incommensurate part a: index ~ a / sqrt(1 + a^2) (spread a/sqrt2 over size sqrt((1+a^2)/2))
    assert vals[1] == pytest.approx(0.1 / math.sqrt(1.01), rel=0.15)


def test_scale_invariant_and_static_is_zero():
    t = np.arange(0, 0.05, 1e-5)
    sig = np.cos(W * t) + 0.5 * np.cos(0.37 * W * t)
    assert quasi_periodicity_index(t, 1e-6 * sig, W) == pytest.approx(quasi_periodicity_index(t, sig, W), rel=1e-9)
    assert quasi_periodicity_index(t, np.full_like(t, 3e-5), W) == 0.0


def test_window_too_short_is_an_error():
    t = np.arange(0, 0.004, 1e-5)
    with pytest.raises(ValueError, match="3 shaft periods"):
        quasi_periodicity_index(t, np.cos(W * t), W)


def test_peak_to_peak_and_rms():
    t = np.arange(0, 1, 1e-4)
    s = 2.0 * np.sin(2 * math.pi * 10 * t) + 5.0
    assert peak_to_peak(s, t, after_s=0.5) == pytest.approx(4.0, rel=1e-3)
    assert rms(s) == pytest.approx(2 / math.sqrt(2), rel=1e-3)
    with pytest.raises(ValueError):
        peak_to_peak(s, t, after_s=2.0)
