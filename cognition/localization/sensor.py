"""Sensor models of the particle filter and the packing of percepts into observation rows.

Every model compares an observation with the map landmark it is associated with, seen
from the particle's pose, by CMU's ``point_likelihood`` (Alg. 3): Gaussians of the
difference of distances and of the bearing difference, with sigmas that grow linearly with
the distance (CMU III.C tables, :mod:`cognition.localization.params`):

* **goal posts** (CMU III.C.1): a left or right post is compared with that post; an
  unknown one with every candidate and the most likely is kept. Goals of different colours
  restrict the candidates to one goal; the white SPL goals do not.
* **crossings** (III.C.2): the nearest map crossing of the same type (grid lookup) and a
  Gaussian of the orientation difference (L and T: full turn, X: modulo 90 degrees). Not in the
  paper, with ``partial_crossings`` w > 0 (default 0.1; 0 is the paper's model): a crossing seen
  in part looks like a lesser kind, so the nearest crossing may also be of a larger kind than the
  one seen, compared in the directions its arms give: a T with an X (the stem along one of its
  arms), an L with an X (the bisector in one of its right angles) or with a T (the stem and one
  half of the bar: the bisector 45 degrees to either side of the stem); such a partial view
  counts w times the likelihood of a full one (``O.PARTIAL`` holds log w). Vision reports the
  halfway line's X with the centre circle as a T when the circle's far arc is too thin to be
  seen; that T, unexplained by the true pose, reset an accurate estimate onto a penalty-area T
  (traced in the study ``percepts-vs-images``, ``reset`` on images, seed 1). At w = 1 the rule
  tracked a walking robot more closely but relocalized it less often after a kidnap (a wrong
  pose explains an L by more map crossings); w = 0.1 kept the first without the second
  (``docs/studies/partial-crossings``).
* **lines** (III.C.3), ``nearest`` model: the observation is the point of the segment
  nearest to the robot; the map line is the nearest one of the matching orientation class
  (grid lookup), the expected point its point nearest to the particle; times a Gaussian of
  the orientation difference (modulo 180 degrees); then 0.9 is added (false positives).
  Segments shorter than 10 cm are dropped before. Not in the paper: when the seen segment ends
  before the foot of the robot's perpendicular on its line (``O.FOOT`` 0; a robot beside a line
  sees it only from the image's lower border on, so its nearest seen point is where the image
  cuts it), that point says nothing about where along the line the robot stands. Then only the
  distance across the line is compared: the offset, along the observed line's normal, between the
  seen point and the foot of the particle's perpendicular on the whole map line, with the same
  distance sigma, and the orientation as before. Taken at face value, the cut end pulled
  estimates along the line (traced in a 5 v 5 image match: 0.7 m along the penalty area's side
  line against good odometry, then a reset into the other half). Also not in the paper: a line
  no longer than the centre circle's radius may be a straight piece of the circle (vision
  reports the circle seen from near its centre as such pieces), so its likelihood is the larger
  of the line model's and that of the circle's tangent where the particle puts the seen point
  (Gaussians of that point's distance from the circle, with the distance sigma, and of the
  direction's turn from the tangent, with the orientation sigma).
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

Observation rows (:class:`O` columns) are in the robot frame (m, rad); the compiled
likelihood is in :mod:`cognition.localization.kernels`.
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
    FOOT = 16
    """Lines: 1 when the observed segment holds the foot of the robot's perpendicular on its line
    (X, Y is that foot), 0 when the segment ends first (X, Y is its end nearer the robot)."""
    PARTIAL = 17
    """Crossings: log of the weight of explaining the crossing by a larger kind
    (``partial_crossings``; 0 when off, where no larger kind is associated)."""


N_O = len(O)
NO_OBSERVATIONS = np.zeros((0, N_O))
"""No observations. Left writable: with no rows nothing can be written to it, and a read-only
array is another numba type, for which every kernel taking observations would be compiled a
second time (about 12 s more on the first run)."""
_SQRT12 = math.sqrt(12.0)


def sensor_table(p: LocalizationParams) -> NDArray[np.float64]:
    """The parameters :func:`pack_nb` needs, as one array (see there)."""
    return np.array(
        [
            1.0 if p.adaptive else 0.0, p.confidence, p.line_floor, p.line_min_length,
            p.post_sigma_min, p.post_sigma_rate, p.post_sigma_bearing_min, p.post_sigma_bearing_rate,
            p.corner_sigma_min, p.corner_sigma_rate, p.corner_sigma_bearing, p.corner_sigma_orientation,
            p.line_sigma_min, p.line_sigma_rate, p.line_sigma_bearing, p.line_sigma_orientation,
            p.circle_sigma_min, p.circle_sigma_rate, p.circle_sigma_bearing, 0.0 if p.field_lines else 1.0,
            p.mark_sigma_min, p.mark_sigma_rate, p.mark_sigma_bearing, 0.0,
            math.log(p.partial_crossings) if p.partial_crossings > 0.0 else 0.0,
        ]
    )  # fmt: skip


def pack_observations(percepts: Percepts | None, table: NDArray[np.float64]) -> NDArray[np.float64]:
    """Observation rows (K x :data:`N_O`) for the filter from one image's percepts.

    ``table`` is :func:`sensor_table` of the parameters. Balls and robots are not used;
    lines shorter than the minimum length are dropped, and so are all painted-line features
    (crossings, lines, circle, marks) when ``field_lines`` is off.
    """
    if percepts is None:
        return NO_OBSERVATIONS
    rows, offsets = percepts.table_and_offsets
    n = int(offsets[-1] - offsets[0])
    if n == 0:
        return NO_OBSERVATIONS
    out = np.empty((n, N_O))
    k = pack_nb(rows, offsets, table, out)
    return out[:k]


@nb.njit(cache=True, error_model="numpy", fastmath=False)
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


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def pack_nb(rows, offsets, tab, out):  # pragma: no cover - compiled
    """Fill ``out`` with observation rows from percept rows (kind k in rows
    offsets[k] .. offsets[k + 1]); returns how many."""
    adaptive = tab[0] > 0.5
    no_lines = tab[19] > 0.5
    k = 0
    kind = 0
    for r in range(offsets[0], offsets[-1]):
        while r >= offsets[kind + 1]:
            kind += 1
        if no_lines and kind >= 1 and kind <= 4:  # crossings, lines, circle, marks: painted lines
            continue
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
            if not (row[9] >= 0.0 and row[9] <= 2.0):  # unknown crossing kind: unusable
                continue
            out[k, 0] = 1.0
            sr, sb = _sig(tab, 8, adaptive, row, x, y)
            if not adaptive:
                sb = tab[10]
            out[k, 3], out[k, 4], out[k, 7], out[k, 17] = row[9], row[8], tab[11], tab[24]
        elif kind == 2:
            x1, y1, dx, dy = row[0], row[1], row[4] - row[0], row[5] - row[1]
            length = math.sqrt(dx * dx + dy * dy)
            if length < tab[3]:
                continue
            t_foot = -(x1 * dx + y1 * dy) / max(length * length, 1e-12)
            t = min(max(t_foot, 0.0), 1.0)
            x, y = x1 + t * dx, y1 + t * dy  # the point nearest to the robot
            out[k, 16] = 1.0 if t_foot > 0.0 and t_foot < 1.0 else 0.0
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
