"""Hertz load-deflection constants (App. A) against the exact Hertz solution.

Exact solution (Johnson, Contact Mechanics, sec. 4.2): for relative curvatures A = 1/(2 R_x) >
B = 1/(2 R_y) the contact ellipse has semi-axes b (along x) < a (along y), eccentricity
e^2 = 1 - b^2/a^2, and with the complete elliptic integrals K(e), E(e)

    A / B = [(a/b)^2 E - K] / [K - E],
    a^3   = 3 P (K - E) / (2 pi E* B e^2),      delta = 3 P K / (2 pi a E*),

E* = E / (2 (1 - nu^2)). The load-deflection constant is P / delta^1.5 (independent of P).
"""

import math

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import ellipe, ellipk

from bearing_gym.physics.hertz import (HERTZ_POLY_RTOL, hertz_constant, hertz_constant_poly,
                                       hertz_polynomial, inner_rx, outer_rx)

DB, DP, RI, RO = 19.05e-3, 140e-3, 10.287e-3, 9.906e-3
E_EFF = 208e9 / (1 - 0.3 ** 2)


def exact_hertz_constant(r_x: float, r_y: float, e_eff: float) -> float:
    a_curv, b_curv = 1 / (2 * r_x), 1 / (2 * r_y)
    ratio = a_curv / b_curv

    def f(m):  # m = e^2
        k, e = ellipk(m), ellipe(m)
        return (e / (1 - m) - k) / (k - e) - ratio

    m = brentq(f, 1e-12, 1 - 1e-14, xtol=1e-15)
    k, e = ellipk(m), ellipe(m)
    e_star = e_eff / 2
    load = 1000.0
    a3 = 3 * load * (k - e) / (2 * math.pi * e_star * b_curv * m)
    a = a3 ** (1 / 3)
    delta = 3 * load * k / (2 * math.pi * a * e_star)
    return load / delta ** 1.5


@pytest.mark.parametrize("alpha_deg", [0.0, 10.0, 25.0, 40.0, 60.0])
@pytest.mark.parametrize("race", ["inner", "outer"])
def test_fit_matches_exact_hertz_within_2_percent(alpha_deg, race):
    a = math.radians(alpha_deg)
    if race == "inner":
        r_x, _ = inner_rx(DB, DP, math.cos(a), math.sin(a))
        r_y = RI / (2 * RI / DB - 1)
    else:
        r_x, _ = outer_rx(DB, DP, math.cos(a), math.sin(a))
        r_y = RO / (2 * RO / DB - 1)
    k_fit, _ = hertz_constant(r_x, r_y, E_EFF)
    k_exact = exact_hertz_constant(r_x, r_y, E_EFF)
    assert k_fit == pytest.approx(k_exact, rel=0.02)


def test_exact_solution_reduces_to_sphere_on_sphere():
    # equal relative radii R_x = R_y = R: delta = (9 P^2 / (16 E*^2 R))^(1/3)
    r = 5e-3
    r_eff = r          # R_x = R_y = r is already the relative radius (sphere on a flat)
    e_star = E_EFF / 2
    expected = 1.0 / (9 / (16 * e_star ** 2 * r_eff)) ** 0.5
    assert exact_hertz_constant(r, r * (1 + 1e-9), E_EFF) == pytest.approx(expected, rel=1e-6)


def test_reference_constants_at_25_degrees():
    """docs/model.md: Brewe-Hamrock constants at 25 deg, inner ~3.18e10, outer ~4.19e10 N/m^1.5."""
    a = math.radians(25)
    k_i, _ = hertz_constant(inner_rx(DB, DP, math.cos(a), math.sin(a))[0], RI / (2 * RI / DB - 1), E_EFF)
    k_o, _ = hertz_constant(outer_rx(DB, DP, math.cos(a), math.sin(a))[0], RO / (2 * RO / DB - 1), E_EFF)
    assert k_i == pytest.approx(3.18e10, rel=0.005)
    assert k_o == pytest.approx(4.19e10, rel=0.005)


@pytest.mark.parametrize("r_x", [6e-3, 8e-3, 9e-3])
def test_derivative_matches_central_difference(r_x):
    r_y = 0.12
    h = r_x * 1e-6
    k_p, _ = hertz_constant(r_x + h, r_y, E_EFF)
    k_m, _ = hertz_constant(r_x - h, r_y, E_EFF)
    _, dk = hertz_constant(r_x, r_y, E_EFF)
    assert dk == pytest.approx((k_p - k_m) / (2 * h), rel=1e-6)


@pytest.mark.parametrize("alpha", np.linspace(0.05, 1.2, 5))
def test_rx_derivatives(alpha):
    h = 1e-7
    for fn in (inner_rx, outer_rx):
        rp, _ = fn(DB, DP, math.cos(alpha + h), math.sin(alpha + h))
        rm, _ = fn(DB, DP, math.cos(alpha - h), math.sin(alpha - h))
        _, d = fn(DB, DP, math.cos(alpha), math.sin(alpha))
        assert d == pytest.approx((rp - rm) / (2 * h), rel=1e-6)


@pytest.mark.parametrize("d_b", [DB, 2 * DB])        # the paper's bearing; one with balls twice as large
@pytest.mark.parametrize("outer", [False, True])
def test_the_packed_polynomial_is_the_brewe_hamrock_constant(d_b, outer):
    """The kernel evaluates K(cos alpha) from a degree-12 interpolant (hertz.hertz_polynomial):
    it must equal eq A.1 (the fit above) to HERTZ_POLY_RTOL relative over the whole range
    cos(alpha) in [0, 1], between the nodes too, and its derivative must be that of eq A.1,
    dK/dR_x dR_x/d(cos alpha) (A.6/A.7: dR_x/dc = -/+ D_b^2 / (2 D_p)), to 1e-9."""
    r = (RO / DB if outer else RI / DB) * d_b         # the same groove conformity
    r_y = r / (2 * r / d_b - 1)
    coef = hertz_polynomial(d_b, DP, r_y, E_EFF, outer=outer)
    rx = outer_rx if outer else inner_rx
    drx_dc = (1.0 if outer else -1.0) * d_b * d_b / (2 * DP)
    for c in np.linspace(0.0, 1.0, 997):
        k_poly, dk_dc = hertz_constant_poly(coef, 0, c)
        k, dk_drx = hertz_constant(rx(d_b, DP, c, 0.0)[0], r_y, E_EFF)
        assert abs(k_poly / k - 1.0) <= HERTZ_POLY_RTOL
        assert dk_dc == pytest.approx(dk_drx * drx_dc, rel=1e-9, abs=1e-9 * k)


def test_a_bearing_the_polynomial_cannot_follow_is_refused_by_name():
    """Balls almost as large as the pitch diameter bring the interpolant's singularity
    (cos alpha = D_p / D_b) next to [0, 1]: the packing refuses instead of running a wrong K."""
    d_b = 0.9 * DP
    with pytest.raises(ValueError, match="ball_diameter_m / pitch_diameter_m = 0.9 "):
        hertz_polynomial(d_b, DP, 1.1 * d_b / 2 / (1.1 - 1), E_EFF, outer=False)
