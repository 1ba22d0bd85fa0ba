"""Power spectra and characteristic frequencies of a simulated response (paper section 3.2,
Figs 10, 14, 18, 19).

* :func:`power_spectrum`: one-sided power spectral density by Welch's method (Hann window, 50 %
  overlap) or a single Hann-windowed periodogram (``scipy.signal``).
* :func:`spectral_peaks` / :func:`principal_frequency`: the strongest local maxima of the
  spectrum. The *principal frequency of the cage speed* ω_cp of the paper (section 3.2) is
  ``principal_frequency(t, cage_speed)``.
* :func:`ball_pass_frequency`: the paper's "ball passage frequency", defined (section 3.2, its
  ref. [7]) as the number of balls times the cage speed, ``N ω_c / 2π`` in Hz. That is the
  frequency at which balls pass a point of the *stationary* outer race (BPFO).
  :func:`ball_pass_frequency_inner` gives ``N (ω − ω_c) / 2π``, the rate at which balls pass a
  point of the *rotating* inner race (BPFI), i.e. a load that turns with the shaft such as the
  unbalance. Both are reported because the cage speed of eq 7 (mean orbital speed of the balls
  touching the inner race) changes whenever a ball enters or leaves the unbalance load zone,
  which happens at BPFI.

All frequencies are in Hz; ``scipy`` is imported lazily so ``import bearing_gym`` stays fast.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["power_spectrum", "spectral_peaks", "principal_frequency", "ball_pass_frequency",
           "ball_pass_frequency_inner", "sample_rate"]


def sample_rate(t: np.ndarray) -> float:
    """Sampling frequency (Hz) of the uniformly sampled time vector ``t``.

    Raises ValueError if ``t`` has fewer than 2 samples or is not uniform to 1e-6 relative.
    """
    t = np.asarray(t, dtype=float)
    if t.ndim != 1 or t.size < 2:
        raise ValueError("t must be a 1-D array of at least 2 sample times")
    dt = np.diff(t)
    mean = float(np.mean(dt))
    if not mean > 0 or float(np.max(np.abs(dt - mean))) > 1e-6 * mean + 1e-15:
        raise ValueError("t must be increasing and uniformly sampled (record with a fixed "
                         "record_every); resample with np.interp first otherwise")
    return 1.0 / mean


def power_spectrum(t: np.ndarray, signal: np.ndarray, *, method: str = "welch",
                   segment_s: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """One-sided PSD of ``signal`` (mean removed) sampled at times ``t``.

    ``method="welch"``: Hann segments of ``segment_s`` seconds (default: the whole record if it
    is shorter than 0.2 s, else a quarter of it, so the resolution is ``1/segment_s`` Hz),
    50 % overlap, averaged. ``method="periodogram"``: one Hann-windowed periodogram of the
    whole record (finest resolution, no averaging).

    Returns ``(f_hz, psd)`` with ``psd`` in signal units squared per Hz.
    """
    from scipy import signal as sps

    fs = sample_rate(t)
    s = np.asarray(signal, dtype=float)
    if s.shape != np.shape(t):
        raise ValueError(f"signal shape {s.shape} must match t shape {np.shape(t)}")
    s = s - s.mean()
    if method == "periodogram":
        return sps.periodogram(s, fs=fs, window="hann", detrend=False)
    if method != "welch":
        raise ValueError(f"method must be 'welch' or 'periodogram', got {method!r}")
    duration = s.size / fs
    if segment_s is None:
        segment_s = duration if duration < 0.2 else duration / 4.0
    nperseg = int(min(s.size, max(16, round(segment_s * fs))))
    return sps.welch(s, fs=fs, window="hann", nperseg=nperseg, noverlap=nperseg // 2,
                     detrend=False)


def spectral_peaks(t: np.ndarray, signal: np.ndarray, n: int = 5, *, fmin_hz: float = 0.0,
                   fmax_hz: float | None = None, method: str = "welch",
                   segment_s: float | None = None) -> list[tuple[float, float]]:
    """The ``n`` strongest local maxima of the PSD in [fmin_hz, fmax_hz] as (f_hz, psd),
    strongest first. The peak frequency is refined by a parabola through the log-PSD of the
    three bins around the maximum (accuracy a small fraction of a bin for a Hann window)."""
    from scipy import signal as sps

    f, p = power_spectrum(t, signal, method=method, segment_s=segment_s)
    hi = f[-1] if fmax_hz is None else fmax_hz
    idx = sps.find_peaks(p)[0]
    idx = idx[(f[idx] >= fmin_hz) & (f[idx] <= hi)]
    if idx.size == 0:
        return []
    idx = idx[np.argsort(-p[idx])][:n]
    df = f[1] - f[0]
    out = []
    for i in idx:
        a, b, c = (math.log(max(v, 1e-300)) for v in p[i - 1:i + 2])
        den = a - 2 * b + c
        shift = 0.5 * (a - c) / den if den < 0 else 0.0
        out.append((float(f[i] + shift * df), float(p[i])))
    return out


def principal_frequency(t: np.ndarray, signal: np.ndarray, *, fmin_hz: float = 1.0,
                        fmax_hz: float | None = None, method: str = "welch",
                        segment_s: float | None = None) -> float:
    """Frequency (Hz) of the strongest spectral peak above ``fmin_hz`` (the DC part and, by
    default, drifts slower than 1 Hz are excluded). For the cage speed this is the paper's
    ω_cp (section 3.2). Returns NaN for a constant signal."""
    peaks = spectral_peaks(t, signal, 1, fmin_hz=fmin_hz, fmax_hz=fmax_hz, method=method,
                           segment_s=segment_s)
    return peaks[0][0] if peaks else math.nan


def ball_pass_frequency(cage_speed_rad_s: float, n_balls: int) -> float:
    """Paper's ball passage frequency N ω_c / 2π (Hz): balls passing a point of the
    stationary outer race (BPFO)."""
    return n_balls * float(cage_speed_rad_s) / (2.0 * math.pi)


def ball_pass_frequency_inner(shaft_speed_rad_s: float, cage_speed_rad_s: float,
                              n_balls: int) -> float:
    """N (ω − ω_c) / 2π (Hz): balls passing a point of the rotating inner race (BPFI), the
    rate at which balls cross a load zone that turns with the shaft (unbalance)."""
    return n_balls * (float(shaft_speed_rad_s) - float(cage_speed_rad_s)) / (2.0 * math.pi)
