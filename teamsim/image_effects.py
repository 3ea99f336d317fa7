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


@nb.njit(cache=True, fastmath=FASTMATH)
def _tri_cdf(x: float) -> float:
    """Integral of the unit triangle (pixel footprint of linear interpolation) from -inf to ``x`` px."""
    if x <= -1.0:
        return 0.0
    if x <= 0.0:
        return 0.5 * (1.0 + x) ** 2
    if x < 1.0:
        return 1.0 - 0.5 * (1.0 - x) ** 2
    return 1.0


@nb.njit(cache=True, fastmath=FASTMATH)
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
        w = np.empty(K + 1, dtype=np.float32)  # tap weights at offsets 0..K (symmetric)
        for k in range(K + 1):
            w[k] = (_tri_cdf(h - k) - _tri_cdf(-h - k)) * inv
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
            for k_ in range(W - max(m, 0) // 3):  # the border pixels
                i = k_ if k_ < K else k_ + max(m, 0) // 3
                for c in range(3):
                    acc = w[0] * np.float32(s[3 * i + c])
                    for k in range(1, K + 1):
                        lft, rgt = 3 * max(i - k, 0) + c, 3 * min(i + k, W - 1) + c
                        acc += w[k] * (np.float32(s[lft]) + np.float32(s[rgt]))
                    d[3 * i + c] = acc
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


@nb.njit(cache=True, fastmath=FASTMATH)
def _blur_cols(src: NDArray, dst: NDArray[np.float32], length: float) -> None:
    """Vertical motion blur of ``length`` px from ``src`` (H x 3W) into ``dst``: running sums over rows."""
    H, n = src.shape[0], src.shape[1]
    h = 0.5 * length
    kh = math.floor(h)
    inv = np.float32(1.0 / length)
    ar, al = h - kh, 1.0 - (h - kh)
    cr0, cr1 = np.float32(ar - 0.5 * ar * ar), np.float32(0.5 * ar * ar)
    cl0, cl1 = np.float32(al - 0.5 * al * al), np.float32(0.5 * al * al)
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


@nb.njit(cache=True, fastmath=FASTMATH)
def _rolling_shutter(src: NDArray, dst: NDArray[np.float32], sx: float, sy: float) -> None:
    """Rolling-shutter skew from ``src`` (H x 3W) into ``dst``.

    Row ``j`` (time factor ``t = j + 0.5 - H/2`` rows) shows the image shifted ``sx t`` px right
    and ``sy t`` px up: it samples ``(u - sx t, j + sy t)``, bilinear, borders replicated.
    """
    H, W = src.shape[0], src.shape[1] // 3
    for j in range(H):
        t = j + 0.5 - 0.5 * H
        x = min(max(-sx * t, -2.0 * W), 2.0 * W)  # source column offset (px); beyond +-W all is edge
        m = math.floor(x)
        a = np.float32(x - m)
        y = min(max(j + sy * t, -2.0 * H), 3.0 * H)  # source row (px)
        y0 = math.floor(y)
        b = np.float32(y - y0)
        A, B = src[min(max(y0, 0), H - 1)], src[min(max(y0 + 1, 0), H - 1)]
        d = dst[j]
        one = np.float32(1.0)
        w00, w01, w10, w11 = (one - a) * (one - b), a * (one - b), (one - a) * b, a * b
        i0, i1 = max(0, -m), min(W, W - 1 - m)  # columns whose two sources are inside the row
        if i1 > i0:
            n = 3 * (i1 - i0)
            di, a0, a1 = d[3 * i0 : 3 * i1], A[3 * (i0 + m) :], A[3 * (i0 + m + 1) :]
            b0, b1 = B[3 * (i0 + m) :], B[3 * (i0 + m + 1) :]
            for q in range(n):
                di[q] = w00 * a0[q] + w01 * a1[q] + w10 * b0[q] + w11 * b1[q]
        for k in range(W - max(i1 - i0, 0)):  # columns with a source outside the row
            i = k if k < i0 else k + max(i1 - i0, 0)
            q0, q1 = 3 * min(max(i + m, 0), W - 1), 3 * min(max(i + m + 1, 0), W - 1)
            for c in range(3):
                d[3 * i + c] = w00 * A[q0 + c] + w01 * A[q1 + c] + w10 * B[q0 + c] + w11 * B[q1 + c]


@nb.njit(cache=True, fastmath=FASTMATH)
def _photometric(
    src: NDArray,
    dst: NDArray[np.uint8],
    gain: NDArray[np.float32],
    vrow: NDArray[np.float32],
    vcol: NDArray[np.float32],
    pool: NDArray[np.float32],
    offset: int,
    read2: float,
    shot: float,
    noise: bool,
) -> None:
    """Gains, vignetting ``vrow[j] - vcol[i]``, noise ``pool[offset:]``, rounding: ``src`` (H x 3W) into ``dst``."""
    H, W = src.shape[0], src.shape[1] // 3
    n = 3 * W
    gv = np.empty(n, dtype=np.float32)
    gc = np.empty(n, dtype=np.float32)
    for i in range(W):
        for c in range(3):
            gv[3 * i + c] = gain[c]
            gc[3 * i + c] = gain[c] * vcol[i]
    r2, sh, zero, top = np.float32(read2), np.float32(shot), np.float32(0.0), np.float32(255.0)
    sig = np.empty(n, dtype=np.float32)  # the row's signal (DN); src may be dst
    for j in range(H):
        s, d, a = src[j], dst[j], vrow[j]
        for q in range(n):
            sig[q] = np.float32(s[q]) * (a * gv[q] - gc[q])
        if noise:
            z = pool[offset + j * n : offset + (j + 1) * n]
            for q in range(n):
                y = sig[q] + np.sqrt(r2 + sh * max(sig[q], zero)) * z[q]
                d[q] = np.uint8(min(max(np.rint(y), zero), top))
        else:
            for q in range(n):
                d[q] = np.uint8(min(max(np.rint(sig[q]), zero), top))


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
        self._buffers: dict[tuple[int, int], tuple[NDArray[np.float32], NDArray[np.float32]]] = {}
        self._vignette: dict[tuple[int, int], tuple[NDArray[np.float32], NDArray[np.float32]]] = {}
        self._pool: NDArray[np.float32] | None = None
        self._cursor = 0

    @property
    def active(self) -> bool:
        """True when the parameters have any effect (``params.has_effects``). All but the hall's
        uneven light, which the renderer draws, are applied by ``apply``."""
        return self.params.has_effects

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
        for name, v in (("fx", fx), ("fy", fy)):
            if not math.isfinite(v) or v <= 0.0:
                raise ValueError(f"focal length {name} must be finite and > 0, got {v!r}")
        for name, v in (("yaw_rate", yaw_rate), ("pitch_rate", pitch_rate)):
            if not math.isfinite(v):
                raise ValueError(f"{name} must be finite, got {v!r}")
        if not self.params.has_effects:
            return
        p = self.params
        img = image.reshape(H, 3 * W)
        cur: NDArray = img
        bufs = self._buffers.get((H, W))
        if bufs is None:
            bufs = self._buffers[H, W] = (np.empty((H, 3 * W), np.float32), np.empty((H, 3 * W), np.float32))

        def spare() -> NDArray[np.float32]:  # the float buffer not holding the current image
            return bufs[1] if cur is bufs[0] else bufs[0]

        lh = min(abs(yaw_rate) * fx * p.exposure, MAX_BLUR)
        lv = min(abs(pitch_rate) * fy * p.exposure + (p.walking_shake if walking else 0.0), MAX_BLUR)
        if lh >= MIN_BLUR:
            _blur_rows(cur, dst := spare(), lh)
            cur = dst
        if lv >= MIN_BLUR:
            _blur_cols(cur, dst := spare(), lv)
            cur = dst
        if p.rolling_shutter > 0.0:
            sx, sy = yaw_rate * fx * p.rolling_shutter, pitch_rate * fy * p.rolling_shutter
            if max(abs(sx), abs(sy)) * H >= MIN_SHIFT:
                _rolling_shutter(cur, dst := spare(), sx, sy)
                cur = dst
        if not self._photometric and cur is img:
            return
        self._photometric_pass(cur, img, H, W)

    def _photometric_pass(self, src: NDArray, img: NDArray[np.uint8], H: int, W: int) -> None:
        """Draw this image's gains (and noise offset) and run the photometric kernel into ``img``."""
        p, rng = self.params, self.rng
        gain = np.array(p.white_balance, dtype=np.float64) * p.brightness
        if p.brightness_jitter > 0.0 or p.white_balance_jitter > 0.0:
            z = rng.standard_normal(4)
            gain *= np.exp(p.brightness_jitter * z[0] + p.white_balance_jitter * z[1:])
        vrow, vcol = self._vignetting(H, W)
        offset = 0
        pool = self._noise_pool(3 * H * W) if self._noise else vrow
        if self._noise:
            offset = int(rng.integers(0, pool.size - 3 * H * W + 1))
        _photometric(
            src, img, gain.astype(np.float32), vrow, vcol, pool, offset, p.read_noise**2, p.shot_noise, self._noise
        )

    def _vignetting(self, H: int, W: int) -> tuple[NDArray[np.float32], NDArray[np.float32]]:
        """Separable vignetting map, cached per size: gain ``vrow[j] - vcol[i]`` of pixel (i, j)."""
        terms = self._vignette.get((H, W))
        if terms is None:
            k = self.params.vignetting / (0.25 * (W * W + H * H))  # per px^2 of r^2
            vrow = (1.0 - k * (np.arange(H) + 0.5 - 0.5 * H) ** 2).astype(np.float32)
            vcol = (k * (np.arange(W) + 0.5 - 0.5 * W) ** 2).astype(np.float32)
            terms = self._vignette[H, W] = (vrow, vcol)
        return terms

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
        self.rng.standard_normal(dtype=np.float32, out=pool[a:b])
        if a + m > pool.size:
            self.rng.standard_normal(dtype=np.float32, out=pool[: a + m - pool.size])
        self._cursor = (a + m) % pool.size
        return pool
