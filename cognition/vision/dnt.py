"""The DNT line method in one compiled function: scanline points, centre circle, chained segments.

DNT section 3.6.2: line points are the centres of white runs between green on vertical and
horizontal scanlines (:mod:`.scanlines`); they are projected to the ground (robot frame, m)
and those farther than ``max_distance`` dropped. The centre circle is looked for first
(:mod:`.circle`, voting at the radius as NimbRo 5.2 does, then checked against the image),
and its points are kept out of the lines; the remaining points are chained into straight
segments in the image and merged (:mod:`.segments`, DNT Algorithm 1); chains that bend like
the centre circle, alone or with a neighbouring chain (its arcs when the circle was not
found), are dropped, and the segments are finally extended along the white, projected to the
ground and given real or open ends (:mod:`.ends`). The stages are compiled functions; this
module strings them together in one compiled function (run by :mod:`.frame`).
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.vision.circle import find_circle_nb, ring_bounds_nb, verify_circle_nb
from cognition.vision.ends import segments_on_ground_nb
from cognition.vision.projection import ground_nb
from cognition.vision.scanlines import line_points_nb
from cognition.vision.segments import buckets_nb, segments_nb


@nb.njit(cache=True, error_model="python", fastmath=False)
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


@nb.njit(cache=True, error_model="python", fastmath=False)
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
    vote_every: int = 1,
) -> tuple[float, float, NDArray[np.bool_]]:  # pragma: no cover - compiled
    """The centre circle's centre (robot frame, m; NaN if none) and which points lie on it."""
    n = ground.shape[0]
    on = np.zeros(n, dtype=np.bool_)
    if radius <= 0.0:
        return math.nan, math.nan, on
    pts = ground[valid]
    cx, cy, _, _ = find_circle_nb(pts, radius, cell, directions, inlier, min_points, min_span, vote_every)
    if not math.isfinite(cx):
        return math.nan, math.nan, on
    seen, share = verify_circle_nb(classes, boundary, cam, cx, cy, radius, 64, line_width, blur_u, blur_v)
    if seen < 12 or share < min_coverage:  # a fifth of the circle visibly in view, mostly on white
        return math.nan, math.nan, on
    near2, far2 = ring_bounds_nb(radius, 1.5 * inlier)
    for k in range(n):
        dx, dy = ground[k, 0] - cx, ground[k, 1] - cy
        q = dx * dx + dy * dy
        if valid[k] and near2 <= q <= far2 and abs(math.hypot(dx, dy) - radius) <= 1.5 * inlier:
            on[k] = True
    return cx, cy, on


ARC_PAIR_GAP = 0.25
"""Farthest apart (m, on the ground) the nearest ends of two segments tested together as one arc."""
ARC_PAIR_TURN = math.radians(50.0)
"""Largest angle between two segments tested together as one arc: consecutive chords of the
centre circle turn by (l1 + l2) / (2 r), 25 degrees for two pieces of 0.33 m; field lines meet
at right angles, so no corner or crossing is tested as an arc."""


@nb.njit(cache=True, error_model="python", fastmath=False)
def _bends(
    ground: NDArray[np.float64],
    idx: NDArray[np.int64],
    radius: float,
    t: NDArray[np.float64],
    d: NDArray[np.float64],
    m: NDArray[np.float64],
    r: NDArray[np.float64],
    axis: NDArray[np.float64],
) -> bool:  # pragma: no cover - compiled
    """Whether the points ``ground[idx]`` (robot frame, m; at least 3) bend like an arc of a circle
    of ``radius``: a parabola fits them clearly better than a straight line, with a curvature
    between half and twice 1 / ``radius``. Writes their mean, direction and the extent along it
    into ``axis`` (mx, my, ux, uy, t_min, t_max); ``t``, ``d``, ``m``, ``r`` are scratch space."""
    n = idx.shape[0]
    mx, my = 0.0, 0.0
    for k in idx:
        mx += ground[k, 0]
        my += ground[k, 1]
    mx /= n
    my /= n
    sxx = sxy = syy = 0.0
    for k in idx:
        dx, dy = ground[k, 0] - mx, ground[k, 1] - my
        sxx += dx * dx
        sxy += dx * dy
        syy += dy * dy
    th = 0.5 * math.atan2(2.0 * sxy, sxx - syy)
    ux, uy = math.cos(th), math.sin(th)
    # d = a t^2 + b t + c by least squares (normal equations), and the straight line's rms
    m[:] = 0.0
    r[:] = 0.0
    line2 = 0.0
    t_min, t_max = math.inf, -math.inf
    for q in range(n):
        dx, dy = ground[idx[q], 0] - mx, ground[idx[q], 1] - my
        t[q] = dx * ux + dy * uy
        d[q] = -dx * uy + dy * ux
        t_min, t_max = min(t_min, t[q]), max(t_max, t[q])
        line2 += d[q] * d[q]
        row = (t[q] * t[q], t[q], 1.0)
        for i in range(3):
            r[i] += row[i] * d[q]
            for j in range(3):
                m[i, j] += row[i] * row[j]
    axis[0], axis[1], axis[2], axis[3], axis[4], axis[5] = mx, my, ux, uy, t_min, t_max
    if t_max - t_min < 0.3 or abs(np.linalg.det(m)) < 1e-12:
        return False
    a, b, c = np.linalg.solve(m, r)
    quad2 = 0.0
    for q in range(n):
        e = d[q] - (a * t[q] * t[q] + b * t[q] + c)
        quad2 += e * e
    rms_line, rms_quad = math.sqrt(line2 / n), math.sqrt(quad2 / n)
    kappa = abs(2.0 * a)
    return 0.5 / radius <= kappa <= 2.0 / radius and rms_line > 0.01 and rms_line > 1.5 * rms_quad


@nb.njit(cache=True, error_model="python", fastmath=False)
def arcs_nb(
    ground: NDArray[np.float64], labels: NDArray[np.int64], n_seg: int, radius: float
) -> NDArray[np.bool_]:  # pragma: no cover - compiled
    """Which segments' points (``ground`` K x 2 robot frame, m; ``labels`` the segment of each
    point or -1) bend like an arc of the centre circle (:func:`_bends`), alone or together with a
    neighbour: two segments whose nearest ends are within :data:`ARC_PAIR_GAP` and that turn by
    at most :data:`ARC_PAIR_TURN` are tested as one. Pieces of a circle that was not found are
    locally straight in the image and chain into short false lines; a piece shorter than about
    half the radius bends too little to tell alone (a robot inside the circle sees it as a row
    of such pieces), two consecutive ones bend enough."""
    out = np.zeros(n_seg, dtype=np.bool_)
    if radius <= 0.0:
        return out
    # the points of each segment in increasing index (one counting sort instead of a search per
    # segment; unlabelled points go to an extra bucket), and scratch space for two segments
    key = np.empty(labels.shape[0], dtype=np.int64)
    for k in range(labels.shape[0]):
        key[k] = labels[k] if 0 <= labels[k] < n_seg else n_seg
    sizes, flat = buckets_nb(key, n_seg + 1)
    longest = 0
    for g in range(n_seg):
        longest = max(longest, sizes[g + 1] - sizes[g])
    m = np.zeros((3, 3))
    r = np.zeros(3)
    t_buf = np.empty(2 * longest)
    d_buf = np.empty(2 * longest)
    pair = np.empty(2 * longest, dtype=np.int64)
    axes = np.full((n_seg, 6), np.nan)  # per segment: mean, direction, extent (_bends); NaN: < 3 points
    scratch = np.empty(6)
    for g in range(n_seg):
        idx = flat[sizes[g] : sizes[g + 1]]
        n = idx.shape[0]
        if n < 3:
            continue
        # every segment's axis (for the pairs); alone, only a segment of 6 points or more is an arc
        out[g] = _bends(ground, idx, radius, t_buf, d_buf, m, r, axes[g]) and n >= 6
    cos_turn = math.cos(ARC_PAIR_TURN)
    gap2 = ARC_PAIR_GAP * ARC_PAIR_GAP
    for g in range(n_seg):
        if math.isnan(axes[g, 0]):
            continue
        for h in range(g + 1, n_seg):
            if math.isnan(axes[h, 0]) or (out[g] and out[h]):
                continue
            if abs(axes[g, 2] * axes[h, 2] + axes[g, 3] * axes[h, 3]) < cos_turn:
                continue
            near2 = math.inf
            for eg in (4, 5):
                px = axes[g, 0] + axes[g, eg] * axes[g, 2]
                py = axes[g, 1] + axes[g, eg] * axes[g, 3]
                for eh in (4, 5):
                    qx = axes[h, 0] + axes[h, eh] * axes[h, 2]
                    qy = axes[h, 1] + axes[h, eh] * axes[h, 3]
                    near2 = min(near2, (px - qx) ** 2 + (py - qy) ** 2)
            if near2 > gap2:
                continue
            a, b = flat[sizes[g] : sizes[g + 1]], flat[sizes[h] : sizes[h + 1]]
            n = a.shape[0] + b.shape[0]
            if n < 6:
                continue
            pair[: a.shape[0]] = a
            pair[a.shape[0] : n] = b
            if _bends(ground, pair[:n], radius, t_buf, d_buf, m, r, scratch):
                out[g] = out[h] = True
    return out


@nb.njit(cache=True, error_model="python", fastmath=False)
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
    span, min coverage, vote every), ``chain`` the chaining parameters in pixels of this image (gap,
    tolerance, min white, min points, merge angle), ``blur_u``, ``blur_v`` the motion blur
    (px) along image rows and columns. Returns ``(points, seg_px, seg_ground,
    open_ends, cx, cy, loose)``: line points K x 4 (u, v, run, direction), segments in the
    image and on the ground (S x 4), open ends (S x 2), the circle's centre (NaN if none) and
    which points lie neither on the circle nor in a kept segment (penalty-mark seeds).
    """
    points = line_points_nb(classes, boundary, cam, step, line_width, edge_gap, blur_u, blur_v)
    ground, valid = ground_points_nb(cam, points, max_distance)
    cx, cy, on_circle = centre_circle_nb(
        ground, valid, classes, boundary, cam, radius, circle[0], int(circle[1]), circle[2], int(circle[3]),
        circle[4], circle[5], line_width, blur_u, blur_v, int(circle[6]),
    )  # fmt: skip
    free = valid & ~on_circle
    idx = np.flatnonzero(free)
    seg, labels = segments_nb(points[idx], classes, chain[0], chain[1], chain[2], int(chain[3]), chain[4])
    arc = arcs_nb(ground[idx], labels, seg.shape[0], radius)
    if arc.any():  # arcs of a circle not found are no lines (their points stay loose: no marks there)
        keep = ~arc
        remap = np.cumsum(keep) - 1
        for k in range(labels.shape[0]):
            if labels[k] >= 0:
                labels[k] = remap[labels[k]] if keep[labels[k]] else -2
        seg = seg[keep]
    seg_px, seg_ground, open_ends, kept = segments_on_ground_nb(
        cam, seg, classes, boundary, min_line_length, max_distance, probe
    )
    loose = free.copy()  # the points of no kept segment: those of a dropped one too (a mark chains into one)
    for k in range(idx.shape[0]):
        if labels[k] == -2 or (labels[k] >= 0 and kept[labels[k]]):
            loose[idx[k]] = False
    return points, seg_px, seg_ground, open_ends, cx, cy, loose
