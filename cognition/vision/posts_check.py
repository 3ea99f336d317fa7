"""A goal-post candidate checked along its axis, and the crossbar: steps 2-3 and 5 of DNT section 3.8.

Compiled pieces :func:`~cognition.vision.posts.detect_posts` runs on each candidate of
:mod:`.posts_scan` (the module docstring of :mod:`.posts` describes the method and holds the
parameter table):

- the goal-coloured run walked pixel by pixel up the predicted axis from the candidate's foot,
  the band around the axis and each of its columns (a net string is thinner than a post),
  whether enough of the post is in view and, near the camera, whether its lower rows are no
  wider than a post (a robot's legs); when the run fails right above the foot, the next foot
  up (:func:`_check_axis`, :func:`_check_at`, :func:`_band_fill`, :func:`_row_widths`,
  :func:`_row_run`);
- for a run too narrow or too wide, the window one diameter wide that passes and stands lowest
  (:func:`_search`);
- the crossbar traced sideways from a post's top, which tells the left post from the right
  (:func:`_crossbar`).

Pixels ``u`` right, ``v`` down; ground points in metres in the robot frame (+x forward, +y left).
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.vision.posts_scan import (
    _P_BAND,
    _P_COL,
    _P_DMAX,
    _P_FILL,
    _P_GAP,
    _P_HEIGHT,
    _P_HRANGE,
    _P_LEN,
    _P_POLE,
    _P_ROBOT,
    _P_SLACK,
    _P_WHI,
    _axis_run,
    _is_goal,
    _median_feet,
    _post_at,
    _visible_top,
)
from cognition.vision.projection import pixel_nb

_Check = tuple[int, float, float, float, float, float, float, float, int, int, float, float]
"""What :func:`_check_axis` returns."""


@nb.njit(cache=True)
def _row_run(
    classes: NDArray[np.uint8], g0: int, g1: int, u: float, j: int, cap: int
) -> tuple[int, int]:  # pragma: no cover - compiled
    """The goal-coloured run of row j through (or next to) column u: (first, last) column, or (-1, -2)."""
    width = classes.shape[1]
    i = int(u)
    if i < 0 or i >= width:
        return -1, -2
    if not _is_goal(classes[j, i], g0, g1):
        if i + 1 < width and _is_goal(classes[j, i + 1], g0, g1):
            i += 1
        elif i - 1 >= 0 and _is_goal(classes[j, i - 1], g0, g1):
            i -= 1
        else:
            return -1, -2
    a = i
    while a - 1 >= 0 and i - a < cap and _is_goal(classes[j, a - 1], g0, g1):
        a -= 1
    e = i
    while e + 1 < width and e - i < cap and _is_goal(classes[j, e + 1], g0, g1):
        e += 1
    return a, e


@nb.njit(cache=True)
def _row_widths(
    classes: NDArray[np.uint8], g0: int, g1: int, ub: float, vb: float, ut: float, vt: float, last: float, cap: int
) -> float:  # pragma: no cover - compiled
    """Median width of the goal-coloured row runs through the axis (foot (ub, vb), top (ut,
    vt)) at eight heights between the foot and row ``last`` (px)."""
    slope = (ut - ub) / (vb - vt) if vb - vt > 1e-9 else 0.0
    widths = np.empty(8)
    k = 0
    for q in range(8):
        j = int(vb - 1.0 - (q + 0.5) * (vb - 1.0 - last) / 8.0)
        first, end = _row_run(classes, g0, g1, ub + slope * (vb - (j + 0.5)), j, cap)
        widths[k] = end - first + 1.0
        k += 1
    return float(np.median(widths[:k]))


@nb.njit(cache=True)
def _band_fill(
    classes: NDArray[np.uint8], g0: int, g1: int, ub: float, vb: float, ut: float, vt: float, last: int, band: float
) -> tuple[float, float]:  # pragma: no cover - compiled
    """Share of goal-coloured pixels in a band ``band`` px wide around the axis from the foot
    (ub, vb) up to row ``last``, and the smallest share of one column of the band (noise
    spreads over all columns, a thin string in front of a background leaves whole columns)."""
    height, width = classes.shape
    slope = (ut - ub) / (vb - vt) if vb - vt > 1e-9 else 0.0
    n = min(max(int(band + 0.5), 1), 16)
    hits = np.zeros(n)
    seen = np.zeros(n)
    for j in range(min(int(vb) - 1, height - 1), max(last, 0) - 1, -1):
        i0 = math.floor(ub + slope * (vb - (j + 0.5)) - 0.5 * n + 0.5)
        for k in range(n):
            i = i0 + k
            if 0 <= i < width:
                seen[k] += 1.0
                if _is_goal(classes[j, i], g0, g1):
                    hits[k] += 1.0
    total = seen.sum()
    if total <= 0.0:
        return 0.0, 0.0
    lo = 1.0
    for k in range(n):
        if seen[k] > 0.0:
            lo = min(lo, hits[k] / seen[k])
    return hits.sum() / total, lo


@nb.njit(cache=True)
def _crossbar(
    classes: NDArray[np.uint8], g0: int, g1: int, u: float, v: float, side: int, thick: float, steps: int
) -> tuple[int, bool, bool]:  # pragma: no cover - compiled
    """Follow a goal-coloured bar sideways from (u, v) (side -1 left, +1 right) for at most
    ``steps`` columns: (columns followed, reached the image edge, goal colour right below most
    of it: a wall of the hall in the goal's colour, not a bar)."""
    height, width = classes.shape
    half = 0.5 * thick + 2.0
    need = max(1, math.ceil(thick))
    vc = v
    below = 0
    for k in range(steps):
        i = int(u) + side * (k + 1)
        if i < 0 or i >= width:
            return k, True, k >= 3 and below > 0.6 * k
        lo = max(0, int(vc - half))
        hi = min(height - 1, int(vc + half))
        best = -1.0
        best_d = 1e9
        run = 0
        for j in range(lo, hi + 2):
            g = j <= hi and _is_goal(classes[j, i], g0, g1)
            if g:
                run += 1
            elif run > 0:
                if run >= need:
                    mid = j - 0.5 * run
                    dd = abs(mid - vc)
                    if dd < best_d:
                        best_d = dd
                        best = mid
                run = 0
        if best < 0.0:
            return k, False, k >= 3 and below > 0.6 * k
        vc = best
        j = int(vc + half + 1.0)
        if j < height and _is_goal(classes[j, i], g0, g1):
            below += 1
    return steps, False, below > 0.6 * steps


@nb.njit(cache=True)
def _check_axis(
    classes: NDArray[np.uint8],
    cam: NDArray[np.float64],
    feet: NDArray[np.float64],
    g0: int,
    g1: int,
    uc: float,
    ua: float,
    i0: int,
    i1: int,
    r: float,
    goal_h: float,
    prm: NDArray[np.float64],
) -> _Check:  # pragma: no cover - compiled
    """Check a post centred at column ``uc`` whose foot is that of columns i0..i1 (see
    :func:`.posts_scan._median_feet`), along the axis through column ``ua`` (the middle of its
    visible part): (outcome, band fill, run share, foot row, centre x, y, top u, v, goal pixels
    of g0, of g1, last row of the run, smallest column fill). Outcomes as in
    :func:`.posts._posts_nb`. When the run fails right above that foot (it is a line's, in front
    of the post), the next foot up is tried."""
    vb = _median_feet(feet, i0, i1)
    if vb < 0.0:
        return 2, 0.0, 0.0, vb, 0.0, 0.0, 0.0, 0.0, 0, 0, 0.0, 0.0
    res = _check_at(classes, cam, g0, g1, uc, ua, vb, i0, i1, r, goal_h, prm)
    if res[0] == 2 and res[2] < 0.3:
        top = -1.0
        for i in range(i0, i1 + 1):
            if top < feet[i] < vb - 0.5:
                top = feet[i]
        if top >= 0.0:
            other = _check_at(classes, cam, g0, g1, uc, ua, top, i0, i1, r, goal_h, prm)
            if other[0] == 0:
                return other
    return res


@nb.njit(cache=True)
def _check_at(
    classes: NDArray[np.uint8],
    cam: NDArray[np.float64],
    g0: int,
    g1: int,
    uc: float,
    ua: float,
    vb: float,
    i0: int,
    i1: int,
    r: float,
    goal_h: float,
    prm: NDArray[np.float64],
) -> _Check:  # pragma: no cover - compiled
    """:func:`_check_axis` for the foot row ``vb``."""
    width = classes.shape[1]
    ok, xc, yc, ut, vt, w_exp = _post_at(cam, uc, vb, r, goal_h)
    oka, _, _, uta, vta, _ = _post_at(cam, ua, vb, r, goal_h)
    if not (ok and oka):
        return 5, 0.0, 0.0, vb, 0.0, 0.0, 0.0, 0.0, 0, 0, 0.0, 0.0
    visible = vb - _visible_top(ua, vb, uta, vta, width)
    # one colour per post (a KidSize corner pole has bands of both goal colours)
    gs = g0
    fill, gap = prm[_P_FILL], int(prm[_P_GAP])
    filled, last, n0, _, ended = _axis_run(classes, g0, g0, ua, vb, uta, vta, int(vb) - 1, fill, gap, 1)
    n1 = 0
    if g1 != g0:
        filled1, last1, m1, _, ended1 = _axis_run(classes, g1, g1, ua, vb, uta, vta, int(vb) - 1, fill, gap, 1)
        if m1 > n0:
            gs, filled, last, n0, n1, ended = g1, filled1, last1, 0, m1, ended1
    share = (n0 + n1) / max(visible, 1e-9)
    band = max(1.0, 0.6 * min(w_exp, (i1 - i0 + 1.0) if ua != uc else w_exp))
    bf, col_min = _band_fill(classes, gs, gs, ua, vb, uta, vta, last, band)
    code = 0
    vtop = vb - visible
    # the visible part must reach min_height up the post (less, as 1 / distance, beyond
    # min_height_range): near the camera a line seen along the axis looks like a post's foot
    dist = math.hypot(xc - cam[9], yc - cam[10])
    _, vh, okh = pixel_nb(cam, xc, yc, prm[_P_HEIGHT] * min(1.0, prm[_P_HRANGE] / max(dist, 1e-9)))
    if g1 != g0:  # two goal colours: a corner pole has bands of both, its lowest one pole_band high
        _, vp, okp = pixel_nb(cam, xc, yc, prm[_P_POLE])
        if ended == g0 + g1 - gs or not okp or vp < vtop + 3.0:  # 3 px: room to see the next band
            okh = False
    if not filled or vb - last < prm[_P_LEN] or not okh or vh < vtop - 0.5:
        code = 2  # too little of the post in view (a line seen along the axis looks the same)
    elif bf < prm[_P_BAND] or col_min < prm[_P_COL]:
        code = 3
    elif math.hypot(xc, yc) > prm[_P_DMAX]:
        code = 4
    else:
        # only the part below a robot's height in view: a robot's legs would pass as well,
        # unless the goal-coloured rows of the lower half are no wider than a post
        _, vr, okr = pixel_nb(cam, xc, yc, prm[_P_ROBOT])
        if not okr or vr < vtop - 0.5:
            w_med = _row_widths(classes, gs, gs, ua, vb, uta, vta, 0.5 * (vb + last), int(4.0 * w_exp + 8.0))
            if w_med > prm[_P_WHI] * w_exp + prm[_P_SLACK]:
                code = 6
    return code, bf, share, vb, xc, yc, ut, vt, n0, n1, float(last), col_min


@nb.njit(cache=True)
def _search(
    classes: NDArray[np.uint8],
    cam: NDArray[np.float64],
    feet: NDArray[np.float64],
    g0: int,
    g1: int,
    a: int,
    e: int,
    lo: float,
    hi: float,
    w_exp: float,
    r: float,
    goal_h: float,
    prm: NDArray[np.float64],
) -> tuple[_Check, float]:  # pragma: no cover - compiled
    """The post centred between columns ``lo`` and ``hi`` (1 px steps) over the candidate
    columns a..e: of the centres that pass :func:`_check_axis`, the middle of those whose foot
    is lowest (a post stands in front of its net). Returns the check and the centre."""
    best_v = -1.0
    first_u = 0.0
    last_u = 0.0
    for q in range(int(hi - lo) + 1):
        uq = lo + q
        i0 = min(e, max(a, int(uq - 0.5 * w_exp)))
        i1 = max(i0, min(e, int(uq + 0.5 * w_exp)))
        rq = _check_axis(classes, cam, feet, g0, g1, uq, uq, i0, i1, r, goal_h, prm)
        if rq[0] != 0:
            continue
        if rq[3] > best_v + 0.5:
            best_v = rq[3]
            first_u = uq
            last_u = uq
        elif rq[3] >= best_v - 0.5:
            last_u = uq
    if best_v < 0.0:
        return (3, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0, 0, 0.0, 0.0), lo
    uc = 0.5 * (first_u + last_u)
    i0 = min(e, max(a, int(uc - 0.5 * w_exp)))
    i1 = max(i0, min(e, int(uc + 0.5 * w_exp)))
    return _check_axis(classes, cam, feet, g0, g1, uc, uc, i0, i1, r, goal_h, prm), uc
