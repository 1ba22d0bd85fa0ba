"""Hertz load-deflection constants (paper App. A, eqs A.1-A.7) and their derivatives (C.11-C.18).

The Brewe-Hamrock curve fits (A.2-A.4) replace the elliptic integrals of the exact Hertz
solution; ``tests/physics/test_hertz.py`` checks them against the exact solution. Their powers
and logarithm are the portable ones of :mod:`.portable_math` (the same bits on every CPU).
"""

from __future__ import annotations

import math

from numba import njit

from .portable_math import cbrt, exp, log, pow


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
