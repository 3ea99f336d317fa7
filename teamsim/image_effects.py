"""Image effects: degrade a rendered RGB camera image the way a real robot camera does.

The geometric error sources are the ones the Darmstadt paper (Kohlbrecher & von Stryk,
"Modeling observation uncertainty for soccer playing humanoid robots", section IV.B) attributes
to head and body motion, in the order light takes through the camera:

1. **Motion blur** while the shutter is open. The image moves ``rate * focal * exposure``
   pixels meanwhile (rad/s * px/rad * s): ``Lh = |yaw_rate| fx exposure`` horizontally,
   ``Lv = |pitch_rate| fy exposure (+ walking_shake while walking)`` vertically. A pixel is the
   time average of the moving image: a box of length ``L`` px centred on the pixel over the
   linearly interpolated image (partial weights at both ends, sub-pixel lengths blur a
   little), which is the box filter convolved with the pixel's footprint. Borders replicate.
2. **Rolling-shutter skew** (``rolling_shutter`` s per row > 0): row ``j`` is exposed
   ``dt_j = (j + 0.5 - H/2) rolling_shutter`` s after the centre row, when the image has moved
   ``yaw_rate fx dt_j`` px to the right and ``pitch_rate fy dt_j`` px up.
3. **Photometric model** in digital numbers (DN, 0..255): per image an exposure gain
   ``brightness exp(N(0, brightness_jitter))`` and channel gains ``white_balance[c]
   exp(N(0, white_balance_jitter))``; lens vignetting ``1 - vignetting r^2 / r_corner^2`` (``r``
   in px from the image centre); sensor noise of sigma ``sqrt(read_noise^2 + shot_noise s)``
   DN at signal ``s`` DN; rounding and clipping to 8 bits.

Image frame: ``u`` (column) to the right, ``v`` (row) down, pixel ``(i, j)`` covers
``[i, i + 1) x [j, j + 1)``. Rates in rad/s: positive yaw turns the camera left (image content
moves toward larger ``u``), positive pitch looks further down (content moves toward smaller
``v``). Parameters in :class:`~teamsim.image_params.ImageParams`.

The uneven light of the hall (``sun_stripes``, ``shadows``, ``light_falloff``) is an image
effect of the same parameters, but not applied here: it is fixed in the world, so the
renderer draws it with the scene (:func:`teamsim.image_venue.light_map`,
:class:`teamsim.images.ImageRenderer`).

Random numbers come only from the ``numpy.random.Generator`` handed in; the sensor noise
reads a pool of pre-drawn standard normals at a random start per image, and the pool is
redrawn a slice per image, about ``POOL_REUSE`` uses per value.

**Compiled passes** (:func:`_effects`, one call per image): the blurs and the skew write
float32 images; the photometric step (gains, vignetting, noise and rounding in one loop per
value, :func:`_dn`) reads the last of them and writes the 8-bit image. The last geometric
step is done in the same loop as the photometric step where that saves a pass over the image:
the rolling-shutter skew (:func:`_rolling_shutter_photometric`), else a vertical blur after a
horizontal one (:func:`_blur_cols_photometric`) or a short horizontal blur alone
(:func:`_blur_rows_photometric`). Every value is computed by the same float32 operations, in
the same order, whichever way the passes are combined.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.fastmath import FASTMATH
from teamsim.image_params import ImageParams

MIN_BLUR = 0.05
"""Blur lengths (px) below this skip their pass."""
MIN_SHIFT = 1e-3
"""Rolling-shutter skew (px between the first and the last row) below this skips the pass."""
DIRECT_HALF_WIDTH = 2
"""Horizontal blurs with at most this many taps each side are direct sums, longer ones running sums."""
MAX_BLUR = 4096.0
"""Blur lengths (px) are clipped to this (only absurd rates reach it)."""
POOL_SIZE = 1 << 21
"""Minimum number of standard normals in the noise pool (float32); at least twice an image."""
POOL_REUSE = 256
"""Each image redraws ``ceil(n / POOL_REUSE)`` pool values (``n`` = values per image), cyclically."""
_ROUND = np.float32(1.5 * 2**23)  # x + _ROUND holds the nearest integer to x (0 <= x < 2^22) in its low bits


@nb.njit(cache=True, error_model="python", fastmath=FASTMATH)
def _tri_cdf(x: float) -> float:
    """Integral of the unit triangle (pixel footprint of linear interpolation) from -inf to ``x`` px."""
    if x <= -1.0:
        return 0.0
    if x <= 0.0:
        return 0.5 * (1.0 + x) ** 2
    if x < 1.0:
        return 1.0 - 0.5 * (1.0 - x) ** 2
    return 1.0


@nb.njit(cache=True, error_model="python", fastmath=FASTMATH)
def _taps(length: float) -> NDArray[np.float32]:
    """Weights of the direct horizontal blur of ``length`` px at offsets 0..K (symmetric), K =
    ceil(L / 2): the overlap of each pixel's footprint with the blur box, over ``L``."""
    h = 0.5 * length
    inv = 1.0 / length
    K = math.ceil(h)
    w = np.empty(K + 1, dtype=np.float32)
    for k in range(K + 1):
        w[k] = (_tri_cdf(h - k) - _tri_cdf(-h - k)) * inv
    return w


@nb.njit(cache=True, error_model="python", fastmath=FASTMATH)
def _blur_border(s: NDArray, d: NDArray[np.float32], w: NDArray[np.float32]) -> None:
    """The pixels within ``K`` (= len(w) - 1) of either end of row ``s`` (3W) blurred by the taps
    ``w`` into ``d``, borders replicated (the interior is the caller's vector loop)."""
    K = w.shape[0] - 1
    W = s.shape[0] // 3
    inner = max(W - 2 * K, 0)
    for k_ in range(W - inner):
        i = k_ if k_ < K else k_ + inner
        for c in range(3):
            acc = w[0] * np.float32(s[3 * i + c])
            for k in range(1, K + 1):
                lft, rgt = 3 * max(i - k, 0) + c, 3 * min(i + k, W - 1) + c
                acc += w[k] * (np.float32(s[lft]) + np.float32(s[rgt]))
            d[3 * i + c] = acc


@nb.njit(cache=True, error_model="python", fastmath=FASTMATH)
def _blur_rows(src: NDArray[np.uint8], dst: NDArray[np.float32], length: float) -> None:
    """Horizontal motion blur of ``length`` px from ``src`` (H x 3W, RGB interleaved) into ``dst``.

    Pixel ``i`` becomes the mean of the linearly interpolated row over ``[i - L/2, i + L/2]``.
    Short blurs are direct sums over ``2K + 1`` taps; longer ones use exact integer prefix sums
    of the row extended by ``e`` replicated pixels at each end (cost independent of ``L``).
    """
    H, W = src.shape[0], src.shape[1] // 3
    n = 3 * W
    h = 0.5 * length
    inv = 1.0 / length
    K = math.ceil(h)
    if K <= DIRECT_HALF_WIDTH:
        w = _taps(length)
        lo, m = 3 * K, n - 6 * K  # interior: pixels K..W-K-1, flat indices lo..lo+m-1
        for j in range(H):
            s, d = src[j], dst[j]
            if m > 0:
                di, s0, w0 = d[lo : lo + m], s[lo : lo + m], w[0]
                for q in range(m):
                    di[q] = w0 * np.float32(s0[q])
                for k in range(1, K + 1):
                    a, b, wk = s[lo - 3 * k : lo - 3 * k + m], s[lo + 3 * k : lo + 3 * k + m], w[k]
                    for q in range(m):
                        di[q] += wk * (np.float32(a[q]) + np.float32(b[q]))
            _blur_border(s, d, w)
        return
    # out(i) L = C(i + h) - C(i - h), C the integral of the interpolated row; with kh = floor(h) the
    # window runs from pixel i - kh - 1 (extended index t = i) to i + kh (t = i + o / 3), fractions at the ends
    kh = math.floor(h)
    e = kh + 1
    o = 3 * (2 * kh + 1)
    ar, al = h - kh, 1.0 - (h - kh)
    cr0, cr1 = np.float32((ar - 0.5 * ar * ar) * inv), np.float32(0.5 * ar * ar * inv)
    cl0, cl1 = np.float32((al - 0.5 * al * al) * inv), np.float32(0.5 * al * al * inv)
    half = np.float32(0.5 * inv)
    fx = np.empty(3 * (W + 2 * e), dtype=np.uint8)  # the row extended by replicated pixels
    E = np.empty(3 * (W + 2 * e + 1), dtype=np.int32)  # exclusive prefix sums of fx per channel
    E[0] = E[1] = E[2] = 0
    for j in range(H):
        s, d = src[j], dst[j]
        for c in range(3):
            first, last = s[c], s[n - 3 + c]
            for t in range(e):
                fx[3 * t + c] = first
                fx[3 * (W + e + t) + c] = last
        mid = fx[3 * e : 3 * e + n]
        for q in range(n):
            mid[q] = s[q]
        a0 = a1 = a2 = 0
        for t in range(W + 2 * e):
            a0 += np.int32(fx[3 * t])
            a1 += np.int32(fx[3 * t + 1])
            a2 += np.int32(fx[3 * t + 2])
            E[3 * t + 3] = a0
            E[3 * t + 4] = a1
            E[3 * t + 5] = a2
        Eo, Eo1, E1 = E[o : o + n], E[o + 3 : o + 3 + n], E[3 : 3 + n]
        Fo, Fo1, F1 = fx[o : o + n], fx[o + 3 : o + 3 + n], fx[3 : 3 + n]
        for q in range(n):
            d[q] = (
                half * np.float32(Eo[q] + Eo1[q] - E[q] - E1[q])
                + cr0 * np.float32(Fo[q])
                + cr1 * np.float32(Fo1[q])
                - cl0 * np.float32(fx[q])
                - cl1 * np.float32(F1[q])
            )


@nb.njit(cache=True, error_model="python", fastmath=FASTMATH)
def _col_weights(length: float) -> tuple[int, np.float32, np.float32, np.float32, np.float32, np.float32]:
    """Constants of a vertical blur of ``length`` px (running sums over rows, see :func:`_blur_cols`):
    kh = floor(L / 2), 1 / L and the weights of the partial rows at the window's ends."""
    h = 0.5 * length
    kh = math.floor(h)
    ar, al = h - kh, 1.0 - (h - kh)
    cr0, cr1 = np.float32(ar - 0.5 * ar * ar), np.float32(0.5 * ar * ar)
    cl0, cl1 = np.float32(al - 0.5 * al * al), np.float32(0.5 * al * al)
    return kh, np.float32(1.0 / length), cr0, cr1, cl0, cl1


@nb.njit(cache=True, error_model="python", fastmath=FASTMATH)
def _blur_cols(src: NDArray, dst: NDArray[np.float32], length: float) -> None:
    """Vertical motion blur of ``length`` px from ``src`` (H x 3W) into ``dst``: running sums over rows."""
    H, n = src.shape[0], src.shape[1]
    kh, inv, cr0, cr1, cl0, cl1 = _col_weights(length)
    S = np.zeros(n, dtype=np.float32)  # trapezoid sums over rows [j - kh - 1, j + kh], all columns
    for m in range(-kh - 1, kh):
        a, b = src[min(max(m, 0), H - 1)], src[min(max(m + 1, 0), H - 1)]
        for p in range(n):
            S[p] += np.float32(0.5) * (np.float32(a[p]) + np.float32(b[p]))
    for j in range(H):
        fr, fr1 = src[min(j + kh, H - 1)], src[min(j + kh + 1, H - 1)]
        fl, fl1 = src[max(j - kh - 1, 0)], src[max(j - kh, 0)]
        d = dst[j]
        for p in range(n):
            r, r1, q, q1 = np.float32(fr[p]), np.float32(fr1[p]), np.float32(fl[p]), np.float32(fl1[p])
            d[p] = (S[p] + cr0 * r + cr1 * r1 - cl0 * q - cl1 * q1) * inv
            S[p] += np.float32(0.5) * (r + r1 - q - q1)


@nb.njit(cache=True, error_model="python", fastmath=FASTMATH)
def _gains(gain: NDArray[np.float64], vcol: NDArray[np.float32]) -> tuple[NDArray[np.float32], NDArray[np.float32]]:
    """Per value of a row (3W): the channel gain ``gv`` and ``gc = gv vcol[i]``; a value of row ``j``
    is scaled by ``vrow[j] gv - gc`` (gains and vignetting)."""
    W = vcol.shape[0]
    gv = np.empty(3 * W, dtype=np.float32)
    gc = np.empty(3 * W, dtype=np.float32)
    for i in range(W):
        for c in range(3):
            g = np.float32(gain[c])
            gv[3 * i + c] = g
            gc[3 * i + c] = g * vcol[i]
    return gv, gc


@nb.njit(cache=True, error_model="python", fastmath=FASTMATH)
def _dn(sig: np.float32, z: np.float32, r2: np.float32, sh: np.float32) -> np.uint8:
    """Signal ``sig`` (DN) with noise ``sqrt(r2 + sh sig) z``, rounded to the nearest integer (ties to
    even, as ``rint``) and clipped to 0..255. The integer is in the low bits of the clipped value
    plus 1.5 2^23: one addition instead of a rounding and a pack, in vector loops."""
    y = sig + np.sqrt(r2 + sh * max(sig, np.float32(0.0))) * z
    return np.uint8(np.int32(min(max(y, np.float32(0.0)), np.float32(255.0)) + _ROUND))


@nb.njit(cache=True, error_model="python", fastmath=FASTMATH)
def _photometric(
    src: NDArray,
    dst: NDArray[np.uint8],
    gain: NDArray[np.float64],
    vrow: NDArray[np.float32],
    vcol: NDArray[np.float32],
    pool: NDArray[np.float32],
    offset: int,
    read2: float,
    shot: float,
) -> None:
    """Gains, vignetting ``vrow[j] - vcol[i]``, noise ``pool[offset:]`` (:func:`_dn`): ``src`` (H x 3W,
    not ``dst``: loops vectorize only where reads and writes cannot overlap) into ``dst``."""
    H, n = src.shape
    gv, gc = _gains(gain, vcol)
    r2, sh = np.float32(read2), np.float32(shot)
    for j in range(H):
        s, d, a = src[j], dst[j], vrow[j]
        z = pool[offset + j * n : offset + (j + 1) * n]
        for q in range(n):
            d[q] = _dn(np.float32(s[q]) * (a * gv[q] - gc[q]), z[q], r2, sh)


@nb.njit(cache=True, error_model="python", fastmath=FASTMATH)
def _blur_rows_photometric(
    img: NDArray[np.uint8],
    length: float,
    gain: NDArray[np.float64],
    vrow: NDArray[np.float32],
    vcol: NDArray[np.float32],
    pool: NDArray[np.float32],
    offset: int,
    read2: float,
    shot: float,
) -> None:
    """:func:`_blur_rows` (direct taps only) and :func:`_photometric` of ``img`` (H x 3W) in place,
    row by row: the row as float32, its centre tap and borders, then one loop adds the side
    taps and maps to 8 bits. Each value is rounded as in the two passes."""
    H, n = img.shape
    w = _taps(length)
    K = w.shape[0] - 1
    lo, m = 3 * K, max(n - 6 * K, 0)  # interior values lo..lo+m-1
    gv, gc = _gains(gain, vcol)
    r2, sh = np.float32(read2), np.float32(shot)
    sf = np.empty(n, dtype=np.float32)  # the row
    t = np.empty(n, dtype=np.float32)  # the blurred row: centre tap first
    w0, w1 = w[0], w[1]
    w2 = w[2] if K > 1 else np.float32(0.0)
    for j in range(H):
        s, d, a = img[j], img[j], vrow[j]
        for q in range(n):
            x = np.float32(s[q])
            sf[q] = x
            t[q] = w0 * x
        _blur_border(sf, t, w)
        z = pool[offset + j * n : offset + (j + 1) * n]
        for q in range(lo):
            d[q] = _dn(t[q] * (a * gv[q] - gc[q]), z[q], r2, sh)
        for q in range(lo + m, n):
            d[q] = _dn(t[q] * (a * gv[q] - gc[q]), z[q], r2, sh)
        ti, l1, r1, gvi, gci, zi, di = t[lo:], sf[lo - 3 :], sf[lo + 3 :], gv[lo:], gc[lo:], z[lo:], d[lo:]
        if K == 1:  # the side taps at 1 px to the left and right, then (K = 2) at 2 px
            for q in range(m):
                v = ti[q] + w1 * (l1[q] + r1[q])
                di[q] = _dn(v * (a * gvi[q] - gci[q]), zi[q], r2, sh)
        else:
            l2, r2_ = sf[lo - 6 :], sf[lo + 6 :]
            for q in range(m):
                v = (ti[q] + w1 * (l1[q] + r1[q])) + w2 * (l2[q] + r2_[q])
                di[q] = _dn(v * (a * gvi[q] - gci[q]), zi[q], r2, sh)


@nb.njit(cache=True, error_model="python", fastmath=FASTMATH)
def _blur_cols_photometric(
    src: NDArray[np.float32],
    dst: NDArray[np.uint8],
    length: float,
    gain: NDArray[np.float64],
    vrow: NDArray[np.float32],
    vcol: NDArray[np.float32],
    pool: NDArray[np.float32],
    offset: int,
    read2: float,
    shot: float,
) -> None:
    """:func:`_blur_cols` and :func:`_photometric` in one loop per row: ``src`` (H x 3W float32,
    blurred horizontally) into ``dst``. Each value is rounded as in the two passes."""
    H, n = src.shape
    kh, inv, cr0, cr1, cl0, cl1 = _col_weights(length)
    gv, gc = _gains(gain, vcol)
    r2, sh = np.float32(read2), np.float32(shot)
    S = np.zeros(n, dtype=np.float32)  # trapezoid sums over rows [j - kh - 1, j + kh], all columns
    for m in range(-kh - 1, kh):
        a, b = src[min(max(m, 0), H - 1)], src[min(max(m + 1, 0), H - 1)]
        for p in range(n):
            S[p] += np.float32(0.5) * (a[p] + b[p])
    for j in range(H):
        fr, fr1 = src[min(j + kh, H - 1)], src[min(j + kh + 1, H - 1)]
        fl, fl1 = src[max(j - kh - 1, 0)], src[max(j - kh, 0)]
        d, a = dst[j], vrow[j]
        z = pool[offset + j * n : offset + (j + 1) * n]
        for p in range(n):
            r, r1, q, q1 = fr[p], fr1[p], fl[p], fl1[p]
            v = (S[p] + cr0 * r + cr1 * r1 - cl0 * q - cl1 * q1) * inv
            S[p] += np.float32(0.5) * (r + r1 - q - q1)
            d[p] = _dn(v * (a * gv[p] - gc[p]), z[p], r2, sh)


@nb.njit(cache=True, error_model="python", fastmath=FASTMATH)
def _rolling_shutter_photometric(
    src: NDArray,
    dst: NDArray[np.uint8],
    sx: float,
    sy: float,
    gain: NDArray[np.float64],
    vrow: NDArray[np.float32],
    vcol: NDArray[np.float32],
    pool: NDArray[np.float32],
    offset: int,
    read2: float,
    shot: float,
) -> None:
    """Rolling-shutter skew of ``src`` (H x 3W, not ``dst``) and the photometric step of
    :func:`_photometric`, in one loop per row, into ``dst``.

    Row ``j`` (time factor ``t = j + 0.5 - H/2`` rows) shows the image shifted ``sx t`` px right
    and ``sy t`` px up: it samples ``(u - sx t, j + sy t)``, bilinear, borders replicated.
    """
    H, n = src.shape
    W = n // 3
    gv, gc = _gains(gain, vcol)
    r2, sh = np.float32(read2), np.float32(shot)
    one = np.float32(1.0)
    for j in range(H):
        t = j + 0.5 - 0.5 * H
        x = min(max(-sx * t, -2.0 * W), 2.0 * W)  # source column offset (px); beyond +-W all is edge
        m = math.floor(x)
        a = np.float32(x - m)
        y = min(max(j + sy * t, -2.0 * H), 3.0 * H)  # source row (px)
        y0 = math.floor(y)
        b = np.float32(y - y0)
        A, B = src[min(max(y0, 0), H - 1)], src[min(max(y0 + 1, 0), H - 1)]
        d, vr = dst[j], vrow[j]
        z = pool[offset + j * n : offset + (j + 1) * n]
        w00, w01, w10, w11 = (one - a) * (one - b), a * (one - b), (one - a) * b, a * b
        i0, i1 = max(0, -m), min(W, W - 1 - m)  # columns whose two sources are inside the row
        if i1 > i0:
            lo = 3 * i0
            di, a0, a1 = d[lo : 3 * i1], A[3 * (i0 + m) :], A[3 * (i0 + m + 1) :]
            b0, b1, gvi, gci, zi = B[3 * (i0 + m) :], B[3 * (i0 + m + 1) :], gv[lo:], gc[lo:], z[lo:]
            for q in range(3 * (i1 - i0)):
                v = w00 * a0[q] + w01 * a1[q] + w10 * b0[q] + w11 * b1[q]
                di[q] = _dn(v * (vr * gvi[q] - gci[q]), zi[q], r2, sh)
        for k in range(W - max(i1 - i0, 0)):  # columns with a source outside the row
            i = k if k < i0 else k + max(i1 - i0, 0)
            q0, q1 = 3 * min(max(i + m, 0), W - 1), 3 * min(max(i + m + 1, 0), W - 1)
            for c in range(3):
                v = w00 * A[q0 + c] + w01 * A[q1 + c] + w10 * B[q0 + c] + w11 * B[q1 + c]
                p = 3 * i + c
                d[p] = _dn(v * (vr * gv[p] - gc[p]), z[p], r2, sh)


@nb.njit(cache=True, error_model="python", fastmath=FASTMATH)
def _copy(src: NDArray[np.uint8], dst: NDArray[np.uint8]) -> None:
    """``dst[:] = src`` for two H x 3W images (a loop: numba's slice assignment is much slower)."""
    a, b = src.reshape(src.size), dst.reshape(dst.size)
    for q in range(a.size):
        b[q] = a[q]


@nb.njit(cache=True, error_model="python", fastmath=FASTMATH)
def _effects(
    img: NDArray[np.uint8],
    lh: float,
    lv: float,
    sx: float,
    sy: float,
    shutter: bool,
    gain: NDArray[np.float64],
    vrow: NDArray[np.float32],
    vcol: NDArray[np.float32],
    pool: NDArray[np.float32],
    offset: int,
    read2: float,
    shot: float,
    buf0: NDArray[np.float32],
    buf1: NDArray[np.float32],
    copy: NDArray[np.uint8],
) -> None:
    """All effects on ``img`` (H x 3W uint8) in place, in one call: horizontal and vertical blur of
    ``lh``, ``lv`` px (0: none), the rolling-shutter skew (``sx``, ``sy``) if ``shutter``, then gains,
    vignetting and noise (``pool[offset:]``). ``buf0``, ``buf1`` (H x 3W float32) hold intermediate
    images, ``copy`` (H x 3W uint8) the input when no blur comes first.

    The last geometric step runs in one loop with the photometric step (no float image in
    between): the skew, a vertical blur after a horizontal one, or a short horizontal one alone.
    """
    if shutter:  # the blurs, then the skew (it reads any row) with the photometric step
        if lh > 0.0 or lv > 0.0:
            if lh > 0.0 and lv > 0.0:
                _blur_rows(img, buf1, lh)
                _blur_cols(buf1, buf0, lv)
            elif lh > 0.0:
                _blur_rows(img, buf0, lh)
            else:
                _blur_cols(img, buf0, lv)
            _rolling_shutter_photometric(buf0, img, sx, sy, gain, vrow, vcol, pool, offset, read2, shot)
        else:
            _copy(img, copy)
            _rolling_shutter_photometric(copy, img, sx, sy, gain, vrow, vcol, pool, offset, read2, shot)
    elif lh > 0.0 and lv > 0.0:
        _blur_rows(img, buf0, lh)
        _blur_cols_photometric(buf0, img, lv, gain, vrow, vcol, pool, offset, read2, shot)
    elif lv > 0.0:
        _blur_cols(img, buf0, lv)
        _photometric(buf0, img, gain, vrow, vcol, pool, offset, read2, shot)
    elif lh > 0.0 and math.ceil(0.5 * lh) <= DIRECT_HALF_WIDTH:
        _blur_rows_photometric(img, lh, gain, vrow, vcol, pool, offset, read2, shot)
    elif lh > 0.0:
        _blur_rows(img, buf0, lh)
        _photometric(buf0, img, gain, vrow, vcol, pool, offset, read2, shot)
    else:
        _copy(img, copy)
        _photometric(copy, img, gain, vrow, vcol, pool, offset, read2, shot)


class ImageEffects:
    """Applies :class:`ImageParams` effects in place to RGB uint8 images (H x W x 3).

    One instance serves any image size (per-size buffers are cached). All randomness comes from
    ``rng``: the same seed and the same calls give bit-identical images.
    """

    def __init__(self, params: ImageParams, rng: np.random.Generator) -> None:
        if not isinstance(params, ImageParams):
            raise TypeError(f"params must be an ImageParams, got {type(params).__name__}")
        if not isinstance(rng, np.random.Generator):
            raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
        self.params = params
        self.rng = rng
        p = params
        self._noise = p.read_noise > 0.0 or p.shot_noise > 0.0
        self._gains = not (
            p.brightness == 1.0
            and p.brightness_jitter == 0.0
            and p.white_balance == (1.0, 1.0, 1.0)
            and p.white_balance_jitter == 0.0
        )
        self._photometric = self._gains or self._noise or p.vignetting > 0.0
        self._active = p.has_effects
        self._jitter = p.brightness_jitter > 0.0 or p.white_balance_jitter > 0.0
        self._gain = np.array(p.white_balance, dtype=np.float64) * p.brightness  # channel gains before jitter
        self._read2 = p.read_noise**2
        self._buffers: dict[tuple[int, int], tuple[NDArray, NDArray, NDArray]] = {}
        self._vignette: dict[tuple[int, int], tuple[NDArray[np.float32], NDArray[np.float32]]] = {}
        self._pool: NDArray[np.float32] | None = None
        self._zero_pool = np.zeros(0, dtype=np.float32)
        self._cursor = 0

    @property
    def active(self) -> bool:
        """True when the parameters have any effect (``params.has_effects``). All but the hall's
        uneven light, which the renderer draws, are applied by ``apply``."""
        return self._active

    def apply(self, image: np.ndarray, fx: float, fy: float, yaw_rate: float, pitch_rate: float, walking: bool) -> None:
        """Degrade ``image`` (H x W x 3 uint8, C-contiguous, RGB, H and W >= 8) in place.

        ``fx``, ``fy``: focal lengths (px/rad, > 0). ``yaw_rate``: rotation rate of the camera
        about the vertical axis (rad/s, head yaw plus body turn; positive = turning left, image
        content moves toward larger ``u``). ``pitch_rate``: head pitch rate (rad/s; positive =
        looking further down, content moves toward smaller ``v``). ``walking``: the legs move
        (adds ``walking_shake`` px of vertical blur).
        """
        if not isinstance(image, np.ndarray) or image.dtype != np.uint8 or image.ndim != 3 or image.shape[2] != 3:
            what = f"{image.dtype} array of shape {image.shape}" if isinstance(image, np.ndarray) else type(image)
            raise ValueError(f"image must be a numpy uint8 array of shape (H, W, 3), got {what}")
        if not image.flags.c_contiguous:
            raise ValueError("image must be C-contiguous")
        H, W = image.shape[0], image.shape[1]
        if H < 8 or W < 8:
            raise ValueError(f"image must be at least 8 x 8 pixels, got H={H}, W={W}")
        if not (math.isfinite(fx) and fx > 0.0 and math.isfinite(fy) and fy > 0.0):
            name, v = ("fx", fx) if not (math.isfinite(fx) and fx > 0.0) else ("fy", fy)
            raise ValueError(f"focal length {name} must be finite and > 0, got {v!r}")
        if not (math.isfinite(yaw_rate) and math.isfinite(pitch_rate)):
            name, v = ("yaw_rate", yaw_rate) if not math.isfinite(yaw_rate) else ("pitch_rate", pitch_rate)
            raise ValueError(f"{name} must be finite, got {v!r}")
        if not self._active:
            return
        p = self.params
        lh = min(abs(yaw_rate) * fx * p.exposure, MAX_BLUR)
        lv = min(abs(pitch_rate) * fy * p.exposure + (p.walking_shake if walking else 0.0), MAX_BLUR)
        lh = lh if lh >= MIN_BLUR else 0.0
        lv = lv if lv >= MIN_BLUR else 0.0
        sx, sy = yaw_rate * fx * p.rolling_shutter, pitch_rate * fy * p.rolling_shutter
        shutter = p.rolling_shutter > 0.0 and max(abs(sx), abs(sy)) * H >= MIN_SHIFT
        if not (self._photometric or lh or lv or shutter):
            return
        # this image's random numbers, in this order: gain jitter, noise pool refresh, noise offset
        gain = self._gain
        if self._jitter:  # the log gains as floats: the same double arithmetic as on arrays, faster
            z0, z1, z2, z3 = self.rng.standard_normal(4).tolist()
            bj, wj = p.brightness_jitter, p.white_balance_jitter
            gain = gain * np.exp(np.array((bj * z0 + wj * z1, bj * z0 + wj * z2, bj * z0 + wj * z3)))
        vrow, vcol = self._vignetting(H, W)
        if self._noise:
            pool = self._noise_pool(3 * H * W)
            offset = int(self.rng.integers(0, pool.size - 3 * H * W + 1))
        else:  # zero noise: y = signal + sigma * 0 is the signal exactly
            pool, offset = self._zeros(3 * H * W), 0
        bufs = self._buffers.get((H, W))
        if bufs is None:
            n = 3 * W
            bufs = self._buffers[H, W] = (
                np.empty((H, n), np.float32),
                np.empty((H, n), np.float32),
                np.empty((H, n), np.uint8),
            )
        _effects(
            image.reshape(H, 3 * W), lh, lv, sx, sy, shutter, gain, vrow, vcol, pool, offset, self._read2,
            p.shot_noise, *bufs,
        )  # fmt: skip

    def _vignetting(self, H: int, W: int) -> tuple[NDArray[np.float32], NDArray[np.float32]]:
        """Separable vignetting map, cached per size: gain ``vrow[j] - vcol[i]`` of pixel (i, j)."""
        terms = self._vignette.get((H, W))
        if terms is None:
            k = self.params.vignetting / (0.25 * (W * W + H * H))  # per px^2 of r^2
            vrow = (1.0 - k * (np.arange(H) + 0.5 - 0.5 * H) ** 2).astype(np.float32)
            vcol = (k * (np.arange(W) + 0.5 - 0.5 * W) ** 2).astype(np.float32)
            terms = self._vignette[H, W] = (vrow, vcol)
        return terms

    def _zeros(self, n: int) -> NDArray[np.float32]:
        """At least ``n`` zeros (float32): the noise pool of noise-free parameters."""
        if self._zero_pool.size < n:
            self._zero_pool = np.zeros(n, dtype=np.float32)
        return self._zero_pool

    def _noise_pool(self, n: int) -> NDArray[np.float32]:
        """The pool of standard normals for an image of ``n`` values, refreshed by ``ceil(n / POOL_REUSE)``."""
        pool = self._pool
        if pool is None or pool.size < 2 * n:
            size = max(POOL_SIZE, 1 << (2 * n - 1).bit_length())
            self._pool = pool = self.rng.standard_normal(size, dtype=np.float32)
            self._cursor = 0
            return pool
        m, a = -(-n // POOL_REUSE), self._cursor
        b = min(a + m, pool.size)
        pool[a:b] = self.rng.standard_normal(b - a, dtype=np.float32)  # faster than out=, the same numbers
        if a + m > pool.size:
            pool[: a + m - pool.size] = self.rng.standard_normal(a + m - pool.size, dtype=np.float32)
        self._cursor = (a + m) % pool.size
        return pool
