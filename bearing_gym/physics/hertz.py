"""Hertz load-deflection constants (paper App. A, eqs A.1-A.7) and their derivatives (C.11-C.18).

The Brewe-Hamrock curve fits (A.2-A.4) replace the elliptic integrals of the exact Hertz
solution; ``tests/physics/test_hertz.py`` checks them against the exact solution. Their powers
and logarithm are the portable ones of :mod:`.portable_math` (the same bits on every CPU).

The ball model needs K at every residual, and there K depends on nothing but cos(alpha) (R_x of
A.6/A.7; R_y and E' are the bearing's constants). So :func:`hertz_polynomial` interpolates
K(cos alpha) of each race once, when the parameters are packed, by a polynomial of degree
``HERTZ_POLY_DEGREE`` on [0, 1] (Chebyshev nodes; the function is analytic there, its nearest
singularity at cos alpha = D_p / D_b, so the interpolation error falls geometrically: ~3e-15
relative at degree 8 for the paper's bearing, measured; degree 12 keeps it below 1e-13 up to
D_b / D_p = 0.45, and :func:`hertz_polynomial` checks it for every packed bearing), and :func:`hertz_constant_poly` evaluates it and its derivative by
Estrin's scheme: a few dozen multiplications and additions instead of a logarithm, an
exponential, a square root and ten divisions per contact.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .portable_math import PI, cbrt, cos, exp, log, pow

#: Degree of the polynomial of K(cos alpha) (module docstring); :func:`hertz_constant_poly`
#: is written out for this degree.
HERTZ_POLY_DEGREE = 12
#: Coefficients per contact: K's (degree + 1), then dK/d(cos alpha)'s (degree).
N_HERTZ_COEF = 2 * HERTZ_POLY_DEGREE + 1
#: The interpolant must match eq A.1 this closely (relative) on [0, 1]; it reaches ~3e-15.
HERTZ_POLY_RTOL = 1e-13
#: and its derivative dK/d(cos alpha) that of eq A.1, relative to its largest value on [0, 1]
#: (it reaches 2-3e-11 for the paper's bearing; it feeds the Jacobian and the first-order last
#: Newton step, not the force)
HERTZ_SLOPE_RTOL = 1e-9


@njit(cache=True, inline="always")
def hertz_constant(r_x: float, r_y: float, e_eff: float):
    """Load-deflection constant K (N/m^1.5) of a point contact, eq A.1, and dK/dR_x.

    ``r_x``, ``r_y``: effective radii in the rolling and transverse directions (A.6, A.7);
    ``e_eff`` = E / (1 - nu^2). Returns ``(K, dK_dRx)``; R_y does not depend on the contact angle,
    so dK/dR_x with dR_x/dalpha gives the paper's C.11-C.18 (with the C.16/C.18 errata fixed).
    """
    ratio = r_y / r_x                                   # R_y / R_x
    log_ratio = log(ratio)
    k_bar = 1.0339 * exp(0.6360 * log_ratio)            # A.2: ratio**0.6360 (portable_math.pow)
    e_bar = 1.0003 + 0.5968 / ratio                     # A.3
    f_bar = 1.5277 + 0.6023 * log_ratio                 # A.4
    r_bar = r_x * r_y / (r_x + r_y)                     # A.5
    k = math.pi * e_eff * k_bar * math.sqrt(r_bar * e_bar / (4.5 * f_bar * f_bar * f_bar))
    # d ln K / d ratio (C.12-C.14) and d ln K / d R_x
    dlnk_dratio = 0.6360 / ratio + 0.5 * (-0.5968 / (ratio * ratio)) / e_bar \
        - 1.5 * (0.6023 / ratio) / f_bar
    dratio_drx = -ratio / r_x
    dlnrbar_drx = r_y / (r_x * (r_x + r_y))
    dk_drx = k * (dlnk_dratio * dratio_drx + 0.5 * dlnrbar_drx)
    return k, dk_drx


@njit(cache=True, inline="always")
def inner_rx(db: float, dp: float, cos_alpha: float, sin_alpha: float):
    """R_x of the ball / inner-race contact (A.6) and dR_x/dalpha."""
    return db * (dp - db * cos_alpha) / (2.0 * dp), db * db * sin_alpha / (2.0 * dp)


@njit(cache=True, inline="always")
def outer_rx(db: float, dp: float, cos_alpha: float, sin_alpha: float):
    """R_x of the ball / outer-race contact (A.7) and dR_x/dalpha."""
    return db * (dp + db * cos_alpha) / (2.0 * dp), -db * db * sin_alpha / (2.0 * dp)


@njit(cache=True, inline="always")
def contact_semi_major_axis(load: float, r_x: float, r_y: float, e_eff: float):
    """Semi-major axis a (m) of the contact ellipse and the fitted elliptic integral E-bar.

    Hamrock-Brewe: a = (6 k^2 E W R / (pi E'))^(1/3), with the fits A.2, A.3, A.5. Used by the
    Jones/Harris race-control criterion (``race_control="auto"``).
    """
    ratio = r_y / r_x
    k_bar = 1.0339 * pow(ratio, 0.6360)
    e_bar = 1.0003 + 0.5968 / ratio
    r_bar = r_x * r_y / (r_x + r_y)
    if load <= 0.0:
        return 0.0, e_bar
    return cbrt(6.0 * k_bar * k_bar * e_bar * load * r_bar / (math.pi * e_eff)), e_bar


def hertz_polynomial(d_b: float, d_p: float, r_y: float, e_eff: float, outer: bool) -> np.ndarray:
    """``N_HERTZ_COEF`` coefficients for :func:`hertz_constant_poly`: c_0..c_n (n =
    ``HERTZ_POLY_DEGREE``) of K(cos alpha) = sum_k c_k x^k, x = 2 cos(alpha) - 1, for the inner
    (A.6) or outer (A.7) contact, then those of dK/d(cos alpha) = sum_k 2 (k + 1) c_(k+1) x^k.
    K is the interpolant at the n + 1 Chebyshev nodes of [0, 1], turned into powers of x. Plain
    IEEE arithmetic in a fixed order and the portable cosine, so the coefficients are the same
    bits on every CPU.

    Raises ``ValueError`` when the interpolant misses eq A.1 by more than ``HERTZ_POLY_RTOL``
    (relative), or its derivative eq A.1's by more than ``HERTZ_SLOPE_RTOL``, at 4 (n + 1) + 1
    points of [0, 1] (a bearing so far from the usual proportions that
    the degree is too low)."""
    n = HERTZ_POLY_DEGREE
    rx = outer_rx if outer else inner_rx

    def k_of(c: float) -> float:
        return hertz_constant(rx(d_b, d_p, c, 0.0)[0], r_y, e_eff)[0]

    theta = [PI * (j + 0.5) / (n + 1) for j in range(n + 1)]
    nodes = [cos(t) for t in theta]                                   # x_j in [-1, 1]
    values = [k_of(0.5 * (x + 1.0)) for x in nodes]
    # Chebyshev coefficients a_k = (2 - [k = 0]) / (n + 1) sum_j f_j T_k(x_j)
    cheb = []
    for k in range(n + 1):
        total = 0.0
        for j in range(n + 1):
            total += values[j] * cos(k * theta[j])
        cheb.append(total * (1.0 if k == 0 else 2.0) / (n + 1))
    # powers of x: T_0 = 1, T_1 = x, T_{k+1} = 2 x T_k - T_{k-1}
    coef = [0.0] * (n + 1)
    t_prev = [1.0] + [0.0] * n
    t_cur = [0.0, 1.0] + [0.0] * (n - 1)
    for i in range(n + 1):
        coef[i] += cheb[0] * t_prev[i] + cheb[1] * t_cur[i]
    for k in range(2, n + 1):
        t_next = [(2.0 * t_cur[i - 1] if i > 0 else 0.0) - t_prev[i] for i in range(n + 1)]
        for i in range(n + 1):
            coef[i] += cheb[k] * t_next[i]
        t_prev, t_cur = t_cur, t_next
    out = np.array(coef + [2.0 * (k + 1) * coef[k + 1] for k in range(n)])
    drx_dc = (1.0 if outer else -1.0) * d_b * d_b / (2.0 * d_p)          # A.6/A.7
    checks = [m / (4.0 * (n + 1)) for m in range(4 * (n + 1) + 1)]
    slopes = [hertz_constant(rx(d_b, d_p, c, 0.0)[0], r_y, e_eff)[1] * drx_dc for c in checks]
    slope_scale = max(abs(v) for v in slopes)
    for c, slope in zip(checks, slopes):
        exact = k_of(c)
        approx, approx_slope = hertz_constant_poly(out, 0, c)
        if not (abs(approx - exact) <= HERTZ_POLY_RTOL * exact
                and abs(approx_slope - slope) <= HERTZ_SLOPE_RTOL * slope_scale):
            raise ValueError(f"ball_diameter_m / pitch_diameter_m = {d_b / d_p:.3g} is beyond what "
                             f"the kernel's Hertz constant follows: its degree-{n} polynomial "
                             f"misses eq A.1 (or its slope) by {abs(approx / exact - 1):.1e} (relative) at "
                             f"cos(alpha) = {c:.3f} (ratios up to about 0.45 are followed to "
                             f"{HERTZ_POLY_RTOL:g}; raise HERTZ_POLY_DEGREE for larger balls)")
    return out


@njit(cache=True, inline="always")
def hertz_constant_poly(coef, start, cos_alpha):
    """K (N/m^1.5) and dK/d(cos alpha) from ``coef[start:start + N_HERTZ_COEF]`` of
    :func:`hertz_polynomial`, in x = 2 cos(alpha) - 1 by Estrin's scheme (the powers x^2, x^4,
    x^8 and pairs of terms: four dependent multiply-adds deep instead of Horner's twelve)."""
    x = 2.0 * cos_alpha - 1.0
    x2 = x * x
    x4 = x2 * x2
    x8 = x4 * x4
    c = start
    k = ((coef[c] + coef[c + 1] * x + (coef[c + 2] + coef[c + 3] * x) * x2)
         + (coef[c + 4] + coef[c + 5] * x + (coef[c + 6] + coef[c + 7] * x) * x2) * x4
         + ((coef[c + 8] + coef[c + 9] * x + (coef[c + 10] + coef[c + 11] * x) * x2)
            + coef[c + 12] * x4) * x8)
    d = start + HERTZ_POLY_DEGREE + 1
    dk = ((coef[d] + coef[d + 1] * x + (coef[d + 2] + coef[d + 3] * x) * x2)
          + (coef[d + 4] + coef[d + 5] * x + (coef[d + 6] + coef[d + 7] * x) * x2) * x4
          + (coef[d + 8] + coef[d + 9] * x + (coef[d + 10] + coef[d + 11] * x) * x2) * x8)
    return k, dk
