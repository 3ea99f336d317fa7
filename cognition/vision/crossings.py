"""Line crossings L, T and X from pairs of line segments (DNT section 3.7).

DNT intersects every pair of detected lines that differ in direction by at least 10 degrees
and whose intersection lies inside the image, and ranks the three crossing types by where
the intersection lies on each line: **T** on one line away from its ends and at an end of
the other, **X** away from the ends of both, **L** at an end of both; two T's close together
with opposite stems form an X. Here the test runs on the ground (the segments' end points
projected with the camera matrix), where SPL field lines meet at right angles, so a pair must
be perpendicular within ``max_angle_error``; "at an end" means within ``margin`` metres of
it. An end that the segment has only because the line leaves the image, disappears behind a
robot or reaches the field boundary (an *open* end) says nothing about where the line ends,
so a crossing that needs it as a real end is not reported (DNT's confidence, made strict).

Orientation as in :class:`cognition.field.LineCrossing` (robot frame): L the bisector of the
two arms, pointing between them; T the stem, pointing away from the junction; X one line's
direction modulo pi/2. Confidence in [0, 1] grows with the arms' visible lengths and with
how close the angle is to 90 degrees.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

L_KIND, T_KIND, X_KIND = 0, 1, 2


@nb.njit(cache=True)
def _wrap(a: float) -> float:  # pragma: no cover - compiled
    a = (a + math.pi) % (2.0 * math.pi)
    if a <= 0.0:
        a += 2.0 * math.pi
    return a - math.pi


@nb.njit(cache=True)
def _position(t: float, length: float, margin: float, open0: bool, open1: bool) -> int:  # pragma: no cover
    """Where the intersection at ``t`` (m from end 0) lies: -1 off, 0 / 1 at that end, 2 inside, -2 unknown."""
    if t < -margin or t > length + margin:
        return -1
    if t < margin:
        return -2 if open0 else 0
    if t > length - margin:
        return -2 if open1 else 1
    return 2


@nb.njit(cache=True)
def crossings_nb(
    seg: NDArray[np.float64],
    open_ends: NDArray[np.bool_],
    margin: float,
    max_angle_error: float,
    min_arm: float,
    merge_distance: float,
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """Crossings of the ground segments ``seg`` (S x 4, m), C x 6: x, y, kind, orientation,
    confidence, and 1 if it was merged from two T's."""
    s = seg.shape[0]
    out = np.zeros((s * s + 1, 6))
    n = 0
    for a in range(s):
        ax, ay = seg[a, 0], seg[a, 1]
        adx, ady = seg[a, 2] - ax, seg[a, 3] - ay
        la = math.hypot(adx, ady)
        if la < min_arm:
            continue
        for b in range(a + 1, s):
            bx, by = seg[b, 0], seg[b, 1]
            bdx, bdy = seg[b, 2] - bx, seg[b, 3] - by
            lb = math.hypot(bdx, bdy)
            if lb < min_arm:
                continue
            cross = adx * bdy - ady * bdx
            sin_angle = abs(cross) / (la * lb)
            if sin_angle < math.cos(max_angle_error):  # not perpendicular enough
                continue
            ta = ((bx - ax) * bdy - (by - ay) * bdx) / cross  # fraction along a
            tb = ((bx - ax) * ady - (by - ay) * adx) / cross  # fraction along b
            px, py = ax + ta * adx, ay + ta * ady
            pa = _position(ta * la, la, margin, open_ends[a, 0], open_ends[a, 1])
            pb = _position(tb * lb, lb, margin, open_ends[b, 0], open_ends[b, 1])
            if pa < 0 or pb < 0:
                continue
            # arms: unit vectors from the junction toward the far ends
            ua = (adx / la, ady / la) if pa == 0 else (-adx / la, -ady / la)
            ub = (bdx / lb, bdy / lb) if pb == 0 else (-bdx / lb, -bdy / lb)
            if pa == 2 and pb == 2:
                kind = X_KIND
                o = math.atan2(ady, adx) % (0.5 * math.pi)
            elif pa == 2:
                kind = T_KIND
                o = math.atan2(ub[1], ub[0])
            elif pb == 2:
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
    # duplicates (the same junction from several segment pairs): keep the most confident
    for i in range(n):
        if not keep[i]:
            continue
        for j in range(i + 1, n):
            if keep[j] and math.hypot(out[i, 0] - out[j, 0], out[i, 1] - out[j, 1]) < merge_distance:
                if out[j, 4] > out[i, 4]:
                    out[i, :] = out[j, :]
                keep[j] = False
    return out[:n][keep]
