"""Elementary functions from IEEE basic operations only: the same bits on every CPU.

glibc's libm picks its ``exp``/``log``/``pow``/``sin``/``cos`` code by CPU feature (FMA, AVX2,
AVX-512; ifunc), NumPy dispatches its own SIMD versions by CPU feature, and OpenBLAS picks its
kernels by core type. On a quasi-periodic orbit a last-bit difference in one of them grows into
another trajectory within an episode. Everything that feeds the simulator's state, an
observation or the reward therefore calls the functions of this module, which use only
``+ - * /`` and ``sqrt`` (correctly rounded by IEEE 754 on every CPU), in a fixed order, with
no fused multiply-add (numba compiles without ``fastmath``, so LLVM never contracts
``a * b + c``), no table look-up by bit pattern and no library call.

The algorithms are those of fdlibm (Sun Microsystems, 1993; as kept in FreeBSD's msun):

* :func:`exp`: argument reduction x = k ln2 + r with ln2 split in two (``e_exp.c``), the
  Remez rational approximation of ``e_exp.c``, then an exact scaling by 2**k;
* :func:`log`: x = 2**k (1 + f) with 1 + f in [sqrt(2)/2, sqrt(2)) (k and 1 + f read from the
  bits, as fdlibm does), the series in s = f / (2 + f) of ``e_log.c``;
* :func:`pow`: exp(y log x) for x > 0 (relative error about |y log x| x 2**-53 above exp's
  own; the physics uses exponents of order one);
* :func:`sincos`: Cody-Waite reduction by pi/2 split into five 24-bit pieces (exact products
  for |x| < 2**29 pi/2, about 8.4e8 rad), then the minimax kernels of ``k_sin.c`` and
  ``k_cos.c`` (FreeBSD's versions, which need no bit manipulation). Beyond 8.4e8 rad the
  result is NaN (an angle that large means a simulation 10,000 s long at ball-spin speed).

Accuracy (``tests/physics/test_portable_math.py``, against libm): within 1 ulp for
``exp``/``log`` and 2 ulp for ``sin``/``cos``, a few ulp for ``pow`` and ``cbrt``; the point is not
the last ulp but that every CPU gets the same one.

Scalar functions are numba ``njit`` (inlined into the kernels) and callable from Python;
:func:`pow_array` and :func:`sincos_array` serve NumPy arrays on the Python side (reward,
scenario, sensor).
"""

from __future__ import annotations

import numpy as np
from llvmlite import ir
from numba import njit
from numba.core import types
from numba.extending import intrinsic

__all__ = ["exp", "expm1", "log", "pow", "sincos", "sin", "cos", "cbrt", "cube_root_near", "tanh", "pow_array",
           "sincos_array", "standard_normal", "PI", "TWO_PI"]

PI = float.fromhex("0x1.921fb54442d18p+1")          # the double nearest pi (= math.pi)
TWO_PI = 2.0 * PI
_INF = float("inf")
_NAN = float("nan")

# -- exp (fdlibm e_exp.c) -------------------------------------------------------------------
_LN2_HI = 6.93147180369123816490e-01     # 32 significant bits: k * _LN2_HI is exact for |k| < 2**21
_LN2_LO = 1.90821492927058770002e-10
_INV_LN2 = 1.44269504088896338700e+00
_EXP_P1 = 1.66666666666666019037e-01
_EXP_P2 = -2.77777777770155933842e-03
_EXP_P3 = 6.61375632143793436117e-05
_EXP_P4 = -1.65339022054652515390e-06
_EXP_P5 = 4.13813679705723846039e-08
_EXP_OVERFLOW = 7.09782712893383973096e+02
_EXP_UNDERFLOW = -7.45133219101941108420e+02
_TO_INT = float.fromhex("0x1.8p52")      # x + 1.5 * 2**52 - 1.5 * 2**52 rounds x to an integer

# -- log (fdlibm e_log.c) -------------------------------------------------------------------
_LG1 = 6.666666666666735130e-01
_LG2 = 3.999999999940941908e-01
_LG3 = 2.857142874366239149e-01
_LG4 = 2.222219843214978396e-01
_LG5 = 1.818357216161805012e-01
_LG6 = 1.531383769920937332e-01
_LG7 = 1.479819860511658591e-01
_SQRT2 = float.fromhex("0x1.6a09e667f3bcdp+0")
_TWO54 = float.fromhex("0x1p54")
_MIN_NORMAL = float.fromhex("0x1p-1022")
_MANTISSA = 0x000FFFFFFFFFFFFF
_ONE_BITS = 0x3FF0000000000000
_TWO_M1000 = float.fromhex("0x1p-1000")

# -- sin / cos (FreeBSD msun k_sin.c, k_cos.c; pi/2 in 24-bit pieces) ------------------------
_S1 = -1.66666666666666324348e-01
_S2 = 8.33333333332248946124e-03
_S3 = -1.98412698298579493134e-04
_S4 = 2.75573137070700676789e-06
_S5 = -2.50507602534068634195e-08
_S6 = 1.58969099521155010221e-10
_C1 = 4.16666666666666019037e-02
_C2 = -1.38888888888741095749e-03
_C3 = 2.48015872894767294178e-05
_C4 = -2.75573143513906633035e-07
_C5 = 2.08757232129817482790e-09
_C6 = -1.13596475577881948265e-11
_INV_PIO2 = 6.36619772367581382433e-01
_PIO4 = float.fromhex("0x1.921fb54442d18p-1")
#: pi/2 = _PIO2_1 + ... + _PIO2_5 + 1.2e-36, each piece 24 significant bits (n * piece exact
#: for |n| < 2**29); tests/physics/test_portable_math.py checks the split against 100 digits of pi
_PIO2_1 = float.fromhex("0x1.921fb4p+0")
_PIO2_2 = float.fromhex("0x1.4442d0p-24")
_PIO2_3 = float.fromhex("0x1.846988p-48")
_PIO2_4 = float.fromhex("0x1.8cc516p-72")
_PIO2_5 = float.fromhex("0x1.01b838p-96")
_MAX_QUADRANT = float.fromhex("0x1p29")


@intrinsic
def _bits(typingctx, x):
    """The IEEE 754 bit pattern of a float64 as an int64 (a reinterpretation, no arithmetic)."""
    if x != types.float64:
        return None

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.IntType(64))
    return types.int64(types.float64), codegen


@intrinsic
def _from_bits(typingctx, n):
    """The float64 whose IEEE 754 bit pattern is the int64 ``n``."""
    if n != types.int64:
        return None

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.DoubleType())
    return types.float64(types.int64), codegen


@njit(cache=True, inline="always")
def _two_pow(k):
    """2.0**k for an integer k in [-1022, 1023], exactly (its bit pattern)."""
    return _from_bits((k + 1023) << 52)


@njit(cache=True)
def exp(x):
    """e**x (fdlibm e_exp.c from basic operations)."""
    if x != x:
        return x
    if x > _EXP_OVERFLOW:
        return _INF
    if x < _EXP_UNDERFLOW:
        return 0.0
    t = x * _INV_LN2
    kf = (t + _TO_INT) - _TO_INT                 # nearest integer to x / ln2 (exact rounding)
    k = int(kf)
    hi = x - kf * _LN2_HI                       # exact (Sterbenz)
    lo = kf * _LN2_LO
    r = hi - lo
    t = r * r
    c = r - t * (_EXP_P1 + t * (_EXP_P2 + t * (_EXP_P3 + t * (_EXP_P4 + t * _EXP_P5))))
    if k == 0:
        return 1.0 - ((r * c) / (c - 2.0) - r)
    y = 1.0 - ((lo - (r * c) / (2.0 - c)) - hi)
    if k > 1023:
        return y * 2.0 * _two_pow(k - 1)
    if k < -1021:
        return (y * _two_pow(k + 1000)) * _TWO_M1000
    return y * _two_pow(k)


@njit(cache=True)
def log(x):
    """Natural logarithm (fdlibm e_log.c from basic operations); NaN for x < 0, -inf at 0."""
    if x != x or x < 0.0:
        return _NAN
    if x == 0.0:
        return -_INF
    if x == _INF:
        return x
    k = 0
    if x < _MIN_NORMAL:                          # subnormal: make it normal first
        x *= _TWO54
        k = -54
    bits = _bits(x)                              # x = 2**e m, m in [1, 2), from the bits
    k += (bits >> 52) - 1023
    x = _from_bits((bits & _MANTISSA) | _ONE_BITS)
    if x > _SQRT2:                               # 1 + f in [sqrt(2)/2, sqrt(2))
        x *= 0.5
        k += 1
    f = x - 1.0                                  # exact (Sterbenz)
    dk = float(k)
    if f == 0.0:
        return dk * _LN2_HI + dk * _LN2_LO
    s = f / (2.0 + f)
    z = s * s
    w = z * z
    t1 = w * (_LG2 + w * (_LG4 + w * _LG6))
    t2 = z * (_LG1 + w * (_LG3 + w * (_LG5 + w * _LG7)))
    r = t2 + t1
    hfsq = 0.5 * f * f
    return dk * _LN2_HI - ((hfsq - (s * (hfsq + r) + dk * _LN2_LO)) - f)


@njit(cache=True)
def pow(x, y):
    """x**y for x >= 0 as exp(y log x) (0**y = 0 for y > 0, 1 for y = 0); NaN for x < 0.

    For the integer and half-integer powers of the physics write products instead
    (``d * sqrt(d)``, ``x * x * x``): they are exact to the last bit and cheaper.
    """
    if y == 0.0:
        return 1.0
    if x == 0.0:
        return 0.0 if y > 0.0 else _INF
    if x == 1.0:
        return 1.0
    return exp(y * log(x))


@njit(cache=True)
def cbrt(x):
    """Cube root of x >= 0 (one Newton step on exp(log(x) / 3))."""
    if x == 0.0:
        return 0.0
    y = exp(log(x) / 3.0)
    return y - (y * y * y - x) / (3.0 * y * y)


@njit(cache=True)
def expm1(x):
    """e**x - 1, accurate near 0 (Taylor series to x**17 / 17! for |x| < 0.5, else exp(x) - 1)."""
    if x != x:
        return x
    if -0.5 < x < 0.5:
        acc = 1.0 / 355687428096000.0              # 1 / 17!
        for n in range(16, 0, -1):                  # Horner: x (1 + x/2 (1 + x/3 (...)))
            acc = acc * x + _INV_FACTORIAL[n]
        return acc * x
    return exp(x) - 1.0


_INV_FACTORIAL = np.array([1.0 / float(np.prod(np.arange(1, n + 1, dtype=np.float64))) for n in range(18)])


@njit(cache=True)
def tanh(x):
    """Hyperbolic tangent, -expm1(-2|x|) / (2 + expm1(-2|x|)) with the sign of x."""
    if x != x:
        return x
    a = x if x >= 0.0 else -x
    if a > 22.0:
        y = 1.0
    else:
        t = expm1(-2.0 * a)
        y = -t / (2.0 + t)
    return y if x >= 0.0 else -y


@njit(cache=True, inline="always")
def _kernel_sin(x):
    z = x * x
    w = z * z
    r = _S2 + z * (_S3 + z * _S4) + z * w * (_S5 + z * _S6)
    v = z * x
    return x + v * (_S1 + z * r)


@njit(cache=True, inline="always")
def _kernel_cos(x):
    z = x * x
    w = z * z
    r = z * (_C1 + z * (_C2 + z * _C3)) + w * w * (_C4 + z * (_C5 + z * _C6))
    hz = 0.5 * z
    w = 1.0 - hz
    return w + (((1.0 - w) - hz) + z * r)


@njit(cache=True)
def sincos(x):
    """(sin x, cos x) (fdlibm kernels, Cody-Waite reduction by pi/2; NaN for |x| > 8.4e8)."""
    if -_PIO4 <= x <= _PIO4:
        return _kernel_sin(x), _kernel_cos(x)
    fn = x * _INV_PIO2
    if not (-_MAX_QUADRANT < fn < _MAX_QUADRANT):   # also NaN and infinity
        return _NAN, _NAN
    fn = (fn + _TO_INT) - _TO_INT                   # nearest integer
    r = x - fn * _PIO2_1                            # exact (Sterbenz)
    r = r - fn * _PIO2_2
    r = r - fn * _PIO2_3
    r = r - fn * _PIO2_4
    r = r - fn * _PIO2_5
    s = _kernel_sin(r)
    c = _kernel_cos(r)
    q = int(fn) & 3
    if q == 0:
        return s, c
    if q == 1:
        return c, -s
    if q == 2:
        return -s, -c
    return -c, s


@njit(cache=True)
def sin(x):
    return sincos(x)[0]


@njit(cache=True)
def cos(x):
    return sincos(x)[1]


@njit(cache=True)
def pow_array(x, y):
    """Element-wise :func:`pow` of a float64 array ``x`` (any shape) and a scalar ``y``."""
    flat = x.ravel()
    out = np.empty(flat.shape[0])
    for i in range(flat.shape[0]):
        out[i] = pow(flat[i], y)
    return out.reshape(x.shape)


@njit(cache=True)
def sincos_array(x):
    """Element-wise :func:`sincos` of a float64 array: (sin, cos) arrays of its shape."""
    flat = x.ravel()
    s = np.empty(flat.shape[0])
    c = np.empty(flat.shape[0])
    for i in range(flat.shape[0]):
        s[i], c[i] = sincos(flat[i])
    return s.reshape(x.shape), c.reshape(x.shape)


def standard_normal(rng: np.random.Generator, size: int) -> np.ndarray:
    """``size`` standard normal draws from ``rng``'s uniform stream by the Box-Muller transform
    with this module's log, sqrt and sin/cos (NumPy's ziggurat calls libm's exp/log1p in its
    rare branches, so ``rng.normal`` is not the same on every CPU)."""
    pairs = (int(size) + 1) // 2
    u = rng.random(2 * pairs)
    u1 = 1.0 - u[:pairs]                      # (0, 1]: log is finite
    radius = np.sqrt(-2.0 * _log_array(u1))
    s, c = sincos_array(TWO_PI * u[pairs:])
    return np.concatenate([radius * c, radius * s])[:int(size)]


@njit(cache=True)
def _log_array(x):
    out = np.empty(x.shape[0])
    for i in range(x.shape[0]):
        out[i] = log(x[i])
    return out


@njit(cache=True, inline="always")
def cube_root_near(x, guess):
    """x^(1/3) for x > 0 from ``guess``, a cube root of a nearby value: two Halley steps
    y <- y (y^3 + 2x) / (2y^3 + x) (relative error e -> (2/3) e^3 each) when guess^3 is within
    10 % of x (then e < 3.5 % and the result is within 2e-14), else the portable cbrt. Only
    IEEE operations: the same bits on every CPU, at a tenth of cbrt's price when the guess is
    last step's root of the same contact."""
    y = guess
    y3 = y * y * y
    if not (0.9 * x < y3 < 1.1 * x):
        return cbrt(x)
    y = y * (y3 + 2.0 * x) / (2.0 * y3 + x)
    y3 = y * y * y
    return y * (y3 + 2.0 * x) / (2.0 * y3 + x)
