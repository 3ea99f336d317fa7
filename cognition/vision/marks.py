"""Penalty marks: small white blobs of the mark's size, surrounded by carpet.

Neither DNT nor NimbRo detect the penalty mark (their fields had none that mattered); this
follows the same colour-and-geometry reasoning as their other detectors. Every line point
that ended up on no kept line segment and not on the centre circle seeds a blob (with the
DNT method also the points of a chained segment dropped as shorter than a line: a mark's own
points chain into one): the white pixels around it within a window twice the size a mark has
at that distance (from the camera matrix). The blob is a mark when its ground size is within
``size_tolerance`` of the field's mark size in both directions, when the ring of pixels just
outside it is mostly green (a mark lies on open carpet; a line, a robot or the ball touches
other colours), when it holds no black (the modern ball's patches) and when it is at least
``min_px`` pixels tall and wide (fragments of far lines are smaller). Pixels: ``u`` right,
``v`` down.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.vision.projection import ground_nb, metres_per_pixel_nb

GREEN, WHITE, BLACK = 1, 2, 3


@nb.njit(cache=True, error_model="python", fastmath=False)
def marks_nb(
    classes: NDArray[np.uint8],
    pts: NDArray[np.float64],
    free: NDArray[np.bool_],
    cam: NDArray[np.float64],
    size: float,
    size_tolerance: float,
    min_green: float,
    min_px: int,
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """Mark candidates (M x 4: u, v centre pixel, width and height in px) from the free points."""
    height, width = classes.shape
    out = np.zeros((pts.shape[0], 4))
    n = 0
    for k in range(pts.shape[0]):
        if not free[k]:
            continue
        u, v = pts[k, 0], pts[k, 1]
        dup = False
        for m in range(n):
            if abs(out[m, 0] - u) <= out[m, 2] and abs(out[m, 1] - v) <= out[m, 3]:
                dup = True
        if dup:
            continue
        mv, mu = metres_per_pixel_nb(cam, u, v)
        if not (np.isfinite(mv) and np.isfinite(mu)) or mv <= 0.0 or mu <= 0.0:
            continue
        hw = int(size / mu) + 2
        hh = int(size / mv) + 2
        i0, i1 = max(0, int(u) - hw), min(width - 1, int(u) + hw)
        j0, j1 = max(0, int(v) - hh), min(height - 1, int(v) + hh)
        # extent of the white pixels in the window, grown from the seed's row and column
        lo_i, hi_i, lo_j, hi_j = int(u), int(u), int(v), int(v)
        black = 0
        for j in range(j0, j1 + 1):
            for i in range(i0, i1 + 1):
                c = classes[j, i]
                if c == WHITE:
                    lo_i = min(lo_i, i)
                    hi_i = max(hi_i, i)
                    lo_j = min(lo_j, j)
                    hi_j = max(hi_j, j)
                elif c == BLACK:
                    black += 1
        if black > 0 or lo_i <= i0 or hi_i >= i1 or lo_j <= j0 or hi_j >= j1:
            continue  # touches the window: part of something larger, or dark patches inside
        if hi_i - lo_i + 1 < min_px or hi_j - lo_j + 1 < min_px:
            continue  # too small to tell from a fragment of a far line
        w_m = (hi_i - lo_i + 1) * mu
        h_m = (hi_j - lo_j + 1) * mv
        lo, hi = size * (1.0 - size_tolerance), size * (1.0 + size_tolerance)
        if not (lo <= w_m <= hi and lo <= h_m <= hi):
            continue
        ring = 0
        green = 0
        for i in range(max(0, lo_i - 2), min(width, hi_i + 3)):
            for j in (lo_j - 2, hi_j + 2):
                if 0 <= j < height:
                    ring += 1
                    green += classes[j, i] == GREEN
        for j in range(max(0, lo_j - 2), min(height, hi_j + 3)):
            for i in (lo_i - 2, hi_i + 2):
                if 0 <= i < width:
                    ring += 1
                    green += classes[j, i] == GREEN
        if ring == 0 or green < min_green * ring:
            continue
        out[n, 0] = 0.5 * (lo_i + hi_i + 1)
        out[n, 1] = 0.5 * (lo_j + hi_j + 1)
        out[n, 2] = hi_i - lo_i + 1
        out[n, 3] = hi_j - lo_j + 1
        n += 1
    return out[:n]


@nb.njit(cache=True, error_model="python", fastmath=False)
def loose_points_nb(
    pts: NDArray[np.float64],
    seg_px: NDArray[np.float64],
    cam: NDArray[np.float64],
    cx: float,
    cy: float,
    radius: float,
    inlier: float,
    tolerance: float,
) -> NDArray[np.bool_]:  # pragma: no cover - compiled
    """Which line points (K x >=2 pixels) lie farther than ``tolerance`` px from every segment
    (S x 4 pixels) and, when a circle was found (centre ``cx, cy`` in the robot frame, m), not
    within ``1.5 inlier`` m of its ring: the penalty-mark seeds of a line method that keeps
    no point labels (``hough``)."""
    n = pts.shape[0]
    out = np.ones(n, dtype=np.bool_)
    for k in range(n):
        u, v = pts[k, 0], pts[k, 1]
        for s in range(seg_px.shape[0]):
            ax, ay = seg_px[s, 0], seg_px[s, 1]
            dx, dy = seg_px[s, 2] - ax, seg_px[s, 3] - ay
            d2 = dx * dx + dy * dy
            t = 0.0 if d2 <= 0.0 else min(1.0, max(0.0, ((u - ax) * dx + (v - ay) * dy) / d2))
            if math.hypot(u - ax - t * dx, v - ay - t * dy) <= tolerance:
                out[k] = False
                break
        if out[k] and math.isfinite(cx):
            x, y, ok = ground_nb(cam, u, v, 0.0)
            if ok and abs(math.hypot(x - cx, y - cy) - radius) <= 1.5 * inlier:
                out[k] = False
    return out
