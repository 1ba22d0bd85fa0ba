"""Numba features of one control interval's recorded response (used by the env's step kernel).

``window_features`` computes, from the rows ``rec[:rows]`` written by
:func:`bearing_gym.physics.rotor.integrate`, the peak-to-peak and RMS of x, y, z, the mean and
peak-to-peak of the cage speed, the quasi-periodicity index of
:mod:`bearing_gym.analysis.signals`, the mean x, y, z (the static offset a displacement probe
reads: it carries the radial load and, through the axial play, the clearance) and the RMS of
the non-synchronous displacement.

The index is taken on the shaft angle rather than on time (Poincare points where the shaft angle
has advanced by whole turns), which is the same section at constant speed and stays right while
the speed ramps; ``tests/envs/test_features.py`` checks it against
:func:`bearing_gym.analysis.signals.quasi_periodicity_index`.

Non-synchronous RMS (``F_NS_RMS``, metres): x, y and z are each fitted by least squares with
the shaft-synchronous series ``c_0 + sum_{k=1..H} (a_k cos k theta + b_k sin k theta)``
(theta = shaft angle, ``H = SYNC_HARMONICS``): the once-per-revolution response and its
harmonics, which is what unbalance and a period-1 orbit produce. What remains is the motion
that does not repeat every turn (the Neimark-Sacker frequency of a quasi-periodic orbit,
ball-pass vibration, transients); ``F_NS_RMS = sqrt(sum_k mean_t(residual_k^2))``. A window
shorter than two shaft turns cannot separate the series from the rest: then only the mean is
removed (the RMS of the whole motion, an upper bound). The fit's normal equations are solved by
:func:`bearing_gym.physics.portable_linalg.solve` and its cosines come from
:mod:`bearing_gym.physics.portable_math`, so the features are the same bits on every CPU.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from bearing_gym.physics.portable_linalg import solve
from bearing_gym.physics.portable_math import TWO_PI, sincos
from bearing_gym.physics.rotor import R_CAGE_SPEED, R_SHAFT, R_X

F_PTP_X = 0
F_PTP_Y = 1
F_PTP_Z = 2
F_RMS_X = 3
F_RMS_Y = 4
F_RMS_Z = 5
F_CAGE_MEAN = 6
F_CAGE_PTP = 7
F_QPI = 8
F_MEAN_X = 9      # then y, z
F_NS_RMS = 12     # RMS of the non-synchronous displacement (m)
N_FEATURES = 13
SYNC_HARMONICS = 3        # shaft harmonics removed as synchronous (1x, 2x, 3x, and the mean)


@njit(cache=True)
def window_features(rec, rows, out):
    """Fill ``out`` (N_FEATURES,) from ``rec[:rows]``; returns False if the window is too short
    (fewer than 3 shaft turns or 2 rows), in which case the index is set to 0."""
    for k in range(N_FEATURES):
        out[k] = 0.0
    if rows < 2:
        return False
    # means
    mean = np.zeros(3)
    cmean = 0.0
    for r in range(rows):
        for k in range(3):
            mean[k] += rec[r, R_X + k]
        cmean += rec[r, R_CAGE_SPEED]
    for k in range(3):
        mean[k] /= rows
        out[F_MEAN_X + k] = mean[k]
    cmean /= rows
    var_total = 0.0
    for k in range(3):
        lo = rec[0, R_X + k]
        hi = lo
        ss = 0.0
        for r in range(rows):
            v = rec[r, R_X + k]
            if v < lo:
                lo = v
            if v > hi:
                hi = v
            d = v - mean[k]
            ss += d * d
        out[F_PTP_X + k] = hi - lo
        out[F_RMS_X + k] = math.sqrt(ss / rows)
        var_total += ss / rows
    lo = rec[0, R_CAGE_SPEED]
    hi = lo
    for r in range(rows):
        v = rec[r, R_CAGE_SPEED]
        if v < lo:
            lo = v
        if v > hi:
            hi = v
    out[F_CAGE_MEAN] = cmean
    out[F_CAGE_PTP] = hi - lo
    out[F_NS_RMS] = nonsynchronous_rms(rec, rows)
    # quasi-periodicity index: Poincare points at shaft angle theta_0 + 2 pi m
    theta0 = rec[0, R_SHAFT]
    if rec[rows - 1, R_SHAFT] <= theta0:
        return False
    turns = int((rec[rows - 1, R_SHAFT] - theta0) / TWO_PI + 1e-9) + 1   # int() of a positive: floor
    if turns < 3:
        return False
    size = math.sqrt(var_total)
    if size <= 1e-12:
        return True
    pts = np.zeros((turns, 3))
    r = 0
    for m in range(turns):
        target = theta0 + TWO_PI * m
        while r < rows - 2 and rec[r + 1, R_SHAFT] < target:
            r += 1
        a0 = rec[r, R_SHAFT]
        a1 = rec[r + 1, R_SHAFT]
        w = 0.0 if a1 == a0 else (target - a0) / (a1 - a0)
        if w < 0.0:
            w = 0.0
        if w > 1.0:
            w = 1.0
        for k in range(3):
            pts[m, k] = rec[r, R_X + k] + w * (rec[r + 1, R_X + k] - rec[r, R_X + k])
    spread2 = 0.0
    for k in range(3):
        pm = 0.0
        for m in range(turns):
            pm += pts[m, k]
        pm /= turns
        for m in range(turns):
            d = pts[m, k] - pm
            spread2 += d * d / turns
    out[F_QPI] = math.sqrt(spread2) / size
    return True


@njit(cache=True)
def nonsynchronous_rms(rec, rows):
    """RMS (m) of x, y, z about their least-squares shaft-synchronous series (module docstring)."""
    theta0 = rec[0, R_SHAFT]
    span_turns = (rec[rows - 1, R_SHAFT] - theta0) / TWO_PI
    n_h = SYNC_HARMONICS if span_turns >= 2.0 else 0
    nb = 1 + 2 * n_h
    ata = np.zeros((nb, nb))
    aty = np.zeros((nb, 3))
    basis = np.zeros(nb)
    for r in range(rows):
        _sync_basis(rec[r, R_SHAFT] - theta0, n_h, basis)
        for i in range(nb):
            for j in range(nb):
                ata[i, j] += basis[i] * basis[j]
            for k in range(3):
                aty[i, k] += basis[i] * rec[r, R_X + k]
    coef = solve(ata, aty)
    ss = 0.0
    for r in range(rows):
        _sync_basis(rec[r, R_SHAFT] - theta0, n_h, basis)
        for k in range(3):
            fit = 0.0
            for i in range(nb):
                fit += basis[i] * coef[i, k]
            d = rec[r, R_X + k] - fit
            ss += d * d
    return math.sqrt(ss / rows)


@njit(cache=True, inline="always")
def _sync_basis(theta, n_h, out):
    """[1, cos theta, sin theta, ..., cos n_h theta, sin n_h theta] into ``out``."""
    out[0] = 1.0
    s1, c1 = sincos(theta)
    c, s = 1.0, 0.0
    for k in range(n_h):
        c, s = c * c1 - s * s1, s * c1 + c * s1
        out[1 + 2 * k] = c
        out[2 + 2 * k] = s
