"""The vision pipeline (:mod:`cognition.vision`) stage by stage, on synthetic images with
known content, on rendered frames, on YUV422 input and on bad input.

Synthetic images are painted here from ground-plane geometry with the camera model (a green
carpet, white lines of the field's width projected as polygons), so the truth is exact and
independent of the simulator's renderer.
"""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest
from helpers import clip_front

from cognition.camera import CameraMatrix, CameraRig, torso_rotation
from cognition.field import FIELD_PRESETS, Field
from cognition.percepts import Kind, Percepts
from cognition.vision import Colour, Vision, VisionError, VisionParams, rgb_to_yuv422
from cognition.vision.birdseye import birds_eye, ground_to_view
from cognition.vision.boundary import field_boundary
from cognition.vision.colour import ColourClassifier

FIELD = Field(FIELD_PRESETS["spl2025"], "spl2025")
GREEN = (0, 140, 40)
WHITE = (250, 250, 250)


def paint(
    camera: CameraMatrix,
    lines: list[tuple[float, float, float, float]],
    width: float = 0.05,
    seed: int = 0,
    circle: tuple[float, float, float] | None = None,
) -> np.ndarray:
    """A camera image of green carpet with white ground lines (robot frame, m), slightly noisy;
    the sky above the horizon is grey."""
    s = camera.spec
    img = np.full((s.height, s.width, 3), (90, 90, 96), dtype=np.uint8)
    carpet = np.array([[-1.0, -20.0, 0.0], [30.0, -20.0, 0.0], [30.0, 20.0, 0.0], [-1.0, 20.0, 0.0]])
    _fill(img, camera, carpet, GREEN)
    for x1, y1, x2, y2 in lines:
        d = np.array([x2 - x1, y2 - y1])
        n = np.array([-d[1], d[0]]) / np.linalg.norm(d) * width / 2
        a, b = np.array([x1, y1]), np.array([x2, y2])
        quad = np.array([a + n, b + n, b - n, a - n])
        _fill(img, camera, np.column_stack([quad, np.zeros(4)]), WHITE)
    if circle is not None:
        cx, cy, r = circle
        a = np.linspace(0.0, 2.0 * math.pi, 181)
        for k in range(180):
            for lo, hi in ((r - width / 2, r + width / 2),):
                quad = [
                    (cx + lo * math.cos(a[k]), cy + lo * math.sin(a[k])),
                    (cx + hi * math.cos(a[k]), cy + hi * math.sin(a[k])),
                    (cx + hi * math.cos(a[k + 1]), cy + hi * math.sin(a[k + 1])),
                    (cx + lo * math.cos(a[k + 1]), cy + lo * math.sin(a[k + 1])),
                ]
                _fill(img, camera, np.column_stack([np.array(quad), np.zeros(4)]), WHITE)
    rng = np.random.default_rng(seed)
    return np.clip(img + rng.normal(0.0, 2.0, img.shape), 0, 255).astype(np.uint8)


def _fill(img: np.ndarray, camera: CameraMatrix, polygon: np.ndarray, colour: tuple[int, int, int]) -> None:
    """Fill a ground polygon (clipped to the part in front of the camera)."""
    pts = clip_front(camera, polygon)
    if len(pts) < 3:
        return
    uv, _ = camera.project(pts)
    cv2.fillPoly(img, [np.round(uv * 16).astype(np.int32)], colour, lineType=cv2.LINE_AA, shift=4)


def _camera(yaw: float = 0.0, pitch: float = 0.25, roll: float = 0.0, torso_pitch: float = 0.0) -> CameraMatrix:
    return CameraRig().camera_matrix("upper", yaw, pitch, torso_roll=roll, torso_pitch=torso_pitch)


# -- stages on synthetic images -----------------------------------------------------------


def test_colour_classes_and_calibration_follow_the_exposure() -> None:
    cam = _camera()
    img = paint(cam, [(1.0, -1.0, 3.0, -1.0)])
    for gain in (0.55, 1.0, 1.35):  # dim hall, normal, overexposed
        dark = np.clip(img.astype(np.float32) * gain, 0, 255).astype(np.uint8)
        cl = ColourClassifier()
        classes = cl.classify(dark, cam)
        below = classes[cam.spec.height // 2 :]
        assert np.mean(below == Colour.GREEN) > 0.85, gain
        u, v = cam.project([[2.0, -1.0, 0.0]])[0][0]
        assert classes[int(v), int(u)] == Colour.WHITE, gain
        assert abs(cl.calibration.value - np.median(dark[-20:, :, 1])) < 12


def test_field_boundary_ignores_green_above_the_horizon() -> None:
    cam = _camera(pitch=0.1)
    img = paint(cam, [])
    img[5:25, 100:200] = GREEN  # a green board in the hall, above the horizon
    classes = ColourClassifier().classify(img, cam)
    b = field_boundary(classes, cam, 6)
    hz = cam.horizon()
    assert hz is not None
    assert np.all(b[100:200] >= min(hz) - 3)
    assert np.all(b < cam.spec.height)


def test_a_known_t_crossing_is_found_as_a_t_at_its_pixel_and_orientation() -> None:
    cam = _camera(pitch=0.3)
    # a T: bar along y at x = 2.5, stem from the bar toward the robot
    img = paint(cam, [(2.5, -1.2, 2.5, 1.2), (1.3, 0.3, 2.5, 0.3)])
    p = Vision(field=FIELD, scheme="classic").detect(img, cam)
    cross = p.crossings
    assert len(cross) == 1, cross.rows
    assert cross.subtype[0] == 1  # T
    u, v = cam.project([[2.5, 0.3, 0.0]])[0][0]
    assert np.hypot(*(cross.uv[0] - (u, v))) < 3.0
    assert np.hypot(*(cross.xy[0] - (2.5, 0.3))) < 0.1
    stem = math.pi  # from the junction toward the robot
    assert abs(math.remainder(cross.orientation[0] - stem, 2 * math.pi)) < math.radians(5)


def test_l_and_x_crossings_and_their_orientations() -> None:
    cam = _camera(pitch=0.3)
    corner = paint(cam, [(2.0, 0.0, 2.0, 1.2), (2.0, 0.0, 3.2, 0.0)])
    p = Vision(field=FIELD, scheme="classic").detect(corner, cam)
    assert p.crossings.subtype.tolist() == [0]
    assert np.hypot(*(p.crossings.xy[0] - (2.0, 0.0))) < 0.1
    assert abs(math.remainder(p.crossings.orientation[0] - math.pi / 4, 2 * math.pi)) < math.radians(6)
    cross = paint(cam, [(2.5, -1.0, 2.5, 1.0), (1.5, 0.2, 3.5, 0.2)])
    p = Vision(field=FIELD, scheme="classic").detect(cross, cam)
    assert p.crossings.subtype.tolist() == [2]
    assert np.hypot(*(p.crossings.xy[0] - (2.5, 0.2))) < 0.1


def test_a_line_seen_to_the_image_edge_makes_no_l() -> None:
    """A line that leaves the image has no known end: a corner there would be a guess."""
    cam = _camera(pitch=0.3)
    img = paint(cam, [(2.0, 0.0, 2.0, 5.0), (2.0, 0.0, 9.0, 0.0)])
    img[:, :40] = (60, 60, 60)  # an object covers the left of the image (not carpet)
    p = Vision(field=FIELD, scheme="classic").detect(img, cam)
    ls = p.crossings.xy[p.crossings.subtype == 0]
    assert all(np.hypot(*(xy - (2.0, 0.0))) < 0.15 for xy in ls)


def test_lines_are_measured_on_the_ground() -> None:
    cam = _camera(yaw=0.3, pitch=0.28)
    img = paint(cam, [(1.0, 0.4, 3.0, 1.4)])
    p = Vision(field=FIELD, scheme="classic").detect(img, cam)
    assert len(p.lines) == 1
    a, b = p.lines.xy[0], p.lines.xy2[0]
    for q in (a, b):  # end points lie on the true line (within 3 cm)
        r = q - (1.0, 0.4)
        d = (2.0 * r[1] - 1.0 * r[0]) / math.hypot(2.0, 1.0)
        assert abs(d) < 0.03
    assert abs(p.lines.orientation[0] - math.atan2(1.0, 2.0)) < math.radians(2)


def test_centre_circle_found_and_not_made_up() -> None:
    cam = _camera(pitch=0.35)
    img = paint(cam, [(2.2, -1.5, 2.2, 1.5)], circle=(2.2, 0.0, FIELD.centre_circle.radius))
    p = Vision(field=FIELD, scheme="classic").detect(img, cam)
    assert len(p.circle) == 1
    assert np.hypot(*(p.circle.xy[0] - (2.2, 0.0))) < 0.1
    # the halfway line through the centre crosses the circle twice: two X
    xs = p.crossings.xy[p.crossings.subtype == 2]
    assert len(xs) >= 1
    assert all(min(np.hypot(*(x - (2.2, s * 0.75))) for s in (-1, 1)) < 0.12 for x in xs)
    corner = paint(cam, [(1.5, -0.75, 1.5, 1.5), (1.5, -0.75, 3.0, -0.75), (3.0, -1.5, 3.0, 1.5)])
    assert len(Vision(field=FIELD, scheme="classic").detect(corner, cam).circle) == 0


def test_arcs_of_the_centre_circle_seen_from_inside_are_no_lines() -> None:
    """A robot near the centre spot sees a short arc of the circle ahead: too little of it for
    the circle, and its pieces are nearly straight in the image. They must not become lines
    (matched to the halfway line they turned the estimate of a robot there by tens of degrees).
    Over 40 such views (no straight line in any), testing neighbouring pieces together leaves
    a short piece now and then (about 0.3 per view; 2.3 when each piece was tested alone)."""
    r = FIELD.centre_circle.radius
    rng = np.random.default_rng(1)
    lines = with_lines = 0
    for k in range(40):
        cam = _camera(yaw=rng.uniform(-0.8, 0.8), pitch=rng.uniform(0.35, 0.55))
        d, a = rng.uniform(0.0, 0.5), rng.uniform(-math.pi, math.pi)
        p = Vision(field=FIELD, scheme="classic").detect(
            paint(cam, [], circle=(d * math.cos(a), d * math.sin(a), r), seed=k), cam
        )
        lines += len(p.lines)
        with_lines += len(p.lines) > 0
        assert all(np.hypot(*(p.lines.xy[q] - p.lines.xy2[q])) < 0.45 for q in range(len(p.lines)))
    assert lines <= 0.6 * 40 and with_lines <= 0.4 * 40, (lines, with_lines)


def test_chords_of_an_arc_are_tested_together_and_corners_are_not() -> None:
    """``arcs_nb``: three chords of 0.33 m of the circle are each too straight alone and an arc
    together; an L corner and two pieces of one straight line are no arcs."""
    from cognition.vision.dnt import arcs_nb

    r = FIELD.centre_circle.radius
    rng = np.random.default_rng(0)

    def chord(a0: float, a1: float, label: int) -> tuple[np.ndarray, np.ndarray]:
        a = np.linspace(a0, a1, 12)
        pts = np.column_stack([r * np.cos(a), r * np.sin(a)]) + rng.normal(0.0, 0.003, (12, 2))
        return pts, np.full(12, label)

    def straight(p: tuple[float, float], q: tuple[float, float], label: int) -> tuple[np.ndarray, np.ndarray]:
        t = np.linspace(0.0, 1.0, 12)[:, None]
        pts = np.asarray(p) + t * (np.asarray(q) - np.asarray(p)) + rng.normal(0.0, 0.003, (12, 2))
        return pts, np.full(12, label)

    step = 0.33 / r
    pieces = [chord(k * step, (k + 0.9) * step, k) for k in range(3)]
    ground, labels = np.vstack([p for p, _ in pieces]), np.concatenate([lab for _, lab in pieces])
    assert arcs_nb(ground, labels, 3, r).tolist() == [True, True, True]
    for k in range(3):  # alone, each piece is too straight to tell
        assert not arcs_nb(pieces[k][0], np.zeros(12, dtype=np.int64), 1, r)[0]
    corner = [straight((1.0, 0.0), (1.0, 0.4), 0), straight((1.05, 0.0), (1.45, 0.0), 1)]
    line = [straight((1.0, -0.5), (1.0, -0.15), 0), straight((1.0, 0.0), (1.0, 0.35), 1)]
    for case in (corner, line):
        ground, labels = np.vstack([p for p, _ in case]), np.concatenate([lab for _, lab in case])
        assert arcs_nb(ground, labels, 2, r).tolist() == [False, False]


def test_the_torso_lean_is_part_of_the_camera_matrix() -> None:
    """A robot leaning forward by 5 degrees: the upright model misplaces a T by decimetres,
    the camera matrix with the IMU's pitch finds it where it is."""
    lean = math.radians(5)
    real = _camera(pitch=0.2, torso_pitch=lean)
    img = paint(real, [(2.8, -1.2, 2.8, 1.2), (1.6, 0.2, 2.8, 0.2)])
    right = Vision(field=FIELD, scheme="classic").detect(img, real).crossings
    wrong = Vision(field=FIELD, scheme="classic").detect(img, _camera(pitch=0.2)).crossings
    assert len(right) == 1 and np.hypot(*(right.xy[0] - (2.8, 0.2))) < 0.1
    assert len(wrong) == 0 or np.hypot(*(wrong.xy[0] - (2.8, 0.2))) > 0.4
    # the rotation pivots at the ground point between the feet
    assert np.allclose(torso_rotation(0.0, lean) @ np.array([0.0, 0.0, 1.0]), [math.sin(lean), 0.0, math.cos(lean)])
    roundtrip, ok = real.pixel_to_ground(real.project([[2.0, -0.4, 0.0]])[0])
    assert ok[0] and np.allclose(roundtrip[0], [2.0, -0.4], atol=1e-9)


def test_birds_eye_view_puts_ground_points_where_they_are() -> None:
    cam = _camera(pitch=0.3)
    img = paint(cam, [(2.0, -0.5, 2.0, 0.5)])
    view = birds_eye(img, cam, far=4.0, half_width=2.0, metres_per_pixel=0.02)
    c, r = ground_to_view(np.array([[2.0, 0.0]]), far=4.0, half_width=2.0, metres_per_pixel=0.02)[0]
    assert view[int(r), int(c)].min() > 200  # the white line
    assert view[int(r) + 10, int(c), 1] > view[int(r) + 10, int(c), 0] + 60  # carpet 20 cm nearer
    assert view[-1, 0].max() == 0  # beside and behind the camera's view: black


# -- input formats and bad input -----------------------------------------------------------


def _same(a: Percepts, b: Percepts, tolerance: float) -> tuple[int, int]:
    """(percepts of ``a`` with a percept of the same kind in ``b`` within ``tolerance`` px, all of ``a``)."""
    found = total = 0
    for kind in Kind:
        ta, tb = a.table(kind), b.table(kind)
        for k in range(len(ta)):
            total += 1
            if kind == Kind.LINE:
                m = (ta.uv[k] + ta.uv2[k]) / 2
                gaps = [_point_segment(m, s0, s1) for s0, s1 in zip(tb.uv, tb.uv2, strict=True)]
            else:
                gaps = list(np.hypot(*(tb.uv - ta.uv[k]).T))
            found += bool(gaps) and min(gaps) < tolerance
    return found, total


def test_yuv422_gives_the_same_percepts_as_rgb() -> None:
    """NAO cameras deliver YUV422; a frame packed from an RGB image gives its percepts. Chroma
    subsampling moves blended edge pixels, so on rendered frames a borderline detection may
    come and go; on clean painted images everything is the same."""
    cam = _camera(pitch=0.3)
    for lines, circle in (
        ([(2.5, -1.2, 2.5, 1.2), (1.3, 0.3, 2.5, 0.3)], None),
        ([(2.0, 0.0, 2.0, 1.2), (2.0, 0.0, 3.2, 0.0)], None),
        ([(2.2, -1.5, 2.2, 1.5)], (2.2, 0.0, 0.75)),
    ):
        img = paint(cam, lines, circle=circle)
        a = Vision(field=FIELD, scheme="classic").detect(img, cam)
        b = Vision(field=FIELD, scheme="classic").detect(rgb_to_yuv422(img), cam)
        assert [len(a.table(k)) for k in Kind] == [len(b.table(k)) for k in Kind]
        assert _same(a, b, 1.5) == (len(a), len(a)) and len(a) >= 2

    from teamsim.images import ImageRenderer
    from teamsim.percepts import Scene, SceneRobot

    ren = ImageRenderer(FIELD, "classic", CameraRig(), "default", np.random.default_rng(3))
    found = total = 0
    rng = np.random.default_rng(7)
    for _ in range(12):
        pose = (rng.uniform(-4, 4), rng.uniform(-2.5, 2.5), rng.uniform(-3, 3))
        scene = Scene.build([SceneRobot(0, 1, *pose, head_pitch=rng.uniform(0.1, 0.4))], (pose[0] + 1.0, pose[1]), 1)
        img, cam = ren.render(scene, 0), ren.camera_matrix(scene, 0)
        a = Vision(field=FIELD, scheme="classic").detect(img, cam)
        b = Vision(field=FIELD, scheme="classic").detect(rgb_to_yuv422(img), cam)
        for x, y in ((a, b), (b, a)):
            f, t = _same(x, y, 6.0)
            found, total = found + f, total + t
    assert total >= 30 and found >= 0.85 * total, (found, total)


def _point_segment(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    """Distance (px) of point p from the segment a-b."""
    d = b - a
    t = float(np.clip(np.dot(p - a, d) / max(np.dot(d, d), 1e-12), 0.0, 1.0))
    return float(np.hypot(*(p - a - t * d)))


@pytest.mark.parametrize(
    ("image", "message"),
    [
        ([[1, 2, 3]], "must be a numpy array"),
        (np.zeros((240, 320, 3), dtype=np.float32), "dtype uint8"),
        (np.zeros((240, 320), dtype=np.uint8), r"H x W x 3 \(RGB\) or H x W x 2"),
        (np.zeros((240, 320, 4), dtype=np.uint8), r"H x W x 3 \(RGB\) or H x W x 2"),
        (np.zeros((120, 160, 3), dtype=np.uint8), "160 x 120 pixels but the camera matrix is for 320 x 240"),
        (np.zeros((4, 4, 3), dtype=np.uint8), "outside"),
    ],
)
def test_bad_images_are_clear_errors(image: object, message: str) -> None:
    with pytest.raises(VisionError, match=message):
        Vision().detect(image, _camera())  # type: ignore[arg-type]


def test_bad_camera_matrices_are_clear_errors() -> None:
    cam = _camera()
    img = np.zeros((240, 320, 3), dtype=np.uint8)
    rot = cam.rotation.copy()
    rot[0, 0] = np.nan
    with pytest.raises(VisionError, match="non-finite entries in its rotation"):
        Vision().detect(img, CameraMatrix(rot, cam.position, cam.spec))
    pos = cam.position.copy()
    pos[2] = np.inf
    with pytest.raises(VisionError, match="non-finite entries in its position"):
        Vision().detect(img, CameraMatrix(cam.rotation, pos, cam.spec))
    with pytest.raises(VisionError, match="CameraMatrix"):
        Vision().detect(img, "upper")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="torso_pitch must be a finite angle"):
        CameraRig().camera_matrix("upper", 0.0, 0.0, torso_pitch=math.nan)


def test_degenerate_images_give_no_percepts() -> None:
    cam = _camera()
    for img in (
        np.zeros((240, 320, 3), dtype=np.uint8),
        np.full((240, 320, 3), 255, dtype=np.uint8),
        np.full((240, 320, 3), GREEN, dtype=np.uint8),
        np.random.default_rng(0).integers(0, 256, (240, 320, 3), dtype=np.uint8),
    ):
        p = Vision().detect(img, cam)
        assert len(p.crossings) == len(p.circle) == len(p.posts) == 0
    tiny = CameraRig().with_resolution(8, 8).camera_matrix("upper", 0.0, 0.4)
    assert len(Vision().detect(np.full((8, 8, 3), GREEN, dtype=np.uint8), tiny)) == 0


def test_params_are_checked() -> None:
    with pytest.raises(ValueError, match=r"VisionParams\.scan_step"):
        VisionParams(scan_step=0)
    with pytest.raises(ValueError, match="method"):
        from cognition.params import from_mapping

        from_mapping(VisionParams, {"method": "canny"})
    with pytest.raises(ValueError, match="unknown VisionParams key"):
        from cognition.params import from_mapping

        from_mapping(VisionParams, {"scanstep": 3})


def test_fast_paths_of_the_line_kernels_decide_as_the_plain_computations() -> None:
    """The shortcuts of the compiled line stages (scanline search eight pixels at a time, white
    ratios that stop early, squared-distance bounds before ``math.hypot``) give the same
    answers as the plain computations they stand in for."""
    from cognition.vision.circle import ring_bounds_nb
    from cognition.vision.scanlines import _next_white
    from cognition.vision.segments import white_ratio_nb

    rng = np.random.default_rng(5)
    for _ in range(200):
        n = int(rng.integers(1, 60))
        line = np.zeros((n + 15) // 8 * 8, dtype=np.uint8)
        line[:n] = rng.choice([0, 1, 2, 3], size=n, p=[0.3, 0.5, 0.1, 0.1])
        k = int(rng.integers(0, n + 1))
        plain = next((q for q in range(k, n) if line[q] == Colour.WHITE), n)
        assert _next_white(line, line.view(np.uint64), k, n) == plain
    classes = rng.choice([1, 2], size=(40, 50), p=[0.4, 0.6]).astype(np.uint8)
    for _ in range(300):
        u0, u1 = rng.uniform(-5.0, 55.0, 2)
        v0, v1 = rng.uniform(-5.0, 45.0, 2)
        full = white_ratio_nb(classes, u0, v0, u1, v1)
        at_least, above = rng.uniform(0.0, 1.0), rng.uniform(-1.0, 1.0)
        cut = white_ratio_nb(classes, u0, v0, u1, v1, at_least, above)
        assert cut == full or (cut == -1.0 and (full < at_least or full <= above))
    radius, inlier = 0.75, 0.08
    near2, far2 = ring_bounds_nb(radius, inlier)
    for d in np.concatenate([rng.uniform(0.0, 2.0, 2000), radius + inlier * np.array([-1.0, 1.0]) + 1e-15]):
        a = rng.uniform(-math.pi, math.pi)
        dx, dy = d * math.cos(a), d * math.sin(a)
        if abs(math.hypot(dx, dy) - radius) <= inlier:
            assert near2 <= dx * dx + dy * dy <= far2
