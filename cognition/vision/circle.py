"""Centre circle: voting at the circle's radius on the ground (NimbRo 5.2, after de Jong et al.).

NimbRo finds the centre circle before extracting lines, because arcs of the circle would
otherwise become short false lines: every line point votes for the positions at the circle's
radius from it, the largest cluster of votes is the centre, and it is accepted only if the
points that voted for it cover a wide range of directions. DNT (3.9) fits ellipses in the
image instead; on the ground, with the radius known from the field map, voting is simpler
and needs no ellipse fit. Both line methods use this detector: DNT's chains then run on the
points that are not on the circle.

Here every ground point votes on a ring of ``directions`` positions at the radius into a
grid of ``cell`` metres; the best cell (summed with its neighbours) is refined by a
least-squares fit of the centre (radius fixed) to the points within ``inlier`` of the
circle, and accepted when there are at least ``min_points`` of them spanning at least
``min_span`` radians of the circle seen from the centre. Points: robot frame, metres.

A circle found this way is then checked against the image (:func:`verify_circle_nb`, in
the spirit of DNT 3.9's *a contrario* validation: predict, then look): the circle is
projected back into the image, and of its points that should be visible (inside the
image, below the field boundary) at least ``min_coverage`` must land on white. Circles
that voting builds from pieces of straight lines (a corner's two arms, say) predict white
where there is only carpet, and fail.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.vision.projection import pixel_nb


@nb.njit(cache=True, error_model="python", fastmath=False)
def ring_bounds_nb(radius: float, inlier: float) -> tuple[float, float]:  # pragma: no cover - compiled
    """Bounds on the squared distance from the centre (m^2) outside of which a point certainly
    lies farther than ``inlier`` from the circle: a cheap test before the exact one with
    ``math.hypot``, which alone decides for the points within the bounds (the factors leave
    a margin far above the rounding errors of either computation)."""
    near = radius - inlier
    near2 = near * near * (1.0 - 1e-9) if near > 0.0 else -1.0
    far = radius + inlier
    return near2, far * far * (1.0 + 1e-9)


@nb.njit(cache=True, error_model="python", fastmath=False)
def _refine(pts: NDArray[np.float64], cx: float, cy: float, radius: float, inlier: float) -> tuple:  # pragma: no cover
    """Gauss-Newton on the centre with the radius fixed; returns (cx, cy, inlier count)."""
    near2, far2 = ring_bounds_nb(radius, inlier)
    n_in = 0
    for _ in range(6):
        jtj00 = jtj01 = jtj11 = 0.0
        jtr0 = jtr1 = 0.0
        n_in = 0
        for k in range(pts.shape[0]):
            dx, dy = pts[k, 0] - cx, pts[k, 1] - cy
            q = dx * dx + dy * dy
            if q < near2 or q > far2:
                continue
            d = math.hypot(dx, dy)
            if d < 1e-9 or abs(d - radius) > inlier:
                continue
            n_in += 1
            r = d - radius
            jx, jy = -dx / d, -dy / d
            jtj00 += jx * jx
            jtj01 += jx * jy
            jtj11 += jy * jy
            jtr0 += jx * r
            jtr1 += jy * r
        det = jtj00 * jtj11 - jtj01 * jtj01
        if n_in < 3 or abs(det) < 1e-12:
            break
        sx = -(jtj11 * jtr0 - jtj01 * jtr1) / det
        sy = -(-jtj01 * jtr0 + jtj00 * jtr1) / det
        cx += sx
        cy += sy
        if abs(sx) + abs(sy) < 1e-4:
            break
    return cx, cy, n_in


@nb.njit(cache=True, error_model="python", fastmath=False)
def _span(pts: NDArray[np.float64], cx: float, cy: float, radius: float, inlier: float) -> float:  # pragma: no cover
    """Angle (rad) of the circle covered by the inliers: 2 pi minus the largest empty gap."""
    angles = np.empty(pts.shape[0])
    near2, far2 = ring_bounds_nb(radius, inlier)
    n = 0
    for k in range(pts.shape[0]):
        dx, dy = pts[k, 0] - cx, pts[k, 1] - cy
        q = dx * dx + dy * dy
        if q >= near2 and q <= far2 and abs(math.hypot(dx, dy) - radius) <= inlier:
            angles[n] = math.atan2(dy, dx)
            n += 1
    if n < 2:
        return 0.0
    a = angles[:n]
    for k in range(1, n):  # insertion sort in place: for tens of angles a third of np.sort's cost
        x = a[k]
        m = k
        while m > 0 and a[m - 1] > x:
            a[m] = a[m - 1]
            m -= 1
        a[m] = x
    gap = a[0] + 2.0 * math.pi - a[n - 1]
    for k in range(1, n):
        gap = max(gap, a[k] - a[k - 1])
    return 2.0 * math.pi - gap


@nb.njit(cache=True, error_model="python", fastmath=False)
def find_circle_nb(
    pts: NDArray[np.float64],
    radius: float,
    cell: float,
    directions: int,
    inlier: float,
    min_points: int,
    min_span: float,
    vote_every: int = 1,
) -> tuple:  # pragma: no cover - compiled
    """The circle centre (x, y), its inlier count and covered angle, or NaNs (module docstring);
    only every ``vote_every``-th point votes (all of them are fitted)."""
    n = pts.shape[0]
    if n < min_points:
        return math.nan, math.nan, 0, 0.0
    x0, x1 = np.min(pts[:, 0]) - radius - cell, np.max(pts[:, 0]) + radius + cell
    y0, y1 = np.min(pts[:, 1]) - radius - cell, np.max(pts[:, 1]) + radius + cell
    gw = min(int((x1 - x0) / cell) + 1, 400)
    gh = min(int((y1 - y0) / cell) + 1, 400)
    acc = np.zeros((gh, gw), dtype=np.int32)
    voted_x = np.empty(n * directions, dtype=np.int32)  # the cells with votes, in the order of their first
    voted_y = np.empty(n * directions, dtype=np.int32)
    n_voted = 0
    inv = 1.0 / cell
    cs = np.cos(2.0 * math.pi * np.arange(directions) / directions) * (radius * inv)  # in cells
    sn = np.sin(2.0 * math.pi * np.arange(directions) / directions) * (radius * inv)
    for k in range(0, n, vote_every):
        bx0 = (pts[k, 0] - x0) * inv
        by0 = (pts[k, 1] - y0) * inv
        for d in range(directions):
            gx = int(bx0 + cs[d])
            gy = int(by0 + sn[d])
            if 0 <= gx < gw and 0 <= gy < gh:
                voted_x[n_voted] = gx  # (kept only if the cell had no vote yet: no branch to mispredict)
                voted_y[n_voted] = gy
                n_voted += acc[gy, gx] == 0
                acc[gy, gx] += 1
    # the best cell, its votes summed with its 8 neighbours; only cells with votes can win
    best = 0
    bx, by = -1, -1
    for q in range(n_voted):
        gy, gx = voted_y[q], voted_x[q]
        if gy < 1 or gx < 1 or gy >= gh - 1 or gx >= gw - 1:
            continue
        s = 0
        for a in range(-1, 2):
            for b in range(-1, 2):
                s += acc[gy + a, gx + b]
        if s > best or (s == best and gy * gw + gx < by * gw + bx):
            best, bx, by = s, gx, gy
    if bx < 0:
        return math.nan, math.nan, 0, 0.0
    cx, cy, n_in = _refine(pts, x0 + (bx + 0.5) * cell, y0 + (by + 0.5) * cell, radius, 2.0 * inlier)
    cx, cy, n_in = _refine(pts, cx, cy, radius, inlier)
    if n_in < min_points:
        return math.nan, math.nan, n_in, 0.0
    span = _span(pts, cx, cy, radius, inlier)
    if span < min_span:
        return math.nan, math.nan, n_in, span
    return cx, cy, n_in, span


@nb.njit(cache=True, error_model="python", fastmath=False)
def verify_circle_nb(
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    cx: float,
    cy: float,
    radius: float,
    samples: int,
    line_width: float = 0.0,
    blur_u: float = 0.0,
    blur_v: float = 0.0,
) -> tuple:  # pragma: no cover - compiled
    """(visible samples, share of them on white) of the circle projected into the image.

    With ``line_width`` (m) > 0, a sample counts as visible only where the ring's line would
    show in this image: at least 1 px thick across its image direction, and smeared across it
    by the motion blur (``blur_u`` along rows, ``blur_v`` along columns, px) by no more than
    twice its thickness (a line smeared wider fades below the white threshold).
    """
    height, width = classes.shape
    visible = 0
    white = 0
    for k in range(samples):
        a = 2.0 * math.pi * (k + 0.5) / samples
        ca, sa = math.cos(a), math.sin(a)
        u, v, ok = pixel_nb(cam, cx + radius * ca, cy + radius * sa, 0.0)
        if not ok:
            continue
        i, j = int(u), int(v)
        if i < 1 or j < 1 or i >= width - 1 or j >= height - 1 or j < boundary[i]:
            continue
        if line_width > 0.0:
            h = 0.5 * line_width
            u1, v1, ok1 = pixel_nb(cam, cx + (radius - h) * ca, cy + (radius - h) * sa, 0.0)
            u2, v2, ok2 = pixel_nb(cam, cx + (radius + h) * ca, cy + (radius + h) * sa, 0.0)
            ut, vt, ok3 = pixel_nb(cam, cx + radius * ca - 0.05 * sa, cy + radius * sa + 0.05 * ca, 0.0)
            if not (ok1 and ok2 and ok3):
                continue
            tu, tv = ut - u, vt - v
            tn = math.hypot(tu, tv)
            if tn < 1e-9:
                continue
            nu, nv = -tv / tn, tu / tn  # the ring's image normal
            thick = abs((u2 - u1) * nu + (v2 - v1) * nv)
            smear = abs(blur_u * nu) + abs(blur_v * nv)
            if thick < 1.0 or smear > 2.0 * thick:
                continue
        visible += 1
        hit = False
        for dj in range(-1, 2):
            for di in range(-1, 2):
                if classes[j + dj, i + di] == 2:
                    hit = True
        white += hit
    return visible, white / visible if visible > 0 else 0.0
