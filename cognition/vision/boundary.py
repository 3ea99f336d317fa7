"""Field boundary: where the carpet starts in each image column (DNT section 3.4).

DNT's background removal scans each column from the top and takes the first run of a set
number of consecutive green pixels as the start of the field; everything above it is
background, never a field feature. The hall around a field holds green boards, green
shirts and bright walls, so a single green pixel says nothing, and a run of green does.
Two additions: the scan starts a little above the horizon of the camera matrix (the carpet
is on the ground, so it can never appear above the horizon; this skips the hall's upper
half) and the run length scales with the image height.

Result: an ``int32`` array with one entry per column, the first row (``v``) of the field
in that column, or the image height when the column shows no field.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.camera import CameraMatrix
from cognition.vision.colour import camera_row
from cognition.vision.projection import horizon_row_nb


def field_boundary(
    classes: NDArray[np.uint8], camera: CameraMatrix | NDArray[np.float64] | None, min_run: int
) -> NDArray[np.int32]:
    """The first field row of each column of the class image (see the module docstring);
    ``camera`` is the camera matrix, its row (:meth:`CameraMatrix.as_row`) or ``None``."""
    out = np.empty(classes.shape[1], dtype=np.int32)
    cam = camera_row(camera)
    _boundary(classes, cam, max(1, int(min_run)), out)
    return out


_GROUP = 64
"""Columns scanned together, row by row (one cache line of the class image per row)."""


@nb.njit(cache=True, error_model="python", fastmath=False)
def _boundary(
    classes: NDArray[np.uint8], cam: NDArray[np.float64], run: int, out: NDArray[np.int32]
) -> None:  # pragma: no cover - compiled
    """The scan of the module docstring for every column of ``classes`` into ``out``.

    Each column's scan is the same as reading it from its start row down, but the columns go
    in groups of :data:`_GROUP`, read row by row (contiguous pixels) with branch-free updates
    of every column's green run that the compiler vectorizes, until every column of the group
    has found its run: about twice as fast as reading column by column."""
    height, width = classes.shape
    start = np.empty(width, dtype=np.int32)
    n = np.zeros(width, dtype=np.int32)
    h32, r32, none = np.int32(height), np.int32(run), np.int32(0)
    for i in range(width):
        out[i] = h32
        hz = horizon_row_nb(cam, i + 0.5) if math.isfinite(cam[0]) else 0.0
        start[i] = int(min(max(math.floor(hz) - 2.0, 0.0), float(height))) if math.isfinite(hz) else 0
    for g0 in range(0, width, _GROUP):
        g1 = min(width, g0 + _GROUP)
        first = height
        for i in range(g0, g1):
            first = min(first, start[i])
        st, cnt, found = start[g0:g1], n[g0:g1], out[g0:g1]
        for j in range(first, height):
            row = classes[j, g0:g1]
            j32 = np.int32(j)
            searching = 0
            for k in range(g1 - g0):
                active = (j32 >= st[k]) & (found[k] == h32)  # scanned and not found yet
                c = (cnt[k] + np.int32(1)) if row[k] == 1 else none
                cnt[k] = c if active else cnt[k]
                found[k] = j32 - r32 + np.int32(1) if active & (c >= r32) else found[k]
                searching += np.int32((found[k] == h32) & (st[k] < h32))
            if searching == 0:
                break
    for i in range(width):
        if out[i] == height and n[i] >= 2:
            out[i] = height - n[i]  # a shorter run touching the bottom edge still is carpet
