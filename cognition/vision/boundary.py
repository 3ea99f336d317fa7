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


@nb.njit(cache=True)
def _boundary(
    classes: NDArray[np.uint8], cam: NDArray[np.float64], run: int, out: NDArray[np.int32]
) -> None:  # pragma: no cover - compiled
    height, width = classes.shape
    for i in range(width):
        out[i] = height
        n = 0
        hz = horizon_row_nb(cam, i + 0.5) if math.isfinite(cam[0]) else 0.0
        start = int(min(max(math.floor(hz) - 2.0, 0.0), float(height))) if math.isfinite(hz) else 0
        for j in range(start, height):
            if classes[j, i] == 1:
                n += 1
                if n >= run:
                    out[i] = j - run + 1
                    break
            else:
                n = 0
        if out[i] == height and n >= 2:
            out[i] = height - n  # a shorter run touching the bottom edge still is carpet
