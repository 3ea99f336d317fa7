"""Branch-free stand-ins for libm's atan2, sin and cos, exp and log, for particle loops.

numba on this machine has no vector math library (SVML), so a ``math.exp`` or ``math.atan2`` in
a loop over particles is one C library call per element and keeps the whole loop scalar. These
are polynomials and table look-ups the compiler vectorizes: :func:`fast_atan2` (error below
2e-5 rad), :func:`fast_sincos` (below 1e-6), :func:`fast_exp` (within 1 ulp of libm's) and
:func:`log_into_nb` (within 2 ulp, over an array). :mod:`cognition.localization.kernels` and
:mod:`cognition.localization.kld` use them.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from cognition.fastmath import FASTMATH

_PI = math.pi
_TWO_PI = 2.0 * math.pi


@nb.njit(cache=True, inline="always", fastmath=FASTMATH)
def fast_atan2(y, x):  # pragma: no cover - compiled
    """atan2(y, x) in (-pi, pi] with an absolute error below 2e-5 rad; branch-free."""
    ax, ay = abs(x), abs(y)
    mn, mx = min(ax, ay), max(ax, ay)
    a = mn / max(mx, 1e-300)
    s = a * a
    r = ((((0.0208351 * s - 0.0851330) * s + 0.1801410) * s - 0.3302995) * s + 0.9998660) * a
    r = 0.5 * _PI - r if ay > ax else r
    r = _PI - r if x < 0.0 else r
    return -r if y < 0.0 else r


_POW2 = np.ldexp(1.0, np.arange(-1100, 1024)).astype(np.float64)
_POW2.setflags(write=False)
"""2^k for k in [-1100, 1023] (0 below 2^-1074), the scale of :func:`fast_exp`."""
_LOG2E = 1.4426950408889634
_LN2_HI = 6.93147180369123816490e-01  # ln 2 in two parts (Cody-Waite): k * _LN2_HI is exact
_LN2_LO = 1.90821492927058770002e-10


@nb.njit(cache=True, inline="always", fastmath=FASTMATH)
def fast_exp(x):  # pragma: no cover - compiled
    """exp(x) within about 1 ulp of libm's (0 below -745.2, x clamped at 709), branch-free so
    that loops over particles vectorize (a libm call per element does not: about 4x slower).
    x = k ln 2 + r with |r| <= ln 2 / 2; exp(r) by its Taylor series to r^13 (truncation
    below 1e-17); 2^k from a table."""
    x = min(max(x, -745.2), 709.0)
    k = math.floor(x * _LOG2E + 0.5)
    r = (x - k * _LN2_HI) - k * _LN2_LO
    p = 1.0 / 6227020800.0
    p = p * r + 1.0 / 479001600.0
    p = p * r + 1.0 / 39916800.0
    p = p * r + 1.0 / 3628800.0
    p = p * r + 1.0 / 362880.0
    p = p * r + 1.0 / 40320.0
    p = p * r + 1.0 / 5040.0
    p = p * r + 1.0 / 720.0
    p = p * r + 1.0 / 120.0
    p = p * r + 1.0 / 24.0
    p = p * r + 1.0 / 6.0
    p = p * r + 0.5
    p = p * r + 1.0
    p = p * r + 1.0
    return p * _POW2[min(max(int(k) + 1100, 0), 2123)]  # clamped: a NaN x never indexes outside


_MANTISSA = np.int64(0x000FFFFFFFFFFFFF)
_ONE_BITS = np.int64(0x3FF0000000000000)
_S52 = np.int64(52)
_SQRT2 = math.sqrt(2.0)
_MIN_NORMAL = 2.2250738585072014e-308


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def log_into_nb(src, dst, n):  # pragma: no cover - compiled
    """``dst[i] = log(src[i])`` for i < n, within about 2 ulp of libm's, in loops that vectorize
    (a libm call per element does not). ``src`` is clamped in place to at least the smallest
    normal number (its log, -708.4, stands for 0 and subnormals); NaN and infinity pass through.
    log x = e ln 2 + log m with x = m 2^e, m in [sqrt(1/2), sqrt(2)), read off the bits;
    log m = 2 atanh(s), s = (m - 1) / (m + 1), |s| < 0.172, by its series to s^21."""
    for i in range(n):
        src[i] = max(src[i], _MIN_NORMAL)
    bits = src[:n].view(np.int64)
    mant = np.empty(n, dtype=np.int64)
    expo = np.empty(n, dtype=np.int64)
    for i in range(n):  # integer work on the bits
        b = bits[i]
        mant[i] = (b & _MANTISSA) | _ONE_BITS
        expo[i] = (b >> _S52) & 2047
    mf = mant.view(np.float64)
    for i in range(n):
        m = mf[i]
        big = m > _SQRT2
        m = 0.5 * m if big else m
        e = float(expo[i] - 1023 + (1 if big else 0))
        s = (m - 1.0) / (m + 1.0)
        z = s * s
        t = 1.0 / 21.0
        t = t * z + 1.0 / 19.0
        t = t * z + 1.0 / 17.0
        t = t * z + 1.0 / 15.0
        t = t * z + 1.0 / 13.0
        t = t * z + 1.0 / 11.0
        t = t * z + 1.0 / 9.0
        t = t * z + 1.0 / 7.0
        t = t * z + 1.0 / 5.0
        t = t * z + 1.0 / 3.0
        r = e * _LN2_HI + (2.0 * s + (2.0 * s * z * t + e * _LN2_LO))
        dst[i] = r if expo[i] != 2047 else src[i]  # NaN and infinity as they are


@nb.njit(cache=True, inline="always", fastmath=FASTMATH)
def fast_sincos(a):  # pragma: no cover - compiled
    """(sin a, cos a) for any a, absolute error below 1e-6; branch-free polynomials."""
    a = a - _TWO_PI * math.floor((a + _PI) / _TWO_PI)  # [-pi, pi)
    h = 0.5 * a  # [-pi/2, pi/2): sin and cos of the half angle, then double it
    s2 = h * h
    sh = h * (1.0 + s2 * (-1 / 6 + s2 * (1 / 120 + s2 * (-1 / 5040 + s2 * (1 / 362880 - s2 / 39916800)))))
    ch = 1.0 + s2 * (-0.5 + s2 * (1 / 24 + s2 * (-1 / 720 + s2 * (1 / 40320 + s2 * (-1 / 3628800 + s2 / 479001600)))))
    return 2.0 * sh * ch, ch * ch - sh * sh
