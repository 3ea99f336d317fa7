"""Line segments on the ground, and whether each end is a real line end (DNT 3.6.2 and 3.7).

Both line methods end here: a segment found in the image (pixels) is extended along its
direction as long as the white continues (scanlines and Hough points stop up to a scan step
short of the true end), projected to the ground with the camera matrix (robot frame, metres), cut at ``max_distance``
(the cut end is open) and dropped when it is too short on the ground. Each end is then classified
for the crossing detector (:mod:`.crossings`, DNT 3.7's confidence made strict): an end is
*real* when carpet follows it, and *open* when the image edge, the field boundary or three
pixels of something other than white or green (a robot, the ball) come first, because then
the line may go on where the camera cannot see it.

Pixels: ``u`` right, ``v`` down; class codes of :class:`~cognition.vision.colour.Colour`.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.vision.projection import ground_nb, pixel_nb

GREEN, WHITE = 1, 2


@nb.njit(cache=True, error_model="python", fastmath=False)
def follow_white_nb(
    classes: NDArray[np.uint8], u: float, v: float, du: float, dv: float, steps: int
) -> tuple[float, float]:  # pragma: no cover - compiled
    """The last point along (du, dv) from (u, v), at most ``steps`` px, that is still white (or
    has a white neighbour across the direction)."""
    height, width = classes.shape
    last_u, last_v = u, v
    for q in range(1, steps + 1):
        cu, cv = u + du * q, v + dv * q
        i, j = int(cu), int(cv)
        if i < 0 or j < 0 or i >= width or j >= height:
            break
        ni, nj = int(cu - dv), int(cv + du)
        mi, mj = int(cu + dv), int(cv - du)
        white = classes[j, i] == WHITE
        if not white and 0 <= ni < width and 0 <= nj < height:
            white = classes[nj, ni] == WHITE
        if not white and 0 <= mi < width and 0 <= mj < height:
            white = classes[mj, mi] == WHITE
        if not white:
            break
        last_u, last_v = cu, cv
    return last_u, last_v


@nb.njit(cache=True, error_model="python", fastmath=False)
def _is_open(
    classes: NDArray[np.uint8], boundary: NDArray[np.int32], eu: float, ev: float, du: float, dv: float, probe: int
) -> bool:  # pragma: no cover - compiled
    """Whether the line end at (eu, ev), looking on along (du, dv), is open (module docstring)."""
    height, width = classes.shape
    other = 0
    for q in range(1, probe + 1):
        i = int(eu + du * q)
        j = int(ev + dv * q)
        if i < 0 or j < 0 or i >= width or j >= height or j < boundary[i] + 2:
            return True
        c = classes[j, i]
        if c == GREEN:
            return False
        other = 0 if c == WHITE else other + 1
        if other >= 3:  # three pixels of something else (blended edges give one or two)
            return True
    return False


@nb.njit(cache=True, error_model="python", fastmath=False)
def _reach(x1: float, y1: float, x2: float, y2: float, r: float) -> float:  # pragma: no cover - compiled
    """The fraction t in [0, 1] of the way from (x1, y1) (within ``r`` of the origin) to (x2, y2)
    (beyond it) where the segment leaves the circle of radius ``r``."""
    dx, dy = x2 - x1, y2 - y1
    a = dx * dx + dy * dy
    b = 2.0 * (x1 * dx + y1 * dy)
    c = x1 * x1 + y1 * y1 - r * r
    disc = max(b * b - 4.0 * a * c, 0.0)
    return min(1.0, max(0.0, (-b + math.sqrt(disc)) / (2.0 * a))) if a > 0.0 else 0.0


@nb.njit(cache=True, error_model="python", fastmath=False)
def segments_on_ground_nb(
    cam: NDArray[np.float64],
    seg: NDArray[np.float64],
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    min_length: float,
    max_distance: float,
    probe: int,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_], NDArray[np.bool_]]:  # pragma: no cover
    """The kept segments: image end points (S x 4, extended along the white), ground end points
    (S x 4, robot frame, m) and open ends (S x 2); ``seg`` is N x >=4 pixels (u1, v1, u2, v2),
    and the last array (N) says which of them were kept (the others are off the ground, beyond
    ``max_distance`` or shorter than ``min_length`` on the ground)."""
    n = seg.shape[0]
    kept = np.zeros(n, dtype=np.bool_)
    px = np.empty((n, 4))
    ground = np.empty((n, 4))
    open_ends = np.zeros((n, 2), dtype=np.bool_)
    m = 0
    for k in range(n):
        u1, v1, u2, v2 = seg[k, 0], seg[k, 1], seg[k, 2], seg[k, 3]
        length = math.hypot(u2 - u1, v2 - v1)
        if length > 1e-9:
            du, dv = (u2 - u1) / length, (v2 - v1) / length
            u1, v1 = follow_white_nb(classes, u1, v1, -du, -dv, 2 * probe)
            u2, v2 = follow_white_nb(classes, u2, v2, du, dv, 2 * probe)
        x1, y1, ok1 = ground_nb(cam, u1, v1, 0.0)
        x2, y2, ok2 = ground_nb(cam, u2, v2, 0.0)
        if not (ok1 and ok2):
            continue
        # a line running beyond max_distance is kept up to there (that end is then open)
        far1, far2 = math.hypot(x1, y1) > max_distance, math.hypot(x2, y2) > max_distance
        if far1 and far2:
            continue
        if far1 or far2:
            if far1:
                x1, y1, x2, y2 = x2, y2, x1, y1
            t = _reach(x1, y1, x2, y2, max_distance)
            x2, y2 = x1 + t * (x2 - x1), y1 + t * (y2 - y1)
            if far1:
                x1, y1, x2, y2 = x2, y2, x1, y1
            u1, v1, _ = pixel_nb(cam, x1, y1, 0.0)
            u2, v2, _ = pixel_nb(cam, x2, y2, 0.0)
        if math.hypot(x2 - x1, y2 - y1) < min_length:
            continue
        px[m, 0], px[m, 1], px[m, 2], px[m, 3] = u1, v1, u2, v2
        ground[m, 0], ground[m, 1], ground[m, 2], ground[m, 3] = x1, y1, x2, y2
        length = math.hypot(u2 - u1, v2 - v1)
        if length < 1e-9:
            open_ends[m, 0] = open_ends[m, 1] = True
        else:
            du, dv = (u2 - u1) / length, (v2 - v1) / length
            open_ends[m, 0] = far1 or _is_open(classes, boundary, u1, v1, -du, -dv, probe)
            open_ends[m, 1] = far2 or _is_open(classes, boundary, u2, v2, du, dv, probe)
        kept[k] = True
        m += 1
    return px[:m], ground[:m], open_ends[:m], kept
