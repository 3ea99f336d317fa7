"""Tests for cognition.camera: projection, back-projection, horizon, intrinsics and validation."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from numpy.typing import NDArray

from cognition.camera import (
    CAMERA_NAMES,
    CAMERA_ROW_SIZE,
    MIN_IMAGE_SIZE,
    NAO_LOWER,
    NAO_UPPER,
    CameraMatrix,
    CameraRig,
    CameraSpec,
    camera_pose_nb,
    view_sees,
)
from cognition.percepts import N_COLS, N_KINDS, Percepts

RIG = CameraRig()
HEAD_ANGLES = [(yaw, pitch) for yaw in (-1.0, 0.0, 0.7) for pitch in (-0.3, 0.0, 0.3, 0.5)]


def Rz(a: float) -> NDArray[np.float64]:
    return np.array([[math.cos(a), -math.sin(a), 0.0], [math.sin(a), math.cos(a), 0.0], [0.0, 0.0, 1.0]])


def Ry(a: float) -> NDArray[np.float64]:
    return np.array([[math.cos(a), 0.0, math.sin(a)], [0.0, 1.0, 0.0], [-math.sin(a), 0.0, math.cos(a)]])


def visible_points(cam: CameraMatrix, yaw: float, z: float, seed: int, n: int = 4000) -> NDArray[np.float64]:
    """Random points on the plane at height ``z`` around the view direction that are in the image."""
    rng = np.random.default_rng(seed)
    bearing = yaw + rng.uniform(-0.6, 0.6, n)
    dist = np.exp(rng.uniform(math.log(0.05), math.log(15.0), n))
    pts = np.stack([dist * np.cos(bearing), dist * np.sin(bearing), np.full(n, z)], axis=1)
    uv, front = cam.project(pts)
    keep = front & cam.in_image(uv)
    assert keep.sum() >= 50, "too few visible points to test"
    return pts[keep]


@pytest.mark.parametrize("camera", CAMERA_NAMES)
def test_sees_agrees_with_project_and_in_image(camera: str) -> None:
    """The scalar check for one point gives what project + in_image give, for random points
    around the robot (in front, behind, at the image border) and tilted torsos."""
    g = np.random.default_rng(3)
    seen = total = 0
    for _ in range(20):
        cam = RIG.camera_matrix(
            camera, g.uniform(-2, 2), g.uniform(-0.6, 0.5), torso_roll=g.uniform(-0.1, 0.1),
            torso_pitch=g.uniform(-0.1, 0.1),
        )  # fmt: skip
        pts = np.column_stack([g.uniform(-5, 5, 400), g.uniform(-5, 5, 400), g.uniform(-0.1, 0.6, 400)])
        uv, front = cam.project(pts)
        want = front & cam.in_image(uv)
        got = np.array([cam.sees(*p) for p in pts])
        np.testing.assert_array_equal(got, want)
        seen, total = seen + int(want.sum()), total + want.size
    assert 0.02 * total < seen < 0.5 * total, (seen, total)  # both answers were checked, often


@pytest.mark.parametrize("camera", CAMERA_NAMES)
def test_percepts_camera_view_is_the_camera_matrix_as_floats(camera: str) -> None:
    """The view a percept set gives the world model without building its camera matrix holds the
    matrix's own numbers (position, rotation row by row, the spec's width, height, cx, cy, fx,
    fy), and :func:`view_sees` answers as the matrix's ``sees`` does."""
    g = np.random.default_rng(5)
    for _ in range(10):
        cam = RIG.camera_matrix(camera, g.uniform(-2, 2), g.uniform(-0.6, 0.5), torso_roll=g.uniform(-0.1, 0.1))
        percepts = Percepts.of_checked_rows(
            1.0, np.zeros((0, N_COLS)), np.zeros(N_KINDS + 1, dtype=np.int64), cam.as_row(), cam.spec
        )
        view = percepts.camera_view
        assert view is not None and all(type(v) in (float, int) for v in view)
        s = cam.spec
        assert view == (
            *cam.position.tolist(),
            *cam.rotation.reshape(9).tolist(),
            s.width,
            s.height,
            s.cx,
            s.cy,
            s.fx,
            s.fy,
        )
        matrix = percepts.camera
        assert matrix is not None
        pts = np.column_stack([g.uniform(-5, 5, 300), g.uniform(-5, 5, 300), g.uniform(-0.1, 0.6, 300)])
        assert [view_sees(view, *p) for p in pts] == [matrix.sees(*p) for p in pts] == [cam.sees(*p) for p in pts]
        assert set(matrix.__dict__) == {"rotation", "position", "spec"}  # nothing kept beside the fields
    assert Percepts.empty(1.0).camera_view is None


@pytest.mark.parametrize("camera", CAMERA_NAMES)
@pytest.mark.parametrize(("yaw", "pitch"), HEAD_ANGLES)
@pytest.mark.parametrize("z", [0.0, 0.05])
def test_projection_round_trip(camera: str, yaw: float, pitch: float, z: float) -> None:
    cam = RIG.camera_matrix(camera, yaw, pitch)
    pts = visible_points(cam, yaw, z, seed=int(1000 * (yaw + 2) + 100 * (pitch + 1) + 10 * z))
    uv, front = cam.project(pts)
    assert front.all()
    xy, valid = cam.pixel_to_ground(uv, height=z)
    assert valid.all()
    np.testing.assert_allclose(xy, pts[:, :2], rtol=0, atol=1e-9)


def test_optical_centre_heights() -> None:
    upper = RIG.camera_matrix("upper", 0.0, 0.0)
    lower = RIG.camera_matrix("lower", 0.0, 0.0)
    assert upper.height == pytest.approx(RIG.neck_height + NAO_UPPER.offset_z, abs=1e-12)
    assert upper.height == pytest.approx(0.504, abs=1e-3)
    assert lower.height == pytest.approx(0.458, abs=1e-3)
    for cam in (upper, lower):
        assert 0.45 <= cam.height <= 0.51
        assert cam.position[1] == pytest.approx(0.0, abs=1e-15)
    assert upper.position[0] == pytest.approx(NAO_UPPER.offset_x, abs=1e-12)


def test_optical_axis_hits_ground_at_expected_distance() -> None:
    pitch = 0.3
    cam = RIG.camera_matrix("upper", 0.0, pitch)
    s = cam.spec
    xy, valid = cam.pixel_to_ground([[s.cx, s.cy]])
    assert valid[0]
    assert xy[0, 1] == pytest.approx(0.0, abs=1e-12)
    expected = cam.height / math.tan(NAO_UPPER.tilt + pitch)
    assert xy[0, 0] - cam.position[0] == pytest.approx(expected, rel=1e-12)
    assert 0.5 < xy[0, 0] < 3.0


@pytest.mark.parametrize("camera", CAMERA_NAMES)
def test_left_projects_left_and_up_projects_up(camera: str) -> None:
    cam = RIG.camera_matrix(camera, 0.0, 0.2)
    s = cam.spec
    centre = cam.position + 2.0 * cam.rotation[:, 0]  # a point on the optical axis
    offsets = np.array([[0.0, 0.0, 0.0], [0.0, 0.1, 0.0], [0.0, -0.1, 0.0], [0.0, 0.0, 0.1]])
    uv, front = cam.project(centre + offsets)
    assert front.all()
    np.testing.assert_allclose(uv[0], [s.cx, s.cy], atol=1e-9)
    assert uv[1, 0] < s.cx  # left
    assert uv[2, 0] > s.cx  # right
    assert uv[3, 1] < s.cy  # above


@pytest.mark.parametrize("camera", CAMERA_NAMES)
@pytest.mark.parametrize("yaw", [0.5, -0.8])
def test_head_yaw_rotates_view(camera: str, yaw: float) -> None:
    cam = RIG.camera_matrix(camera, yaw, 0.1)
    s = cam.spec
    # the optical centre lies on the vertical plane at bearing `yaw` through the neck
    assert math.atan2(cam.position[1], cam.position[0]) == pytest.approx(yaw, abs=1e-12)
    xy, valid = cam.pixel_to_ground([[s.cx, s.cy]])
    assert valid[0]
    d = xy[0] - cam.position[:2]
    assert math.atan2(d[1], d[0]) == pytest.approx(yaw, abs=1e-12)
    # hence ground points at bearing `yaw` from the robot project onto the centre column
    r = np.array([1.0, 2.0, 4.0])
    uv, front = cam.project(np.stack([r * math.cos(yaw), r * math.sin(yaw), np.zeros(3)], axis=1))
    assert front.all()
    np.testing.assert_allclose(uv[:, 0], s.cx, atol=1e-6)


def test_points_behind_camera_and_in_image() -> None:
    cam = RIG.camera_matrix("upper", 0.0, 0.0)
    s = cam.spec
    behind = cam.position + np.array([[-1.0, 0.0, 0.0], [-2.0, 1.0, -0.4], [0.0, 0.3, 0.0]])
    uv, front = cam.project(behind)
    assert not front.any()
    assert np.isnan(uv).all()
    assert not cam.in_image(uv).any()
    w, h = s.width, s.height
    inside = [[0.0, 0.0], [w - 1e-9, h - 1e-9], [s.cx, s.cy]]
    outside = [[-1e-9, 10.0], [w, 10.0], [10.0, h], [10.0, -1e-9], [np.nan, 10.0], [10.0, np.nan]]
    assert cam.in_image(inside).all()
    assert not cam.in_image(outside).any()


@pytest.mark.parametrize("camera", CAMERA_NAMES)
def test_horizon(camera: str) -> None:
    rows = []
    for pitch in (-0.4, -0.1, 0.0, 0.2, 0.5):
        cam = RIG.camera_matrix(camera, 0.0, pitch)
        hor = cam.horizon()
        assert hor is not None
        v0, v1 = hor
        assert v0 == pytest.approx(v1, abs=1e-9)  # no roll: horizontal horizon
        for yaw in (-1.2, 0.6):
            other = RIG.camera_matrix(camera, yaw, pitch).horizon()
            assert other is not None
            np.testing.assert_allclose(other, hor, atol=1e-9)
        us = np.linspace(0.0, cam.spec.width, 7)
        _, below = cam.pixel_to_ground(np.stack([us, np.full(7, v0 + 1.0)], axis=1))
        xy, above = cam.pixel_to_ground(np.stack([us, np.full(7, v0 - 1.0)], axis=1))
        assert below.all()
        assert not above.any()
        assert np.isnan(xy).all()
        rows.append(v0)
    assert np.all(np.diff(rows) < 0), f"horizon should move up as the head pitches down: {rows}"


@pytest.mark.parametrize("camera", CAMERA_NAMES)
@pytest.mark.parametrize(("yaw", "pitch"), [(0.0, 0.0), (0.6, 0.3)])
def test_field_of_view(camera: str, yaw: float, pitch: float) -> None:
    cam = RIG.camera_matrix(camera, yaw, pitch)
    s = cam.spec

    def uv_of(ay: float, az: float) -> NDArray[np.float64]:
        q = np.array([5.0, 5.0 * math.tan(ay), 5.0 * math.tan(az)])  # camera frame
        uv, front = cam.project(cam.position + cam.rotation @ q)
        assert front[0]
        return uv

    for sign in (1.0, -1.0):
        assert cam.in_image(uv_of(sign * (s.hfov / 2 - 0.01), 0.0))[0]
        assert not cam.in_image(uv_of(sign * (s.hfov / 2 + 0.01), 0.0))[0]
        assert cam.in_image(uv_of(0.0, sign * (s.vfov / 2 - 0.01)))[0]
        assert not cam.in_image(uv_of(0.0, sign * (s.vfov / 2 + 0.01)))[0]
    # the exact half angle maps to the image edge
    assert uv_of(s.hfov / 2, 0.0)[0, 0] == pytest.approx(0.0, abs=1e-9)
    assert uv_of(0.0, -s.vfov / 2)[0, 1] == pytest.approx(s.height, abs=1e-9)


def test_focal_lengths() -> None:
    for s in (NAO_UPPER, NAO_LOWER):
        assert s.fx == pytest.approx((s.width / 2) / math.tan(s.hfov / 2), rel=1e-15)
        assert s.fy == pytest.approx((s.height / 2) / math.tan(s.vfov / 2), rel=1e-15)
        assert abs(s.fx / s.fy - 1.0) < 0.02
        assert (s.cx, s.cy) == (s.width / 2, s.height / 2)
    big = RIG.with_resolution(640, 480)
    for name in CAMERA_NAMES:
        old, new = RIG.spec(name), big.spec(name)
        assert (new.width, new.height) == (640, 480)
        assert new.fx == pytest.approx(2 * old.fx, rel=1e-12)
        assert new.fy == pytest.approx(2 * old.fy, rel=1e-12)
        assert (new.tilt, new.hfov, new.offset_x, new.offset_z) == (old.tilt, old.hfov, old.offset_x, old.offset_z)
    assert big.neck_height == RIG.neck_height


@pytest.mark.parametrize(
    ("changes", "field", "error"),
    [
        ({"width": 0}, "width", ValueError),
        ({"height": 0}, "height", ValueError),
        ({"width": 4}, "width", ValueError),
        ({"height": MIN_IMAGE_SIZE - 1}, "height", ValueError),
        ({"width": 4096}, "width", ValueError),
        ({"width": 320.0}, "width", TypeError),
        ({"width": True}, "width", TypeError),
        ({"hfov": 0.0}, "hfov", ValueError),
        ({"hfov": -0.5}, "hfov", ValueError),
        ({"hfov": 0.9 * math.pi}, "hfov", ValueError),
        ({"hfov": True}, "hfov", TypeError),
        ({"tilt": False}, "tilt", TypeError),
        ({"vfov": 3.0}, "vfov", ValueError),
        ({"tilt": math.nan}, "tilt", ValueError),
        ({"offset_x": math.inf}, "offset_x", ValueError),
        ({"offset_z": "0.1"}, "offset_z", TypeError),
    ],
)
def test_camera_spec_rejects_bad_input(changes: dict[str, object], field: str, error: type[Exception]) -> None:
    with pytest.raises(error, match=rf"CameraSpec\.{field}\b"):
        CameraSpec(**{"tilt": 0.1, "hfov": 1.0, "vfov": 0.75, **changes})  # type: ignore[arg-type]


def test_camera_spec_accepts_minimum_size() -> None:
    s = replace(NAO_UPPER, width=MIN_IMAGE_SIZE, height=np.int64(MIN_IMAGE_SIZE))
    assert s.cx == MIN_IMAGE_SIZE / 2


def test_camera_rig_rejects_bad_input() -> None:
    with pytest.raises(ValueError, match="neck_height"):
        CameraRig(neck_height=-0.1)
    with pytest.raises(ValueError, match="middle"):
        RIG.spec("middle")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="middle"):
        RIG.camera_matrix("middle", 0.0, 0.0)  # type: ignore[arg-type]
    assert RIG.spec(0) is RIG.upper
    assert RIG.spec(1) is RIG.lower


@pytest.mark.parametrize("seed", range(5))
def test_camera_pose_nb_matches_hand_built_rotation(seed: int) -> None:
    rng = np.random.default_rng(seed)
    yaw, pitch = rng.uniform(-2.0, 2.0), rng.uniform(-0.7, 0.6)
    neck, ox, oz, tilt = rng.uniform(0.3, 0.6), rng.uniform(0.0, 0.1), rng.uniform(0.0, 0.1), rng.uniform(0.0, 0.8)
    rot, pos = np.empty((3, 3)), np.empty(3)
    camera_pose_nb(neck, ox, oz, tilt, yaw, pitch, rot, pos)
    np.testing.assert_allclose(rot, Rz(yaw) @ Ry(pitch + tilt), atol=1e-14)
    np.testing.assert_allclose(pos, [0.0, 0.0, neck] + Rz(yaw) @ Ry(pitch) @ [ox, 0.0, oz], atol=1e-14)
    np.testing.assert_allclose(rot @ rot.T, np.eye(3), atol=1e-14)
    assert np.linalg.det(rot) == pytest.approx(1.0, abs=1e-14)
    assert rot[:, 0] @ [0.0, 0.0, 1.0] == pytest.approx(-math.sin(pitch + tilt), abs=1e-14)  # looks down


def test_as_row() -> None:
    cam = RIG.camera_matrix("lower", 0.4, 0.2)
    s = cam.spec
    row = cam.as_row()
    assert row.shape == (18,) == (CAMERA_ROW_SIZE,)
    np.testing.assert_array_equal(row[:9], cam.rotation.ravel())
    np.testing.assert_array_equal(row[:9].reshape(3, 3), cam.rotation)
    np.testing.assert_array_equal(row[9:12], cam.position)
    np.testing.assert_array_equal(row[12:], [s.fx, s.fy, s.cx, s.cy, s.width, s.height])
