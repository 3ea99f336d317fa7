"""Camera images as vision accepts them: RGB or packed YUV422 (YUYV), checked before use.

NAO cameras deliver YUV422: every two pixels share one U and one V sample, packed as the
bytes ``Y0 U Y1 V``. As a numpy array that is H x W x 2 (OpenCV's layout for
``COLOR_YUV2RGB_YUYV``: channel 0 the luma of each pixel, channel 1 alternating U and V).
Vision converts it to RGB with OpenCV (BT.601, the NAO's encoding) and then runs the same
pipeline, so a YUV422 frame and the RGB image it was made from give the same percepts up to
the chroma subsampling. :func:`rgb_to_yuv422` makes such frames (for tests and for feeding
rendered images to code that expects the camera's format).

Bad input is a :class:`VisionError` (a ``ValueError``) that names the problem, raised before
any compiled code runs: not an array, wrong dtype, wrong shape, a size that does not match
the camera matrix, a camera matrix with non-finite entries.
"""

from __future__ import annotations

import math

import cv2
import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.camera import CAMERA_ROW_SIZE, MAX_IMAGE_SIZE, MIN_IMAGE_SIZE, CameraMatrix

_BT601 = np.array([[0.257, 0.504, 0.098], [-0.148, -0.291, 0.439], [0.439, -0.368, -0.071]], dtype=np.float32)
"""RGB -> (Y, U, V) of BT.601 video range (offsets 16, 128, 128), the inverse of OpenCV's YUYV decoding."""


class VisionError(ValueError):
    """Input the vision pipeline cannot use (image or camera matrix)."""


def check_camera(camera: object) -> NDArray[np.float64]:
    """The camera's compact row (:meth:`CameraMatrix.as_row`) after checking it is usable."""
    if not isinstance(camera, CameraMatrix):
        raise VisionError(f"camera must be a cognition.camera.CameraMatrix, got {type(camera).__name__}")
    rot, pos, s = camera.rotation, camera.position, camera.spec
    if (
        type(rot) is np.ndarray
        and type(pos) is np.ndarray
        and rot.dtype == np.float64
        and pos.dtype == np.float64
        and rot.shape == (3, 3)
        and pos.shape == (3,)
    ):  # the common case, in one compiled call
        row = np.empty(CAMERA_ROW_SIZE)
        if _fill_row_nb(rot, pos, float(s.fx), float(s.fy), float(s.cx), float(s.cy), s.width, s.height, row):
            return row
    row = camera.as_row()
    if not np.all(np.isfinite(row)):
        bad = "rotation" if not np.all(np.isfinite(row[:9])) else "position"
        raise VisionError(f"the camera matrix has non-finite entries in its {bad}: {row[:12].tolist()}")
    return np.ascontiguousarray(row)


@nb.njit(cache=True, error_model="python", fastmath=False)
def _fill_row_nb(
    rot: NDArray[np.float64],
    pos: NDArray[np.float64],
    fx: float,
    fy: float,
    cx: float,
    cy: float,
    width: int,
    height: int,
    row: NDArray[np.float64],
) -> bool:  # pragma: no cover - compiled
    """Fill ``row`` as :meth:`CameraMatrix.as_row` does; False when an entry is not finite."""
    for i in range(3):
        for j in range(3):
            row[3 * i + j] = rot[i, j]
    for i in range(3):
        row[9 + i] = pos[i]
    row[12], row[13], row[14], row[15], row[16], row[17] = fx, fy, cx, cy, width, height
    for k in range(CAMERA_ROW_SIZE):  # noqa: SIM110 - compiled, no generators
        if not math.isfinite(row[k]):
            return False
    return True


def as_rgb(image: object, camera: CameraMatrix) -> NDArray[np.uint8]:
    """``image`` as a C-contiguous RGB array (H x W x 3 uint8), converting YUV422 (H x W x 2)."""
    if not isinstance(image, np.ndarray):
        raise VisionError(f"image must be a numpy array, got {type(image).__name__}")
    if image.dtype != np.uint8:
        raise VisionError(f"image must have dtype uint8, got {image.dtype}")
    if image.ndim != 3 or image.shape[2] not in (2, 3):
        raise VisionError(f"image must be H x W x 3 (RGB) or H x W x 2 (packed YUV422, YUYV), got shape {image.shape}")
    h, w = image.shape[:2]
    if not (MIN_IMAGE_SIZE <= h <= MAX_IMAGE_SIZE and MIN_IMAGE_SIZE <= w <= MAX_IMAGE_SIZE):
        raise VisionError(f"image size {w} x {h} is outside [{MIN_IMAGE_SIZE}, {MAX_IMAGE_SIZE}] pixels")
    spec = camera.spec
    if (w, h) != (spec.width, spec.height):
        raise VisionError(
            f"image is {w} x {h} pixels but the camera matrix is for {spec.width} x {spec.height}: "
            "use a CameraSpec of the image's size"
        )
    if image.shape[2] == 2:
        if w % 2:
            raise VisionError(f"a YUV422 image needs an even width, got {w}")
        return cv2.cvtColor(np.ascontiguousarray(image), cv2.COLOR_YUV2RGB_YUYV)
    return np.ascontiguousarray(image)


def rgb_to_yuv422(rgb: NDArray[np.uint8]) -> NDArray[np.uint8]:
    """Pack an RGB image (H x W x 3, even W) as YUV422 (H x W x 2, YUYV, BT.601 video range)."""
    if rgb.dtype != np.uint8 or rgb.ndim != 3 or rgb.shape[2] != 3 or rgb.shape[1] % 2:
        raise VisionError(f"rgb_to_yuv422 needs an H x W x 3 uint8 image with even W, got {rgb.shape} {rgb.dtype}")
    f = rgb.astype(np.float32)
    yuv = f @ _BT601.T + np.array([16.0, 128.0, 128.0], dtype=np.float32)
    out = np.empty((*rgb.shape[:2], 2), dtype=np.uint8)
    out[..., 0] = np.clip(yuv[..., 0] + 0.5, 0, 255)
    u = 0.5 * (yuv[:, 0::2, 1] + yuv[:, 1::2, 1])
    v = 0.5 * (yuv[:, 0::2, 2] + yuv[:, 1::2, 2])
    out[:, 0::2, 1] = np.clip(u + 0.5, 0, 255)
    out[:, 1::2, 1] = np.clip(v + 0.5, 0, 255)
    return out
