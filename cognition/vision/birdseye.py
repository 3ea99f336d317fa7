"""Bird's-eye view: the camera image mapped onto the ground plane (DNT section 3.10).

Inverse perspective mapping: the ground plane and the image plane are related by a
homography (the camera matrix restricted to z = 0), so the image can be redrawn as seen from
above, free of perspective for everything that lies on the ground (lines, marks) and
distorted for everything that does not (robots, posts, the ball). DNT proposes it for
feature detection; here it is a debug view: detections drawn on it show at once whether the
ground projection is right, and :func:`birds_eye` works on any image and camera matrix.

The view covers ``x`` from ``near`` to ``far`` metres ahead and ``y`` within ``±half_width``
(robot frame), ``metres_per_pixel`` per output pixel; the robot is at the bottom centre,
forward is up. Ground points the camera does not see are black.
"""

from __future__ import annotations

import cv2
import numpy as np
from numpy.typing import NDArray

from cognition.camera import CameraMatrix


def ground_homography(
    camera: CameraMatrix, near: float, far: float, half_width: float, metres_per_pixel: float
) -> tuple[NDArray[np.float64], tuple[int, int]]:
    """The 3 x 3 homography from view pixels to image pixels, and the view's (width, height)."""
    if not (0.0 <= near < far and half_width > 0.0 and metres_per_pixel > 0.0):
        raise ValueError(
            f"bird's-eye view needs 0 <= near < far, half_width > 0 and metres_per_pixel > 0, got "
            f"near={near}, far={far}, half_width={half_width}, metres_per_pixel={metres_per_pixel}"
        )
    width = max(1, round(2.0 * half_width / metres_per_pixel))
    height = max(1, round((far - near) / metres_per_pixel))
    # camera frame: x along the optical axis, y left, z up; pixel u = cx - fx y / x, v = cy - fy z / x
    r = camera.rotation.T  # robot -> camera
    t = -r @ camera.position
    s = camera.spec
    k = np.array([[-s.fx, 0.0, s.cx], [0.0, -s.fy, s.cy], [0.0, 0.0, 1.0]])
    rows = np.array([r[1], r[2], r[0]])  # (y, z, x): the pinhole's (a, b, depth)
    shift = np.array([t[1], t[2], t[0]])
    ground_to_image = k @ np.column_stack([rows[:, 0], rows[:, 1], shift])  # ground (x, y, 1) -> image
    # view pixel (c, r) -> ground: x = far - r m, y = half_width - c m
    m = metres_per_pixel
    view_to_ground = np.array([[0.0, -m, far], [-m, 0.0, half_width], [0.0, 0.0, 1.0]])
    return ground_to_image @ view_to_ground, (width, height)


def birds_eye(
    image: NDArray[np.uint8],
    camera: CameraMatrix,
    near: float = 0.0,
    far: float = 6.0,
    half_width: float = 3.0,
    metres_per_pixel: float = 0.02,
) -> NDArray[np.uint8]:
    """The image (H x W x 3 RGB) redrawn on the ground plane (module docstring)."""
    h, size = ground_homography(camera, near, far, half_width, metres_per_pixel)
    flags = cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP
    view = cv2.warpPerspective(image, h, size, flags=flags, borderMode=cv2.BORDER_CONSTANT, borderValue=(0, 0, 0))
    cols, rows = np.meshgrid(np.arange(size[0]) + 0.5, np.arange(size[1]) + 0.5)
    view[h[2, 0] * cols + h[2, 1] * rows + h[2, 2] <= 0.0] = 0  # ground behind the camera
    return view


def ground_to_view(
    xy: NDArray[np.float64], far: float = 6.0, half_width: float = 3.0, metres_per_pixel: float = 0.02
) -> NDArray[np.float64]:
    """View pixels (N x 2: column, row) of robot-frame ground points (N x 2, m), to draw on the view."""
    xy = np.atleast_2d(np.asarray(xy, dtype=np.float64))
    return np.column_stack([(half_width - xy[:, 1]) / metres_per_pixel, (far - xy[:, 0]) / metres_per_pixel])
