"""Votes for the centre circle and for lines: steps 3-5 of the Hough line method (NimbRo section 5.2).

The compiled pieces :func:`~cognition.vision.hough.hough_lines` assembles (its module
docstring describes the method and holds the parameter table), all working on the short
segments and line points of :mod:`.hough_points` (NimbRo 5.1):

- the centre circle (after de Jong et al.): every short segment votes at the circle's radius
  on both sides of it, the best cell is refined by a fixed-radius fit and accepted when the
  segments on the ring cover enough of it (:func:`_circle`, :func:`_on_ring`);
- the oriented Hough transform: a short segment votes only for normals near its own
  (:func:`_vote`), peaks are the largest 3 x 3 sums within a strip of angles around a main
  orientation (:func:`_strip`, :func:`_peak`, :func:`_wrapped`);
- a peak's line refined on the free line points that support it (:func:`_support`,
  :func:`_fit`) and the resulting segments cut to the distance the detector trusts (:func:`_clip`).

Ground points in metres in the robot frame (+x forward, +y left), pixels ``u`` right, ``v``
down, angles in radians; the accumulator's rows are normal angles ``theta`` in [0, pi), its
columns signed distances ``rho`` from the robot.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.vision.hough_points import (
    _EU,
    _EV,
    _J00,
    _J01,
    _J10,
    _J11,
    _MPP,
    _RESP,
    _SN,
    _SPHI,
    _SX,
    _SY,
    _X,
    _Y,
    _angle_diff,
)
from cognition.vision.projection import pixel_nb

# -- 3. centre circle ------------------------------------------------------------------------


@nb.njit(cache=True, error_model="python", fastmath=False)
def _on_ring(
    x: float, y: float, phi: float, cx: float, cy: float, radius: float, inlier: float, tangent: float
) -> bool:  # pragma: no cover - compiled
    """A point or short segment at (x, y) with direction ``phi`` lies on the circle (tangent to it)."""
    dx, dy = x - cx, y - cy
    d = math.hypot(dx, dy)
    if d < 1e-9 or abs(d - radius) > inlier:
        return False
    return _angle_diff(phi, math.atan2(dy, dx) + 0.5 * math.pi) <= tangent


@nb.njit(cache=True, error_model="python", fastmath=False)
def _circle(
    segs: NDArray[np.float64],
    radius: float,
    cell: float,
    inlier: float,
    tangent: float,
    min_points: int,
    min_span: float,
) -> tuple[float, float]:  # pragma: no cover - compiled
    """Centre of the circle the short segments vote for (oriented votes), or NaNs."""
    n = segs.shape[0]
    total = 0.0
    for k in range(n):
        total += segs[k, _SN]
    if total < min_points:
        return math.nan, math.nan
    votes = np.empty((2 * n, 3))
    for k in range(n):
        nx, ny = -math.sin(segs[k, _SPHI]), math.cos(segs[k, _SPHI])
        for s in range(2):
            sign = 1.0 if s == 0 else -1.0
            votes[2 * k + s, 0] = segs[k, _SX] + sign * radius * nx
            votes[2 * k + s, 1] = segs[k, _SY] + sign * radius * ny
            votes[2 * k + s, 2] = segs[k, _SN]
    x0, y0 = np.min(votes[:, 0]) - cell, np.min(votes[:, 1]) - cell
    gw = min(int((np.max(votes[:, 0]) + cell - x0) / cell) + 1, 300)
    gh = min(int((np.max(votes[:, 1]) + cell - y0) / cell) + 1, 300)
    acc = np.zeros((gh, gw))
    for k in range(2 * n):
        gx, gy = int((votes[k, 0] - x0) / cell), int((votes[k, 1] - y0) / cell)
        if 0 <= gx < gw and 0 <= gy < gh:
            acc[gy, gx] += votes[k, 2]
    best = 0.0
    bx, by = -1, -1
    for gy in range(1, gh - 1):
        for gx in range(1, gw - 1):
            if acc[gy, gx] == 0.0:
                continue
            s = 0.0
            for a in range(-1, 2):
                for b in range(-1, 2):
                    s += acc[gy + a, gx + b]
            if s > best:
                best, bx, by = s, gx, gy
    if bx < 0 or best < min_points:
        return math.nan, math.nan
    cx, cy = x0 + (bx + 0.5) * cell, y0 + (by + 0.5) * cell
    # fixed-radius fit: the centre is the mean of the voters' points moved by the radius toward it
    ring = 2.0 * inlier
    angles = np.empty(n)
    na = 0
    for _ in range(6):
        sx = 0.0
        sy = 0.0
        w = 0.0
        na = 0
        for k in range(n):
            x, y = segs[k, _SX], segs[k, _SY]
            if not _on_ring(x, y, segs[k, _SPHI], cx, cy, radius, ring, tangent):
                continue
            d = math.hypot(cx - x, cy - y)
            sx += segs[k, _SN] * (x + radius * (cx - x) / d)
            sy += segs[k, _SN] * (y + radius * (cy - y) / d)
            w += segs[k, _SN]
            angles[na] = math.atan2(y - cy, x - cx)
            na += 1
        if w < min_points:
            return math.nan, math.nan
        cx, cy = sx / w, sy / w
        ring = inlier
    if na < 3:
        return math.nan, math.nan
    a = np.sort(angles[:na])
    gap = a[0] + 2.0 * math.pi - a[na - 1]
    for k in range(1, na):
        gap = max(gap, a[k] - a[k - 1])
    if 2.0 * math.pi - gap < min_span:
        return math.nan, math.nan
    return cx, cy


# -- 4. Hough transform ----------------------------------------------------------------------


@nb.njit(cache=True, error_model="python", fastmath=False)
def _vote(
    acc: NDArray[np.float64],
    x: float,
    y: float,
    phi: float,
    weight: float,
    theta_bin: float,
    rho_bin: float,
    spread: int,
) -> None:  # pragma: no cover - compiled
    """Add ``weight`` to the bins (theta +- spread bins, rho) of the normal of direction ``phi``."""
    n_theta, n_rho = acc.shape
    half = (n_rho - 1) // 2
    centre = round(((phi + 0.5 * math.pi) % math.pi) / theta_bin)
    for i in range(centre - spread, centre + spread + 1):
        theta = i * theta_bin
        rho = x * math.cos(theta) + y * math.sin(theta)
        row = i % n_theta
        if i < 0 or i >= n_theta:
            rho = -rho  # theta + pi is the same line with rho negated
        f = rho / rho_bin + half
        j = math.floor(f)
        frac = f - j
        if 0 <= j < n_rho:
            acc[row, j] += weight * (1.0 - frac)
        if 0 <= j + 1 < n_rho:
            acc[row, j + 1] += weight * frac


@nb.njit(cache=True, error_model="python", fastmath=False)
def _support(
    pts: NDArray[np.float64],
    free: NDArray[np.bool_],
    nx: float,
    ny: float,
    rho: float,
    distance: float,
    pixels: float,
    max_angle: float,
    out: NDArray[np.int64],
) -> int:  # pragma: no cover - compiled
    """Free points near the line ``x nx + y ny = rho`` with a direction along it; their count."""
    sin_max = math.sin(max_angle)
    gx, gy = -ny, nx  # the line's direction on the ground
    m = 0
    for p in range(pts.shape[0]):
        if not free[p]:
            continue
        tol = max(distance, pixels * pts[p, _MPP])
        if abs(pts[p, _X] * nx + pts[p, _Y] * ny - rho) > tol:
            continue
        # the angle is compared in the image, where the points' directions were measured: the
        # line's image direction at the point is the inverse Jacobian times its ground direction
        a, b, c, d = pts[p, _J00], pts[p, _J01], pts[p, _J10], pts[p, _J11]
        du, dv = d * gx - b * gy, -c * gx + a * gy  # (times the determinant, which cancels)
        norm = math.hypot(du, dv)
        if norm < 1e-12 or abs(pts[p, _EU] * dv - pts[p, _EV] * du) > sin_max * norm:
            continue
        out[m] = p
        m += 1
    return m


@nb.njit(cache=True, error_model="python", fastmath=False)
def _fit(
    pts: NDArray[np.float64], idx: NDArray[np.int64], m: int, pixels: float, distance: float
) -> tuple:  # pragma: no cover
    """Weighted total least-squares line (nx, ny, rho) of the points ``idx[:m]`` (weights 1 / tolerance^2)."""
    sw = 0.0
    mx = 0.0
    my = 0.0
    for k in range(m):
        p = idx[k]
        tol = max(distance, pixels * pts[p, _MPP])
        w = pts[p, _RESP] / (tol * tol)
        sw += w
        mx += w * pts[p, _X]
        my += w * pts[p, _Y]
    mx /= sw
    my /= sw
    sxx = 0.0
    sxy = 0.0
    syy = 0.0
    for k in range(m):
        p = idx[k]
        tol = max(distance, pixels * pts[p, _MPP])
        w = pts[p, _RESP] / (tol * tol)
        dx, dy = pts[p, _X] - mx, pts[p, _Y] - my
        sxx += w * dx * dx
        sxy += w * dx * dy
        syy += w * dy * dy
    t = 0.5 * math.atan2(2.0 * sxy, sxx - syy)  # the line's direction
    nx, ny = -math.sin(t), math.cos(t)
    return nx, ny, mx * nx + my * ny


@nb.njit(cache=True, error_model="python", fastmath=False)
def _clip(
    px: NDArray[np.float64],
    ground: NDArray[np.float64],
    open_ends: NDArray[np.bool_],
    cam: NDArray[np.float64],
    max_distance: float,
    min_length: float,
) -> tuple:  # pragma: no cover - compiled
    """The segments cut to the disc of ``max_distance`` around the robot (a cut end is open),
    those still at least ``min_length`` long."""
    n = px.shape[0]
    keep = np.zeros(n, dtype=np.bool_)
    for k in range(n):
        x1, y1, x2, y2 = ground[k, 0], ground[k, 1], ground[k, 2], ground[k, 3]
        dx, dy = x2 - x1, y2 - y1
        a = dx * dx + dy * dy
        if a < 1e-12:
            continue
        # |p1 + t d| = max_distance: a t^2 + 2 b t + c = 0
        b = x1 * dx + y1 * dy
        c = x1 * x1 + y1 * y1 - max_distance * max_distance
        disc = b * b - a * c
        if disc <= 0.0:
            continue
        root = math.sqrt(disc)
        t0, t1 = max(0.0, (-b - root) / a), min(1.0, (-b + root) / a)
        if t1 <= t0 or (t1 - t0) * math.sqrt(a) < min_length:
            continue
        keep[k] = True
        for e in range(2):
            t = t0 if e == 0 else t1
            if (e == 0 and t > 0.0) or (e == 1 and t < 1.0):
                x, y = x1 + t * dx, y1 + t * dy
                u, v, _ = pixel_nb(cam, x, y, 0.0)
                ground[k, 2 * e], ground[k, 2 * e + 1] = x, y
                px[k, 2 * e], px[k, 2 * e + 1] = u, v
                open_ends[k, e] = True
    return px[keep], ground[keep], open_ends[keep]


@nb.njit(cache=True, error_model="python", fastmath=False)
def _wrapped(acc: NDArray[np.float64], i: int, j: int) -> tuple[int, int]:  # pragma: no cover - compiled
    """Row and column of bin (i, j) for any angle index ``i`` (theta + pi: the same line, rho negated)."""
    n_theta, n_rho = acc.shape
    if i < 0 or i >= n_theta:
        return i % n_theta, n_rho - 1 - j
    return i, j


@nb.njit(cache=True, error_model="python", fastmath=False)
def _strip(acc: NDArray[np.float64], first: int, out: NDArray[np.float64]) -> None:  # pragma: no cover - compiled
    """Copy the accumulator rows ``first, first + 1, ...`` (any angle indices) into ``out``."""
    n_theta = acc.shape[0]
    for r in range(out.shape[0]):
        i = first + r
        if 0 <= i < n_theta:
            out[r, :] = acc[i, :]
        else:
            out[r, :] = acc[i % n_theta, ::-1]


@nb.njit(cache=True, error_model="python", fastmath=False)
def _peak(strip: NDArray[np.float64]) -> tuple[float, int, int]:  # pragma: no cover - compiled
    """The largest 3 x 3 sum of the strip's inner rows: (sum, row, column)."""
    rows, n_rho = strip.shape
    best = 0.0
    bi, bj = -1, -1
    col = np.empty(n_rho)
    for r in range(1, rows - 1):
        for j in range(n_rho):
            col[j] = strip[r - 1, j] + strip[r, j] + strip[r + 1, j]
        for j in range(1, n_rho - 1):
            if strip[r, j] <= 0.0:
                continue
            s = col[j - 1] + col[j] + col[j + 1]
            if s > best:
                best, bi, bj = s, r, j
    return best, bi, bj
