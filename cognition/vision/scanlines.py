"""Line points from scanlines: the centres of white runs between green (DNT section 3.6.2).

DNT scans the binarized image every 5-10 pixels vertically and horizontally and keeps the
middle of every dark-white-dark transition as a line point. Here the scan runs on the
class image below the field boundary; "dark" is carpet green (at most ``max_gap`` pixels of
anything else between the green and the white, for blurred edges), and a run counts only if
its length fits a painted line: at most about twice the width a line of the field's line
width has at that pixel (from the camera matrix), so that robots' white bodies, the modern
goals' posts and large white blobs do not become line points, and at least about half of it,
so that the strands of a goal's net (much thinner than a line) do not either. Motion blur
while the head turns widens a line by the blur length (px) along the scan, which the caller
knows from the head rates and the exposure, and the upper limit grows by it.

A point is ``(u, v, run, direction)``: pixel centre of the run, its length (px) and 0 for a
vertical scan (a column), 1 for a horizontal one (a row).
"""

from __future__ import annotations

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.vision.projection import metres_per_pixel_along_nb

WHITE = 2
GREEN = 1


@nb.njit(cache=True, inline="always")
def _green_within(classes: NDArray[np.uint8], j: int, i: int, dj: int, di: int, gap: int) -> bool:  # pragma: no cover
    """True if a green pixel lies within ``gap`` steps of (j, i) in direction (dj, di), before any white."""
    height, width = classes.shape
    for k in range(gap):
        jj, ii = j + k * dj, i + k * di
        if jj < 0 or jj >= height or ii < 0 or ii >= width:
            return False
        c = classes[jj, ii]
        if c == GREEN:
            return True
        if c == WHITE:
            return False
    return False


@nb.njit(cache=True, inline="always")
def _accept(
    cam: NDArray[np.float64], u: float, v: float, run: int, vertical: bool, width: float, blur: float
) -> bool:  # pragma: no cover
    """Whether a run of ``run`` px centred at (u, v) fits a painted line of ``width`` m seen
    along the scan (module docstring), with ``blur`` px of motion blur along it."""
    m = metres_per_pixel_along_nb(cam, u, v, vertical)
    if not np.isfinite(m) or m <= 0.0:
        return False
    expected = width / m
    return run <= 2.0 * expected + 2.0 + blur and run >= 0.5 * expected - 0.5


_ZERO = np.uint64(0)
_ONES = np.uint64(0x0101010101010101)
_HIGHS = np.uint64(0x8080808080808080)
_WHITES = np.uint64(WHITE * 0x0101010101010101)


@nb.njit(cache=True, inline="always")
def _next_white(line: NDArray[np.uint8], words: NDArray[np.uint64], k: int, end: int) -> int:  # pragma: no cover
    """The first index in [k, end) where ``line`` is WHITE, else ``end``. ``words`` is ``line``
    seen as 64-bit words: at a word boundary, eight pixels without WHITE are skipped at once (a
    word has a WHITE byte exactly when its XOR with all-WHITE bytes has a zero byte)."""
    while k < end:
        if k & 7 == 0:
            x = words[k >> 3] ^ _WHITES
            if (x - _ONES) & ~x & _HIGHS == _ZERO:
                k += 8
                continue
        if line[k] == WHITE:
            return k
        k += 1
    return end


@nb.njit(cache=True, inline="always")
def _copy_column(classes: NDArray[np.uint8], i: int, j: int, line: NDArray[np.uint8]) -> None:  # pragma: no cover
    """``line[j:height] = classes[j:, i]`` (``j`` >= 0), by unsigned indices: numba then leaves
    out its wraparound of negative indices, which costs more than the copy itself."""
    ui = np.uint64(i)
    for q in range(np.uint64(j), np.uint64(classes.shape[0])):
        line[q] = classes[q, ui]


@nb.njit(cache=True, inline="always")
def _copy_row(
    classes: NDArray[np.uint8], boundary: NDArray[np.int32], j: int, line: NDArray[np.uint8]
) -> None:  # pragma: no cover
    """``line[:width] = classes[j]``, with the pixels above the field boundary (``j <
    boundary[i]``) set to 0 (no WHITE): the scan then skips the white above the field (goals,
    robots, the hall: most of a row's white) eight pixels at a time instead of one by one,
    and a run ends where the boundary cuts it, as it must."""
    row = classes[j]
    for q in range(np.uint64(classes.shape[1])):
        line[q] = row[q] if j >= boundary[q] else 0


@nb.njit(cache=True, error_model="python", fastmath=False)
def line_points_nb(
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    step: int,
    line_width: float,
    max_gap: int,
    blur_u: float,
    blur_v: float,
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """All line points of the vertical and horizontal scanlines (module docstring), K x 4;
    ``blur_u`` and ``blur_v`` are the motion blur lengths (px) along rows and columns.

    Each scanline is first copied into a contiguous buffer (a column's pixels lie one image row
    apart), where :func:`_next_white` finds the next WHITE pixel eight pixels at a time; a
    row's pixels above the field boundary are copied as 0 (:func:`_copy_row`), so the scan
    never stops on them. The helpers are inlined (``inline="always"``, compiled with this
    function's flags): as calls, each would take and release a reference to its array
    arguments (atomic operations that cost more than a helper's work) for every run."""
    height, width = classes.shape
    cap = (width // step + 1) * height // 2 + (height // step + 1) * width // 2 + 16
    out = np.empty((cap, 4))
    n = 0
    line = np.zeros((max(height, width) + 15) // 8 * 8, dtype=np.uint8)  # zero past the scanline: no WHITE
    words = line.view(np.uint64)
    for i in range(step // 2, width, step):
        j = max(boundary[i], 0)
        _copy_column(classes, i, j, line)
        while j < height and n < cap:
            j = _next_white(line, words, j, height)
            if j >= height:
                break
            j0 = j
            while j < height and line[j] == WHITE:
                j += 1
            run = j - j0
            before = j0 == boundary[i] or _green_within(classes, j0 - 1, i, -1, 0, max_gap)
            after = j < height and _green_within(classes, j, i, 1, 0, max_gap)
            vm = 0.5 * (j0 + j)
            if before and after and _accept(cam, i + 0.5, vm, run, True, line_width, blur_v):
                out[n, 0] = i + 0.5
                out[n, 1] = vm
                out[n, 2] = run
                out[n, 3] = 0.0
                n += 1
    for j in range(step // 2, height, step):
        _copy_row(classes, boundary, j, line)
        i = 0
        while i < width and n < cap:
            i = _next_white(line, words, i, width)
            if i >= width:
                break
            i0 = i
            while i < width and line[i] == WHITE:
                i += 1
            run = i - i0
            before = _green_within(classes, j, i0 - 1, 0, -1, max_gap)
            after = i < width and _green_within(classes, j, i, 0, 1, max_gap)
            um = 0.5 * (i0 + i)
            if before and after and _accept(cam, um, j + 0.5, run, False, line_width, blur_u):
                out[n, 0] = um
                out[n, 1] = j + 0.5
                out[n, 2] = run
                out[n, 3] = 1.0
                n += 1
    points = np.empty((n, 4))  # a copy: a view would keep the large buffer alive
    for k in range(n):
        for c in range(4):
            points[k, c] = out[k, c]
    return points
