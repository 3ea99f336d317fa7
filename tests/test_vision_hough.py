"""The Hough line method (:mod:`cognition.vision.hough`, NimbRo 5.1-5.2) on painted images with
known ground lines: positions and directions on the ground, crossings built from its segments,
the centre circle found and kept out of the lines, nothing made up, parameters and bad input.

The images are painted as in ``tests/test_vision.py`` (green carpet, white lines of the field's
width projected with the camera model), so the truth is exact.
"""

from __future__ import annotations

import dataclasses
import math

import cv2
import numpy as np
import pytest

from cognition.camera import CameraMatrix, CameraRig
from cognition.field import FIELD_PRESETS, Field
from cognition.vision.boundary import field_boundary
from cognition.vision.colour import ColourClassifier
from cognition.vision.crossings import L_KIND, T_KIND, X_KIND, crossings_nb
from cognition.vision.hough import HoughLines, HoughParams, hough_lines
from cognition.vision.params import VisionParams
from tests.test_vision import paint

FIELD = Field(FIELD_PRESETS["spl2025"], "spl2025")
LINE_WIDTH = FIELD.dims.line_width
RADIUS = FIELD.centre_circle.radius


def _camera(yaw: float = 0.0, pitch: float = 0.3) -> CameraMatrix:
    return CameraRig().camera_matrix("upper", yaw, pitch)


def _inputs(camera: CameraMatrix, image: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    classes = ColourClassifier().classify(image, camera)
    return classes, field_boundary(classes, camera, 6), camera.as_row()


def _lines(camera: CameraMatrix, image: np.ndarray, radius: float = RADIUS) -> HoughLines:
    classes, boundary, cam = _inputs(camera, image)
    return hough_lines(classes, boundary, cam, LINE_WIDTH, radius, HoughParams())


def _crossings(camera: CameraMatrix, image: np.ndarray, lines: HoughLines) -> np.ndarray:
    """crossings_nb on the Hough segments with the vision defaults, as the pipeline calls it."""
    classes, boundary, cam = _inputs(camera, image)
    p = VisionParams()
    return crossings_nb(
        lines.seg_ground, lines.open_ends, classes, boundary, cam, p.crossing_margin, p.crossing_margin_in,
        p.crossing_beyond, p.crossing_angle, p.crossing_min_arm, 0.3, p.merge_angle, p.merge_offset, p.merge_gap,
        p.crossing_max_mpp,
    )  # fmt: skip


def _off_line(q: np.ndarray, a: tuple[float, float], b: tuple[float, float]) -> float:
    """Distance (m) of the ground point q from the line through a and b."""
    d = np.subtract(b, a)
    r = np.subtract(q, a)
    return abs(float(d[0] * r[1] - d[1] * r[0])) / float(np.hypot(*d))


def _direction_error(seg: np.ndarray, a: tuple[float, float], b: tuple[float, float]) -> float:
    got = math.atan2(seg[3] - seg[1], seg[2] - seg[0])
    want = math.atan2(b[1] - a[1], b[0] - a[0])
    return abs(math.remainder(got - want, math.pi))


def _length(seg: np.ndarray) -> float:
    return float(np.hypot(seg[2] - seg[0], seg[3] - seg[1]))


# -- lines on the ground --------------------------------------------------------------------


@pytest.mark.parametrize(
    ("yaw", "pitch", "a", "b"),
    [
        (0.3, 0.28, (1.0, 0.4), (3.0, 1.4)),  # oblique
        (0.0, 0.30, (2.5, -1.5), (2.5, 1.5)),  # across the view
        (-0.5, 0.35, (0.8, -0.2), (2.6, -1.2)),  # to the right, steep in the image
    ],
)
def test_one_straight_line_has_its_direction_and_distance_on_the_ground(
    yaw: float, pitch: float, a: tuple[float, float], b: tuple[float, float]
) -> None:
    cam = _camera(yaw, pitch)
    img = paint(cam, [(*a, *b)])
    lines = _lines(cam, img)
    assert len(lines.seg_ground) >= 1
    k = int(np.argmax([_length(s) for s in lines.seg_ground]))
    seg = lines.seg_ground[k]
    for q in (seg[:2], seg[2:]):  # both ends on the true line (a few cm)
        assert _off_line(q, a, b) < 0.03
    assert _direction_error(seg, a, b) < math.radians(1.0)
    assert _length(seg) > 0.6 * math.dist(a, b) - 0.1  # most of the line (the view may cut it)
    for s in lines.seg_ground:  # nothing else made up
        assert _off_line(s[:2], a, b) < 0.05 and _off_line(s[2:], a, b) < 0.05
    # the image ends are the ground ends' pixels
    for e in range(2):
        u, v = lines.seg_px[k, 2 * e : 2 * e + 2]
        xy, ok = cam.pixel_to_ground(np.array([[u, v]]))
        assert ok[0] and np.hypot(*(xy[0] - seg[2 * e : 2 * e + 2])) < 0.02
    # the oriented points lie on the line and point along it
    pts = lines.points
    assert pts.shape[1] == 5 and len(pts) >= 10
    on = np.array([_off_line(p[2:4], a, b) for p in pts])
    assert np.median(on) < 0.03  # (the painter's polygons sit half a pixel off the camera model's pixels)
    want = math.atan2(b[1] - a[1], b[0] - a[0]) % math.pi
    err = np.abs(np.remainder(pts[:, 4] - want + math.pi / 2, math.pi) - math.pi / 2)
    assert np.all((pts[:, 4] >= 0.0) & (pts[:, 4] < math.pi))
    assert np.median(err) < math.radians(3.0)


def test_parallel_lines_are_separate_segments() -> None:
    """Goal line and goal area line (0.6 m apart) are two peaks of one main orientation."""
    cam = _camera(0.0, 0.3)
    img = paint(cam, [(1.8, -1.5, 1.8, 1.5), (2.4, -1.5, 2.4, 1.5), (3.4, -1.5, 3.4, 1.5)])
    lines = _lines(cam, img)
    xs = sorted(0.5 * (s[0] + s[2]) for s in lines.seg_ground)
    assert len(xs) == 3
    assert np.allclose(xs, [1.8, 2.4, 3.4], atol=0.06)
    for s in lines.seg_ground:
        assert abs(s[0] - s[2]) < 0.05  # across the view: x constant


def test_a_line_leaving_the_image_has_an_open_end_there() -> None:
    cam = _camera(0.0, 0.3)
    img = paint(cam, [(2.0, 0.0, 2.0, -5.0)])  # starts in view, runs out of the right of the image
    lines = _lines(cam, img)
    assert len(lines.seg_ground) == 1
    seg, ends = lines.seg_ground[0], lines.open_ends[0]
    inner = 0 if seg[1] > seg[3] else 1
    assert abs(seg[2 * inner + 1]) < 0.05  # the real end, where the paint stops
    assert not ends[inner] and ends[1 - inner]
    assert max(lines.seg_px[0, 0], lines.seg_px[0, 2]) > 318.0  # followed to the image edge


def test_thin_white_strands_are_not_lines() -> None:
    """A goal net's strands over the carpet: white with green on both sides, but one pixel wide
    where a painted line is several."""
    cam = _camera(0.0, 0.45)
    img = paint(cam, [])
    for k in range(6):
        cv2.line(img, (40 + 40 * k, 150), (60 + 40 * k, 235), (250, 250, 250), 1)
        cv2.line(img, (20, 160 + 12 * k), (300, 165 + 12 * k), (250, 250, 250), 1)
    lines = _lines(cam, img)
    assert len(lines.seg_ground) == 0
    assert len(lines.points) < 10


def test_a_robot_on_a_line_leaves_open_ends_not_a_corner() -> None:
    """A dark object standing on a line splits it; the ends at the object are open, so no L
    is made there."""
    cam = _camera(0.0, 0.3)
    img = paint(cam, [(2.5, -1.5, 2.5, 1.5)])
    u, v = cam.project([[2.5, 0.0, 0.0]])[0][0]
    img[: int(v) + 12, int(u) - 14 : int(u) + 14] = (60, 60, 70)  # a robot's legs in front of the line
    lines = _lines(cam, img)
    assert len(lines.seg_ground) == 2
    for seg, ends in zip(lines.seg_ground, lines.open_ends, strict=True):
        inner = 0 if abs(seg[1]) < abs(seg[3]) else 1
        assert abs(seg[2 * inner + 1]) < 0.25 and ends[inner]  # the end at the robot is open
        assert abs(seg[0] - 2.5) < 0.04 and abs(seg[2] - 2.5) < 0.04


# -- crossings from the segments ------------------------------------------------------------


def test_perpendicular_lines_give_the_t_and_the_l_at_their_place() -> None:
    cam = _camera(0.0, 0.3)
    t_img = paint(cam, [(2.5, -1.2, 2.5, 1.2), (1.3, 0.3, 2.5, 0.3)])  # bar and a stem toward the robot
    lines = _lines(cam, t_img)
    assert len(lines.seg_ground) == 2
    cross = _crossings(cam, t_img, lines)
    assert cross[:, 2].tolist() == [T_KIND]
    assert np.hypot(cross[0, 0] - 2.5, cross[0, 1] - 0.3) < 0.08
    assert abs(math.remainder(cross[0, 3] - math.pi, 2 * math.pi)) < math.radians(5)  # the stem points back
    l_img = paint(cam, [(2.0, 0.0, 2.0, 1.2), (2.0, 0.0, 3.2, 0.0)])
    cross = _crossings(cam, l_img, _lines(cam, l_img))
    assert cross[:, 2].tolist() == [L_KIND]
    assert np.hypot(cross[0, 0] - 2.0, cross[0, 1]) < 0.08
    assert abs(math.remainder(cross[0, 3] - math.pi / 4, 2 * math.pi)) < math.radians(6)


def test_two_lines_crossing_give_an_x() -> None:
    cam = _camera(0.0, 0.3)
    img = paint(cam, [(2.5, -1.0, 2.5, 1.0), (1.5, 0.2, 3.5, 0.2)])
    cross = _crossings(cam, img, _lines(cam, img))
    assert cross[:, 2].tolist() == [X_KIND]
    assert np.hypot(cross[0, 0] - 2.5, cross[0, 1] - 0.2) < 0.08


# -- the centre circle ----------------------------------------------------------------------


def test_the_circle_is_found_and_its_points_make_no_lines() -> None:
    cam = _camera(0.0, 0.35)
    img = paint(cam, [(2.2, -1.5, 2.2, 1.5)], circle=(2.2, 0.0, RADIUS))
    lines = _lines(cam, img)
    assert np.hypot(lines.circle[0] - 2.2, lines.circle[1]) < 0.08
    assert len(lines.seg_ground) >= 1
    for s in lines.seg_ground:  # only the halfway line, none of the arcs
        assert abs(s[0] - 2.2) < 0.04 and abs(s[2] - 2.2) < 0.04
    assert max(abs(s[1] - s[3]) for s in lines.seg_ground) > 1.0
    # without the circle step the arcs do make lines: the removal is what keeps them out
    blind = _lines(cam, img, radius=0.0)
    assert math.isnan(blind.circle[0])
    assert any(abs(s[0] - 2.2) > 0.1 or abs(s[2] - 2.2) > 0.1 for s in blind.seg_ground)


def test_no_circle_is_made_up_from_straight_lines() -> None:
    cam = _camera(0.0, 0.35)
    corner = paint(cam, [(1.5, -0.75, 1.5, 1.5), (1.5, -0.75, 3.0, -0.75), (3.0, -1.5, 3.0, 1.5)])
    lines = _lines(cam, corner)
    assert math.isnan(lines.circle[0]) and math.isnan(lines.circle[1])
    assert len(lines.seg_ground) == 3


# -- nothing, parameters, bad input ---------------------------------------------------------


def test_bare_carpet_gives_nothing() -> None:
    cam = _camera(0.0, 0.3)
    lines = _lines(cam, paint(cam, []))
    assert lines.seg_px.shape == (0, 4) and lines.seg_ground.shape == (0, 4) and lines.open_ends.shape == (0, 2)
    assert lines.points.shape == (0, 5)
    assert math.isnan(lines.circle[0])
    # nor does a camera looking into the sky
    sky = _camera(0.0, -0.6)
    classes = np.zeros((240, 320), dtype=np.uint8)
    empty = hough_lines(classes, np.full(320, 240, dtype=np.int32), sky.as_row(), LINE_WIDTH, RADIUS, HoughParams())
    assert len(empty.seg_px) == 0 and len(empty.points) == 0


def test_parameters_have_ranges() -> None:
    p = HoughParams()
    assert dataclasses.replace(p) == p
    assert p.theta_bin == pytest.approx(math.radians(2.5)) and p.rho_bin == 0.06  # NimbRo's discretization
    assert p.orientations == 4
    for name, bad in (("rho_bin", 0.0), ("min_response", 1.5), ("orientations", 1), ("max_lines", 0)):
        with pytest.raises(ValueError, match=rf"HoughParams\.{name}"):
            dataclasses.replace(p, **{name: bad})
    with pytest.raises(TypeError, match=r"HoughParams\.scan_step"):
        dataclasses.replace(p, scan_step=2.5)
    with pytest.raises(ValueError, match=r"HoughParams\.theta_bin"):
        HoughParams(theta_bin=math.nan)


def test_bad_input_is_refused_with_a_clear_error() -> None:
    cam = _camera(0.0, 0.3)
    classes, boundary, row = _inputs(cam, paint(cam, [(2.0, -1.0, 2.0, 1.0)]))
    p = HoughParams()
    with pytest.raises(ValueError, match="uint8 class image"):
        hough_lines(classes.astype(np.float64), boundary, row, LINE_WIDTH, RADIUS, p)
    with pytest.raises(ValueError, match="uint8 class image"):
        hough_lines(classes[None], boundary, row, LINE_WIDTH, RADIUS, p)
    with pytest.raises(ValueError, match="boundary"):
        hough_lines(classes, boundary[:-1], row, LINE_WIDTH, RADIUS, p)
    with pytest.raises(ValueError, match="boundary"):
        hough_lines(classes, boundary.astype(np.float64), row, LINE_WIDTH, RADIUS, p)
    with pytest.raises(ValueError, match="camera row"):
        hough_lines(classes, boundary, row[:9], LINE_WIDTH, RADIUS, p)
    bad = row.copy()
    bad[0] = np.nan
    with pytest.raises(ValueError, match="camera row"):
        hough_lines(classes, boundary, bad, LINE_WIDTH, RADIUS, p)
    with pytest.raises(ValueError, match="camera is 640 x 480"):
        big = CameraRig().with_resolution(640, 480).camera_matrix("upper", 0.0, 0.3)
        hough_lines(classes, boundary, big.as_row(), LINE_WIDTH, RADIUS, p)
    for width in (0.0, -0.05, math.nan):
        with pytest.raises(ValueError, match="line_width"):
            hough_lines(classes, boundary, row, width, RADIUS, p)
    with pytest.raises(ValueError, match="circle_radius"):
        hough_lines(classes, boundary, row, LINE_WIDTH, -1.0, p)
    with pytest.raises(TypeError, match="HoughParams"):
        hough_lines(classes, boundary, row, LINE_WIDTH, RADIUS, VisionParams())  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="at least 8 x 8"):
        hough_lines(classes[:4, :4], boundary[:4], row, LINE_WIDTH, RADIUS, p)
