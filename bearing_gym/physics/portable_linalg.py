"""Small dense linear algebra in a fixed order of IEEE basic operations: the same bits on every CPU.

LAPACK and BLAS (NumPy's and SciPy's OpenBLAS) choose their kernels by CPU core type, with FMA and
blocking that change the last bits. The two small systems that feed the simulator's state and
the observation are solved here instead (numba ``njit``, no ``fastmath``):

* :func:`solve`: Gaussian elimination with partial pivoting, for the 7 x 7 normal equations of
  the synchronous fit of the observation's non-synchronous RMS (``envs/features.py``);
* :func:`lstsq`: least squares by the one-sided Jacobi SVD (Hestenes 1958; Demmel and Veselic
  1992), with singular values below ``rcond`` times the largest treated as zero, as
  ``numpy.linalg.lstsq`` does: the Newton step of the static equilibrium (5 x 5 stiffness,
  ``physics/equilibrium.py``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["solve", "lstsq"]

_JACOBI_SWEEPS = 60
_EPS = 2.220446049250313e-16


@njit(cache=True)
def solve(a, b):
    """x with a x = b for a square ``a`` (n, n) and ``b`` (n, k), by Gaussian elimination with
    partial pivoting (rows swapped in a fixed order; the first largest pivot wins). A zero pivot
    (a singular system) gives 0 for that unknown instead of an exception. ``a`` and ``b`` are
    not modified."""
    n = a.shape[0]
    m = a.copy()
    x = b.copy()
    k_rhs = x.shape[1]
    for col in range(n):
        piv = col
        big = abs(m[col, col])
        for r in range(col + 1, n):
            v = abs(m[r, col])
            if v > big:
                big = v
                piv = r
        if piv != col:
            for c in range(n):
                t = m[col, c]
                m[col, c] = m[piv, c]
                m[piv, c] = t
            for c in range(k_rhs):
                t = x[col, c]
                x[col, c] = x[piv, c]
                x[piv, c] = t
        p = m[col, col]
        if p == 0.0:
            continue
        for r in range(col + 1, n):
            f = m[r, col] / p
            if f == 0.0:
                continue
            for c in range(col, n):
                m[r, c] = m[r, c] - f * m[col, c]
            for c in range(k_rhs):
                x[r, c] = x[r, c] - f * x[col, c]
    for col in range(n - 1, -1, -1):
        p = m[col, col]
        for c in range(k_rhs):
            if p == 0.0:
                x[col, c] = 0.0
                continue
            acc = x[col, c]
            for j in range(col + 1, n):
                acc = acc - m[col, j] * x[j, c]
            x[col, c] = acc / p
    return x


@njit(cache=True)
def lstsq(a, b, rcond):
    """Minimum-norm least-squares solution x of a x ~ b for ``a`` (m, n) with m >= n and ``b``
    (m,), through the one-sided Jacobi SVD a = U S V^T: x = V S^+ U^T b, singular values at or
    below ``rcond`` times the largest dropped (``numpy.linalg.lstsq``'s convention)."""
    m, n = a.shape
    w = a.copy()                       # columns orthogonalised in place: w = U S
    v = np.eye(n)
    for _ in range(_JACOBI_SWEEPS):
        rotated = False
        for p in range(n - 1):
            for q in range(p + 1, n):
                alpha = 0.0
                beta = 0.0
                gamma = 0.0
                for i in range(m):
                    alpha += w[i, p] * w[i, p]
                    beta += w[i, q] * w[i, q]
                    gamma += w[i, p] * w[i, q]
                if gamma == 0.0 or abs(gamma) <= _EPS * math.sqrt(alpha * beta):
                    continue
                rotated = True
                zeta = (beta - alpha) / (2.0 * gamma)
                t = 1.0 / (abs(zeta) + math.sqrt(1.0 + zeta * zeta))
                if zeta < 0.0:
                    t = -t
                c = 1.0 / math.sqrt(1.0 + t * t)
                s = c * t
                for i in range(m):
                    wp = w[i, p]
                    wq = w[i, q]
                    w[i, p] = c * wp - s * wq
                    w[i, q] = s * wp + c * wq
                for i in range(n):
                    vp = v[i, p]
                    vq = v[i, q]
                    v[i, p] = c * vp - s * vq
                    v[i, q] = s * vp + c * vq
        if not rotated:
            break
    sigma = np.zeros(n)
    for j in range(n):
        ss = 0.0
        for i in range(m):
            ss += w[i, j] * w[i, j]
        sigma[j] = math.sqrt(ss)
    smax = 0.0
    for j in range(n):
        if sigma[j] > smax:
            smax = sigma[j]
    x = np.zeros(n)
    for j in range(n):
        if sigma[j] <= rcond * smax or sigma[j] == 0.0:
            continue
        # (U^T b)_j / sigma_j with U_j = w_j / sigma_j
        ub = 0.0
        for i in range(m):
            ub += w[i, j] * b[i]
        coef = ub / (sigma[j] * sigma[j])
        for i in range(n):
            x[i] += v[i, j] * coef
    return x
