"""Sensor models of the particle filter: observation packing and the compiled likelihood.

Every model compares an observation with the map landmark it is associated with, seen
from the particle's pose, by CMU's ``point_likelihood`` (Alg. 3): Gaussians of the
difference of distances and of the bearing difference, with sigmas that grow linearly with
the distance (CMU III.C tables, :mod:`cognition.localization.params`):

* **goal posts** (CMU III.C.1): a left or right post is compared with that post; an
  unknown one with every candidate and the most likely is kept. Goals of different colours
  restrict the candidates to one goal; the white SPL goals do not.
* **crossings** (III.C.2): the nearest map crossing of the same type (grid lookup) and a
  Gaussian of the orientation difference (L and T: full turn, X: modulo 90 degrees).
* **lines** (III.C.3), ``nearest`` model: the observation is the point of the segment
  nearest to the robot; the map line is the nearest one of the matching orientation class
  (grid lookup), the expected point its point nearest to the particle; times a Gaussian of
  the orientation difference (modulo 180 degrees); then 0.9 is added (false positives).
  Segments shorter than 10 cm are dropped before.
* **lines**, ``hough`` model (NimbRo Sec. 6.2, eq. 7): the observed segment's Hough
  parameters (theta of the normal, rho) are matched to the nearest map line of the same
  orientation class in Hough space; the likelihood compares theta, rho, the mean position
  u-bar along the line (eq. 6) and its spread sigma(u). The expected u-bar is the observed
  one clamped into the map segment's extent and the expected spread is at most the map
  segment's (an observed line can be shorter than the map line, not longer). The paper's
  printed exponents use |difference| / (2 sigma^2); we use the Gaussian form
  (difference / sigma)^2 / 2, as for every other model.
* **centre circle** (III.C.4) and **penalty marks** (nearest of the two) and **corner
  poles** (nearest): point landmarks.

Each observation's likelihood p is floored by NimbRo eq. 9, p' = (1 - c) + c p, with the
confidence c; everything is accumulated as log-likelihoods. With the Darmstadt option
(``adaptive``) the distance and bearing sigmas come from each percept's own covariance
(Darmstadt eqs. 8-15, written into the percepts by the camera model).

Observation rows (:class:`O` columns) are in the robot frame (m, rad).
"""

from __future__ import annotations

import math
from enum import IntEnum

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.localization.params import LocalizationParams
from cognition.percepts import Percepts


class T(IntEnum):
    """Observation types."""

    POST = 0
    CROSS = 1
    LINE = 2
    CIRCLE = 3
    MARK = 4
    POLE = 5


class O(IntEnum):  # noqa: E742 - short column enum used in kernels
    """Columns of an observation row."""

    TYPE = 0
    X = 1
    """Point (m, robot frame): landmark, or the line point nearest to the robot."""
    Y = 2
    A = 3
    """Post side (0 unknown, 1 left, 2 right) / crossing kind / line direction in [0, pi)."""
    B = 4
    """Post goal (-1 unknown, 0 own, 1 opponent) / crossing orientation (rad)."""
    SR = 5
    """Distance sigma (m)."""
    SB = 6
    """Bearing sigma (rad)."""
    SO = 7
    """Orientation sigma (rad)."""
    CONF = 8
    """Confidence c of NimbRo eq. 9."""
    FLOOR = 9
    """Added to the likelihood before the confidence floor (CMU lines: 0.9)."""
    RHO = 10
    """Hough distance of the line (m)."""
    HTH = 11
    """Hough angle of the line's normal (rad, robot frame)."""
    UBAR = 12
    """Mean position along the line (m, NimbRo eq. 6)."""
    USPREAD = 13
    """Spread sigma(u) of the positions along the line (m)."""
    DIST = 14
    """|(X, Y)| (m)."""
    BEAR = 15
    """atan2(Y, X) (rad)."""


N_O = len(O)
_SQRT12 = math.sqrt(12.0)


def sensor_table(p: LocalizationParams) -> NDArray[np.float64]:
    """The parameters :func:`pack_nb` needs, as one array (see there)."""
    return np.array(
        [
            1.0 if p.adaptive else 0.0, p.confidence, p.line_floor, p.line_min_length,
            p.post_sigma_min, p.post_sigma_rate, p.post_sigma_bearing_min, p.post_sigma_bearing_rate,
            p.corner_sigma_min, p.corner_sigma_rate, p.corner_sigma_bearing, p.corner_sigma_orientation,
            p.line_sigma_min, p.line_sigma_rate, p.line_sigma_bearing, p.line_sigma_orientation,
            p.circle_sigma_min, p.circle_sigma_rate, p.circle_sigma_bearing, 0.0,
            p.mark_sigma_min, p.mark_sigma_rate, p.mark_sigma_bearing, 0.0,
        ]
    )  # fmt: skip


def pack_observations(percepts: Percepts | None, table: NDArray[np.float64]) -> NDArray[np.float64]:
    """Observation rows (K x :data:`N_O`) for the filter from one image's percepts.

    ``table`` is :func:`sensor_table` of the parameters. Balls and robots are not used;
    lines shorter than the minimum length are dropped.
    """
    if percepts is None or len(percepts) == 0:
        return np.zeros((0, N_O))
    rows = percepts.rows
    out = np.empty((rows.shape[0], N_O))
    k = pack_nb(rows, percepts.kinds, table, out)
    return out[:k]


@nb.njit(cache=True, error_model="numpy")
def _sig(tab, base, adaptive, row, x, y):  # pragma: no cover - compiled
    """Distance and bearing sigmas at (x, y): the table at ``base`` (min, rate, bearing, bearing
    rate) or, ``adaptive``, from the percept's covariance (Darmstadt eqs. 8-15)."""
    d = math.sqrt(x * x + y * y)
    if adaptive:
        dd = max(d, 1e-3) ** 2
        cxx, cxy, cyy = row[10], row[11], row[12]
        var_r = (x * x * cxx + 2 * x * y * cxy + y * y * cyy) / dd
        var_t = (y * y * cxx - 2 * x * y * cxy + x * x * cyy) / dd
        return math.sqrt(max(var_r, 1e-4)), math.sqrt(max(var_t, 1e-6)) / max(d, 0.05)
    return tab[base] + tab[base + 1] * d, tab[base + 2] + tab[base + 3] * d


@nb.njit(cache=True, error_model="numpy")
def pack_nb(rows, kinds, tab, out):  # pragma: no cover - compiled
    """Fill ``out`` with observation rows from percept rows; returns how many."""
    adaptive = tab[0] > 0.5
    k = 0
    for r in range(rows.shape[0]):
        kind = kinds[r]
        row = rows[r]
        for c in range(out.shape[1]):
            out[k, c] = 0.0
        out[k, 8] = tab[1]
        x, y = row[0], row[1]
        if kind == 0 or kind == 7:  # post / corner pole (pole: same sigmas)
            out[k, 0] = 0.0 if kind == 0 else 5.0
            sr, sb = _sig(tab, 4, adaptive, row, x, y)
            if kind == 0:
                out[k, 3], out[k, 4] = row[9], row[17]
        elif kind == 1:
            out[k, 0] = 1.0
            sr, sb = _sig(tab, 8, adaptive, row, x, y)
            if not adaptive:
                sb = tab[10]
            out[k, 3], out[k, 4], out[k, 7] = row[9], row[8], tab[11]
        elif kind == 2:
            x1, y1, dx, dy = row[0], row[1], row[4] - row[0], row[5] - row[1]
            length = math.sqrt(dx * dx + dy * dy)
            if length < tab[3]:
                continue
            t = min(max(-(x1 * dx + y1 * dy) / max(length * length, 1e-12), 0.0), 1.0)
            x, y = x1 + t * dx, y1 + t * dy  # the point nearest to the robot
            out[k, 0] = 2.0
            sr, sb = _sig(tab, 12, adaptive, row, x, y)
            if not adaptive:
                sb = tab[14]
            direction = math.atan2(dy, dx)
            direction -= math.pi * math.floor(direction / math.pi)
            out[k, 3], out[k, 7], out[k, 9] = direction, tab[15], tab[2]
            hth = direction + 0.5 * math.pi
            rho = math.cos(hth) * x1 + math.sin(hth) * y1
            if rho < 0.0:
                rho, hth = -rho, hth + math.pi
            hth = _wrap(hth)
            out[k, 10], out[k, 11] = rho, hth
            mx, my = x1 + 0.5 * dx, y1 + 0.5 * dy
            out[k, 12] = mx * math.sin(hth) - my * math.cos(hth)
            out[k, 13] = length / _SQRT12
        elif kind == 3 or kind == 4:
            out[k, 0] = 3.0 if kind == 3 else 4.0
            sr, sb = _sig(tab, 16 if kind == 3 else 20, adaptive, row, x, y)
            if not adaptive:
                sb = tab[18 if kind == 3 else 22]
        else:
            continue
        out[k, 1], out[k, 2], out[k, 5], out[k, 6] = x, y, sr, sb
        out[k, 14] = math.sqrt(x * x + y * y)
        out[k, 15] = math.atan2(y, x)
        k += 1
    return k


@nb.njit(cache=True, inline="always")
def _wrap(a):  # pragma: no cover - compiled
    """Angle wrapped to [-pi, pi)."""
    return a - 2.0 * math.pi * math.floor((a + math.pi) / (2.0 * math.pi))


@nb.njit(cache=True, inline="always")
def _point_q(px, py, c, s, th, mx, my, dist, bear, sr, sb):  # pragma: no cover - compiled
    """CMU Alg. 3 in log form: -(dd / sr)^2 / 2 - (db / sb)^2 / 2 for the landmark at (mx, my)."""
    ex, ey = mx - px, my - py
    de = math.sqrt(ex * ex + ey * ey)
    dd = (dist - de) / sr
    db = _wrap(bear - (math.atan2(ey, ex) - th)) / sb
    return -0.5 * (dd * dd + db * db)


@nb.njit(cache=True, inline="always")
def _cell(gx, gy, geo):  # pragma: no cover - compiled
    """Grid cell (row, column) of field point (gx, gy), clamped to the grid."""
    ix = int((gx - geo[0]) / geo[2])
    iy = int((gy - geo[1]) / geo[2])
    return min(max(iy, 0), int(geo[4]) - 1), min(max(ix, 0), int(geo[3]) - 1)


@nb.njit(cache=True, error_model="numpy")
def log_likelihood_nb(
    parts, n, obs, hough, posts, crossings, lines, marks, poles, cross_grid, line_grid, geo, out
):  # pragma: no cover - compiled
    """Sum over observations of each particle's log-likelihood into ``out[:n]``.

    ``parts``: N x 3 particle poses (team frame); ``obs``: K x N_O rows; ``hough``: 1 to use
    the NimbRo line model (else 0), then its sigmas of rho, theta, u-bar and spread; map
    arrays from :class:`~cognition.localization.fieldmodel.FieldModel`.
    """
    k_obs = obs.shape[0]
    for i in range(n):
        px, py, th = parts[i, 0], parts[i, 1], parts[i, 2]
        c, s = math.cos(th), math.sin(th)
        total = 0.0
        for k in range(k_obs):
            t = int(obs[k, 0])
            ox, oy = obs[k, 1], obs[k, 2]
            dist, bear, sr, sb = obs[k, 14], obs[k, 15], obs[k, 5], obs[k, 6]
            q = -1e4
            if t == 0:  # goal post: the most likely candidate
                side, goal = obs[k, 3], obs[k, 4]
                for j in range(posts.shape[0]):
                    if (side > 0.5 and posts[j, 2] != side) or (goal > -0.5 and posts[j, 3] != goal):
                        continue
                    q = max(q, _point_q(px, py, c, s, th, posts[j, 0], posts[j, 1], dist, bear, sr, sb))
            elif t == 1:  # crossing of the same kind nearest to the observation's field position
                gx, gy = px + c * ox - s * oy, py + s * ox + c * oy
                r, col = _cell(gx, gy, geo)
                j = cross_grid[int(obs[k, 3]), r, col]
                if j >= 0:
                    q = _point_q(px, py, c, s, th, crossings[j, 0], crossings[j, 1], dist, bear, sr, sb)
                    do = obs[k, 4] + th - crossings[j, 2]
                    do = _wrap(4.0 * do) / 4.0 if crossings[j, 3] == 2 else _wrap(do)
                    do /= obs[k, 7]
                    q -= 0.5 * do * do
            elif t == 2 and hough[0] < 0.5:  # line: nearest point model (CMU)
                gdir = obs[k, 3] + th
                g = gdir - math.pi * math.floor(gdir / math.pi)  # [0, pi)
                cls = 0 if min(g, math.pi - g) <= 0.25 * math.pi else 1
                gx, gy = px + c * ox - s * oy, py + s * ox + c * oy
                r, col = _cell(gx, gy, geo)
                j = line_grid[cls, r, col]
                if j >= 0:
                    x1, y1, x2, y2 = lines[j, 0], lines[j, 1], lines[j, 2], lines[j, 3]
                    dx, dy = x2 - x1, y2 - y1
                    u = ((px - x1) * dx + (py - y1) * dy) / (dx * dx + dy * dy)
                    u = min(max(u, 0.0), 1.0)
                    q = _point_q(px, py, c, s, th, x1 + u * dx, y1 + u * dy, dist, bear, sr, sb)
                    do = g - lines[j, 4]
                    do = (do - math.pi * math.floor(do / math.pi + 0.5)) / obs[k, 7]
                    q -= 0.5 * do * do
            elif t == 2:  # line: Hough model (NimbRo eq. 7)
                gdir = obs[k, 3] + th
                g = gdir - math.pi * math.floor(gdir / math.pi)
                cls = 0 if min(g, math.pi - g) <= 0.25 * math.pi else 1
                best = 1e300
                for j in range(lines.shape[0]):
                    if lines[j, 5] != cls:
                        continue
                    x1, y1, x2, y2 = lines[j, 0], lines[j, 1], lines[j, 2], lines[j, 3]
                    nth = lines[j, 4] + 0.5 * math.pi - th  # normal, robot frame
                    ax, ay = x1 - px, y1 - py
                    rx, ry = c * ax + s * ay, -s * ax + c * ay  # endpoint 1, robot frame
                    bx, by = x2 - px, y2 - py
                    sx, sy = c * bx + s * by, -s * bx + c * by  # endpoint 2, robot frame
                    rho = math.cos(nth) * rx + math.sin(nth) * ry
                    if rho < 0.0:
                        rho, nth = -rho, nth + math.pi
                    d_rho = (rho - obs[k, 10]) / hough[1]
                    d_th = _wrap(nth - obs[k, 11]) / hough[2]
                    m = d_rho * d_rho + d_th * d_th
                    if m >= best:
                        continue
                    sn, cn = math.sin(obs[k, 11]), math.cos(obs[k, 11])
                    u1, u2 = rx * sn - ry * cn, sx * sn - sy * cn
                    lo, hi = min(u1, u2), max(u1, u2)
                    ue = min(max(obs[k, 12], lo), hi)
                    se = min(obs[k, 13], (hi - lo) / math.sqrt(12.0))
                    d_u = (ue - obs[k, 12]) / hough[3]
                    d_s = (se - obs[k, 13]) / hough[4]
                    best = m
                    q = -0.5 * (m + d_u * d_u + d_s * d_s)
            elif t == 3:  # centre circle
                q = _point_q(px, py, c, s, th, 0.0, 0.0, dist, bear, sr, sb)
            else:  # penalty mark or corner pole: the nearest one to the observation
                arr = marks if t == 4 else poles
                gx, gy = px + c * ox - s * oy, py + s * ox + c * oy
                bj, bd = -1, 1e300
                for j in range(arr.shape[0]):
                    dd = (arr[j, 0] - gx) ** 2 + (arr[j, 1] - gy) ** 2
                    if dd < bd:
                        bj, bd = j, dd
                if bj >= 0:
                    q = _point_q(px, py, c, s, th, arr[bj, 0], arr[bj, 1], dist, bear, sr, sb)
            q = max(q, -1e4)
            conf, floor = obs[k, 8], obs[k, 9]
            base = floor + (1.0 - conf)
            if base > 0.0:
                total += math.log(base + conf * math.exp(q))
            else:
                total += q
        out[i] = total
