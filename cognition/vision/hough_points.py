"""Oriented line points and short segments: steps 1-2 of the Hough line method (NimbRo section 5.1).

The compiled front end of :func:`~cognition.vision.hough.hough_lines` (its module docstring
describes the method and holds the parameter table). Line points are looked for at the
centres of line-wide white runs below the field boundary, where oriented kernels (white
along, green on both sides; their cross-section follows the width a painted line has at that
pixel) respond; each point keeps the best orientation and its better neighbour, projected to
the ground. Points close in the image with similar image directions are then merged into
short segments (ground centroid, direction, weight, how uncertain the direction is on the
ground), which the Hough transform of :mod:`.hough_votes` (NimbRo 5.2) votes with.

Pixels ``u`` right, ``v`` down; ground points in metres in the robot frame (+x forward, +y
left); angles in radians.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.vision.projection import ground_nb
from cognition.vision.segments import grid_nb

_DEG = math.pi / 180.0
GREEN = 1
WHITE = 2
_N_SAMPLES = 2
"""Kernel samples on each side of the centre along the kernel (5 in all)."""
_WEIGHTS = np.exp(-0.125 * np.arange(-_N_SAMPLES, _N_SAMPLES + 1) ** 2)
"""Gaussian weights of the samples along a kernel (sigma: two thirds of its half-length)."""
_WEIGHT_SUM = float(_WEIGHTS.sum())


@nb.njit(cache=True, inline="always")
def _norm(x: float, y: float) -> float:  # pragma: no cover - compiled
    """sqrt(x^2 + y^2) (math.hypot guards against overflow, which costs time in the hot loops)."""
    return math.sqrt(x * x + y * y)


@nb.njit(cache=True, inline="always")
def _ground_jacobian(cam: NDArray[np.float64], u: float, v: float) -> tuple:  # pragma: no cover - compiled
    """Ground point (x, y) of pixel (u, v), the Jacobian of the projection there (m per px:
    dx/du, dx/dv, dy/du, dy/dv) and whether the ray meets the ground in front of the camera
    (:func:`~cognition.vision.projection.ground_nb` and its derivatives, written out)."""
    b, c = (cam[14] - u) / cam[12], (cam[15] - v) / cam[13]
    rx = cam[0] + cam[1] * b + cam[2] * c
    ry = cam[3] + cam[4] * b + cam[5] * c
    rz = cam[6] + cam[7] * b + cam[8] * c
    if rz >= -1e-9 or cam[11] <= 0.0:
        return math.nan, math.nan, 0.0, 0.0, 0.0, 0.0, False
    h = -cam[11] / rz  # ray length factor to the ground
    # d(ray)/du = -column 1 / fx, d(ray)/dv = -column 2 / fy; d(r / rz) = (dr rz - r drz) / rz^2
    dxu, dyu, dzu = -cam[1] / cam[12], -cam[4] / cam[12], -cam[7] / cam[12]
    dxv, dyv, dzv = -cam[2] / cam[13], -cam[5] / cam[13], -cam[8] / cam[13]
    k = -cam[11] / (rz * rz)
    return (
        cam[9] + h * rx,
        cam[10] + h * ry,
        k * (dxu * rz - rx * dzu),
        k * (dxv * rz - rx * dzv),
        k * (dyu * rz - ry * dzu),
        k * (dyv * rz - ry * dzv),
        True,
    )


# -- 1. oriented line points -----------------------------------------------------------------

# point columns
_U, _V, _X, _Y, _PHI, _RESP, _IMG, _MPP = 0, 1, 2, 3, 4, 5, 6, 7
_EU, _EV = 8, 9  # unit image direction (cos, sin of _IMG)
_J00, _J01, _J10, _J11 = 10, 11, 12, 13  # ground step (m) per pixel: dx/du, dx/dv, dy/du, dy/dv
_N_PT = 14


@nb.njit(cache=True, error_model="python", fastmath=False)
def _detect(
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    u: float,
    v: float,
    x: float,
    y: float,
    jac: tuple[float, float, float, float],
    line_width: float,
    dirs: NDArray[np.float64],
    k_small: float,
    k_large: float,
    switch: float,
    min_response: float,
    run: int,
    min_width: float,
    resp: NDArray[np.float64],
    out: NDArray[np.float64],
) -> bool:  # pragma: no cover - compiled
    """Evaluate the oriented kernels (``dirs``: unit image directions) at pixel (u, v), ground
    point (x, y) with the projection's Jacobian ``jac`` (m per px: dx/du, dx/dv, dy/du, dy/dv);
    fill the point row ``out`` and return True if it is a line point.

    The class lookups are written out in the loops (a compiled call per sample costs more
    than the sample).
    """
    height, width = classes.shape
    j00, j01, j10, j11 = jac
    det = abs(j00 * j11 - j01 * j10)
    if det < 1e-12:
        return False
    n_orient = dirs.shape[0]
    floor = 0.5 * min_response
    for k in range(n_orient):
        resp[k] = 0.0
        du, dv = dirs[k, 0], dirs[k, 1]
        w = line_width * _norm(j00 * du + j01 * dv, j10 * du + j11 * dv) / det  # line width (px) across
        step = (k_small if w < switch else k_large) / _N_SAMPLES
        su, sv = du * step, dv * step
        # shares of the samples inside the image (an image edge says nothing about the line)
        c_sum = 0.0
        c_in = 0.0
        for q in range(-_N_SAMPLES, _N_SAMPLES + 1):
            pu, pv = u + q * su, v + q * sv
            i, j = int(pu), int(pv)
            if pu >= 0.0 and pv >= 0.0 and i < width and j < height:
                c_in += _WEIGHTS[q + _N_SAMPLES]
                if j >= boundary[i] and classes[j, i] == WHITE:
                    c_sum += _WEIGHTS[q + _N_SAMPLES]
        if c_in < 0.5 * _WEIGHT_SUM or c_sum < floor * c_in:
            continue  # too little white along this orientation to matter (response left at 0)
        side = max(w, 0.5 * w + 2.0)
        lu, lv = -side * dv, side * du
        l_sum = 0.0
        r_sum = 0.0
        l_in = 0.0
        r_in = 0.0
        for q in range(-_N_SAMPLES, _N_SAMPLES + 1):
            pu, pv = u + q * su + lu, v + q * sv + lv
            i, j = int(pu), int(pv)
            if pu >= 0.0 and pv >= 0.0 and i < width and j < height:
                l_in += _WEIGHTS[q + _N_SAMPLES]
                if j >= boundary[i] and classes[j, i] == GREEN:
                    l_sum += _WEIGHTS[q + _N_SAMPLES]
            pu, pv = u + q * su - lu, v + q * sv - lv
            i, j = int(pu), int(pv)
            if pu >= 0.0 and pv >= 0.0 and i < width and j < height:
                r_in += _WEIGHTS[q + _N_SAMPLES]
                if j >= boundary[i] and classes[j, i] == GREEN:
                    r_sum += _WEIGHTS[q + _N_SAMPLES]
        if l_in < 0.5 * _WEIGHT_SUM or r_in < 0.5 * _WEIGHT_SUM:
            continue
        resp[k] = min(c_sum / c_in, l_sum / l_in, r_sum / r_in)
    best = 0
    for k in range(1, n_orient):
        if resp[k] > resp[best]:
            best = k
    if resp[best] < min_response:
        return False
    # the white run crossed by the scan is at least as wide as the line across it: thinner
    # white (a goal net's strands, a robot's seams) is not a painted line
    du, dv = dirs[best, 0], dirs[best, 1]
    if run < min_width * line_width * _norm(j00 * du + j01 * dv, j10 * du + j11 * dv) / det - 1.0:
        return False
    lo, hi = (best - 1) % n_orient, (best + 1) % n_orient
    other = lo if resp[lo] >= resp[hi] else hi
    # both orientations on the ground, their weighted mean (doubled angles: directions mod pi;
    # cos 2a and sin 2a of a vector (p, q) are (p^2 - q^2) / r^2 and 2 p q / r^2)
    sx = 0.0
    sy = 0.0
    ix = 0.0
    iy = 0.0
    for t in range(2):
        k = best if t == 0 else other
        du, dv = dirs[k, 0], dirs[k, 1]
        gx, gy = j00 * du + j01 * dv, j10 * du + j11 * dv
        r2 = gx * gx + gy * gy
        sx += resp[k] * (gx * gx - gy * gy) / r2
        sy += resp[k] * 2.0 * gx * gy / r2
        ix += resp[k] * (du * du - dv * dv)
        iy += resp[k] * 2.0 * du * dv
    out[_U] = u
    out[_V] = v
    out[_X] = x
    out[_Y] = y
    out[_PHI] = (0.5 * math.atan2(sy, sx)) % math.pi
    out[_RESP] = resp[best]
    out[_IMG] = (0.5 * math.atan2(iy, ix)) % math.pi
    out[_MPP] = max(_norm(j00, j10), _norm(j01, j11))
    out[_EU] = math.cos(out[_IMG])
    out[_EV] = math.sin(out[_IMG])
    out[_J00], out[_J01], out[_J10], out[_J11] = j00, j01, j10, j11
    return True


@nb.njit(cache=True, error_model="python", fastmath=False)
def _candidate(
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    u: float,
    v: float,
    run: int,
    vertical: bool,
    line_width: float,
    max_distance: float,
    dirs: NDArray[np.float64],
    k_small: float,
    k_large: float,
    switch: float,
    min_response: float,
    min_width: float,
    resp: NDArray[np.float64],
    out: NDArray[np.float64],
) -> bool:  # pragma: no cover - compiled
    """Whether the white run of ``run`` px centred at (u, v) holds a line point (into ``out``).

    Runs much longer than a line is wide along the scan are skipped (a robot, or a line
    along the scan, which the other scan direction crosses).
    """
    x, y, j00, j01, j10, j11, ok = _ground_jacobian(cam, u, v)
    if not ok or x * x + y * y > max_distance * max_distance:
        return False
    jac = (j00, j01, j10, j11)
    mpp = _norm(j01, j11) if vertical else _norm(j00, j10)
    if mpp <= 0.0 or run > 3.0 * line_width / mpp + 4.0:
        return False
    return _detect(
        classes, boundary, u, v, x, y, jac, line_width, dirs, k_small, k_large, switch, min_response, run, min_width,
        resp, out,
    )  # fmt: skip


@nb.njit(cache=True, error_model="python", fastmath=False)
def _line_points(
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    line_width: float,
    step: int,
    n_orient: int,
    k_small: float,
    k_large: float,
    switch: float,
    min_response: float,
    max_distance: float,
    edge: int,
    min_width: float,
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """Oriented line points (K x 8 point columns) at the centres of line-wide white runs with
    carpet within ``edge`` px of both ends."""
    height, width = classes.shape
    cap = (width // step + 1) * (height // 2 + 1) + (height // step + 1) * (width // 2 + 1)
    out = np.empty((cap, _N_PT))
    dirs = np.empty((n_orient, 2))
    for k in range(n_orient):
        dirs[k, 0] = math.cos(math.pi * k / n_orient)
        dirs[k, 1] = math.sin(math.pi * k / n_orient)
    resp = np.empty(n_orient)
    n = 0
    for i in range(step // 2, width, step):  # columns
        j = max(boundary[i], 0)
        while j < height and n < cap:
            if classes[j, i] != WHITE:
                j += 1
                continue
            j0 = j
            while j < height and classes[j, i] == WHITE:
                j += 1
            # carpet close to both ends along the scan (a cheap test before the kernels)
            before = False
            for q in range(max(j0 - edge, boundary[i]), j0):
                before = before or classes[q, i] == GREEN
            after = False
            for q in range(j, min(j + edge, height)):
                after = after or classes[q, i] == GREEN
            if before and after and _candidate(
                classes, boundary, cam, i + 0.5, 0.5 * (j0 + j), j - j0, True, line_width, max_distance, dirs,
                k_small, k_large, switch, min_response, min_width, resp, out[n],
            ):  # fmt: skip
                n += 1
    for j in range(step // 2, height, step):  # rows
        i = 0
        while i < width and n < cap:
            if classes[j, i] != WHITE or j < boundary[i]:
                i += 1
                continue
            i0 = i
            while i < width and classes[j, i] == WHITE and j >= boundary[i]:
                i += 1
            before = False
            for q in range(max(i0 - edge, 0), i0):
                before = before or (classes[j, q] == GREEN and j >= boundary[q])
            after = False
            for q in range(i, min(i + edge, width)):
                after = after or (classes[j, q] == GREEN and j >= boundary[q])
            if before and after and _candidate(
                classes, boundary, cam, 0.5 * (i0 + i), j + 0.5, i - i0, False, line_width, max_distance, dirs,
                k_small, k_large, switch, min_response, min_width, resp, out[n],
            ):  # fmt: skip
                n += 1
    return out[:n]


# -- 2. short segments -----------------------------------------------------------------------

# short segment columns
_SX, _SY, _SPHI, _SW, _SN, _SUNC = 0, 1, 2, 3, 4, 5
_KERNEL_ERROR = 10.0 * _DEG
"""How far off the kernels' interpolated image direction may be (4 orientations)."""


@nb.njit(cache=True, error_model="python", fastmath=False)
def _angle_diff(a: float, b: float) -> float:  # pragma: no cover - compiled
    """Difference of two directions modulo pi, in [0, pi/2]."""
    d = abs(a - b) % math.pi
    return min(d, math.pi - d)


@nb.njit(cache=True, error_model="python", fastmath=False)
def _merge(
    pts: NDArray[np.float64],
    cam: NDArray[np.float64],
    width: int,
    height: int,
    radius: float,
    max_angle: float,
    position_error: float,
    labels: NDArray[np.int64],
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """Merge nearby points of similar orientation into short segments (S x 6 columns above:
    ground centroid, direction, weight, points and how uncertain the direction is on the
    ground, rad)."""
    n = pts.shape[0]
    segs = np.zeros((n, 6))
    if n == 0:
        return segs
    gw = int(width / radius) + 1
    gh = int(height / radius) + 1
    count, order = grid_nb(pts, radius, gw, gh)  # pixels (_U, _V are columns 0, 1)
    members = np.empty(n, dtype=np.int64)
    perp_tol = max(1.5, 0.25 * radius)
    ns = 0
    for s in np.argsort(-pts[:, _RESP]):
        if labels[s] >= 0:
            continue
        su, sv, sa = pts[s, _U], pts[s, _V], pts[s, _IMG]
        du, dv = math.cos(sa), math.sin(sa)
        cx, cy = int(su / radius), int(sv / radius)
        m = 0
        for gy in range(max(0, cy - 1), min(gh, cy + 2)):
            for gx in range(max(0, cx - 1), min(gw, cx + 2)):
                c = gy * gw + gx
                for k in range(count[c], count[c + 1]):
                    p = order[k]
                    if labels[p] >= 0:
                        continue
                    ru, rv = pts[p, _U] - su, pts[p, _V] - sv
                    if ru * ru + rv * rv > radius * radius:
                        continue
                    if abs(-ru * dv + rv * du) > perp_tol:
                        continue
                    da = abs(pts[p, _IMG] - sa)  # directions differ modulo pi
                    if min(da, math.pi - da) > max_angle:
                        continue
                    members[m] = p
                    m += 1
        w = 0.0
        mx = 0.0
        my = 0.0
        mu = 0.0
        mv = 0.0
        for k in range(m):
            p = members[k]
            labels[p] = ns
            r = pts[p, _RESP]
            w += r
            mx += r * pts[p, _X]
            my += r * pts[p, _Y]
            mu += r * pts[p, _U]
            mv += r * pts[p, _V]
        mx /= w
        my /= w
        mu /= w
        mv /= w
        # direction: the principal axis of the points in the image, projected to the ground,
        # when they spread along a line; else the weighted mean of the points' directions
        suu = 0.0
        suv = 0.0
        svv = 0.0
        for k in range(m):
            p = members[k]
            eu, ev = pts[p, _U] - mu, pts[p, _V] - mv
            suu += eu * eu
            suv += eu * ev
            svv += ev * ev
        half = 0.5 * (suu + svv)
        root = math.sqrt(max(0.0, 0.25 * (suu - svv) ** 2 + suv * suv))
        big, small = half + root, half - root
        phi = math.nan
        a = pts[s, _IMG]  # image direction and how far off it may be
        error = _KERNEL_ERROR
        if m >= 3 and big > 4.0 * m and small < 0.05 * big:
            t = 0.5 * math.atan2(2.0 * suv, suu - svv)
            eu, ev = math.cos(t), math.sin(t)
            x1, y1, ok1 = ground_nb(cam, mu - 2.0 * eu, mv - 2.0 * ev, 0.0)
            x2, y2, ok2 = ground_nb(cam, mu + 2.0 * eu, mv + 2.0 * ev, 0.0)
            if ok1 and ok2:
                phi = math.atan2(y2 - y1, x2 - x1) % math.pi
                a = t
                # half a pixel (run centres are half-pixel quantized) over the points' spread L
                error = math.atan(position_error / math.sqrt(12.0 * big / m))
                for k in range(m):  # better than the kernels' estimates: the points take it
                    p = members[k]
                    pts[p, _PHI] = phi
                    pts[p, _IMG] = t % math.pi
                    pts[p, _EU] = eu
                    pts[p, _EV] = ev
        if not math.isfinite(phi):
            sx = 0.0
            sy = 0.0
            for k in range(m):
                p = members[k]
                sx += pts[p, _RESP] * math.cos(2.0 * pts[p, _PHI])
                sy += pts[p, _RESP] * math.sin(2.0 * pts[p, _PHI])
            phi = (0.5 * math.atan2(sy, sx)) % math.pi
        # the image direction's error on the ground: far away and seen at a slant, a degree in
        # the image is many on the ground
        p = s
        unc = 0.0
        for sign in (-1.0, 1.0):
            b = a + sign * error
            gx = pts[p, _J00] * math.cos(b) + pts[p, _J01] * math.sin(b)
            gy = pts[p, _J10] * math.cos(b) + pts[p, _J11] * math.sin(b)
            d = abs(math.atan2(gy, gx) % math.pi - phi)
            unc = max(unc, min(d, math.pi - d))
        segs[ns, _SX] = mx
        segs[ns, _SY] = my
        segs[ns, _SPHI] = phi
        segs[ns, _SW] = w
        segs[ns, _SN] = m
        segs[ns, _SUNC] = unc
        ns += 1
    return segs[:ns]
