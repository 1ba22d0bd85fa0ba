"""The portable elementary functions and linear solvers against libm, NumPy/LAPACK and exact
arithmetic (their bit-identity across CPUs is tests/portability's business)."""

import math
from decimal import Decimal, getcontext
from fractions import Fraction

import numpy as np
import pytest

from bearing_gym.physics import portable_linalg as pl
from bearing_gym.physics import portable_math as pm

RNG = np.random.default_rng(20261203)


def ulps(got: float, want: float) -> float:
    return abs(got - want) / math.ulp(want) if want != 0.0 else abs(got) / math.ulp(0.0)


def worst(fn, ref, xs) -> float:
    return max(ulps(fn(float(x)), ref(float(x))) for x in xs)


def test_exp_within_one_ulp_of_libm():
    xs = np.concatenate([RNG.uniform(-700, 700, 4000), RNG.uniform(-1, 1, 4000), RNG.uniform(-1e-9, 1e-9, 200)])
    assert worst(pm.exp, math.exp, xs) <= 1.0


def test_log_within_one_ulp_of_libm_over_the_whole_range():
    xs = np.concatenate([np.exp(RNG.uniform(-700, 700, 4000)), RNG.uniform(0.5, 2.0, 4000),
                         1.0 + RNG.uniform(-1e-7, 1e-7, 200), [5e-324, 1e-310, 2.2e-308, 1.7e308]])
    assert worst(pm.log, math.log, xs) <= 1.0


def test_sin_cos_within_two_ulp_and_1e16_absolute():
    xs = np.concatenate([RNG.uniform(-1, 1, 3000), RNG.uniform(-50, 50, 3000), RNG.uniform(-1e5, 1e5, 3000),
                         RNG.uniform(-8e8, 8e8, 1000)])
    for x in xs:
        s, c = pm.sincos(float(x))
        assert abs(s - math.sin(x)) <= 2.3e-16 and abs(c - math.cos(x)) <= 2.3e-16, x
    small = RNG.uniform(-10, 10, 3000)
    assert worst(pm.sin, math.sin, small) <= 2.0 and worst(pm.cos, math.cos, small) <= 2.0


def test_pow_and_cbrt_on_the_physics_ranges():
    ratios = RNG.uniform(1.0, 100.0, 3000)            # R_y / R_x of the Hertz fits (A.2)
    assert worst(lambda x: pm.pow(x, 0.6360), lambda x: x ** 0.6360, ratios) <= 4.0
    fractions_ = np.exp(RNG.uniform(-30, 0, 3000))     # (Q / K) ** (2/3), (P / P_max) ** 1.33
    assert worst(lambda x: pm.pow(x, 2.0 / 3.0), lambda x: x ** (2.0 / 3.0), fractions_) <= 16.0
    assert worst(lambda x: pm.pow(x, 1.33), lambda x: x ** 1.33, fractions_) <= 32.0
    assert worst(pm.cbrt, lambda x: float(np.cbrt(x)), np.exp(RNG.uniform(-60, 60, 3000))) <= 4.0   # not x ** (1/3): 1/3 is inexact
    np.testing.assert_array_equal(pm.pow_array(fractions_, 1.33), [pm.pow(x, 1.33) for x in fractions_])


def test_special_values():
    assert pm.exp(0.0) == 1.0 and pm.exp(800.0) == math.inf and pm.exp(-800.0) == 0.0
    assert math.isnan(pm.exp(math.nan))
    assert pm.log(1.0) == 0.0 and pm.log(0.0) == -math.inf and math.isnan(pm.log(-1.0))
    assert pm.pow(0.0, 1.33) == 0.0 and pm.pow(2.5, 0.0) == 1.0 and pm.pow(1.0, 7.3) == 1.0
    assert pm.sincos(0.0) == (0.0, 1.0)
    assert all(math.isnan(v) for v in pm.sincos(1e9))            # beyond the reduction's range
    assert all(math.isnan(v) for v in pm.sincos(math.inf))
    for k in range(-4, 5):                                        # exact quadrant bookkeeping
        s, c = pm.sincos(k * math.pi / 2)
        assert abs(s - math.sin(k * math.pi / 2)) < 1e-15 and abs(c - math.cos(k * math.pi / 2)) < 1e-15


def test_the_pi_over_two_split_is_exact_to_the_last_piece():
    getcontext().prec = 110
    pi = Fraction(Decimal("3.141592653589793238462643383279502884197169399375105820974944592307816406286208998628034825342117068"))
    pieces = [pm._PIO2_1, pm._PIO2_2, pm._PIO2_3, pm._PIO2_4, pm._PIO2_5]
    rest = pi / 2 - sum(Fraction(p) for p in pieces)
    assert 0 <= rest < Fraction(1, 2 ** 118)                     # 1.2e-36: negligible times n < 2**29
    for p in pieces:                                              # 24 significant bits: n * p exact
        m, e = math.frexp(p)
        assert (m * 2 ** 24).is_integer()


def test_standard_normal_has_the_moments_of_a_normal():
    z = pm.standard_normal(np.random.default_rng(1), 200001)
    assert z.shape == (200001,)
    assert abs(z.mean()) < 0.01 and abs(z.std() - 1.0) < 0.01     # 4.5 standard errors
    assert abs(np.mean(z ** 4) - 3.0) < 0.05                        # kurtosis of a normal
    again = pm.standard_normal(np.random.default_rng(1), 200001)
    np.testing.assert_array_equal(z, again)


def test_solve_matches_lapack_on_well_conditioned_systems():
    for n in (1, 3, 7):
        a = RNG.normal(size=(n, n)) + n * np.eye(n)
        b = RNG.normal(size=(n, 3))
        np.testing.assert_allclose(pl.solve(a, b), np.linalg.solve(a, b), rtol=1e-12, atol=1e-12)
    # pivoting: a zero in the leading position
    a = np.array([[0.0, 1.0], [1.0, 1.0]])
    np.testing.assert_allclose(pl.solve(a, np.array([[1.0], [2.0]])), [[1.0], [1.0]], rtol=1e-15)


def test_lstsq_matches_numpy_including_rank_deficient():
    a = RNG.normal(size=(5, 5)) @ np.diag([1e3, 10.0, 1.0, 0.1, 1e-3])
    b = RNG.normal(size=5)
    np.testing.assert_allclose(pl.lstsq(a, b, 1e-12), np.linalg.lstsq(a, b, rcond=1e-12)[0], rtol=1e-9)
    singular = np.diag([2.0, 1.0, 0.0, 0.0, 0.0])                 # minimum-norm solution
    np.testing.assert_allclose(pl.lstsq(singular, np.ones(5), 1e-12), [0.5, 1.0, 0.0, 0.0, 0.0], atol=1e-15)
    tall = RNG.normal(size=(8, 3))
    y = RNG.normal(size=8)
    np.testing.assert_allclose(pl.lstsq(tall, y, 1e-12), np.linalg.lstsq(tall, y, rcond=None)[0], rtol=1e-10)


@pytest.mark.parametrize("x", [0.1, 1.0, 12.5, 900.0, 123456.7])
def test_sin_squared_plus_cos_squared(x):
    s, c = pm.sincos(x)
    assert abs(s * s + c * c - 1.0) < 4e-16


def test_expm1_and_tanh_within_a_few_ulp_of_libm():
    xs = np.concatenate([RNG.uniform(-0.5, 0.5, 3000), RNG.uniform(-30, 30, 3000), RNG.uniform(-1e-8, 1e-8, 200)])
    assert worst(pm.expm1, math.expm1, xs) <= 2.0
    assert worst(pm.tanh, math.tanh, xs) <= 3.0
    assert pm.tanh(40.0) == 1.0 and pm.tanh(-40.0) == -1.0 and pm.tanh(0.0) == 0.0
