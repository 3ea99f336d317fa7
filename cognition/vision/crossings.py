"""Line crossings L, T and X from pairs of line segments (DNT section 3.7).

DNT intersects every pair of detected lines that differ in direction by at least 10 degrees
and whose intersection lies inside the image, and ranks the three crossing types by where
the intersection lies on each line: **T** on one line away from its ends and at an end of
the other, **X** away from the ends of both, **L** at an end of both; two T's close together
with opposite stems form an X. Here the test runs on the ground (the segments' end points
projected with the camera matrix), where SPL field lines meet at right angles, so a pair must
be perpendicular within ``max_angle_error`` plus the direction uncertainty of the shorter
line (atan of two pixels' ground size over its length: a 25 cm arm 2.5 m away is known to
about 18 degrees).

Two steps make the ranking hold up on real images:

* **Collinear pieces are merged first** (on the ground): a line is often cut into pieces where
  a robot or the ball stands on it, or where the white blob of a junction breaks the scanline
  runs, and the two halves of a T's bar would otherwise meet its stem as two L's. SPL field
  lines never continue one another across a gap, so pieces on one carrier line (direction
  within ``merge_angle``, offset within ``merge_offset`` plus 3 % of the distance) with a gap
  of at most ``merge_gap`` are one line.
* **Ends are checked in the image** (DNT's confidence, made strict): segments stop up to a
  few decimetres short of a junction, where the white runs of two lines merge and fail the
  scanlines' width test, so "at an end" is a window reaching ``margin`` beyond the end and
  ``margin_in`` inside it. Whether the line really ends at the junction or goes through it is
  then read from the class image just beyond the junction, on the line's continuation
  (``beyond`` metres or three pixels, past the other line's width): white there means the
  line goes on (the bar of a T, a line of an X), carpet means a real end. Where the image
  does not show it (its edge, the field boundary, a robot), the segment's own end decides if
  carpet followed it in the image (:mod:`.ends`); otherwise the type is unknown and no
  crossing is reported. The gap between a
  segment's end and the junction must itself be white, so that two lines whose extensions
  would meet do not make a crossing.

Orientation as in :class:`cognition.field.LineCrossing` (robot frame): L the bisector of the
two arms, pointing between them; T the stem, pointing away from the junction; X one line's
direction modulo pi/2. Confidence in [0, 1] grows with the arms' visible lengths and with
how close the angle is to 90 degrees. Ground points: robot frame, metres; class codes of
:class:`~cognition.vision.colour.Colour`.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.vision.projection import metres_per_pixel_nb, pixel_nb

L_KIND, T_KIND, X_KIND = 0, 1, 2
GREEN, WHITE = 1, 2
_THROUGH, _END, _OFF, _UNKNOWN = 2, 0, -1, -2


@nb.njit(cache=True, error_model="python", fastmath=False)
def _wrap(a: float) -> float:  # pragma: no cover - compiled
    a = (a + math.pi) % (2.0 * math.pi)
    if a <= 0.0:
        a += 2.0 * math.pi
    return a - math.pi


@nb.njit(cache=True, error_model="python", fastmath=False)
def merge_collinear_nb(
    seg: NDArray[np.float64],
    open_ends: NDArray[np.bool_],
    max_angle: float,
    max_offset: float,
    max_gap: float,
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:  # pragma: no cover - compiled
    """Ground segments (S x 4) merged along their carrier lines (module docstring); returns the
    lines (L x 4) and their open ends (L x 2). Longest pieces first; a merged line keeps the
    direction of its longest piece."""
    n = seg.shape[0]
    lengths = np.empty(n)
    for k in range(n):
        lengths[k] = math.hypot(seg[k, 2] - seg[k, 0], seg[k, 3] - seg[k, 1])
    order = np.argsort(-lengths)
    # per line: origin, unit direction, extent [t0, t1] along it, open flags of both extremes
    org = np.empty((n, 2))
    dirs = np.empty((n, 2))
    ext = np.empty((n, 2))
    opn = np.zeros((n, 2), dtype=np.bool_)
    m = 0
    for q in range(n):
        k = order[q]
        length = lengths[k]
        if length < 1e-9:
            continue
        dx, dy = (seg[k, 2] - seg[k, 0]) / length, (seg[k, 3] - seg[k, 1]) / length
        joined = False
        for j in range(m):
            if abs(dx * dirs[j, 1] - dy * dirs[j, 0]) > math.sin(3.0 * max_angle):
                continue
            ok = True
            ta = np.empty(2)
            for e in range(2):
                px, py = seg[k, 2 * e] - org[j, 0], seg[k, 2 * e + 1] - org[j, 1]
                off = abs(px * dirs[j, 1] - py * dirs[j, 0])
                if off > max_offset + 0.03 * math.hypot(seg[k, 2 * e], seg[k, 2 * e + 1]):
                    ok = False
                ta[e] = px * dirs[j, 0] + py * dirs[j, 1]
            if not ok:
                continue
            lo, hi = min(ta[0], ta[1]), max(ta[0], ta[1])
            if lo > ext[j, 1] + max_gap or hi < ext[j, 0] - max_gap:
                continue
            lo_open = open_ends[k, 0] if ta[0] <= ta[1] else open_ends[k, 1]
            hi_open = open_ends[k, 1] if ta[0] <= ta[1] else open_ends[k, 0]
            if lo < ext[j, 0]:
                ext[j, 0] = lo
                opn[j, 0] = lo_open
            if hi > ext[j, 1]:
                ext[j, 1] = hi
                opn[j, 1] = hi_open
            joined = True
            break
        if not joined:
            org[m, 0], org[m, 1] = seg[k, 0], seg[k, 1]
            dirs[m, 0], dirs[m, 1] = dx, dy
            ext[m, 0], ext[m, 1] = 0.0, length
            opn[m, 0], opn[m, 1] = open_ends[k, 0], open_ends[k, 1]
            m += 1
    lines = np.empty((m, 4))
    for j in range(m):
        lines[j, 0] = org[j, 0] + ext[j, 0] * dirs[j, 0]
        lines[j, 1] = org[j, 1] + ext[j, 0] * dirs[j, 1]
        lines[j, 2] = org[j, 0] + ext[j, 1] * dirs[j, 0]
        lines[j, 3] = org[j, 1] + ext[j, 1] * dirs[j, 1]
    return lines, opn[:m].copy()


@nb.njit(cache=True, error_model="python", fastmath=False)
def look_nb(
    classes: NDArray[np.uint8], boundary: NDArray[np.int32], cam: NDArray[np.float64], x: float, y: float
) -> int:  # pragma: no cover - compiled
    """What the image shows at ground point (x, y): 1 white (the pixel or one of its four
    neighbours), 0 carpet (green, no white near), -1 unknown (outside, above the field
    boundary, anything else)."""
    height, width = classes.shape
    u, v, ok = pixel_nb(cam, x, y, 0.0)
    if not ok or not (1.0 <= u < width - 1 and 1.0 <= v < height - 1):
        return -1
    i, j = int(u), int(v)
    if j < boundary[i] + 1:
        return -1
    c = classes[j, i]
    if c == WHITE or classes[j - 1, i] == WHITE or classes[j + 1, i] == WHITE:
        return 1
    if classes[j, i - 1] == WHITE or classes[j, i + 1] == WHITE:
        return 1
    return 0 if c == GREEN else -1


@nb.njit(cache=True, error_model="python", fastmath=False)
def _continues(
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    px: float,
    py: float,
    dx: float,
    dy: float,
    start: float,
    stop: float,
) -> int:  # pragma: no cover - compiled
    """Whether the line through (px, py) goes on along (dx, dy) between ``start`` and ``stop``
    metres: 1 white, 0 carpet, -1 unknown (three samples, two must agree)."""
    white = 0
    green = 0
    for q in range(3):
        t = start + (stop - start) * q / 2.0
        c = look_nb(classes, boundary, cam, px + t * dx, py + t * dy)
        if c == 1:
            white += 1
        elif c == 0:
            green += 1
    if white >= 2:
        return 1
    if green >= 2:
        return 0
    return -1


@nb.njit(cache=True, error_model="python", fastmath=False)
def _white_gap(
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    ax: float,
    ay: float,
    bx: float,
    by: float,
) -> bool:  # pragma: no cover - compiled
    """Whether the ground gap from (ax, ay) to (bx, by) is mostly white in the image."""
    gap = math.hypot(bx - ax, by - ay)
    if gap < 0.05:
        return True
    n = max(3, int(gap / 0.04))
    white = 0
    seen = 0
    for q in range(n + 1):
        t = q / n
        c = look_nb(classes, boundary, cam, ax + t * (bx - ax), ay + t * (by - ay))
        if c >= 0:
            seen += 1
            white += c
    return seen > 0 and white >= 0.6 * seen


@nb.njit(cache=True, error_model="python", fastmath=False)
def _position(
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    line: NDArray[np.float64],
    is_open: NDArray[np.bool_],
    t: float,
    length: float,
    margin: float,
    margin_in: float,
    beyond: float,
    max_mpp: float,
) -> int:  # pragma: no cover - compiled
    """Where the junction at ``t`` metres from the line's first end lies on it: through it
    (2), at a real end (0; the arm then points back into the line), off the line (-1) or
    unknown (-2)."""
    if t < -margin or t > length + margin:
        return _OFF
    dx, dy = (line[2] - line[0]) / length, (line[3] - line[1]) / length
    px, py = line[0] + t * dx, line[1] + t * dy
    # metres per pixel along the line at the junction: ends and looks scale with it
    u0, v0, ok0 = pixel_nb(cam, px, py, 0.0)
    u1, v1, ok1 = pixel_nb(cam, px + 0.05 * dx, py + 0.05 * dy, 0.0)
    mpp = 0.05 / max(math.hypot(u1 - u0, v1 - v0), 1e-6) if ok0 and ok1 else 0.0
    inside = max(margin_in, 6.0 * mpp)
    if inside <= t <= length - inside:
        return _THROUGH
    if not 0.0 < mpp <= max_mpp:  # too few pixels along the line here to tell an end from a line going on
        return _UNKNOWN
    e = 0 if t < 0.5 * length else 1
    s = -1.0 if e == 0 else 1.0  # outward direction at this end
    ex, ey = line[2 * e], line[2 * e + 1]
    if not _white_gap(classes, boundary, cam, ex, ey, px, py):
        return _OFF
    # look past the other line (and the blur around it): at least three pixels beyond the junction
    start = max(beyond, 4.0 * mpp)
    after = _continues(classes, boundary, cam, px, py, s * dx, s * dy, start, start + max(beyond, 3.0 * mpp))
    if after == 1:
        return _THROUGH
    if after == 0:
        return _END
    # the image does not show what follows the junction (its edge, a robot): trust the segment's
    # own end if carpet followed it in the image (:mod:`.ends`) and it reaches the junction
    if not is_open[e] and abs(t - (0.0 if e == 0 else length)) <= inside:
        return _END
    return _UNKNOWN


@nb.njit(cache=True, error_model="python", fastmath=False)
def crossings_nb(
    seg: NDArray[np.float64],
    open_ends: NDArray[np.bool_],
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    margin: float,
    margin_in: float,
    beyond: float,
    max_angle_error: float,
    min_arm: float,
    merge_distance: float,
    merge_angle: float,
    merge_offset: float,
    merge_gap: float,
    max_mpp: float,
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """Crossings of the ground segments ``seg`` (S x 4, m), C x 6: x, y, kind, orientation,
    confidence, and 1 if it was merged from two T's (module docstring)."""
    lines, opn = merge_collinear_nb(seg, open_ends, merge_angle, merge_offset, merge_gap)
    s = lines.shape[0]
    # direction uncertainty of each line: a pixel's ground size at its middle over its length
    slack = np.zeros(s)
    for k in range(s):
        mx, my = 0.5 * (lines[k, 0] + lines[k, 2]), 0.5 * (lines[k, 1] + lines[k, 3])
        u, v, ok = pixel_nb(cam, mx, my, 0.0)
        if ok:
            mv, mu = metres_per_pixel_nb(cam, u, v)
            length = math.hypot(lines[k, 2] - lines[k, 0], lines[k, 3] - lines[k, 1])
            if math.isfinite(mv) and math.isfinite(mu) and length > 0.0:
                slack[k] = math.atan(2.0 * max(mv, mu) / length)
    out = np.zeros((s * s + 1, 6))
    n = 0
    for a in range(s):
        ax, ay = lines[a, 0], lines[a, 1]
        adx, ady = lines[a, 2] - ax, lines[a, 3] - ay
        la = math.hypot(adx, ady)
        if la < min_arm:
            continue
        for b in range(a + 1, s):
            bx, by = lines[b, 0], lines[b, 1]
            bdx, bdy = lines[b, 2] - bx, lines[b, 3] - by
            lb = math.hypot(bdx, bdy)
            if lb < min_arm:
                continue
            cross = adx * bdy - ady * bdx
            sin_angle = abs(cross) / (la * lb)
            tolerance = min(max_angle_error + max(slack[a], slack[b]), 0.5 * math.pi - 0.2)
            if sin_angle < math.cos(tolerance):  # not perpendicular enough
                continue
            ta = ((bx - ax) * bdy - (by - ay) * bdx) / cross  # fraction along a
            tb = ((bx - ax) * ady - (by - ay) * adx) / cross  # fraction along b
            px, py = ax + ta * adx, ay + ta * ady
            pa = _position(classes, boundary, cam, lines[a], opn[a], ta * la, la, margin, margin_in, beyond, max_mpp)
            if pa < 0:
                continue
            pb = _position(classes, boundary, cam, lines[b], opn[b], tb * lb, lb, margin, margin_in, beyond, max_mpp)
            if pb < 0:
                continue
            # arms: unit vectors from the junction toward the far ends
            ea = 0 if ta < 0.5 else 1
            eb = 0 if tb < 0.5 else 1
            ua = (adx / la, ady / la) if ea == 0 else (-adx / la, -ady / la)
            ub = (bdx / lb, bdy / lb) if eb == 0 else (-bdx / lb, -bdy / lb)
            if pa == _THROUGH and pb == _THROUGH:
                kind = X_KIND
                o = math.atan2(ady, adx) % (0.5 * math.pi)
            elif pa == _THROUGH:
                kind = T_KIND
                o = math.atan2(ub[1], ub[0])
            elif pb == _THROUGH:
                kind = T_KIND
                o = math.atan2(ua[1], ua[0])
            else:
                kind = L_KIND
                o = math.atan2(ua[1] + ub[1], ua[0] + ub[0])
            conf = min(1.0, la / (4.0 * min_arm)) * min(1.0, lb / (4.0 * min_arm)) * sin_angle
            out[n, 0] = px
            out[n, 1] = py
            out[n, 2] = kind
            out[n, 3] = o if kind == X_KIND else _wrap(o)
            out[n, 4] = conf
            out[n, 5] = 0.0
            n += 1
    # two T's close together with opposite stems are an X (DNT 3.7)
    keep = np.ones(n, dtype=np.bool_)
    for i in range(n):
        if not keep[i] or out[i, 2] != T_KIND:
            continue
        for j in range(i + 1, n):
            if not keep[j] or out[j, 2] != T_KIND:
                continue
            if math.hypot(out[i, 0] - out[j, 0], out[i, 1] - out[j, 1]) > merge_distance:
                continue
            if abs(_wrap(out[i, 3] - out[j, 3])) < 0.8 * math.pi:
                continue
            out[i, 0] = 0.5 * (out[i, 0] + out[j, 0])
            out[i, 1] = 0.5 * (out[i, 1] + out[j, 1])
            out[i, 2] = X_KIND
            out[i, 3] = out[i, 3] % (0.5 * math.pi)
            out[i, 4] = max(out[i, 4], out[j, 4])
            out[i, 5] = 1.0
            keep[j] = False
    # duplicates (the same junction from several line pairs): keep the most confident
    for i in range(n):
        if not keep[i]:
            continue
        for j in range(i + 1, n):
            if keep[j] and math.hypot(out[i, 0] - out[j, 0], out[i, 1] - out[j, 1]) < merge_distance:
                if out[j, 4] > out[i, 4]:
                    out[i, :] = out[j, :]
                keep[j] = False
    return out[:n][keep]
