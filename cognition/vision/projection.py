"""Ground projection of image points and the percepts' measurement covariance.

Every percept's position comes from its pixel and the camera matrix: the viewing ray
through the pixel meets the ground (or, for the ball's centre, the plane at the ball's
radius) in front of the camera (DNT 3.10 uses the same plane-to-plane mapping for its
bird's-eye view). Its covariance is the Darmstadt paper's (section IV.B): two angular
sigmas, ``alpha`` about the camera's pitch axis and ``beta`` about its yaw axis, each
``base + c * |head rate| (+ moving while walking)`` (eqs. 3-6), turned into a 2 x 2
position covariance (eq. 8 along the viewing direction, eq. 12 across it, rotated by the
bearing, eqs. 13-15) with :func:`cognition.percepts.covariance_nb` — the same model and
the same default numbers the simulator's synthesized percepts report, so localization
weighs vision percepts exactly as it weighs synthesized ones.

The compiled functions take the camera as its compact row (:meth:`CameraMatrix.as_row`:
rotation camera -> robot row-major, optical centre (m, robot frame), fx, fy, cx, cy,
width, height). Robot frame: metres, +x forward, +y left, +z up; pixels ``u`` right, ``v``
down.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray


@nb.njit(cache=True, inline="always")
def ray_nb(cam: NDArray[np.float64], u: float, v: float) -> tuple[float, float, float]:  # pragma: no cover
    """Robot-frame direction (not normalised) of the viewing ray through pixel (u, v).

    Inlined into its callers (this module's, all with the same flags): a call would take a
    reference to the camera array and release it, two atomic operations that cost more than
    the arithmetic (about 8 ns of every ground projection)."""
    a = 1.0
    b = (cam[14] - u) / cam[12]
    c = (cam[15] - v) / cam[13]
    return (
        cam[0] * a + cam[1] * b + cam[2] * c,
        cam[3] * a + cam[4] * b + cam[5] * c,
        cam[6] * a + cam[7] * b + cam[8] * c,
    )


@nb.njit(cache=True, error_model="python", fastmath=False)
def ground_nb(cam: NDArray[np.float64], u: float, v: float, z: float) -> tuple[float, float, bool]:  # pragma: no cover
    """Robot-frame (x, y) where the ray through (u, v) meets the plane at height ``z`` (m)."""
    dx, dy, dz = ray_nb(cam, u, v)
    if dz >= -1e-9:
        return math.nan, math.nan, False
    t = (z - cam[11]) / dz
    if t <= 0.0:
        return math.nan, math.nan, False
    return cam[9] + dx * t, cam[10] + dy * t, True


@nb.njit(cache=True, error_model="python", fastmath=False)
def ground_ok_nb(cam: NDArray[np.float64], u: float, v: float) -> bool:  # pragma: no cover - compiled
    """:func:`ground_nb`'s third result for the ground (``z`` = 0) without the point: whether
    the ray through (u, v) meets it in front of the camera (the same operations and tests)."""
    _, _, dz = ray_nb(cam, u, v)
    if dz >= -1e-9:
        return False
    return not ((0.0 - cam[11]) / dz <= 0.0)


@nb.njit(cache=True, error_model="python", fastmath=False)
def pixel_nb(cam: NDArray[np.float64], x: float, y: float, z: float) -> tuple[float, float, bool]:  # pragma: no cover
    """Pixel (u, v) of the robot-frame point (x, y, z); ``False`` when it is behind the camera."""
    px, py, pz = x - cam[9], y - cam[10], z - cam[11]
    qx = cam[0] * px + cam[3] * py + cam[6] * pz
    qy = cam[1] * px + cam[4] * py + cam[7] * pz
    qz = cam[2] * px + cam[5] * py + cam[8] * pz
    if qx <= 1e-9:
        return math.nan, math.nan, False
    return cam[14] - cam[12] * qy / qx, cam[15] - cam[13] * qz / qx, True


@nb.njit(cache=True, error_model="python", fastmath=False)
def metres_per_pixel_nb(cam: NDArray[np.float64], u: float, v: float) -> tuple[float, float]:  # pragma: no cover
    """Ground size of one pixel at (u, v): along the image column and along the row (m).

    Infinite for pixels at or above the horizon.
    """
    x0, y0, ok0 = ground_nb(cam, u, v, 0.0)
    x1, y1, ok1 = ground_nb(cam, u, v + 1.0, 0.0)
    x2, y2, ok2 = ground_nb(cam, u + 1.0, v, 0.0)
    if not (ok0 and ok1 and ok2):
        return math.inf, math.inf
    return math.hypot(x1 - x0, y1 - y0), math.hypot(x2 - x0, y2 - y0)


@nb.njit(cache=True, inline="always")
def metres_per_pixel_along_nb(
    cam: NDArray[np.float64], u: float, v: float, vertical: bool
) -> float:  # pragma: no cover - compiled
    """One of :func:`metres_per_pixel_nb`'s two sizes, the same to the bit: along the image column
    (``vertical``) or along the row (m; infinite at or above the horizon). Only that direction
    is projected and measured; the other neighbour is only checked to meet the ground. Inlined
    into its callers (the scanlines, with this module's flags), as a call would take and
    release a reference to ``cam``."""
    x0, y0, ok0 = ground_nb(cam, u, v, 0.0)
    x1, y1, ok1 = ground_nb(cam, u, v + 1.0, 0.0) if vertical else ground_nb(cam, u + 1.0, v, 0.0)
    if not (ok0 and ok1 and (ground_ok_nb(cam, u + 1.0, v) if vertical else ground_ok_nb(cam, u, v + 1.0))):
        return math.inf
    return math.hypot(x1 - x0, y1 - y0)


def sigmas(
    base_alpha: float,
    base_beta: float,
    c_tilt: float,
    c_pan: float,
    moving_alpha: float,
    moving_beta: float,
    pitch_rate: float,
    yaw_rate: float,
    walking: bool,
) -> tuple[float, float]:
    """The angular sigmas (rad) of Darmstadt eqs. 3-6 for these head rates (rad/s)."""
    sa = base_alpha + c_tilt * abs(pitch_rate) + (moving_alpha if walking else 0.0)
    sb = base_beta + c_pan * abs(yaw_rate) + (moving_beta if walking else 0.0)
    return sa, sb


@nb.njit(cache=True, error_model="python", fastmath=False)
def horizon_row_nb(cam: NDArray[np.float64], u: float) -> float:  # pragma: no cover - compiled
    """Row of the horizon at column ``u`` (-inf when the camera looks upside down or straight down)."""
    r20, r21, r22 = cam[6], cam[7], cam[8]
    if r22 <= 1e-12:
        return -math.inf
    return cam[15] + cam[13] * (r20 + r21 * (cam[14] - u) / cam[12]) / r22
