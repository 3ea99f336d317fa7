"""Pinhole camera geometry of a NAO-like head, shared by the simulator and the brain.

Implements the projection that the CMU paper's vision features and the Darmstadt paper's
angular observation model (Kohlbrecher & von Stryk, section IV.B and Fig. 2) rest on: a
camera on a head with yaw and pitch joints, mapping points in the robot frame to pixels
and pixels (with a known height) back to points.

Frames and units:

* **robot frame**: metres, origin on the ground between the feet, +x forward, +y left,
  +z up.
* **camera frame**: origin at the optical centre, +x along the optical axis, +y left,
  +z up in the image.
* **pixels**: ``u`` to the right, ``v`` down, continuous coordinates; pixel ``(i, j)`` covers
  ``[i, i + 1) x [j, j + 1)`` and the image is ``0 <= u < width``, ``0 <= v < height``.

The head: yaw about +z at the neck (``CameraRig.neck_height`` above the ground), then pitch
about the rotated +y (positive pitch looks down), then the camera offset (``offset_x``
forward, ``offset_z`` up in the head frame) and the camera's own downward ``tilt``.

=================  =========================  =========================================
NAO V6 camera      upper                      lower
=================  =========================  =========================================
tilt (down)        1.2 deg                    39.7 deg
opening angles     54.7 x 42.5 deg            54.7 x 42.5 deg
offset (x, z)      0.0587, 0.0636 m           0.0507, 0.0177 m
height at pitch 0  0.504 m                    0.458 m  (neck height 0.44 m)
=================  =========================  =========================================

Parameters of :class:`CameraSpec` (one camera) and :class:`CameraRig` (the head):

=================  ==============  ===============  ===================================================
parameter          NAO default     range            meaning
=================  ==============  ===============  ===================================================
tilt               see above       [-pi/2, pi/2]    downward tilt of the optical axis (rad)
hfov               54.7 deg        (0, 2.82743)     horizontal opening angle (rad; below 0.9 pi)
vfov               42.5 deg        (0, 2.82743)     vertical opening angle (rad; below 0.9 pi)
width              320             [8, 2048]        image width (pixels)
height             240             [8, 2048]        image height (pixels)
offset_x           see above       [-1, 1]          forward offset of the optical centre (m, head frame)
offset_z           see above       [-1, 1]          upward offset of the optical centre (m, head frame)
neck_height        0.44            [0.05, 3]        (:class:`CameraRig`) head joints above the ground (m)
=================  ==============  ===============  ===================================================

Every value is checked against its range when a spec or rig is built
(:func:`cognition.params.check_ranges`).

The numba functions at the end (``*_nb``) are the same geometry for compiled hot loops.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import ClassVar, Literal

import numba as nb
import numpy as np
from numpy.typing import ArrayLike, NDArray

from cognition.params import Range, Ranges, check_ranges
from cognition.records import fast_init

CameraName = Literal["upper", "lower"]
CAMERA_NAMES: tuple[CameraName, ...] = ("upper", "lower")
"""Index 0 is the upper camera, 1 the lower one (used in compact arrays)."""

MIN_IMAGE_SIZE = 8
"""Smallest accepted image width or height (pixels)."""
MAX_IMAGE_SIZE = 2048
"""Largest accepted image width or height (pixels): a 2048 x 2048 RGB image is 12 MB, per
robot and camera frame."""


@dataclass(frozen=True)
class CameraSpec:
    """Intrinsics and mounting of one camera (angles in radians, lengths in metres)."""

    tilt: float
    """Downward tilt of the optical axis relative to the head (rad)."""
    hfov: float
    """Horizontal opening angle (rad)."""
    vfov: float
    """Vertical opening angle (rad)."""
    width: int = 320
    """Image width (pixels)."""
    height: int = 240
    """Image height (pixels)."""
    offset_x: float = 0.0
    """Forward offset of the optical centre from the head pitch axis (m, head frame)."""
    offset_z: float = 0.0
    """Upward offset of the optical centre from the head pitch axis (m, head frame)."""

    RANGES: ClassVar[Ranges] = {
        "tilt": Range(-math.pi / 2, math.pi / 2),
        "hfov": Range(0.0, 0.9 * math.pi, low_open=True, high_open=True),
        "vfov": Range(0.0, 0.9 * math.pi, low_open=True, high_open=True),
        "width": Range(MIN_IMAGE_SIZE, MAX_IMAGE_SIZE),
        "height": Range(MIN_IMAGE_SIZE, MAX_IMAGE_SIZE),
        "offset_x": Range(-1.0, 1.0),
        "offset_z": Range(-1.0, 1.0),
    }

    def __post_init__(self) -> None:
        check_ranges(self)

    @property
    def fx(self) -> float:
        """Horizontal focal length (pixels)."""
        return (self.width / 2.0) / math.tan(self.hfov / 2.0)

    @property
    def fy(self) -> float:
        """Vertical focal length (pixels)."""
        return (self.height / 2.0) / math.tan(self.vfov / 2.0)

    @property
    def cx(self) -> float:
        """Principal point, horizontal (pixels)."""
        return self.width / 2.0

    @property
    def cy(self) -> float:
        """Principal point, vertical (pixels)."""
        return self.height / 2.0


NAO_UPPER = CameraSpec(
    tilt=math.radians(1.2), hfov=math.radians(54.7), vfov=math.radians(42.5), offset_x=0.05871, offset_z=0.06364
)
"""NAO V6 upper camera (DESIGN.md reference facts; offsets from the NAO documentation)."""
NAO_LOWER = CameraSpec(
    tilt=math.radians(39.7), hfov=math.radians(54.7), vfov=math.radians(42.5), offset_x=0.05071, offset_z=0.01774
)
"""NAO V6 lower camera."""


@dataclass(frozen=True)
class CameraRig:
    """The head: neck height plus the upper and lower camera."""

    neck_height: float = 0.44
    """Height of the head joints above the ground when standing (m)."""
    upper: CameraSpec = NAO_UPPER
    lower: CameraSpec = NAO_LOWER

    RANGES: ClassVar[Ranges] = {"neck_height": Range(0.05, 3.0)}

    def __post_init__(self) -> None:
        check_ranges(self)

    def spec(self, camera: CameraName | int) -> CameraSpec:
        """The spec of ``camera`` ('upper'/'lower' or index 0/1)."""
        if camera in ("upper", 0):
            return self.upper
        if camera in ("lower", 1):
            return self.lower
        raise ValueError(f"unknown camera {camera!r}; valid: {list(CAMERA_NAMES)}")

    def with_resolution(self, width: int, height: int) -> CameraRig:
        """The same rig with both cameras at ``width`` x ``height`` pixels."""
        upper = replace(self.upper, width=width, height=height)
        return replace(self, upper=upper, lower=replace(self.lower, width=width, height=height))

    def camera_matrix(
        self,
        camera: CameraName | int,
        head_yaw: float,
        head_pitch: float,
        torso_roll: float = 0.0,
        torso_pitch: float = 0.0,
    ) -> CameraMatrix:
        """The camera's pose and intrinsics for these head angles and torso orientation (rad).

        ``torso_roll`` and ``torso_pitch`` are the torso's orientation against gravity as an
        IMU reports it (a NAO standing still leans by 3 to 10 degrees); see
        :func:`torso_rotation` for the conventions. The simulated robots stand upright (0).
        """
        spec = self.spec(camera)
        rot, pos = head_camera_pose(self.neck_height, spec.offset_x, spec.offset_z, spec.tilt, head_yaw, head_pitch)
        if torso_roll != 0.0 or torso_pitch != 0.0:
            tilt = torso_rotation(torso_roll, torso_pitch)
            rot, pos = tilt @ rot, tilt @ pos
        return CameraMatrix(rot, pos, spec)


def torso_rotation(roll: float, pitch: float) -> NDArray[np.float64]:
    """Rotation (3 x 3) of the robot's body about the ground point between its feet.

    ``pitch`` (rad) turns about the robot's +y axis, positive leaning forward (the head
    moves forward and down, as a positive head pitch looks down); ``roll`` (rad) turns about
    +x, positive lifting the left side (leaning to the right). The body is rolled, then
    pitched: ``R = Ry(pitch) @ Rx(roll)``, applied to the camera's rotation and position.
    """
    for name, value in (("torso_roll", roll), ("torso_pitch", pitch)):
        if not math.isfinite(value) or abs(value) > math.pi / 2:
            raise ValueError(f"{name} must be a finite angle in [-pi/2, pi/2] rad, got {value!r}")
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(pitch), math.sin(pitch)
    rx = np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]])
    ry = np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])
    return ry @ rx


def head_camera_pose(
    neck_height: float, offset_x: float, offset_z: float, tilt: float, head_yaw: float, head_pitch: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Rotation (3x3, camera -> robot frame) and optical centre (3, robot frame, m)."""
    rot = np.empty((3, 3))
    pos = np.empty(3)
    camera_pose_nb(neck_height, offset_x, offset_z, tilt, head_yaw, head_pitch, rot, pos)
    return rot, pos


@fast_init
@dataclass(frozen=True, eq=False)
class CameraMatrix:
    """A camera's pose in the robot frame and its intrinsics.

    ``rotation`` maps camera-frame vectors to robot-frame vectors; ``position`` is the
    optical centre in the robot frame (m). All methods accept many points at once.
    """

    rotation: NDArray[np.float64]
    position: NDArray[np.float64]
    spec: CameraSpec

    @property
    def height(self) -> float:
        """Height of the optical centre above the ground (m)."""
        return float(self.position[2])

    def project(self, points: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        """Pixels of robot-frame points (N x 3, m) and a mask of points in front of the camera.

        Points behind the camera (or on its plane) get NaN pixels.
        """
        p = np.atleast_2d(np.asarray(points, dtype=np.float64))
        if p.shape[-1] != 3:
            raise ValueError(f"project expects points of shape (N, 3), got {p.shape}")
        q = (p - self.position) @ self.rotation  # camera frame (R^T (p - c)) for each row
        front = q[:, 0] > 1e-9
        s = self.spec
        with np.errstate(divide="ignore", invalid="ignore"):
            u = np.where(front, s.cx - s.fx * q[:, 1] / q[:, 0], np.nan)
            v = np.where(front, s.cy - s.fy * q[:, 2] / q[:, 0], np.nan)
        return np.stack([u, v], axis=1), front

    def sees(self, x: float, y: float, z: float) -> bool:
        """True if the robot-frame point (x, y, z) (m) is in front of the camera and projects
        inside the image: :meth:`project` then :meth:`in_image` for one point, without arrays. (The
        world model asks this every frame of the percepts' :attr:`~cognition.percepts.Percepts.camera_view`
        through :func:`view_sees`, without building the matrix.)"""
        view = camera_view(self.rotation.reshape(9).tolist(), self.position.tolist(), self.spec)
        return view_sees(view, x, y, z)

    def in_image(self, uv: ArrayLike) -> NDArray[np.bool_]:
        """True for pixels inside the image (NaN pixels are outside)."""
        a = np.atleast_2d(np.asarray(uv, dtype=np.float64))
        s = self.spec
        with np.errstate(invalid="ignore"):
            return (a[:, 0] >= 0) & (a[:, 0] < s.width) & (a[:, 1] >= 0) & (a[:, 1] < s.height)

    def rays(self, uv: ArrayLike) -> NDArray[np.float64]:
        """Robot-frame directions (N x 3, not normalised) of the viewing rays through pixels."""
        a = np.atleast_2d(np.asarray(uv, dtype=np.float64))
        s = self.spec
        d = np.stack([np.ones(len(a)), (s.cx - a[:, 0]) / s.fx, (s.cy - a[:, 1]) / s.fy], axis=1)
        return d @ self.rotation.T

    def pixel_to_ground(self, uv: ArrayLike, height: float = 0.0) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        """Robot-frame (x, y) where the rays through pixels meet the plane z = ``height`` (m).

        Returns the points (N x 2) and a validity mask: rays that never reach the plane in
        front of the camera (at or above the horizon for ``height`` below the camera) are
        invalid and get NaN.
        """
        d = self.rays(uv)
        dz = d[:, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (height - self.position[2]) / dz
        valid = np.isfinite(t) & (t > 0)
        t = np.where(valid, t, np.nan)
        xy = self.position[:2] + d[:, :2] * t[:, None]
        return xy, valid

    def horizon(self) -> tuple[float, float] | None:
        """Rows ``v`` of the horizon at ``u = 0`` and ``u = width``, or ``None`` if it is vertical.

        The horizon is the image line of directions parallel to the ground; ground points
        always lie below it (larger ``v``) when the camera is upright.
        """
        r = self.rotation
        s = self.spec
        if abs(r[2, 2]) < 1e-12:
            return None

        def row(u: float) -> float:
            return s.cy + s.fy * (r[2, 0] + r[2, 1] * (s.cx - u) / s.fx) / r[2, 2]

        return row(0.0), row(float(s.width))

    def as_row(self) -> NDArray[np.float64]:
        """Compact form: 9 rotation entries (row-major), 3 position entries, fx, fy, cx, cy, width, height."""
        s = self.spec
        return np.concatenate([self.rotation.ravel(), self.position, [s.fx, s.fy, s.cx, s.cy, s.width, s.height]])


CAMERA_ROW_SIZE = 18
"""Length of :meth:`CameraMatrix.as_row`."""

CameraView = tuple[float, ...]
"""A camera matrix as 18 Python floats, for single-point work in Python (:func:`camera_view`):
the optical centre (x, y, z; robot frame, m), the rotation row by row (camera -> robot), then
the image width and height and the principal point and focal lengths (cx, cy, fx, fy; pixels)."""
VIEW_X, VIEW_Y, VIEW_Z, VIEW_FX, VIEW_FY = 0, 1, 2, 16, 17
"""Indices in a :data:`CameraView`: the optical centre and the focal lengths."""
_SPEC_VIEWS: dict[int, tuple[CameraSpec, tuple[float, float, float, float, float, float]]] = {}
"""The intrinsics part of a view per spec object (keyed by ``id``, the spec kept to check identity)."""


def camera_view(rotation: list[float], position: list[float], spec: CameraSpec) -> CameraView:
    """The :data:`CameraView` of the camera with ``rotation`` (9 floats, row by row, camera ->
    robot), optical centre ``position`` (3 floats, robot frame, m) and intrinsics ``spec``. The
    intrinsics are the spec's ``width``, ``height``, ``cx``, ``cy``, ``fx`` and ``fy``, worked out once
    per spec object with the same operations as those properties."""
    got = _SPEC_VIEWS.get(id(spec))
    if got is None or got[0] is not spec:
        w, h = spec.width, spec.height
        cx, cy = w / 2.0, h / 2.0
        if len(_SPEC_VIEWS) >= 64:  # specs are few; a program that makes many does not grow this
            _SPEC_VIEWS.clear()
        fx, fy = cx / math.tan(spec.hfov / 2.0), cy / math.tan(spec.vfov / 2.0)
        got = _SPEC_VIEWS[id(spec)] = (spec, (w, h, cx, cy, fx, fy))
    return (*position, *rotation, *got[1])


def view_sees(view: CameraView, x: float, y: float, z: float) -> bool:
    """:meth:`CameraMatrix.sees` of the camera ``view`` (:func:`camera_view`): whether the
    robot-frame point (x, y, z) (m) lies in front of the camera and projects inside the image."""
    c0, c1, c2, r00, r01, r02, r10, r11, r12, r20, r21, r22, w, h, cx, cy, fx, fy = view
    dx, dy, dz = x - c0, y - c1, z - c2
    qx = dx * r00 + dy * r10 + dz * r20
    if not qx > 1e-9:
        return False
    qy = dx * r01 + dy * r11 + dz * r21
    qz = dx * r02 + dy * r12 + dz * r22
    u, v = cx - fx * qy / qx, cy - fy * qz / qx
    return 0.0 <= u < w and 0.0 <= v < h


@fast_init
@dataclass(frozen=True, eq=False)
class CameraImage:
    """One camera image as a robot receives it (the image observation path).

    ``camera`` is the camera's pose in the robot frame when the image was exposed, computed
    from the head joint angles of that moment (``head_yaw``, ``head_pitch``); with it a
    vision module maps pixels to the ground (:meth:`CameraMatrix.pixel_to_ground`).
    """

    time: float
    """When the image was exposed (s since match start)."""
    pixels: NDArray[np.uint8]
    """The image, height x width x 3, RGB, row 0 at the top."""
    camera: CameraMatrix
    """Pose (robot frame) and intrinsics of the camera at exposure."""
    camera_name: CameraName = "upper"
    """Which camera took it."""
    head_yaw: float = 0.0
    """Head yaw at exposure (rad, positive to the left)."""
    head_pitch: float = 0.0
    """Head pitch at exposure (rad, positive looks down)."""

    @property
    def shape(self) -> tuple[int, int]:
        """(height, width) in pixels."""
        return int(self.pixels.shape[0]), int(self.pixels.shape[1])


# -- compiled geometry (same conventions as above) ------------------------------------------
@nb.njit(cache=True, error_model="python", fastmath=False)
def camera_pose_nb(
    neck_height: float,
    offset_x: float,
    offset_z: float,
    tilt: float,
    head_yaw: float,
    head_pitch: float,
    rot: NDArray[np.float64],
    pos: NDArray[np.float64],
) -> None:  # pragma: no cover - compiled
    """Fill ``rot`` (camera -> robot) and ``pos`` (optical centre, robot frame) in place."""
    cy, sy = math.cos(head_yaw), math.sin(head_yaw)
    cp, sp = math.cos(head_pitch), math.sin(head_pitch)
    a = head_pitch + tilt
    ca, sa = math.cos(a), math.sin(a)
    # Rz(yaw) @ Ry(pitch + tilt); Ry(a) maps x to (cos a, 0, -sin a): positive looks down
    rot[0, 0] = cy * ca
    rot[0, 1] = -sy
    rot[0, 2] = cy * sa
    rot[1, 0] = sy * ca
    rot[1, 1] = cy
    rot[1, 2] = sy * sa
    rot[2, 0] = -sa
    rot[2, 1] = 0.0
    rot[2, 2] = ca
    # offset rotated by Rz(yaw) @ Ry(pitch)
    hx = cp * offset_x + sp * offset_z
    hz = -sp * offset_x + cp * offset_z
    pos[0] = cy * hx
    pos[1] = sy * hx
    pos[2] = neck_height + hz


@nb.njit(cache=True, error_model="python", fastmath=False)
def to_camera_nb(rot: NDArray[np.float64], pos: NDArray[np.float64], x: float, y: float, z: float) -> tuple:
    """Camera-frame coordinates of robot-frame point (x, y, z)."""  # pragma: no cover - compiled
    dx, dy, dz = x - pos[0], y - pos[1], z - pos[2]
    return (
        rot[0, 0] * dx + rot[1, 0] * dy + rot[2, 0] * dz,
        rot[0, 1] * dx + rot[1, 1] * dy + rot[2, 1] * dz,
        rot[0, 2] * dx + rot[1, 2] * dy + rot[2, 2] * dz,
    )
