"""Layout of the percept kernel's packed arrays, and its small compiled helpers.

:mod:`teamsim.percept_kernel` runs the per-frame loop; this module defines the column and
index constants of its inputs (observers, occluders, cameras, field map, parameter vector,
per-observer context) and the geometry helpers it calls: projection of world points
(:func:`look`, :func:`pixel`), the Darmstadt measurement through noisy viewing angles
(:func:`measure`, paper section IV.B) and its covariance (:func:`cognition.percepts.covariance_nb`, eqs. 8 and 12-15),
occlusion by robots (:func:`occlusion`, :func:`shadow_interval`) and clipping (:func:`clip`).
World frame (m, rad) throughout; rows are robot-frame measurements.
"""

from __future__ import annotations

import math
from enum import IntEnum

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.percepts import N_COLS, Col, covariance_nb
from teamsim.percept_params import VECTOR_FIELDS


class OBS(IntEnum):
    """Columns of the observer array (one row per robot, world frame)."""

    X = 0
    Y = 1
    TH = 2
    YAW = 3
    PITCH = 4
    YAWR = 5
    PITCHR = 6
    CAM = 7
    WALK = 8
    ACTIVE = 9
    SIGN = 10
    TEAM = 11


class OC(IntEnum):
    """Columns of the occluder array (same robot index as observers)."""

    X = 0
    Y = 1
    R = 2
    H = 3
    PRESENT = 4


class CAM(IntEnum):
    """Columns of the camera array (row 0 upper, row 1 lower)."""

    TILT = 0
    OFFX = 1
    OFFZ = 2
    FX = 3
    FY = 4
    CX = 5
    CY = 6
    W = 7
    H = 8


class F(IntEnum):
    """Columns of the field-map rows; A, B are a line's end point, a crossing's orientation
    and kind, or a post's goal (0 at -x, 1 at +x)."""

    X = 0
    Y = 1
    A = 2
    B = 3
    PERM = 4
    PARTNER = 5


class G(IntEnum):
    """Landmark groups of the field map, in row order (group g spans fidx[g]:fidx[g + 1])."""

    POST = 0
    CROSS = 1
    LINE = 2
    MARK = 3
    POLE = 4
    CIRCLE = 5


class FC(IntEnum):
    """Entries of the field-constants vector."""

    NECK = 0
    GOAL_H = 1
    POST_R = 2
    POLE_R = 3
    BALL_R = 4
    CIRCLE_X = 5
    CIRCLE_Y = 6
    HX = 7
    HY = 8
    DISTINCT = 9
    NPT = 10


_I = {name: i for i, name in enumerate(VECTOR_FIELDS)}
_DETECTED = ("post", "cross", "line", "circle", "mark", "ball", "robot", "pole")
P = IntEnum(
    "P",
    {
        "SA": _I["sigma_alpha_base"], "SB": _I["sigma_beta_base"], "CT": _I["c_tilt"], "CP": _I["c_pan"],
        "SAM": _I["sigma_alpha_moving"], "SBM": _I["sigma_beta_moving"], "SHARED": _I["shared_noise_fraction"],
        "FIXED": _I["reported_fixed"], "FIXED_SIGMA": _I["fixed_sigma"], "ORIENT": _I["orientation_sigma"],
        "RAD_SIGMA": _I["ball_radius_sigma_px"], "CIRCLE_MIN": _I["circle_min_visible"],
        "MIN_LINE": _I["min_line_length"], "HEAD_DET": _I["head_speed_detection"],
        "WALK_DET": _I["walking_detection"], "BALL_DET": _I["ball_speed_detection"], "MAX_OCC": _I["max_occlusion"],
        "PH_CROSS": _I["phantom_crossing_rate"], "PH_MARK": _I["phantom_mark_rate"],
        "BG_POST": _I["background_post_rate"], "FEET_BALL": _I["feet_ball_rate"], "FALSE_BALL": _I["false_ball_rate"],
        "CONFUSE": _I["crossing_confusion"], "TEAM_UNK": _I["robot_team_unknown"],
        "TEAM_WRONG": _I["robot_team_wrong"],
        **{f"DET_{k.upper()}": _I[f"{k}.rate"] for k in _DETECTED},
    },
)  # fmt: skip
"""Entries of the parameter vector (:meth:`PerceptParams.to_vector`); a detection's
``full_range`` and ``max_range`` follow its ``DET_*`` rate at +1 and +2."""


class CTX(IntEnum):
    """Entries of the per-observer context vector the helpers read."""

    CX = 0  # optical centre, world frame
    CY = 1
    HC = 2  # its height (m)
    X = 3  # robot pose, world frame
    Y = 4
    CT = 5  # cos / sin of the robot heading
    ST = 6
    SA = 7  # true angular sigmas (rad)
    SB = 8
    EA = 9  # the image-wide shared standard-normal errors
    EB = 10
    SH = 11  # sqrt(shared fraction), sqrt(1 - shared fraction)
    IND = 12
    PCX = 13  # optical centre over the ground, robot frame
    PCY = 14
    SAR = 15  # reported sigmas
    SBR = 16
    FX = 17  # intrinsics
    FY = 18
    PPX = 19
    PPY = 20
    W = 21
    H = 22


N_OBS_COLS, N_CAM_COLS, N_FMAP_COLS, N_CONSTS, N_CTX = len(OBS), len(CAM), len(F), len(FC), len(CTX)
MAX_PIECES = 6
"""Most pieces a line is split into by robots in front of it."""
NEAR = 0.01
"""Near plane of the camera (m)."""


@nb.njit(cache=True, inline="always")
def wrap(a: float) -> float:  # pragma: no cover - compiled
    a = (a + math.pi) % (2.0 * math.pi)
    if a <= 0.0:
        a += 2.0 * math.pi
    return a - math.pi


@nb.njit(cache=True, inline="always")
def rate(prm: NDArray[np.float64], base: int, d: float) -> float:  # pragma: no cover - compiled
    full, far = prm[base + 1], prm[base + 2]
    if d <= full:
        return prm[base]
    if d >= far:
        return 0.0
    return prm[base] * (far - d) / (far - full)


@nb.njit(cache=True, error_model="python", fastmath=False)
def emit(out, row, x, y, u, v, sub, ctx, h, truth):  # pragma: no cover - compiled
    """Write a point row measured at robot-frame (x, y), ``h`` below the camera (covariance there)."""
    sa, sb = ctx[CTX.SAR], ctx[CTX.SBR]
    cov = covariance_nb(x, y, ctx[CTX.PCX], ctx[CTX.PCY], h, sa, sb)
    for c in range(N_COLS):
        out[row, c] = np.nan
    out[row, 0] = x
    out[row, 1] = y
    out[row, 2] = u
    out[row, 3] = v
    out[row, 9] = sub
    out[row, Col.VAR_XX] = cov[0]
    out[row, Col.VAR_XY] = cov[1]
    out[row, Col.VAR_YY] = cov[2]
    out[row, 13] = sa
    out[row, 14] = sb
    out[row, 16] = truth
    out[row, 17] = -1.0


@nb.njit(cache=True, error_model="python", fastmath=False)
def set_cov(out, row, x, y, ctx, h):  # pragma: no cover - compiled
    """Overwrite a row's covariance with the one at robot-frame (x, y)."""
    cov = covariance_nb(x, y, ctx[CTX.PCX], ctx[CTX.PCY], h, ctx[CTX.SAR], ctx[CTX.SBR])
    out[row, Col.VAR_XX], out[row, Col.VAR_XY], out[row, Col.VAR_YY] = cov[0], cov[1], cov[2]


@nb.njit(cache=True, error_model="python", fastmath=False)
def look(m, ctx, px, py, pz):  # pragma: no cover - compiled
    """(in image, u, v, ground distance from the optical centre, world bearing) of a world point."""
    dx, dy, dz = px - ctx[CTX.CX], py - ctx[CTX.CY], pz - ctx[CTX.HC]
    fx, fy, cx, cy, W, H = ctx[CTX.FX], ctx[CTX.FY], ctx[CTX.PPX], ctx[CTX.PPY], ctx[CTX.W], ctx[CTX.H]
    q0 = m[0, 0] * dx + m[0, 1] * dy + m[0, 2] * dz
    d = math.hypot(dx, dy)
    b = math.atan2(dy, dx)
    if q0 <= NEAR:
        return False, np.nan, np.nan, d, b
    q1 = m[1, 0] * dx + m[1, 1] * dy + m[1, 2] * dz
    q2 = m[2, 0] * dx + m[2, 1] * dy + m[2, 2] * dz
    u = cx - fx * q1 / q0
    v = cy - fy * q2 / q0
    ok = 0.0 <= u < W and 0.0 <= v < H
    return ok, u, v, d, b


@nb.njit(cache=True, error_model="python", fastmath=False)
def pixel(m, ctx, px, py, pz):  # pragma: no cover - compiled
    """Pixel of a world point (NaN behind the camera)."""
    dx, dy, dz = px - ctx[CTX.CX], py - ctx[CTX.CY], pz - ctx[CTX.HC]
    fx, fy, cx, cy = ctx[CTX.FX], ctx[CTX.FY], ctx[CTX.PPX], ctx[CTX.PPY]
    q0 = m[0, 0] * dx + m[0, 1] * dy + m[0, 2] * dz
    if q0 <= 1e-9:
        return np.nan, np.nan
    q1 = m[1, 0] * dx + m[1, 1] * dy + m[1, 2] * dz
    q2 = m[2, 0] * dx + m[2, 1] * dy + m[2, 2] * dz
    return cx - fx * q1 / q0, cy - fy * q2 / q0


@nb.njit(cache=True, error_model="python", fastmath=False)
def measure(px, py, pz, ctx, normals, cursor):  # pragma: no cover - compiled
    """Robot-frame position of a world point seen through noisy viewing angles (Darmstadt IV.B)."""
    Cx, Cy, X, Y, ct, st = ctx[CTX.CX], ctx[CTX.CY], ctx[CTX.X], ctx[CTX.Y], ctx[CTX.CT], ctx[CTX.ST]
    sa, sb, sh, ind = ctx[CTX.SA], ctx[CTX.SB], ctx[CTX.SH], ctx[CTX.IND]
    ea_s, eb_s = ctx[CTX.EA], ctx[CTX.EB]
    dx, dy = px - Cx, py - Cy
    h = ctx[CTX.HC] - pz
    alpha = math.atan2(h, math.hypot(dx, dy))
    beta = math.atan2(dy, dx)
    a2 = alpha + sa * (sh * ea_s + ind * normals[cursor[0]])
    b2 = beta + sb * (sh * eb_s + ind * normals[cursor[0] + 1])
    cursor[0] += 2
    if a2 <= 1e-4 or h <= 0.0:
        return False, np.nan, np.nan
    a2 = min(a2, 0.5 * math.pi - 1e-6)
    d2 = h / math.tan(a2)
    wx, wy = Cx + d2 * math.cos(b2) - X, Cy + d2 * math.sin(b2) - Y
    return True, ct * wx + st * wy, -st * wx + ct * wy


@nb.njit(cache=True, error_model="python", fastmath=False)
def ball_row(out, row, px, py, u, v, truth, ctx, ball_r, rad_sigma, normals, cursor):  # pragma: no cover
    """Write a ball row (projection plus noisy image radius); returns the next row."""
    ok_m, mx, my = measure(px, py, ball_r, ctx, normals, cursor)
    noise = normals[cursor[0]]
    cursor[0] += 1
    if not ok_m:
        return row
    hc = ctx[CTX.HC]
    dist3 = math.sqrt((px - ctx[CTX.CX]) ** 2 + (py - ctx[CTX.CY]) ** 2 + (ball_r - hc) ** 2)
    f_mean = 0.5 * (ctx[CTX.FX] + ctx[CTX.FY])
    rad = f_mean * ball_r / math.sqrt(max(dist3 * dist3 - ball_r * ball_r, 1e-12))
    rad = max(0.5, rad + rad_sigma * noise)
    emit(out, row, mx, my, u, v, 0.0, ctx, hc - ball_r, truth)
    out[row, 15] = rad
    return row + 1


@nb.njit(cache=True, error_model="python", fastmath=False)
def occlusion(d, b, w, z, hc, occg, skip):  # pragma: no cover - compiled
    """Hidden fraction of an object at distance d, bearing b, angular half-width w, height z.

    ``occg`` rows are the other robots seen from the optical centre (distance, bearing,
    angular half-width, height, flag). With ``w == 0`` the object is a point: 1.0 if hidden.
    """
    frac = 0.0
    for j in range(occg.shape[0]):
        if occg[j, 4] < 0.5 or j == skip or occg[j, 0] >= d:
            continue
        if hc - (hc - z) * occg[j, 0] / d >= occg[j, 3]:
            continue  # the line of sight passes above this robot
        rel = wrap(occg[j, 1] - b)
        ow = occg[j, 2]
        if w <= 0.0:
            if abs(rel) < ow:
                return 1.0
            continue
        lo = max(-w, rel - ow)
        hi = min(w, rel + ow)
        if hi > lo:
            frac += (hi - lo) / (2.0 * w)
    return min(frac, 1.0)


@nb.njit(cache=True, error_model="python", fastmath=False)
def visible(m, ctx, occg, px, py, pz, radius, max_range, max_occ, skip):  # pragma: no cover - compiled
    """(seen, u, v, ground distance, hidden fraction) of an object of ``radius`` at world (px, py, pz).

    Seen means in front, inside the image, within ``max_range`` and hidden at most ``max_occ``
    (a point, ``radius == 0``, must not be hidden at all). ``skip`` is the object's own robot
    index (or -1). :func:`look` written out, with the distance and the bearing (C library calls)
    worked out only for a point inside the image: the ground distance is NaN for a point
    outside it, and every caller ignores everything but ``seen`` for an object not seen.
    """
    dx, dy, dz = px - ctx[CTX.CX], py - ctx[CTX.CY], pz - ctx[CTX.HC]
    q0 = m[0, 0] * dx + m[0, 1] * dy + m[0, 2] * dz
    if q0 <= NEAR:
        return False, np.nan, np.nan, np.nan, 1.0
    q1 = m[1, 0] * dx + m[1, 1] * dy + m[1, 2] * dz
    q2 = m[2, 0] * dx + m[2, 1] * dy + m[2, 2] * dz
    u = ctx[CTX.PPX] - ctx[CTX.FX] * q1 / q0
    v = ctx[CTX.PPY] - ctx[CTX.FY] * q2 / q0
    if not (0.0 <= u < ctx[CTX.W] and 0.0 <= v < ctx[CTX.H]):
        return False, u, v, np.nan, 1.0
    d = math.hypot(dx, dy)
    if d > max_range:
        return False, u, v, d, 1.0
    w = math.asin(min(1.0, radius / d)) if radius > 0.0 else 0.0
    frac = occlusion(d, math.atan2(dy, dx), w, pz, ctx[CTX.HC], occg, skip)
    if frac > max_occ or (radius <= 0.0 and frac > 0.0):
        return False, u, v, d, frac
    return True, u, v, d, frac


@nb.njit(cache=True, error_model="python", fastmath=False)
def clip(g0, g1, lo, hi):  # pragma: no cover - compiled
    """Intersect [lo, hi] with {t : g0 + t g1 >= 0}."""
    if abs(g1) < 1e-15:
        return (lo, hi) if g0 >= 0.0 else (1.0, 0.0)
    t = -g0 / g1
    if g1 > 0.0:
        return max(lo, t), hi
    return lo, min(hi, t)


@nb.njit(cache=True, error_model="python", fastmath=False)
def shadow_interval(ax, ay, bx, by, od, oh, hc, c1, s1, c2, s2, cc, sc):  # pragma: no cover - compiled
    """Parameters [lo, hi] of the ground segment a + t b (relative to the camera) hidden by a robot
    at distance ``od`` and of height ``oh``, seen from a camera at height ``hc``: (c1, s1), (c2,
    s2) and (cc, sc) are the cosines and sines of its bearing minus and plus its angular
    half-width and of its bearing (the same for every line, so the caller computes them once)."""
    lo, hi = 0.0, 1.0
    lo, hi = clip(c1 * ay - s1 * ax, c1 * by - s1 * bx, lo, hi)  # left of the right tangent
    lo, hi = clip(ax * s2 - ay * c2, bx * s2 - by * c2, lo, hi)  # right of the left tangent
    lo, hi = clip(ax * cc + ay * sc - od, bx * cc + by * sc, lo, hi)  # behind the robot
    if oh < hc:
        end = od * hc / (hc - oh)  # a lying robot's shadow ends here
        lo, hi = clip(end - (ax * cc + ay * sc), -(bx * cc + by * sc), lo, hi)
    return lo, hi


@nb.njit(cache=True, error_model="python", fastmath=False)
def point_segment_distance(px, py, x1, y1, x2, y2):  # pragma: no cover - compiled
    dx, dy = x2 - x1, y2 - y1
    dd = dx * dx + dy * dy
    t = 0.0 if dd <= 0.0 else min(1.0, max(0.0, ((px - x1) * dx + (py - y1) * dy) / dd))
    return math.hypot(x1 + t * dx - px, y1 + t * dy - py)


@nb.njit(cache=True, error_model="python", fastmath=False)
def line_direction(dx, dy):  # pragma: no cover - compiled
    """Undirected direction of (dx, dy) in [0, pi)."""
    a = math.atan2(dy, dx) % math.pi
    return 0.0 if a >= math.pi - 1e-12 else a


@nb.njit(cache=True, error_model="python", fastmath=False)
def crossing_orientation(kind, a):  # pragma: no cover - compiled
    """Wrap a crossing orientation: (-pi, pi] for L and T, [0, pi/2) for X."""
    if kind == 2:
        q = a % (0.5 * math.pi)
        return 0.0 if q >= 0.5 * math.pi - 1e-12 else q
    return wrap(a)


@nb.njit(cache=True, error_model="python", fastmath=False)
def exit_distance(x, y, ux, uy, hx, hy):  # pragma: no cover - compiled
    """Distance from (x, y) along (ux, uy) to the border of the box |x| <= hx, |y| <= hy."""
    t = 1e9
    if ux > 1e-12:
        t = min(t, (hx - x) / ux)
    elif ux < -1e-12:
        t = min(t, (-hx - x) / ux)
    if uy > 1e-12:
        t = min(t, (hy - y) / uy)
    elif uy < -1e-12:
        t = min(t, (-hy - y) / uy)
    return max(t, 0.0)


@nb.njit(cache=True, error_model="python", fastmath=False)
def random_ground(rot, pos, X, Y, ct, st, W, H, fx, fy, cx, cy, uniforms, cursor):  # pragma: no cover
    """A random image pixel's ground point (world frame); uses uniforms[cursor+1], [cursor+2]."""
    ur = uniforms[cursor[1] + 1] * W
    vr = uniforms[cursor[1] + 2] * H
    d0, d1, d2 = 1.0, (cx - ur) / fx, (cy - vr) / fy
    rx = rot[0, 0] * d0 + rot[0, 1] * d1 + rot[0, 2] * d2
    ry = rot[1, 0] * d0 + rot[1, 1] * d1 + rot[1, 2] * d2
    rz = rot[2, 0] * d0 + rot[2, 1] * d1 + rot[2, 2] * d2
    if rz >= -1e-9:
        return False, 0.0, 0.0
    t = -pos[2] / rz
    gx, gy = pos[0] + t * rx, pos[1] + t * ry
    return True, X + ct * gx - st * gy, Y + st * gx + ct * gy
