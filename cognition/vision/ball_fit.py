"""The ball's outline: its expected image radius, chords, edge points and the circle fit.

Compiled geometry of step 2 (refinement) of :func:`~cognition.vision.ball.detect_ball`, the
ball detector after NimbRo section 6.1 (its module docstring describes the method and holds
the parameter table):

- the image radius ``R(u, v)`` a ball centred at a pixel must have: the pinhole radius on the
  optical axis times the stretch of a sphere's outline off the axis (:func:`_radius`,
  :func:`_expected`, :func:`_stretch`);
- the ends of runs of ball pixels, placed to a sub-pixel by the edge pixel's coverage from the
  red channel (:func:`_run_end`, :func:`_chord`, :func:`_coverage`), and the diagonal chord
  that tells a slanted line from a ball (:func:`_thin`);
- the outline's edge points on 16 rays from a centre (:func:`_silhouette`) and the robust
  circle fit to them, the radius fixed to R or, with more than half the circle, free
  (:func:`_fit`, :func:`_fit_circle`, :func:`_inliers`).

Also the colour class codes the compiled ball code compares with, and which classes are ball
pixels in each scheme (:func:`_is_ball`). Pixels ``u`` right, ``v`` down, radii in pixels;
ground points in metres in the robot frame (+x forward, +y left).
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.vision.projection import ground_nb

OTHER, GREEN, WHITE, BLACK, ORANGE, YELLOW = 0, 1, 2, 3, 4, 5
_STRING = 3
"""Widest gap (px) inside the classic ball that does not end it: a string of a goal's net in front
of it, pixels that noise turned YELLOW or grey (anything but GREEN between ORANGE)."""
_N_RAYS = 16
_RAYS = np.array([(math.cos(a), math.sin(a)) for a in 2.0 * math.pi * np.arange(_N_RAYS) / _N_RAYS])


@nb.njit(cache=True, error_model="numpy", inline="always")
def _is_ball(c: int, modern: bool) -> bool:  # pragma: no cover - compiled
    return c != GREEN if modern else c == ORANGE


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _string(classes: NDArray[np.uint8], i: int, j: int, di: int, dj: int) -> int:  # pragma: no cover - compiled
    """Classic: pixels to step from the non-ball pixel (i, j) in direction (di, dj) to the ORANGE
    pixel after it when (i, j) lies on a thin gap inside the ball (a string of a goal's net in
    front of it, or pixels that noise turned YELLOW or grey: anything but GREEN, ORANGE again
    within ``_STRING`` px); 0 where the ball ends there."""
    if classes[j, i] == GREEN:
        return 0
    h, w = classes.shape
    for k in range(1, _STRING + 1):
        ci, cj = i + k * di, j + k * dj
        if not (0 <= ci < w and 0 <= cj < h):
            return 0
        c = classes[cj, ci]
        if c == ORANGE:
            return k
        if c == GREEN:
            return 0
    return 0


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _in_string(classes: NDArray[np.uint8], i: int, j: int) -> bool:  # pragma: no cover - compiled
    """Classic: the pixel (i, j), neither ORANGE nor GREEN, lies on a thin gap inside the ball (a
    net's string, noise; ORANGE within ``_STRING`` px on both sides, horizontally or vertically)."""
    for di, dj in ((1, 0), (0, 1)):
        if _string(classes, i, j, di, dj) > 0 and _string(classes, i, j, -di, -dj) > 0:
            return True
    return False


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _stretch(cam: NDArray[np.float64], u: float, v: float) -> float:  # pragma: no cover - compiled
    """How much larger than on the optical axis a small sphere looks at pixel (u, v): its outline
    is an ellipse with semi-axes 1 / cos(t) and 1 / cos(t)^2 times the on-axis radius (t the
    angle off the axis); the mean of the two."""
    a = (cam[14] - u) / cam[12]
    b = (cam[15] - v) / cam[13]
    c2 = 1.0 / (1.0 + a * a + b * b)  # cos(t)^2
    c = math.sqrt(c2)
    return 0.5 * (1.0 / c + 1.0 / c2)


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _radius(cam: NDArray[np.float64], u: float, v: float, r: float) -> float:  # pragma: no cover - compiled
    """The outline radius (px) of a ball of radius ``r`` centred at pixel (u, v) (see
    :func:`_expected`; NaN at or above the horizon), in one short computation: the ray's
    camera-frame direction (1, a, b) has squared length 1 / cos(t)^2."""
    a = (cam[14] - u) / cam[12]
    b = (cam[15] - v) / cam[13]
    dz = cam[6] + cam[7] * a + cam[8] * b
    if dz >= -1e-9 or cam[11] <= r:
        return math.nan
    t = (r - cam[11]) / dz
    n2 = 1.0 + a * a + b * b
    d2 = t * t * n2 - r * r
    if d2 <= 0.0:
        return math.nan
    return 0.5 * (cam[12] + cam[13]) * r / math.sqrt(d2) * 0.5 * (math.sqrt(n2) + n2)


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _expected(cam: NDArray[np.float64], u: float, v: float, r: float) -> tuple[float, float, float]:  # pragma: no cover
    """(image radius px of the outline, ground x, ground y) of a ball of radius ``r`` centred at
    pixel (u, v): the pinhole radius on the optical axis times :func:`_stretch`."""
    x, y, ok = ground_nb(cam, u, v, r)
    if not ok:
        return math.nan, math.nan, math.nan
    dx, dy, dz = x - cam[9], y - cam[10], r - cam[11]
    d2 = dx * dx + dy * dy + dz * dz
    f = 0.5 * (cam[12] + cam[13])
    return f * r / math.sqrt(max(d2 - r * r, 1e-12)) * _stretch(cam, u, v), x, y


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _coverage(
    rgb: NDArray[np.uint8], j0: int, i0: int, j1: int, i1: int, j2: int, i2: int
) -> float:  # pragma: no cover
    """Ball coverage of the carpet pixel (j1, i1) between the ball pixel (j0, i0) and the carpet
    pixel (j2, i2) further out, from the red channel (0.5 when the contrast is too low)."""
    h, w = rgb.shape[0], rgb.shape[1]
    inner = float(rgb[j0, i0, 0])
    outer = float(rgb[j1, i1, 0])
    bg = float(rgb[j2, i2, 0]) if 0 <= j2 < h and 0 <= i2 < w else outer
    bg = min(bg, outer)
    if inner - bg < 40.0:
        return 0.5
    return min(1.0, max(0.0, (outer - bg) / (inner - bg)))


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _run_end(
    rgb: NDArray[np.uint8], classes: NDArray[np.uint8], i: int, j: int, di: int, dj: int, reach: int, modern: bool
) -> tuple[float, bool]:  # pragma: no cover - compiled
    """The end (continuous position along the axis of (di, dj)) of the run of ball pixels from
    pixel (i, j) in direction (di, dj), and whether it is a real edge (a non-ball pixel within
    ``reach``; not the image edge). Classic: the strings of a goal's net across the ball do not
    end it (:func:`_string`)."""
    h, w = classes.shape
    skip = 0
    pos = i if di != 0 else j
    lim = w if di != 0 else h
    sg = di + dj
    for k in range(1, reach + 1):
        p = pos + sg * k
        if p < 0 or p >= lim:
            return (0.0 if sg < 0 else float(lim)), False
        if k < skip:
            continue  # on a net's string in front of the ball
        ci, cj = i + di * k, j + dj * k
        c = classes[cj, ci]
        if not _is_ball(c, modern):
            n = 0 if modern else _string(classes, ci, cj, di, dj)
            if n > 0:
                skip = k + n
                continue
            a = _coverage(rgb, cj - dj, ci - di, cj, ci, cj + dj, ci + di) if c == GREEN else 0.5
            return ((float(p) + a) if sg > 0 else (float(p) + 1.0 - a)), True
    return float(pos + sg * reach) + (1.0 if sg > 0 else 0.0), False


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _chord(
    rgb: NDArray[np.uint8], classes: NDArray[np.uint8], u: float, v: float, horizontal: bool, reach: int, modern: bool
) -> tuple[float, float, bool, bool]:  # pragma: no cover - compiled
    """Ends (px, continuous) of the horizontal or vertical run of ball pixels through (u, v) and
    whether each is a real edge (see :func:`_run_end`). Classic: where (u, v) lies on a net's
    string the run beside it is read."""
    h, w = classes.shape
    i, j = math.floor(u), math.floor(v)
    if not (0 <= i < w and 0 <= j < h):
        return math.nan, math.nan, False, False
    di, dj = (1, 0) if horizontal else (0, 1)
    if not modern and classes[j, i] != ORANGE:  # classic: on a net's string, read beside it
        for d in (1, -1, 2, -2):
            i2, j2 = i + d * dj, j + d * di
            if 0 <= i2 < w and 0 <= j2 < h and classes[j2, i2] == ORANGE:
                i, j = i2, j2
                break
    a, ra = _run_end(rgb, classes, i, j, -di, -dj, reach, modern)
    b, rb = _run_end(rgb, classes, i, j, di, dj, reach, modern)
    return a, b, ra, rb


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _thin(classes: NDArray[np.uint8], u: float, v: float, r: float, modern: bool) -> bool:  # pragma: no cover
    """A diagonal chord through (u, v) with carpet at both ends is shorter than r: a slanted line,
    not a ball (every chord through a point near a disc's centre is longer than its radius).
    Classic: a net's strings across the ball do not end the chord."""
    h, w = classes.shape
    i, j = math.floor(u), math.floor(v)
    if not (0 <= i < w and 0 <= j < h):
        return False
    reach = int(r) + 1
    for dj in (-1, 1):
        n = 1
        ends = 0
        for s in (-1, 1):
            skip = 0
            for k in range(1, reach + 1):
                ci, cj = i + s * k, j + s * dj * k
                if not (0 <= ci < w and 0 <= cj < h):
                    break
                if k >= skip and not _is_ball(classes[cj, ci], modern):
                    m = 0 if modern else _string(classes, ci, cj, s, s * dj)
                    if m == 0:
                        ends += 1
                        break
                    skip = k + m
                n += 1
        if ends == 2 and 1.41421356 * n < r:
            return True
    return False


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _silhouette(
    rgb: NDArray[np.uint8],
    classes: NDArray[np.uint8],
    u: float,
    v: float,
    r: float,
    modern: bool,
    pts: NDArray[np.float64],
    used: NDArray[np.bool_],
) -> int:  # pragma: no cover - compiled
    """Edge points of the ball's outline on 16 rays from (u, v) into ``pts``; ``used`` marks the
    rays that found one (an edge to a non-ball pixel within 1.8 r + 2 px inside the image;
    classic: not a net's string with ORANGE behind it). Returns their number."""
    h, w = classes.shape
    reach = 1.8 * r + 2.0
    coarse = max(1.0, math.floor(r / 5.0))  # big balls: walk in coarse steps, then pixel by pixel
    n = 0
    for k in range(_N_RAYS):
        used[k] = False
        cx, sy = _RAYS[k, 0], _RAYS[k, 1]
        inside = 0.0  # the farthest point along the ray known to be on the ball
        t = coarse
        while t <= reach:
            i = math.floor(u + t * cx)
            j = math.floor(v + t * sy)
            if not (0 <= i < w and 0 <= j < h) or not _is_ball(classes[j, i], modern):
                break
            inside = t
            t += coarse
        t = inside + 1.0
        pi_, pj = math.floor(u + inside * cx), math.floor(v + inside * sy)
        while t <= reach:
            i = math.floor(u + t * cx)
            j = math.floor(v + t * sy)
            if not (0 <= i < w and 0 <= j < h):
                break
            if i == pi_ and j == pj:
                t += 1.0
                continue
            c = classes[j, i]
            if not _is_ball(c, modern) and not modern and c != GREEN:
                # classic: a net's string or noise in the ball (ORANGE again within a few px on the ray)
                for q in range(1, _STRING + 1):
                    i2 = math.floor(u + (t + q) * cx)
                    j2 = math.floor(v + (t + q) * sy)
                    if 0 <= i2 < w and 0 <= j2 < h and classes[j2, i2] == ORANGE:
                        c = ORANGE
                        t += q - 1.0
                        i, j = i2, j2
                        break
            if not _is_ball(c, modern):
                a = 0.5
                if c == GREEN:
                    i2 = math.floor(u + (t + 1.0) * cx)
                    j2 = math.floor(v + (t + 1.0) * sy)
                    a = _coverage(rgb, pj, pi_, j, i, j2, i2)
                # the edge crosses the outer pixel's centre when it covers half of it
                tc = (i + 0.5 - u) * cx + (j + 0.5 - v) * sy
                te = tc - 0.5 + a
                pts[n, 0] = u + te * cx
                pts[n, 1] = v + te * sy
                used[k] = True
                n += 1
                break
            pi_, pj = i, j
            t += 1.0
    return n


@nb.njit(cache=True, error_model="numpy", inline="always")
def _det3(a: float, b: float, c: float, d: float, e: float, f: float, g: float, h: float, i: float) -> float:
    """Determinant of the 3 x 3 matrix with rows (a, b, c), (d, e, f), (g, h, i)."""  # pragma: no cover
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _fit_circle(
    pts: NDArray[np.float64], keep: NDArray[np.bool_], n: int, u0: float, v0: float, r: float, free: bool
) -> tuple[bool, float, float, float]:  # pragma: no cover - compiled
    """Circle through the kept points: (ok, centre u, v, radius). ``free``: algebraic fit of
    centre and radius; else the centre (Gauss-Newton from (u0, v0)) with the radius fixed to r."""
    if free:
        # x^2 + y^2 + D x + E y + F = 0 in coordinates relative to (u0, v0)
        s = np.zeros((3, 3))
        b = np.zeros(3)
        for k in range(n):
            if not keep[k]:
                continue
            x, y = pts[k, 0] - u0, pts[k, 1] - v0
            q = -(x * x + y * y)
            row = (x, y, 1.0)
            for a in range(3):
                b[a] += row[a] * q
                for c in range(3):
                    s[a, c] += row[a] * row[c]
        det = _det3(s[0, 0], s[0, 1], s[0, 2], s[1, 0], s[1, 1], s[1, 2], s[2, 0], s[2, 1], s[2, 2])
        if abs(det) < 1e-9:
            return False, u0, v0, r
        d = _det3(b[0], s[0, 1], s[0, 2], b[1], s[1, 1], s[1, 2], b[2], s[2, 1], s[2, 2]) / det
        e = _det3(s[0, 0], b[0], s[0, 2], s[1, 0], b[1], s[1, 2], s[2, 0], b[2], s[2, 2]) / det
        f = _det3(s[0, 0], s[0, 1], b[0], s[1, 0], s[1, 1], b[1], s[2, 0], s[2, 1], b[2]) / det
        cu, cv = -0.5 * d, -0.5 * e
        rr = cu * cu + cv * cv - f
        if rr <= 0.0:
            return False, u0, v0, r
        return True, u0 + cu, v0 + cv, math.sqrt(rr)
    cu, cv = u0, v0
    for _ in range(4):
        a11 = a12 = a22 = g1 = g2 = 0.0
        for k in range(n):
            if not keep[k]:
                continue
            dx, dy = pts[k, 0] - cu, pts[k, 1] - cv
            d = max(math.hypot(dx, dy), 1e-9)
            jx, jy = -dx / d, -dy / d
            e = d - r
            a11 += jx * jx
            a12 += jx * jy
            a22 += jy * jy
            g1 += jx * e
            g2 += jy * e
        det = a11 * a22 - a12 * a12
        if det < 1e-9:
            return False, u0, v0, r
        du = -(a22 * g1 - a12 * g2) / det
        dv = -(a11 * g2 - a12 * g1) / det
        cu += du
        cv += dv
        if abs(du) + abs(dv) < 0.03:
            break
    return True, cu, cv, r


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _inside(classes: NDArray[np.uint8], u: float, v: float, modern: bool) -> bool:  # pragma: no cover - compiled
    """The pixel at (u, v) may be a ball's centre: a ball pixel (classic: or YELLOW, the blend of
    orange with the carpet, or a net's string), or outside the image."""
    h, w = classes.shape
    i, j = math.floor(u), math.floor(v)
    if not (0 <= i < w and 0 <= j < h):
        return True
    c = classes[j, i]
    return _is_ball(c, modern) or (not modern and (c == YELLOW or _in_string(classes, i, j)))


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _inliers(pts: NDArray[np.float64], n: int, u: float, v: float, lo2: float, hi2: float) -> int:  # pragma: no cover
    """Points whose squared distance from (u, v) lies in [lo2, hi2]."""
    m = 0
    for k in range(n):
        dx, dy = pts[k, 0] - u, pts[k, 1] - v
        d2 = dx * dx + dy * dy
        m += lo2 <= d2 <= hi2
    return m


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _fit(
    rgb: NDArray[np.uint8],
    classes: NDArray[np.uint8],
    u: float,
    v: float,
    r: float,
    modern: bool,
    pts: NDArray[np.float64],
    used: NDArray[np.bool_],
    keep: NDArray[np.bool_],
) -> tuple[bool, float, float, float, float]:  # pragma: no cover - compiled
    """The ball's outline around (u, v) with expected radius r: (ok, centre u, v, fitted radius
    (NaN where it was fixed to r), rms residual px).

    First the centre with the radius fixed to r, robustly: of the seed and the centres of the
    circles of radius r through pairs of neighbouring edge points, the one with most points
    within the larger of 1.5 px and r / 4 of the circle (the outline; a seed far off the centre,
    edge points on a robot's foot or beyond a line do not mislead it; a centre must lie on a
    ball pixel, not on the carpet beyond a short arc), then least squares on
    those points. When they span more than half the circle, centre and radius are fitted to
    them freely.
    """
    n = _silhouette(rgb, classes, u, v, r, modern, pts, used)
    if n < 3:
        return False, u, v, math.nan, math.inf
    cut = max(1.5, 0.25 * r)
    lo2, hi2 = max(r - cut, 0.0) ** 2, (r + cut) ** 2
    # the centre with most outline points within the cut of radius r: the seed, or one of the two
    # centres of the circles of radius r through neighbouring outline points
    cu, cv = u, v
    best = _inliers(pts, n, u, v, lo2, hi2)
    for k in range(n if best < max(4, n - 2) else 0):  # search unless the seed fits well
        for d in (1, 2):
            if d >= n:
                continue
            k2 = (k + d) % n
            mx, my = 0.5 * (pts[k, 0] + pts[k2, 0]), 0.5 * (pts[k, 1] + pts[k2, 1])
            qx, qy = 0.5 * (pts[k2, 0] - pts[k, 0]), 0.5 * (pts[k2, 1] - pts[k, 1])
            q2 = qx * qx + qy * qy
            if q2 < 0.25 or q2 >= r * r:
                continue
            f = math.sqrt((r * r - q2) / q2)
            for sg in (-1.0, 1.0):
                hx, hy = mx - sg * f * qy, my + sg * f * qx
                if not _inside(classes, hx, hy, modern):
                    continue  # the circle on the other side of the arc
                m = _inliers(pts, n, hx, hy, lo2, hi2)
                if m > best:
                    best, cu, cv = m, hx, hy
    if best < 3:
        return False, u, v, math.nan, math.inf
    m = 0
    for _ in range(3):
        for k in range(n):
            dx, dy = pts[k, 0] - cu, pts[k, 1] - cv
            d2 = dx * dx + dy * dy
            keep[k] = lo2 <= d2 <= hi2
        ok, fu, fv, _r = _fit_circle(pts, keep, n, cu, cv, r, False)
        if not ok:
            return False, u, v, math.nan, math.inf
        moved = abs(fu - cu) + abs(fv - cv)
        cu, cv = fu, fv
        if moved < 0.05:
            break
    m = 0
    for k in range(n):
        keep[k] = abs(math.hypot(pts[k, 0] - cu, pts[k, 1] - cv) - r) <= cut
        m += keep[k]
    if m < 3:
        return False, u, v, math.nan, math.inf
    # the angular span of the outline: the largest gap between rays with a kept edge point
    gap = 0
    run = 0
    k = 0
    for q in range(2 * _N_RAYS):
        ray = q % _N_RAYS
        if used[ray]:
            kept = keep[k % n]
            k += 1
        else:
            kept = False
        if kept:
            run = 0
        else:
            run += 1
            gap = max(gap, run)
    if gap > _N_RAYS - 4:  # less than about 70 degrees of outline
        return False, u, v, math.nan, math.inf
    rad = math.nan
    if m >= 6 and gap <= _N_RAYS // 2 - 1:  # more than half the circle: fit the radius too
        ok, fu, fv, fr = _fit_circle(pts, keep, n, cu, cv, r, True)
        if ok:
            cu, cv, rad = fu, fv, fr
    rr = rad if math.isfinite(rad) else r
    ss = 0.0
    for k in range(n):
        if keep[k]:
            e = math.hypot(pts[k, 0] - cu, pts[k, 1] - cv) - rr
            ss += e * e
    return True, cu, cv, rad, math.sqrt(ss / m)
