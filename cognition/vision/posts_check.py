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
    _P_WLO,
    _P_WMIN,
    _axis_run,
    _is_goal,
    _median_feet,
    _post_at,
    _visible_top,
)
from cognition.vision.projection import pixel_nb

_Check = tuple[int, float, float, float, float, float, float, float, int, int, float, float]
"""What :func:`_check_axis` returns."""


@nb.njit(cache=True, error_model="python", fastmath=False)
def _row_run(
    classes: NDArray[np.uint8], g0: int, g1: int, u: float, j: int, cap: int
) -> tuple[int, int]:  # pragma: no cover - compiled
    """The goal-coloured run of row j through (or next to) column u: (first, last) column, or (-1, -2)."""
    return _row_span(classes, g0, g1, u, j, cap, False)


@nb.njit(cache=True, error_model="python", fastmath=False)
def _row_span(
    classes: NDArray[np.uint8], g0: int, g1: int, u: float, j: int, cap: int, bridge: bool
) -> tuple[int, int]:  # pragma: no cover - compiled
    """:func:`_row_run`; with ``bridge`` single pixels of another colour inside the run (noise)
    do not end it."""
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
    while a - 1 >= 0 and i - a < cap:
        if _is_goal(classes[j, a - 1], g0, g1):
            a -= 1
        elif bridge and a - 2 >= 0 and _is_goal(classes[j, a - 2], g0, g1):
            a -= 2
        else:
            break
    e = i
    while e + 1 < width and e - i < cap:
        if _is_goal(classes[j, e + 1], g0, g1):
            e += 1
        elif bridge and e + 2 < width and _is_goal(classes[j, e + 2], g0, g1):
            e += 2
        else:
            break
    return a, e


@nb.njit(cache=True, error_model="python", fastmath=False)
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


@nb.njit(cache=True, error_model="python", fastmath=False)
def _clear_widths(
    classes: NDArray[np.uint8], g: int, ub: float, vb: float, ut: float, vt: float, last: float, half: float, cap: int
) -> tuple[int, float, float]:  # pragma: no cover - compiled
    """The rows between the foot (ub, vb) (axis to the top (ut, vt)) and row ``last`` in which
    the axis has the goal colour g and neither column ``half`` px left and right of it: how many, and
    the median and the largest width of the goal-coloured row runs through the axis at eight
    of them (px; noise may cut a run short, not lengthen it)."""
    width = classes.shape[1]
    slope = (ut - ub) / (vb - vt) if vb - vt > 1e-9 else 0.0
    top = max(int(last), 0)
    clear = np.empty(max(int(vb) - top, 1), dtype=np.int64)
    n = 0
    for j in range(int(vb) - 1, top - 1, -1):
        u = ub + slope * (vb - (j + 0.5))
        il, ir, ia = math.floor(u - half), math.floor(u + half), math.floor(u)
        if not (0 <= ia < width and classes[j, ia] == g):
            continue
        if not ((0 <= il < width and classes[j, il] == g) or (0 <= ir < width and classes[j, ir] == g)):
            clear[n] = j
            n += 1
    if n == 0:
        return 0, 0.0, 0.0
    k = min(n, 8)
    widths = np.empty(k)
    for q in range(k):
        j = clear[int((q + 0.5) * n / k)]
        first, end = _row_run(classes, g, g, ub + slope * (vb - (j + 0.5)), j, cap)
        widths[q] = end - first + 1.0
    return n, float(np.median(widths)), float(widths.max())


@nb.njit(cache=True, error_model="python", fastmath=False)
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


@nb.njit(cache=True, error_model="python", fastmath=False)
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


@nb.njit(cache=True, error_model="python", fastmath=False)
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
    if g0 == 2 or g1 == 2:
        # white goals: a line seen along the axis in front of the post, narrower than the post,
        # moves the feet down; the post starts where the rows get as wide as a post
        vp = _post_bottom(classes, cam, g0, g1, ua, vb, r, goal_h, prm)
        if vp < vb - 1.5:
            other = _check_at(classes, cam, g0, g1, uc, ua, vp, i0, i1, r, goal_h, prm)
            if other[0] == 0 or res[0] != 0:
                return other
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


@nb.njit(cache=True, error_model="python", fastmath=False)
def _post_bottom(
    classes: NDArray[np.uint8],
    cam: NDArray[np.float64],
    g0: int,
    g1: int,
    ua: float,
    vb: float,
    r: float,
    goal_h: float,
    prm: NDArray[np.float64],
) -> float:  # pragma: no cover - compiled
    """The foot row of the post along the axis through column ``ua`` from the foot ``vb``: the
    row below the lowest that is as wide as a post (0.6 to ``width_range[1]`` diameters),
    when at least two rows narrower than 0.6 diameters (a line seen along the axis) lie
    between; else ``vb``. Rows of the image's width only count where the post is in view."""
    width = classes.shape[1]
    ok, _, _, ut, vt, w_exp = _post_at(cam, ua, vb, r, goal_h)
    if not ok:
        return vb
    slope = (ut - ua) / (vb - vt) if vb - vt > 1e-9 else 0.0
    w_hi = prm[_P_WHI] * w_exp + prm[_P_SLACK]
    narrow = 0
    stop = max(int(vb - 0.5 * (vb - max(vt, 0.0))), 0)
    for j in range(int(vb) - 1, stop - 1, -1):
        u = ua + slope * (vb - (j + 0.5))
        # the post's width in view at this row (it may be cut by the image side)
        w_in = min(u + 0.5 * w_exp, float(width)) - max(u - 0.5 * w_exp, 0.0)
        first, end = _row_span(classes, g0, g1, u, j, int(2.0 * w_exp + 4.0), True)
        wj = end - first + 1.0
        if 0.6 * min(w_exp, w_in) <= wj <= w_hi:
            return float(j + 1) if narrow >= 2 else vb
        if wj < 0.6 * min(w_exp, w_in):
            narrow += 1
    return vb


@nb.njit(cache=True, error_model="python", fastmath=False)
def _post_shape(
    classes: NDArray[np.uint8],
    cam: NDArray[np.float64],
    g: int,
    ub: float,
    vb: float,
    ut: float,
    vt: float,
    last: float,
    w_exp: float,
    w_hi: float,
) -> bool:  # pragma: no cover - compiled
    """Whether the goal-coloured rows between the foot (ub, vb) of a post centred on the axis
    to (ut, vt) and row ``last`` have the sides of a post: the rows are 0.7 to ``w_hi`` /
    ``w_exp`` of the post's width in view, and a side not cut by the image runs along the axis
    (the median distance from the axis of the upper half of the rows differs from that of the
    lower half by at most max(1.5 px, 0.1 px per row between them); the sides of a line cut by
    the image run along the line), and a side that does not lies beyond the post's side in
    every row (something behind the post). Rows right above the foot (the bottom of the
    cylinder is round) are left out. Near the camera the sides converge: they and the axis
    meet in the image of the vertical direction, so distances from the axis are scaled to the
    foot's row by their distances from that point."""
    width = classes.shape[1]
    slope = (ut - ub) / (vb - vt) if vb - vt > 1e-9 else 0.0
    # the row of the vanishing point of vertical lines (none: they are parallel in the image)
    vv = cam[15] - cam[13] * cam[8] / cam[6] if abs(cam[6]) > 1e-9 else math.inf
    lo = vb - 1.0 - 0.25 * w_exp
    if lo - last < 4.0:
        lo = vb - 1.0
    n = 8
    sides = np.full((2, n), np.nan)
    ratio = np.empty(n)
    nr = 0
    rows = np.empty(n)
    for q in range(n):
        j = int(lo - (q + 0.5) * (lo - last) / n)
        rows[q] = j
        u = ub + slope * (vb - (j + 0.5))
        k = (vv - j - 0.5) / (vv - vb) if math.isfinite(vv) and abs(vv - vb) > 1e-6 else 1.0
        k = min(max(k, 0.25), 4.0)
        w_j = k * w_exp
        w_in = min(u + 0.5 * w_j, float(width)) - max(u - 0.5 * w_j, 0.0)
        if w_in < 2.0:
            continue  # the post is beside the image in this row
        # the run through the axis, or through the image side next to it
        first, end = _row_run(classes, g, g, min(max(u, 0.0), width - 0.5), j, int(2.0 * w_j + 4.0))
        if end < first:
            return False
        ratio[nr] = (end - first + 1.0) / w_in
        nr += 1
        if first > 0:
            sides[0, q] = (first - u) / k
        if end < width - 1:
            sides[1, q] = (end + 1.0 - u) / k
    if nr < n // 2:
        return False
    med = np.median(ratio[:nr])
    if med < 0.7 or med * w_exp > w_hi:
        return False
    h = n // 2
    span = abs(np.mean(rows[:h]) - np.mean(rows[h:]))
    edge = 0.5 * w_exp - max(2.0, 0.15 * w_exp)
    along = False
    for s in range(2):
        low = sides[s, :h][~np.isnan(sides[s, :h])]
        high = sides[s, h:][~np.isnan(sides[s, h:])]
        if low.shape[0] >= 2 and high.shape[0] >= 2 and abs(np.median(high) - np.median(low)) <= max(1.5, 0.1 * span):
            along = True
            continue
        # not along the axis: something behind the post, everywhere beyond its side
        for q in range(n):
            if (s == 0 and sides[s, q] > -edge) or (s == 1 and sides[s, q] < edge):
                return False
    return along


@nb.njit(cache=True, error_model="python", fastmath=False)
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
    if g0 != 2 and g1 != 2:  # lines are not goal-coloured: any visible part will do
        vh, okh = vtop, True
    elif (not okh or vh < vtop - 0.5) and filled:
        # white goals, less in view: the sides of a line cut by the image run along the line,
        # those of a post along its axis, a post's width apart
        okh = _post_shape(classes, cam, gs, uc, vb, ut, vt, last, w_exp, prm[_P_WHI] * w_exp + prm[_P_SLACK])
        vh = vtop
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
            # the rows with nothing of the goal colour beside the post: a robot's legs and body
            # are wide all the way, a post is wider only where a net, a wall or a line is behind
            cap = int(4.0 * w_exp + 8.0)
            clear, w_med, w_max = _clear_widths(classes, gs, ua, vb, uta, vta, last, 0.5 * w_exp + 2.0, cap)
            w_in = min(uc + 0.5 * w_exp, float(width)) - max(uc - 0.5 * w_exp, 0.0)
            if clear < max(3.0, 0.15 * (vb - last)):
                w_med = _row_widths(classes, gs, gs, ua, vb, uta, vta, 0.5 * (vb + last), cap)
            elif gs == 2 and w_max < 0.7 * w_in - prm[_P_SLACK]:
                code = 6  # white, narrower than a post where nothing is beside it: a net seen edge-on
            if w_med > prm[_P_WHI] * w_exp + prm[_P_SLACK]:
                code = 6
    return code, bf, share, vb, xc, yc, ut, vt, n0, n1, float(last), col_min


@nb.njit(cache=True, error_model="python", fastmath=False)
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


@nb.njit(cache=True, error_model="python", fastmath=False)
def _candidate(
    classes: NDArray[np.uint8],
    cam: NDArray[np.float64],
    feet: NDArray[np.float64],
    g0: int,
    g1: int,
    a: int,
    e: int,
    r: float,
    goal_h: float,
    prm: NDArray[np.float64],
) -> tuple[_Check, float, float, bool]:  # pragma: no cover - compiled
    """The candidate columns a..e checked as a post (:mod:`.posts` steps 2-3): its width against
    the projected diameter, then along the axis; a run cut by the image side is centred half a
    diameter from its visible edge, and a run too narrow or too wide is searched for the
    windows of one diameter that pass (:func:`_search`). Returns the check, the centre column,
    the projected diameter at the candidate's foot and whether the run was searched."""
    width = classes.shape[1]
    slack = prm[_P_SLACK]
    um = 0.5 * (a + e + 1)
    ok, _, _, _, _, w_exp = _post_at(cam, um, _median_feet(feet, a, e), r, goal_h)
    measured = e - a + 1.0
    left_edge = a <= 1
    right_edge = e >= width - 2
    w_lo = max(prm[_P_WMIN], prm[_P_WLO] * w_exp - slack)
    w_hi = prm[_P_WHI] * w_exp + slack
    res = (1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0, 0, 0.0, 0.0)
    uc = um
    searched = False
    if not ok:
        res = (5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0, 0, 0.0, 0.0)
    elif (left_edge or right_edge) and measured < w_exp:
        # cut by the image edge: the centre is half a diameter from the visible edge and must
        # be in the image (a post whose base centre is outside is not reported)
        uc = e + 1.0 - 0.5 * w_exp if left_edge else a + 0.5 * w_exp
        if measured >= max(prm[_P_WMIN], 0.25 * w_exp) and 0.0 <= uc < width:
            res = _check_axis(classes, cam, feet, g0, g1, uc, um, a, e, r, goal_h, prm)
    elif w_lo <= measured <= 4.0 * w_exp + slack:
        res = _check_axis(classes, cam, feet, g0, g1, um, um, a, e, r, goal_h, prm)
        if measured > w_hi:
            res = (1, res[1], res[2], res[3], res[4], res[5], res[6], res[7], res[8], res[9], res[10], res[11])
        if res[0] != 0 and abs(measured - w_exp) > 1.0:
            # part of a post (the rest stands on a line) or a post in front of a white net,
            # robot or wall: the windows of one diameter that pass and stand lowest
            if measured < w_exp:
                lo, hi = e + 1.0 - 0.5 * w_exp, a + 0.5 * w_exp
            else:
                lo, hi = a + 0.5 * w_exp, e + 1.0 - 0.5 * w_exp
            res, uc = _search(classes, cam, feet, g0, g1, a, e, lo, hi, w_exp, r, goal_h, prm)
            searched = True
    return res, uc, w_exp, searched


@nb.njit(cache=True, error_model="python", fastmath=False)
def _split(
    cam: NDArray[np.float64], feet: NDArray[np.float64], a: int, e: int, r: float, goal_h: float, jump: float
) -> NDArray[np.int64]:  # pragma: no cover - compiled
    """The candidate columns a..e split where the feet of neighbouring columns jump by more
    than ``jump`` px or 0.3 projected diameters (a post next to something standing further
    back, or to a second post): first and last column of each piece (K x 2)."""
    out = np.empty((e - a + 1, 2), dtype=np.int64)
    n = 0
    start = -1
    prev = -1
    for i in range(a, e + 1):
        if feet[i] < 0.0:
            continue
        if start < 0:
            start = i
        elif prev >= 0:
            lower = max(feet[i], feet[prev])
            ok, _, _, _, _, w = _post_at(cam, i + 0.5, lower, r, goal_h)
            if abs(feet[i] - feet[prev]) > max(jump, 0.3 * w if ok else 0.0):
                out[n, 0], out[n, 1] = start, prev
                n += 1
                start = i
        prev = i
    if start >= 0:
        out[n, 0], out[n, 1] = start, prev
        n += 1
    return out[:n]
