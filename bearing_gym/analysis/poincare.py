"""Poincare sections of a simulated response (paper section 3.2, Fig. 12).

Two sections, both defined by an angle that increases monotonically along the record:

* **stroboscopic (shaft) section** -- the points where the shaft angle θ_s (``record.shaft_angle``)
  passes θ_s(t0) + 2π m. The unbalance forcing of eq 35 (m e ω² at the shaft angle) has exactly
  this period, so a period-1 response gives a single point and a quasi-periodic one (a second,
  incommensurate frequency) a closed curve. At constant speed this is the sampling at
  t0 + m 2π/ω of :func:`.signals.stroboscopic_samples`; on the angle it stays right when the
  speed changes.
* **cage section** -- the points where the cage angle ψ_c of eq 8 (``record.cage_angle``) passes
  ψ_c(t0) + 2π m / ``divisions``: ``divisions=1`` once per cage revolution, ``divisions=N`` once
  per ball passage (the period of the ball-passage excitation, N ω_c). The cage angle is the
  phase of the second forcing of the bearing, so this section is the natural one when ball
  passage dominates.

Points are linearly interpolated between the recorded samples at the exact crossing.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["angle_section", "shaft_section", "cage_section", "section_spread"]


def angle_section(angle: np.ndarray, signals: np.ndarray, period_rad: float = 2.0 * math.pi,
                  phase_rad: float | None = None) -> np.ndarray:
    """Values of ``signals`` (n,) or (n, k) where the increasing ``angle`` (n,) crosses
    ``phase_rad + m * period_rad`` (default phase: the first sample's angle).

    Returns an (M, k) array (M crossings inside the record). Raises ValueError if ``angle``
    is not non-decreasing (a section on an angle needs a monotone angle).
    """
    ang = np.asarray(angle, dtype=float)
    sig = np.asarray(signals, dtype=float)
    if sig.ndim == 1:
        sig = sig[:, None]
    if sig.shape[0] != ang.shape[0]:
        raise ValueError(f"signals has {sig.shape[0]} rows, angle has {ang.shape[0]}")
    if not (period_rad > 0 and math.isfinite(period_rad)):
        raise ValueError(f"period_rad must be positive and finite, got {period_rad!r}")
    if ang.size < 2:
        return np.empty((0, sig.shape[1]))
    if np.any(np.diff(ang) < 0):
        raise ValueError("the section angle must be non-decreasing along the record "
                         "(use the unwrapped shaft or cage angle of the record)")
    p0 = ang[0] if phase_rad is None else float(phase_rad)
    m_lo = math.ceil((ang[0] - p0) / period_rad - 1e-9)
    m_hi = math.floor((ang[-1] - p0) / period_rad + 1e-9)
    if m_hi < m_lo:
        return np.empty((0, sig.shape[1]))
    targets = p0 + period_rad * np.arange(m_lo, m_hi + 1)
    # np.interp needs strictly increasing x; a stalled angle has equal samples: keep the first
    keep = np.concatenate([[True], np.diff(ang) > 0])
    return np.column_stack([np.interp(targets, ang[keep], sig[keep, k])
                            for k in range(sig.shape[1])])


def _columns(record: Any, names: tuple[str, ...]) -> np.ndarray:
    try:
        return np.column_stack([getattr(record, n) for n in names])
    except AttributeError as err:
        raise ValueError(f"record has no field {err.name!r}; use a SimulationRecord from "
                         "Simulator.advance or pass arrays to angle_section") from None


def shaft_section(record: Any, names: tuple[str, ...] = ("x", "y", "z")) -> np.ndarray:
    """Stroboscopic Poincare points (once per shaft revolution) of the record fields ``names``
    (any :class:`~bearing_gym.physics.SimulationRecord` attribute, e.g. ``x_dot``)."""
    return angle_section(record.shaft_angle, _columns(record, names), 2.0 * math.pi)


def cage_section(record: Any, names: tuple[str, ...] = ("x", "y", "z"),
                 divisions: int = 1) -> np.ndarray:
    """Poincare points on the cage angle: ``divisions`` points per cage revolution
    (``divisions = n_balls``: one per ball passage)."""
    if isinstance(divisions, bool) or not isinstance(divisions, (int, np.integer)) or divisions < 1:
        raise ValueError(f"divisions must be an integer >= 1, got {divisions!r}")
    return angle_section(record.cage_angle, _columns(record, names), 2.0 * math.pi / divisions)


def section_spread(points: np.ndarray) -> float:
    """sqrt(sum_k var(points[:, k])): the size of the cloud of section points (0 for a fixed
    point). Divide by the RMS of the signals for the index of :mod:`.signals`."""
    pts = np.asarray(points, dtype=float)
    if pts.ndim == 1:
        pts = pts[:, None]
    if pts.shape[0] < 2:
        return 0.0
    return math.sqrt(float(np.sum(np.var(pts, axis=0))))
