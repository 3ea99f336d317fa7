"""Column histogram and candidate runs of the goal-post detector: steps 1-2 of DNT section 3.8.

The compiled front end of :func:`~cognition.vision.posts.detect_posts` (its module docstring
describes the method and holds the parameter table). DNT builds a histogram of goal-coloured
pixels per image column and takes its peaks as post candidates. Here a column counts when a
post standing at the foot found above its field boundary (:func:`_foot`: goal colour with
carpet right below) would be goal-coloured up the axis the camera matrix predicts for it
(:func:`_post_at`, :func:`_visible_top`, :func:`_axis_run`), and the candidates are the runs
of such columns, two runs split by a line seen along its length joined (:func:`_columns`,
:func:`_intervals`); a candidate's foot is a low percentile of its columns' feet
(:func:`_median_feet`). :mod:`.posts_check` checks each candidate along its axis.

Also the layout of ``PostParams.packed``, the parameter vector all compiled parts read.

Pixels ``u`` right, ``v`` down (sub-pixel positions are pixel edges: the centre of column i is
i + 0.5); ground points in metres in the robot frame (+x forward, +y left).
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.vision.projection import ground_nb, pixel_nb

# entries of PostParams.packed
_P_GAP, _P_LINE, _P_FILL, _P_LEN, _P_WLO, _P_WHI, _P_SLACK = 0, 1, 2, 3, 4, 5, 6
_P_BAR, _P_THICK, _P_DLO, _P_DHI, _P_DMAX, _P_BAND, _P_REACH = 7, 8, 9, 10, 11, 12, 13
_P_WMIN, _P_FOOT, _P_ROBOT, _P_HEIGHT, _P_NMS, _P_HRANGE, _P_COL, _P_POLE = 14, 15, 16, 17, 18, 19, 20, 21
_P_LEN_U = 22
_N_PARAMS = 23
_SAMPLES = 24
"""Samples along the axis of a post in the column histogram (a post checked as a candidate is
walked pixel by pixel)."""


@nb.njit(cache=True, error_model="python", fastmath=False)
def _is_goal(c: int, g0: int, g1: int) -> bool:  # pragma: no cover - compiled
    return c in (g0, g1)


@nb.njit(cache=True, error_model="python", fastmath=False)
def _post_at(
    cam: NDArray[np.float64], u: float, v: float, r: float, goal_h: float
) -> tuple[bool, float, float, float, float, float]:  # pragma: no cover - compiled
    """A post whose front foot is seen at pixel (u, v): (ok, centre x, y, top pixel u, v,
    projected diameter in pixels). When the top is behind the camera, the "top" is a point of
    the axis far above the image."""
    xf, yf, ok = ground_nb(cam, u, v, 0.0)
    if not ok:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0
    dx, dy = xf - cam[9], yf - cam[10]
    d = math.hypot(dx, dy)
    if d < 1e-6:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0
    ex, ey = dx / d, dy / d
    xc, yc = xf + r * ex, yf + r * ey
    ut, vt, okt = pixel_nb(cam, xc, yc, goal_h)
    if not okt:
        # the top is behind the camera (a post right in front of a camera looking down): the
        # axis through a lower point, extended far beyond the image
        ub, vb, okb = pixel_nb(cam, xc, yc, 0.0)
        z = 0.5 * goal_h
        while not okt and z > 0.01 * goal_h:
            ut, vt, okt = pixel_nb(cam, xc, yc, z)
            z *= 0.5
        if not (okb and okt) or vb - vt < 1e-3:
            return False, 0.0, 0.0, 0.0, 0.0, 0.0
        k = 1e4 / (vb - vt)
        ut, vt = ut + k * (ut - ub), vt + k * (vt - vb)
    ua, _, oka = pixel_nb(cam, xc - r * ey, yc + r * ex, 0.0)
    ub, _, okb = pixel_nb(cam, xc + r * ey, yc - r * ex, 0.0)
    if not (oka and okb):
        return False, 0.0, 0.0, 0.0, 0.0, 0.0
    return True, xc, yc, ut, vt, abs(ub - ua)


@nb.njit(cache=True, error_model="python", fastmath=False)
def _axis_run(
    classes: NDArray[np.uint8],
    g0: int,
    g1: int,
    ub: float,
    vb: float,
    ut: float,
    vt: float,
    start: int,
    fill: float,
    gap: int,
    step: int,
) -> tuple[bool, int, int, int, int]:  # pragma: no cover - compiled
    """Walk up the axis from the foot (ub, vb) toward the top (ut, vt), from row ``start`` to
    the top or where the axis leaves the image, every ``step`` rows: (at least ``fill`` of it
    goal-coloured, last goal row, goal samples of class g0, of class g1, class of the pixel
    that ended the run or -1). The run ends where too many samples missed for ``fill``, more
    than ``gap`` pixels in a row or two green or coloured samples in a row (carpet, a jersey);
    single noisy pixels do not end it (a miss with a goal-coloured pixel above it counts)."""
    width = classes.shape[1]
    slope = (ut - ub) / (vb - vt) if vb - vt > 1e-9 else 0.0
    stop = max(math.floor(_visible_top(ub, vb, ut, vt, width)), 0)
    total = (start - stop) // step + 1 if start >= stop else 0
    budget = (1.0 - fill) * total
    gap_samples = max(1, gap // step) if step > 1 else gap
    last = start + 1
    ended = -1
    miss = 0
    hard = 0
    gap_run = 0
    n0 = 0
    n1 = 0
    for j in range(start, stop - 1, -step):
        i = int(ub + slope * (vb - (j + 0.5)))
        if i < 0 or i >= width:
            break
        c = classes[j, i]
        if not _is_goal(c, g0, g1) and j > 0 and _is_goal(classes[j - 1, i], g0, g1):
            c = classes[j - 1, i]
        if c == g0:
            n0 += 1
            last = j
        elif c == g1:
            n1 += 1
            last = j
        else:
            miss += 1
            gap_run += 1
            # carpet or a colour (a jersey) inside the run: not a post (noise is grey or black)
            hard = hard + 1 if c == 1 or c >= 4 else 0
            if miss > budget or hard > 1 or gap_run > gap_samples:
                ended = c
                break
            continue
        hard = 0
        gap_run = 0
    return n0 + n1 >= fill * total - 1.0, last, n0, n1, ended


@nb.njit(cache=True, error_model="python", fastmath=False)
def _foot(
    classes: NDArray[np.uint8],
    u: int,
    start: int,
    stop: int,
    g0: int,
    g1: int,
    line_gap: int,
    foot_gap: int,
) -> tuple[int, int]:  # pragma: no cover - compiled
    """The foot of a goal-coloured run in column u, searched upward from row ``start`` to row
    ``stop``: (lowest goal row, first carpet row below it), or (-1, -1). The run must end on
    green within ``foot_gap`` pixels. Green and up to ``line_gap`` other pixels in a row are
    skipped on the way up (thin lines or noise in the carpet push the field boundary below a
    post's foot). Where white is not a goal colour, white (lines) counts as carpet: a post may
    stand on a line."""
    height = classes.shape[0]
    lines = g0 != 2 and g1 != 2
    other = 0
    for j in range(start, stop - 1, -1):
        c = classes[j, u]
        if _is_goal(c, g0, g1):
            for k in range(j + 1, min(j + 2 + foot_gap, height)):
                ck = classes[k, u]
                if ck == 1 or (lines and ck == 2):
                    return j, k
            return -1, -1
        if c == 1 or (lines and c == 2):
            other = 0
        else:
            other += 1
            if other > line_gap:  # the hall above the carpet
                return -1, -1
    return -1, -1


@nb.njit(cache=True, error_model="python", fastmath=False)
def _median_feet(feet: NDArray[np.float64], lo: int, hi: int) -> float:  # pragma: no cover - compiled
    """The foot row of a post over the candidate columns lo..hi: the 30th percentile of their
    feet (-1 if none). Not the median: columns over a line seen along its length under the
    post (white goals) have their foot where the line ends, lower in the image."""
    vals = np.empty(max(hi - lo + 1, 1))
    k = 0
    for i in range(lo, hi + 1):
        if feet[i] >= 0.0:
            vals[k] = feet[i]
            k += 1
    if k == 0:
        return -1.0
    return float(np.sort(vals[:k])[int(0.3 * (k - 1) + 0.5)])


@nb.njit(cache=True, error_model="python", fastmath=False)
def _visible_top(ub: float, vb: float, ut: float, vt: float, width: int) -> float:  # pragma: no cover - compiled
    """Row where the axis from the foot (ub, vb) to the top (ut, vt) ends or leaves the image."""
    top = max(vt, 0.0)
    if vb - vt > 1e-9:
        slope = (ut - ub) / (vb - vt)  # du per row upward
        if slope > 1e-9:
            top = max(top, vb - (width - ub) / slope)
        elif slope < -1e-9:
            top = max(top, vb + ub / slope)
    return top


@nb.njit(cache=True, error_model="python", fastmath=False)
def _column(
    classes: NDArray[np.uint8],
    cam: NDArray[np.float64],
    u: int,
    start: int,
    stop: int,
    g0: int,
    g1: int,
    r: float,
    goal_h: float,
    prm: NDArray[np.float64],
) -> float:  # pragma: no cover - compiled
    """The foot row of a post in column u whose foot lies between rows ``start`` and ``stop``
    (searched upward, :func:`_foot`) and whose axis is goal-coloured (``min_fill`` of its
    visible length), or -1. When the run up from a foot fails, the next foot above is tried
    once (a line between a post's foot and the boundary ends a run early)."""
    width = classes.shape[1]
    gap, line_gap, foot_gap = int(prm[_P_GAP]), int(prm[_P_LINE]), int(prm[_P_FOOT])
    fill, min_len = prm[_P_FILL], prm[_P_LEN]
    tries = 0
    while start >= stop:
        j0, vf = _foot(classes, u, start, stop, g0, g1, line_gap, foot_gap)
        if j0 < 0:
            break
        vb = float(vf)
        ok, _, _, ut, vt, _ = _post_at(cam, u + 0.5, vb, r, goal_h)
        if not ok:
            break
        visible = vb - _visible_top(u + 0.5, vb, ut, vt, width)
        if visible < min_len:
            break
        c0 = int(classes[j0, u])  # one colour per post
        step = max(1, int(visible / _SAMPLES))  # a candidate test: enough samples
        filled, last, _, _, _ = _axis_run(classes, c0, c0, u + 0.5, vb, ut, vt, j0 - 1, fill, gap, step)
        if filled:
            return vb
        tries += 1
        if tries >= 2:
            break
        start = last - 1
    return -1.0


@nb.njit(cache=True, error_model="python", fastmath=False)
def _columns(
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    g0: int,
    g1: int,
    r: float,
    goal_h: float,
    prm: NDArray[np.float64],
) -> tuple[NDArray[np.bool_], NDArray[np.float64]]:  # pragma: no cover - compiled
    """The column histogram: whether a post standing at the foot found above the field
    boundary of each column would be goal-coloured up its axis (``min_fill`` of its visible
    length), and that foot row (-1 where not). A column next to a candidate whose boundary
    lies elsewhere (pushed down by the ball or a robot in front, or by a line seen along the
    column) is searched for a foot within 3 px of its neighbour's, left to right and back."""
    height, width = classes.shape
    reach = int(prm[_P_REACH])
    cand = np.zeros(width, dtype=np.bool_)
    feet = np.full(width, -1.0)
    lines = g0 != 2 and g1 != 2
    for u in range(width):
        b = boundary[u]
        if b <= 0 or b >= height:
            continue
        # a line seen along the column pushes the field boundary down to its near end: its
        # rows (carpet where white is not a goal colour) do not use up the reach
        top = b - 1
        while lines and top > 0 and classes[top, u] == 2:
            top -= 1
        feet[u] = _column(classes, cam, u, b - 1, max(top + 1 - reach, 0), g0, g1, r, goal_h, prm)
    for sweep in range(2):
        for k in range(1, width):
            u = k if sweep == 0 else width - 1 - k
            n = u - 1 if sweep == 0 else u + 1
            if feet[u] < 0.0 and feet[n] >= 0.0:
                f = int(feet[n])
                feet[u] = _column(classes, cam, u, min(f + 2, height - 1), max(f - 4, 0), g0, g1, r, goal_h, prm)
    for u in range(width):
        cand[u] = feet[u] >= 0.0
    return cand, feet


@nb.njit(cache=True, error_model="python", fastmath=False)
def _intervals(
    classes: NDArray[np.uint8],
    cam: NDArray[np.float64],
    cand: NDArray[np.bool_],
    feet: NDArray[np.float64],
    g0: int,
    g1: int,
    r: float,
    goal_h: float,
    prm: NDArray[np.float64],
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:  # pragma: no cover - compiled
    """The candidates: runs of candidate columns (one-column gaps bridged), first and last
    column. Two runs are one post standing on a line seen along its length (white goals: the
    line's columns have no foot) when the gap between them is goal-coloured just above their
    feet and narrower than the post."""
    width = classes.shape[1]
    starts = np.empty(width, dtype=np.int64)
    ends = np.empty(width, dtype=np.int64)
    n = 0
    u = 0
    while u < width:
        if not cand[u]:
            u += 1
            continue
        a = u
        e = u
        while e + 1 < width and (cand[e + 1] or (e + 2 < width and cand[e + 2])):
            e += 1 if cand[e + 1] else 2
        u = e + 1
        if n > 0:
            pa, pe = starts[n - 1], ends[n - 1]
            row = int(min(feet[pe], feet[a])) - 2
            ok, _, _, _, _, w_exp = _post_at(cam, 0.5 * (pa + e + 1), max(feet[pe], feet[a]), r, goal_h)
            if ok and row >= 0 and a - pe - 1 <= 0.75 * w_exp and e - pa + 1 <= prm[_P_WHI] * w_exp + prm[_P_SLACK]:
                filled = 0
                for i in range(pe + 1, a):
                    if _is_goal(classes[row, i], g0, g1):
                        filled += 1
                if filled >= 0.8 * (a - pe - 1):
                    ends[n - 1] = e
                    continue
        starts[n] = a
        ends[n] = e
        n += 1
    return starts[:n], ends[:n]
