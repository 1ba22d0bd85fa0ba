"""Numba features of one recorded window of the response (used by the environment's step kernel).

``window_features`` computes, from the rows ``rec[:rows]`` written by
:func:`bearing_gym.physics.rotor.integrate`, the peak-to-peak and RMS of x, y, z, the mean and
peak-to-peak of the cage speed, the quasi-periodicity index of :mod:`.signals` and the mean
x, y, z (the static offset a displacement probe reads: it carries the radial load and, through
the axial play, the clearance). The index is
taken on the shaft angle rather than on time (Poincare points where the shaft angle has advanced
by whole turns), which is the same section at constant speed and stays right while the speed
ramps; ``tests/analysis/test_window.py`` checks it against :func:`.signals.quasi_periodicity_index`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

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
N_FEATURES = 12


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
    # quasi-periodicity index: Poincare points at shaft angle theta_0 + 2 pi m
    theta0 = rec[0, R_SHAFT]
    turns = int(math.floor((rec[rows - 1, R_SHAFT] - theta0) / (2.0 * math.pi) + 1e-9)) + 1
    if turns < 3 or rec[rows - 1, R_SHAFT] <= theta0:
        return False
    size = math.sqrt(var_total)
    if size <= 1e-12:
        return True
    pts = np.zeros((turns, 3))
    r = 0
    for m in range(turns):
        target = theta0 + 2.0 * math.pi * m
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
