"""The DNT line method in one compiled call: scanline points, centre circle, chained segments.

DNT section 3.6.2: line points are the centres of white runs between green on vertical and
horizontal scanlines (:mod:`.scanlines`); they are projected to the ground (robot frame, m)
and those farther than ``max_distance`` dropped. The centre circle is looked for first
(:mod:`.circle`, voting at the radius as NimbRo 5.2 does, then checked against the image),
and its points are kept out of the lines; the remaining points are chained into straight
segments in the image and merged (:mod:`.segments`, DNT Algorithm 1), which are finally
extended along the white, projected to the ground and given real or open ends
(:mod:`.ends`). The stages are compiled functions; this module strings them together in one
compiled call so that a frame pays Python's call overhead once.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.vision.circle import find_circle_nb, verify_circle_nb
from cognition.vision.ends import segments_on_ground_nb
from cognition.vision.projection import ground_nb
from cognition.vision.scanlines import line_points_nb
from cognition.vision.segments import segments_nb


@nb.njit(cache=True)
def ground_points_nb(
    cam: NDArray[np.float64], uv: NDArray[np.float64], max_distance: float
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:  # pragma: no cover - compiled
    """Robot-frame ground points (K x 2, m) of pixels ``uv`` (K x >=2) and whether each is usable
    (in front of the camera, at most ``max_distance`` away)."""
    n = uv.shape[0]
    out = np.empty((n, 2))
    ok = np.zeros(n, dtype=np.bool_)
    for k in range(n):
        x, y, front = ground_nb(cam, uv[k, 0], uv[k, 1], 0.0)
        out[k, 0] = x
        out[k, 1] = y
        ok[k] = front and math.hypot(x, y) <= max_distance
    return out, ok


@nb.njit(cache=True)
def centre_circle_nb(
    ground: NDArray[np.float64],
    valid: NDArray[np.bool_],
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    radius: float,
    cell: float,
    directions: int,
    inlier: float,
    min_points: int,
    min_span: float,
    min_coverage: float,
    line_width: float,
    blur_u: float,
    blur_v: float,
) -> tuple[float, float, NDArray[np.bool_]]:  # pragma: no cover - compiled
    """The centre circle's centre (robot frame, m; NaN if none) and which points lie on it."""
    n = ground.shape[0]
    on = np.zeros(n, dtype=np.bool_)
    if radius <= 0.0:
        return math.nan, math.nan, on
    pts = ground[valid]
    cx, cy, _, _ = find_circle_nb(pts, radius, cell, directions, inlier, min_points, min_span)
    if not math.isfinite(cx):
        return math.nan, math.nan, on
    seen, share = verify_circle_nb(classes, boundary, cam, cx, cy, radius, 64, line_width, blur_u, blur_v)
    if seen < 12 or share < min_coverage:  # a fifth of the circle visibly in view, mostly on white
        return math.nan, math.nan, on
    for k in range(n):
        if valid[k] and abs(math.hypot(ground[k, 0] - cx, ground[k, 1] - cy) - radius) <= 1.5 * inlier:
            on[k] = True
    return cx, cy, on


@nb.njit(cache=True)
def dnt_lines_nb(
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    step: int,
    line_width: float,
    edge_gap: int,
    max_distance: float,
    radius: float,
    circle: NDArray[np.float64],
    chain: NDArray[np.float64],
    min_line_length: float,
    probe: int,
    blur_u: float,
    blur_v: float,
) -> tuple:  # pragma: no cover - compiled
    """Lines of one class image by the DNT method (module docstring).

    ``circle`` holds the centre-circle parameters (cell, directions, inlier, min points, min
    span, min coverage), ``chain`` the chaining parameters in pixels of this image (gap,
    tolerance, min white, min points, merge angle), ``blur_u``, ``blur_v`` the motion blur
    (px) along image rows and columns. Returns ``(points, seg_px, seg_ground,
    open_ends, cx, cy, loose)``: line points K x 4 (u, v, run, direction), segments in the
    image and on the ground (S x 4), open ends (S x 2), the circle's centre (NaN if none) and
    which points lie neither on the circle nor in a segment (penalty-mark seeds).
    """
    points = line_points_nb(classes, boundary, cam, step, line_width, edge_gap, blur_u, blur_v)
    ground, valid = ground_points_nb(cam, points, max_distance)
    cx, cy, on_circle = centre_circle_nb(
        ground, valid, classes, boundary, cam, radius, circle[0], int(circle[1]), circle[2], int(circle[3]),
        circle[4], circle[5], line_width, blur_u, blur_v,
    )  # fmt: skip
    free = valid & ~on_circle
    idx = np.flatnonzero(free)
    seg, labels = segments_nb(points[idx], classes, chain[0], chain[1], chain[2], int(chain[3]), chain[4])
    seg_px, seg_ground, open_ends = segments_on_ground_nb(
        cam, seg, classes, boundary, min_line_length, max_distance, probe
    )
    loose = free.copy()
    for k in range(idx.shape[0]):
        if labels[k] >= 0:
            loose[idx[k]] = False
    return points, seg_px, seg_ground, open_ends, cx, cy, loose
