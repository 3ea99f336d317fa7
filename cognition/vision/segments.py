"""Line segments from line points: greedy chaining and collinear merging (DNT section 3.6.2).

DNT's Algorithm 1: starting from a point, repeatedly look at the five nearest unused points,
keep those whose connection to the chain's end is covered by white (the white ratio), and
append the best one as long as the chain stays straight; straightness is the paper's error
function (eq. 1), the sum of the squared distances of the chain's points from a line,
compared here with ``tolerance^2`` times the number of points. DNT measures it about the
line through the chain's first and last point; here it is measured about the chain's
least-squares line (kept as running sums, so each test costs the same for any chain
length), which a single stray first point cannot throw off; and no single point may lie
farther than ``2 tolerance`` from it, or a long chain would swallow a point of a line that
meets it. A chain that cannot grow is stored; before it is stored, DNT checks whether it
extends an already stored line: two segments merge when the error of all their points
about the line through the two farthest end points stays small and the gap between their
nearest ends is covered by white.

Two additions: a chain grows from both of its ends (the first point may lie in the middle of
a line) and only forwards (the next point must not turn back), and the five nearest points
are looked up in a grid of buckets instead of a scan over all points (the points'
coordinates and used flags are kept in the grid's order, so a lookup reads them in sequence).

Pixels: ``u`` right, ``v`` down. Output: per segment the least-squares line's end points
``(u1, v1, u2, v2)`` (the extreme points projected onto the fitted line) and the number of
points; per point the index of its segment or -1.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

WHITE = 2


@nb.njit(cache=True, inline="always")
def white_ratio_nb(
    classes: NDArray[np.uint8], u0: float, v0: float, u1: float, v1: float, at_least: float = 0.0, above: float = -1.0
) -> float:  # pragma: no cover
    """Share of the samples along the pixel segment that are white (or have a white 4-neighbour).

    Returns -1 as soon as the misses so far make it certain that the share will be below
    ``at_least`` or not above ``above`` (a caller that would reject such a share anyway
    stops reading pixels early); the defaults never stop early."""
    height, width = classes.shape
    n = int(max(abs(u1 - u0), abs(v1 - v0))) + 1
    white = 0
    misses = 0
    for k in range(n + 1):
        t = k / n
        i = int(u0 + (u1 - u0) * t)
        j = int(v0 + (v1 - v0) * t)
        if (
            0 <= i < width
            and 0 <= j < height
            and (
                classes[j, i] == WHITE
                or (i > 0 and classes[j, i - 1] == WHITE)
                or (i + 1 < width and classes[j, i + 1] == WHITE)
                or (j > 0 and classes[j - 1, i] == WHITE)
                or (j + 1 < height and classes[j + 1, i] == WHITE)
            )
        ):
            white += 1
            continue
        misses += 1
        best = (n + 1 - misses) / (n + 1)  # the share if every remaining sample is white
        if best < at_least or best <= above:
            return -1.0
    return white / (n + 1)


@nb.njit(cache=True, error_model="python", fastmath=False)
def _scatter_error(sums: NDArray[np.float64], x: float, y: float) -> float:  # pragma: no cover - compiled
    """Sum of squared distances from their least-squares line of the points in ``sums`` plus (x, y).

    ``sums`` holds n, sum x, sum y, sum xx, sum xy, sum yy; the result is the smaller
    eigenvalue of the scatter matrix.
    """
    n = sums[0] + 1.0
    sx, sy = sums[1] + x, sums[2] + y
    cxx = sums[3] + x * x - sx * sx / n
    cxy = sums[4] + x * y - sx * sy / n
    cyy = sums[5] + y * y - sy * sy / n
    half = 0.5 * (cxx + cyy)
    return max(0.0, half - math.sqrt(max(0.0, 0.25 * (cxx - cyy) ** 2 + cxy * cxy)))


@nb.njit(cache=True, error_model="python", fastmath=False)
def _line_of(sums: NDArray[np.float64]) -> tuple[float, float, float, float]:  # pragma: no cover - compiled
    """The least-squares line of the points in ``sums``: its centroid (mx, my) and the sine and
    cosine of its direction (all 0 below 3 points: then no point counts as off the line)."""
    n = sums[0]
    if n < 3.0:
        return 0.0, 0.0, 0.0, 0.0
    mx, my = sums[1] / n, sums[2] / n
    cxx = sums[3] - n * mx * mx
    cxy = sums[4] - n * mx * my
    cyy = sums[5] - n * my * my
    theta = 0.5 * math.atan2(2.0 * cxy, cxx - cyy)
    return mx, my, math.sin(theta), math.cos(theta)


@nb.njit(cache=True, error_model="python", fastmath=False)
def _add(sums: NDArray[np.float64], x: float, y: float) -> None:  # pragma: no cover - compiled
    sums[0] += 1.0
    sums[1] += x
    sums[2] += y
    sums[3] += x * x
    sums[4] += x * y
    sums[5] += y * y


@nb.njit(cache=True, error_model="python", fastmath=False)
def buckets_nb(key: NDArray[np.int64], m: int) -> tuple:  # pragma: no cover - compiled
    """Counting sort of ``key`` (N integers in [0, m)): the start offset of every key (m + 1,
    CSR) and the indices 0..N-1 in key order, ascending within a key."""
    n = key.shape[0]
    count = np.zeros(m + 1, dtype=np.int64)
    for p in range(n):
        count[key[p] + 1] += 1
    for c in range(m):
        count[c + 1] += count[c]
    order = np.empty(n, dtype=np.int64)
    fill = count[:-1].copy()
    for p in range(n):
        order[fill[key[p]]] = p
        fill[key[p]] += 1
    return count, order


@nb.njit(cache=True, error_model="python", fastmath=False)
def grid_nb(pts: NDArray[np.float64], cell: float, gw: int, gh: int) -> tuple:  # pragma: no cover
    """Bucket the points (columns 0, 1: their coordinates) into a gw x gh grid of ``cell``-sized
    cells (CSR: start offsets per cell and the point order, :func:`buckets_nb`)."""
    n = pts.shape[0]
    key = np.empty(n, dtype=np.int64)
    for p in range(n):
        gx = min(gw - 1, int(pts[p, 0] / cell))
        gy = min(gh - 1, int(pts[p, 1] / cell))
        key[p] = gy * gw + gx
    return buckets_nb(key, gw * gh)


@nb.njit(cache=True, inline="always")
def _extend(
    pts: NDArray[np.float64],
    classes: NDArray[np.uint8],
    chain: NDArray[np.int64],
    lo: int,
    hi: int,
    tail: bool,
    taken: NDArray[np.bool_],
    start: NDArray[np.int64],
    order: NDArray[np.int64],
    gu: NDArray[np.float64],
    gv: NDArray[np.float64],
    cell: float,
    gw: int,
    gh: int,
    gap: float,
    tolerance: float,
    min_white: float,
    sums: NDArray[np.float64],
    best_d: NDArray[np.float64],
    best_p: NDArray[np.int64],
) -> int:  # pragma: no cover - compiled
    """The best next point at the chain's tail (or head), or -1 (DNT Algorithm 1, lines 5-9);
    ``best_d`` and ``best_p`` (5 each) are scratch space for the five nearest candidates.

    The candidates are read in the grid's order (``start``, ``order`` of :func:`grid_nb`):
    ``gu``, ``gv`` and ``taken`` hold every point's coordinates and whether it is used at its
    place in ``order``, so the search reads them in sequence, and the three cells of a grid
    row, adjacent in that order, are one run of places. Points certainly beyond ``gap`` or
    beyond the fifth nearest so far (by their squared distance, with a margin above its
    rounding), and points behind the chain's end, are passed over without :func:`math.hypot`
    (the same points are kept as when every distance is computed). Inlined into
    :func:`segments_nb` with :func:`white_ratio_nb` (``inline="always"``, compiled with its
    flags): as calls, every step of a chain would take and release a reference to each array
    argument, atomic operations that cost more than the search."""
    end = chain[hi - 1] if tail else chain[lo]
    other = chain[lo] if tail else chain[hi - 1]
    ex, ey = pts[end, 0], pts[end, 1]
    fx, fy = ex - pts[other, 0], ey - pts[other, 1]
    gx0 = int(ex / cell)
    gy0 = int(ey / cell)
    gx1, gx2 = min(gw, max(0, gx0 - 1)), min(gw, gx0 + 2)
    best_d[:] = np.inf
    best_p[:] = -1
    far2 = gap * gap * (1.0 + 1e-9)  # a margin far above the rounding errors of either distance
    worst2 = np.inf  # the same bound on the fifth nearest so far: a point beyond it cannot enter
    forward = hi - lo >= 2
    for gy in range(max(0, gy0 - 1), min(gh, gy0 + 2)):
        for k in range(start[gy * gw + gx1], start[gy * gw + max(gx1, gx2)]):
            if taken[k]:
                continue
            dx, dy = gu[k] - ex, gv[k] - ey
            q = dx * dx + dy * dy
            if q > far2 or q > worst2:
                continue  # certainly farther than gap or than the fifth nearest: no math.hypot needed
            if forward and dx * fx + dy * fy <= 0.0:
                continue  # would turn back
            d = math.hypot(dx, dy)
            if d > gap or d < 1e-9:
                continue
            # keep the five nearest (insertion into a sorted list of five)
            if d < best_d[4]:
                m = 4
                while m > 0 and best_d[m - 1] > d:
                    best_d[m] = best_d[m - 1]
                    best_p[m] = best_p[m - 1]
                    m -= 1
                best_d[m] = d
                best_p[m] = order[k]
                worst2 = best_d[4] * best_d[4] * (1.0 + 1e-9)
    choice = -1
    choice_ratio = -1.0
    have_line = False  # the chain's line (trigonometry) is computed once, for the first candidate needing it
    mx = my = sn = cs = 0.0
    for m in range(5):
        p = best_p[m]
        if p < 0:
            break
        # eq. 1 for the chain with p appended, about the chain's least-squares line (cheap: first)
        e = _scatter_error(sums, pts[p, 0], pts[p, 1])
        if e > tolerance * tolerance * (hi - lo + 1):
            continue
        if not have_line:
            mx, my, sn, cs = _line_of(sums)
            have_line = True
        if abs(-(pts[p, 0] - mx) * sn + (pts[p, 1] - my) * cs) > 2.0 * tolerance:
            continue  # farther than 2 tolerance from the chain's line (0 below 3 points)
        ratio = white_ratio_nb(classes, ex, ey, pts[p, 0], pts[p, 1], min_white, choice_ratio)
        if ratio < min_white or ratio <= choice_ratio:
            continue
        choice = p
        choice_ratio = ratio
    return choice


@nb.njit(cache=True, error_model="python", fastmath=False)
def _fit(
    pts: NDArray[np.float64], first: NDArray[np.int64], second: NDArray[np.int64], out: NDArray[np.float64]
) -> float:  # pragma: no cover - compiled
    """Least-squares line of the points ``first`` followed by ``second`` (summed in that order,
    so a trial merge needs no concatenated copy): end points into ``out[0:4]``; returns the rms
    distance."""
    n = first.shape[0] + second.shape[0]
    mx = 0.0
    my = 0.0
    for idx in (first, second):
        for p in idx:
            mx += pts[p, 0]
            my += pts[p, 1]
    mx /= n
    my /= n
    sxx = 0.0
    sxy = 0.0
    syy = 0.0
    for idx in (first, second):
        for p in idx:
            dx, dy = pts[p, 0] - mx, pts[p, 1] - my
            sxx += dx * dx
            sxy += dx * dy
            syy += dy * dy
    theta = 0.5 * math.atan2(2.0 * sxy, sxx - syy)
    c, s = math.cos(theta), math.sin(theta)
    tmin, tmax, r2 = np.inf, -np.inf, 0.0
    for idx in (first, second):
        for p in idx:
            dx, dy = pts[p, 0] - mx, pts[p, 1] - my
            t = dx * c + dy * s
            tmin = min(tmin, t)
            tmax = max(tmax, t)
            q = -dx * s + dy * c
            r2 += q * q
    out[0] = mx + tmin * c
    out[1] = my + tmin * s
    out[2] = mx + tmax * c
    out[3] = my + tmax * s
    return math.sqrt(r2 / n)


@nb.njit(cache=True, error_model="python", fastmath=False)
def segments_nb(
    pts: NDArray[np.float64],
    classes: NDArray[np.uint8],
    gap: float,
    tolerance: float,
    min_white: float,
    min_points: int,
    merge_angle: float,
) -> tuple:  # pragma: no cover - compiled
    """Chain the points into segments and merge collinear neighbours (module docstring).

    Returns ``(segments, labels)``: segments S x 5 (u1, v1, u2, v2, number of points) and the
    segment index of every point (-1: in no segment).
    """
    n = pts.shape[0]
    labels = np.full(n, -1, dtype=np.int64)
    if n == 0:
        return np.zeros((0, 5)), labels
    height, width = classes.shape
    cell = max(gap, 1.0)
    gw = int(width / cell) + 1
    gh = int(height / cell) + 1
    start, order = grid_nb(pts, cell, gw, gh)
    place = np.empty(n, dtype=np.int64)  # each point's place in the grid's order
    gu = np.empty(n)
    gv = np.empty(n)
    for k in range(n):
        place[order[k]] = k
        gu[k] = pts[order[k], 0]
        gv[k] = pts[order[k], 1]
    taken = np.zeros(n, dtype=np.bool_)  # used, by place
    chain = np.empty(2 * n + 2, dtype=np.int64)
    sums = np.zeros(6)
    best_d = np.empty(5)
    best_p = np.empty(5, dtype=np.int64)
    n_seg = 0
    for s in range(n):
        if taken[place[s]]:
            continue
        lo = n + 1
        hi = n + 2
        chain[lo] = s
        taken[place[s]] = True
        sums[:] = 0.0
        _add(sums, pts[s, 0], pts[s, 1])
        for tail in (True, False):
            while True:
                p = _extend(
                    pts, classes, chain, lo, hi, tail, taken, start, order, gu, gv, cell, gw, gh, gap, tolerance,
                    min_white, sums, best_d, best_p,
                )  # fmt: skip
                if p < 0:
                    break
                taken[place[p]] = True
                _add(sums, pts[p, 0], pts[p, 1])
                if tail:
                    chain[hi] = p
                    hi += 1
                else:
                    lo -= 1
                    chain[lo] = p
        if hi - lo >= 2:
            for k in range(lo, hi):
                labels[chain[k]] = n_seg
            n_seg += 1
    # merge collinear, connected chains (DNT storeLine)
    ends = np.zeros((n_seg, 4))
    alive = np.ones(n_seg, dtype=np.bool_)
    members = [np.empty(0, dtype=np.int64) for _ in range(0)]
    sizes = np.zeros(n_seg + 1, dtype=np.int64)
    for p in range(n):
        if labels[p] >= 0:
            sizes[labels[p] + 1] += 1
    for g in range(n_seg):
        sizes[g + 1] += sizes[g]
    flat = np.empty(sizes[n_seg], dtype=np.int64)
    fill = sizes[:n_seg].copy()
    for p in range(n):  # the points of each chain, in increasing index as np.where gave them
        if labels[p] >= 0:
            flat[fill[labels[p]]] = p
            fill[labels[p]] += 1
    none = np.empty(0, dtype=np.int64)
    theta = np.empty(n_seg)  # direction of each chain's line (kept with its ends: atan2 once per change)
    for g in range(n_seg):
        members.append(flat[sizes[g] : sizes[g + 1]].copy())
        _fit(pts, members[g], none, ends[g])
        theta[g] = _direction(ends[g])
    trial = np.empty(4)
    merged = True
    passes = 0
    while merged and passes < 6:
        merged = False
        passes += 1
        for a in range(n_seg):
            if not alive[a]:
                continue
            for b in range(a + 1, n_seg):
                if not alive[b]:
                    continue
                if not _collinear(theta[a], theta[b], merge_angle):
                    continue
                rms = _fit(pts, members[a], members[b], trial)
                if rms > tolerance:
                    continue
                if not _connected(classes, ends[a], ends[b], gap, min_white):
                    continue
                members[a] = np.concatenate((members[a], members[b]))
                ends[a, :] = trial
                theta[a] = _direction(trial)
                alive[b] = False
                merged = True
    count = 0
    for g in range(n_seg):
        if alive[g] and members[g].shape[0] >= min_points:
            count += 1
    out = np.zeros((count, 5))
    labels[:] = -1
    k = 0
    for g in range(n_seg):
        if alive[g] and members[g].shape[0] >= min_points:
            out[k, :4] = ends[g]
            out[k, 4] = members[g].shape[0]
            for p in members[g]:
                labels[p] = k
            k += 1
    return out, labels


@nb.njit(cache=True, error_model="python", fastmath=False)
def _direction(a: NDArray[np.float64]) -> float:  # pragma: no cover - compiled
    """Direction (rad) of the segment ``a`` (u1, v1, u2, v2) from its first end to its second."""
    return math.atan2(a[3] - a[1], a[2] - a[0])


@nb.njit(cache=True, error_model="python", fastmath=False)
def _collinear(ta: float, tb: float, max_angle: float) -> bool:  # pragma: no cover - compiled
    """Directions ``ta`` and ``tb`` (rad) differ by at most ``max_angle`` as undirected lines."""
    d = abs(ta - tb) % math.pi
    return min(d, math.pi - d) <= max_angle


@nb.njit(cache=True, error_model="python", fastmath=False)
def _connected(
    classes: NDArray[np.uint8], a: NDArray[np.float64], b: NDArray[np.float64], gap: float, min_white: float
) -> bool:  # pragma: no cover
    """The nearest ends of a and b are close, or the gap between them is covered by white."""
    best = np.inf
    bi, bj = 0, 0
    for i in range(2):
        for j in range(2):
            d = math.hypot(a[2 * i] - b[2 * j], a[2 * i + 1] - b[2 * j + 1])
            if d < best:
                best, bi, bj = d, i, j
    # overlapping segments (one end inside the other's span) are connected
    if best <= gap:
        return True
    return white_ratio_nb(classes, a[2 * bi], a[2 * bi + 1], b[2 * bj], b[2 * bj + 1], min_white) >= min_white
