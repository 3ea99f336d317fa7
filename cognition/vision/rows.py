"""Percept rows (:mod:`cognition.percepts` columns) from vision detections, compiled.

Each detection becomes one row: robot-frame position (m) from its pixel and the camera matrix,
its pixel(s), and the measurement covariance of the Darmstadt model (section IV.B, eqs. 8
and 12-15, :func:`cognition.percepts.covariance_nb`) for the frame's angular sigmas. Unused
columns are NaN, ``subtype`` 0, ``goal`` and ``truth`` -1 (vision does not know which
landmark it saw). Camera rows as in :mod:`.projection`.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.percepts import N_COLS, Col, covariance_nb
from cognition.vision.projection import pixel_nb

_X, _Y, _U, _V = int(Col.X), int(Col.Y), int(Col.U), int(Col.V)
_X2, _Y2, _U2, _V2 = int(Col.X2), int(Col.Y2), int(Col.U2), int(Col.V2)
_ORIENT, _SUB, _TRUTH, _GOAL = int(Col.ORIENTATION), int(Col.SUBTYPE), int(Col.TRUTH), int(Col.GOAL)
_VXX, _VXY, _VYY = int(Col.VAR_XX), int(Col.VAR_XY), int(Col.VAR_YY)
_SA, _SB = int(Col.SIGMA_ALPHA), int(Col.SIGMA_BETA)


@nb.njit(cache=True, error_model="python", fastmath=False)
def _blank(out: NDArray[np.float64], k: int, sa: float, sb: float) -> None:  # pragma: no cover - compiled
    for c in range(out.shape[1]):
        out[k, c] = math.nan
    out[k, _SUB] = 0.0
    out[k, _TRUTH] = -1.0
    out[k, _GOAL] = -1.0
    out[k, _SA] = sa
    out[k, _SB] = sb


@nb.njit(cache=True, error_model="python", fastmath=False)
def point_rows_nb(
    xy: NDArray[np.float64],
    uv: NDArray[np.float64],
    z: float,
    cam: NDArray[np.float64],
    sa: float,
    sb: float,
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """Rows of point percepts at robot-frame ground points ``xy`` (N x 2) seen at height ``z``
    (m; the ball's centre) through pixels ``uv`` (N x 2; NaN rows: projected from ``xy``)."""
    n = xy.shape[0]
    out = np.empty((n, N_COLS))
    for k in range(n):
        _blank(out, k, sa, sb)
        x, y = xy[k, 0], xy[k, 1]
        out[k, _X] = x
        out[k, _Y] = y
        u, v = uv[k, 0], uv[k, 1]
        if not (math.isfinite(u) and math.isfinite(v)):
            u, v, _ = pixel_nb(cam, x, y, z)
        out[k, _U] = u
        out[k, _V] = v
        out[k, _VXX], out[k, _VXY], out[k, _VYY] = covariance_nb(x, y, cam[9], cam[10], cam[11] - z, sa, sb)
    return out


@nb.njit(cache=True, error_model="python", fastmath=False)
def line_rows_nb(
    seg_px: NDArray[np.float64], seg_ground: NDArray[np.float64], cam: NDArray[np.float64], sa: float, sb: float
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """Rows of line percepts: ground end points (S x 4, m), pixels (S x >=4), direction in [0, pi)
    and the covariance at the point of the segment nearest the robot."""
    n = seg_ground.shape[0]
    out = np.empty((n, N_COLS))
    for k in range(n):
        _blank(out, k, sa, sb)
        x1, y1, x2, y2 = seg_ground[k, 0], seg_ground[k, 1], seg_ground[k, 2], seg_ground[k, 3]
        out[k, _X], out[k, _Y], out[k, _X2], out[k, _Y2] = x1, y1, x2, y2
        out[k, _U], out[k, _V], out[k, _U2], out[k, _V2] = seg_px[k, 0], seg_px[k, 1], seg_px[k, 2], seg_px[k, 3]
        a = math.atan2(y2 - y1, x2 - x1) % math.pi
        out[k, _ORIENT] = 0.0 if a >= math.pi - 1e-12 else a
        dx, dy = x2 - x1, y2 - y1
        t = -(x1 * dx + y1 * dy) / max(dx * dx + dy * dy, 1e-12)
        t = min(1.0, max(0.0, t))
        out[k, _VXX], out[k, _VXY], out[k, _VYY] = covariance_nb(
            x1 + t * dx, y1 + t * dy, cam[9], cam[10], cam[11], sa, sb
        )
    return out


@nb.njit(cache=True, error_model="python", fastmath=False)
def crossing_rows_nb(
    cross: NDArray[np.float64], cam: NDArray[np.float64], sa: float, sb: float
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """Rows of crossing percepts from the crossing detector's C x >=4 table (x, y, kind,
    orientation; robot frame, m and rad): pixels projected from the ground points."""
    n = cross.shape[0]
    xy = np.empty((n, 2))
    uv = np.full((n, 2), math.nan)
    for k in range(n):
        xy[k, 0] = cross[k, 0]
        xy[k, 1] = cross[k, 1]
    out = point_rows_nb(xy, uv, 0.0, cam, sa, sb)
    for k in range(n):
        out[k, _SUB] = cross[k, 2]
        out[k, _ORIENT] = cross[k, 3]
    return out
