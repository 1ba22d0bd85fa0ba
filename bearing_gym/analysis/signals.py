"""Signal measures of a simulated response: peak-to-peak, RMS, and the quasi-periodicity index.

The quasi-periodicity index is the normalised spread of the stroboscopic Poincare points
(sampled once per shaft revolution). For a period-1 response every revolution returns to the
same point, so the spread is ~0; for quasi-periodic or chaotic motion the points scatter over a
closed curve or a cloud, and the spread is of the order of the vibration amplitude itself.

Definition, for signals s_k(t) (k = x, y, z, ...) over a window:

    P_k[m]  = s_k(t0 + m T),  T = 2 pi / omega (linear interpolation), m = 0 .. M-1
    spread  = sqrt( sum_k var_m(P_k) )
    size    = sqrt( sum_k var_t(s_k) )            (RMS vibration about the mean)
    index   = spread / size        in [0, ~1.4]; 0 = period-1 (or static), ~1 = no phase locking

A signal with ``size`` below ``floor`` (a static rotor) gets index 0. The index is dimensionless
and the same for any scaling of the signals.

``QPI_THRESHOLD`` (0.1) is the one classification threshold of the package: a window with an
index above it is quasi-periodic (or chaotic), otherwise period-1. Settled period-1 motion reads
0.000-0.03 (the residue of transients and of ball-pass vibration); quasi-periodic motion 0.2-1.4
(weakly quasi-periodic motion just past a Neimark-Sacker bifurcation, 0.15-0.4). The stability
boundaries of the reproduction, the sweeps, the environment's reward and its ``quasi_periodic``
flag and the evaluation all use it.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["peak_to_peak", "rms", "stroboscopic_samples", "quasi_periodicity_index", "QPI_THRESHOLD"]

QPI_THRESHOLD = 0.1


def peak_to_peak(signal: np.ndarray, t: np.ndarray | None = None, after_s: float = 0.0) -> float:
    """max - min of ``signal`` (optionally only where ``t >= after_s``)."""
    s = np.asarray(signal)
    if t is not None:
        s = s[np.asarray(t) >= after_s]
    if s.size == 0:
        raise ValueError("peak_to_peak: no samples after the transient (after_s too large)")
    return float(np.ptp(s))


def rms(signal: np.ndarray, t: np.ndarray | None = None, after_s: float = 0.0) -> float:
    """Root-mean-square about the mean (optionally only where ``t >= after_s``)."""
    s = np.asarray(signal, dtype=float)
    if t is not None:
        s = s[np.asarray(t) >= after_s]
    if s.size == 0:
        raise ValueError("rms: no samples after the transient (after_s too large)")
    return float(np.sqrt(np.mean((s - s.mean()) ** 2)))


def stroboscopic_samples(t: np.ndarray, signals: np.ndarray, period_s: float) -> np.ndarray:
    """Values of ``signals`` (n,) or (n, k) at t[0] + m * period_s (linear interpolation)."""
    t = np.asarray(t, dtype=float)
    sig = np.asarray(signals, dtype=float)
    if sig.ndim == 1:
        sig = sig[:, None]
    if not (period_s > 0 and math.isfinite(period_s)):
        raise ValueError(f"period_s must be positive and finite, got {period_s!r}")
    n_per = int(math.floor((t[-1] - t[0]) / period_s + 1e-9)) + 1
    ts = t[0] + period_s * np.arange(n_per)
    return np.column_stack([np.interp(ts, t, sig[:, k]) for k in range(sig.shape[1])])


def quasi_periodicity_index(t: np.ndarray, signals: np.ndarray, shaft_speed_rad_s: float,
                            floor: float = 1e-12) -> float:
    """Normalised spread of the once-per-revolution Poincare points (see module docstring).

    ``signals``: (n,) or (n, k) samples at times ``t`` (at least 3 shaft periods long).
    """
    sig = np.asarray(signals, dtype=float)
    if sig.ndim == 1:
        sig = sig[:, None]
    if shaft_speed_rad_s <= 0:
        return 0.0
    period = 2.0 * math.pi / shaft_speed_rad_s
    t = np.asarray(t, dtype=float)
    if t[-1] - t[0] < 2.0 * period:
        raise ValueError("quasi_periodicity_index needs a window of at least 3 shaft periods "
                         f"({3 * period:.3g} s), got {t[-1] - t[0]:.3g} s")
    size = math.sqrt(float(np.sum(np.var(sig, axis=0))))
    if size <= floor:
        return 0.0
    pts = stroboscopic_samples(t, sig, period)
    spread = math.sqrt(float(np.sum(np.var(pts, axis=0))))
    return spread / size
