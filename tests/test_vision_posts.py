"""The goal-post detector (:mod:`cognition.vision.posts`): on class images painted here with
exact truth, on rendered frames against the renderer's annotations, and on bad input.

Painted class images: green carpet below the horizon, "other" above, and solids (posts,
crossbars, robots, corner poles) as the convex hull of their projected end circles (the
exact silhouette of a cylinder), lines as ground polygons, all with the camera model. The
field boundary comes from :func:`cognition.vision.boundary.field_boundary`, as in the
pipeline.
"""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest
from helpers import clip_front

from cognition.camera import CameraMatrix, CameraRig
from cognition.field import FIELD_PRESETS, Field
from cognition.percepts import N_COLS, N_KINDS, Col, Percepts, PostSide
from cognition.vision import Colour, VisionError
from cognition.vision.boundary import field_boundary
from cognition.vision.colour import ColourClassifier
from cognition.vision.posts import PostParams, detect_posts
from cognition.vision.projection import metres_per_pixel_nb

FIELD = Field(FIELD_PRESETS["spl2025"], "spl2025")
DIAMETER = FIELD.dims.goal_post_diameter
HEIGHT = FIELD.dims.goal_height
R = DIAMETER / 2
SIGMA = math.radians(1.0)
YELLOW = (int(Colour.YELLOW), int(Colour.YELLOW))
WHITE = (int(Colour.WHITE), int(Colour.WHITE))


def camera(yaw: float = 0.0, pitch: float = 0.15, roll: float = 0.0, rig: CameraRig | None = None) -> CameraMatrix:
    return (rig or CameraRig()).camera_matrix("upper", yaw, pitch, torso_roll=roll)


def carpet(cam: CameraMatrix) -> np.ndarray:
    """Class image: carpet below the horizon (and a strip beyond the far field edge), hall above."""
    s = cam.spec
    img = np.full((s.height, s.width), Colour.OTHER, dtype=np.uint8)
    fill_ground(img, cam, [(-1.0, -30.0), (12.0, -30.0), (12.0, 30.0), (-1.0, 30.0)], Colour.GREEN)
    return img


def fill_ground(img: np.ndarray, cam: CameraMatrix, poly: list[tuple[float, float]], cls: int) -> None:
    """Fill a ground polygon (robot frame, m), clipped to the part in front of the camera."""
    pts = clip_front(cam, np.array([(x, y, 0.0) for x, y in poly]))
    if len(pts) >= 3:
        uv, _ = cam.project(pts)
        _fill(img, uv, cls)


def fill_cylinder(
    img: np.ndarray, cam: CameraMatrix, a: tuple[float, float, float], b: tuple[float, float, float], r: float, cls: int
) -> None:
    """Fill the silhouette of the cylinder of radius ``r`` from ``a`` to ``b`` (robot frame)."""
    pa, pb = np.array(a, dtype=float), np.array(b, dtype=float)
    axis = (pb - pa) / np.linalg.norm(pb - pa)
    n1 = np.cross(axis, [0.0, 0.0, 1.0] if abs(axis[2]) < 0.9 else [1.0, 0.0, 0.0])
    n1 /= np.linalg.norm(n1)
    n2 = np.cross(axis, n1)
    t = np.linspace(0.0, 2 * math.pi, 72, endpoint=False)
    ring = r * (np.outer(np.cos(t), n1) + np.outer(np.sin(t), n2))
    pts = np.concatenate([pa + ring, pb + ring])
    uv, front = cam.project(pts)
    if not front.all():
        raise ValueError("cylinder behind the camera")
    _fill(img, cv2.convexHull(uv.astype(np.float32)).reshape(-1, 2), cls)


_SUB = 4  # subpixels per pixel and axis


def _fill(img: np.ndarray, uv: np.ndarray, cls: int) -> None:
    """Set the pixels at least half covered by the polygon ``uv`` (pixel (i, j) covers
    [i, i + 1) x [j, j + 1)) to ``cls``: OpenCV fills every pixel its outline touches, so the
    polygon is filled on a finer grid and the coverage counted."""
    h, w = img.shape
    mask = np.zeros((h * _SUB, w * _SUB), dtype=np.uint8)
    fixed = np.round((uv * _SUB - 0.5) * 16).astype(np.int32)  # OpenCV centres its pixel j on j
    cv2.fillPoly(mask, [fixed], 1, shift=4)
    cover = mask.reshape(h, _SUB, w, _SUB).mean(axis=(1, 3))
    img[cover >= 0.5] = int(cls)


def paint_post(img: np.ndarray, cam: CameraMatrix, x: float, y: float, cls: int = Colour.YELLOW) -> None:
    fill_cylinder(img, cam, (x, y, 0.0), (x, y, HEIGHT), R, cls)


def paint_goal(img: np.ndarray, cam: CameraMatrix, x: float, y0: float, y1: float, cls: int = Colour.YELLOW) -> None:
    """Two posts at (x, y0) and (x, y1) and the crossbar between their tops."""
    paint_post(img, cam, x, y0, cls)
    paint_post(img, cam, x, y1, cls)
    fill_cylinder(img, cam, (x, y0, HEIGHT - R), (x, y1, HEIGHT - R), R, cls)


def run(img: np.ndarray, cam: CameraMatrix, goals: tuple[int, int] = YELLOW, **kw: object) -> np.ndarray:
    boundary = field_boundary(img, cam, max(1, round(6 * cam.spec.height / 240)))
    return detect_posts(img, boundary, cam.as_row(), goals, DIAMETER, HEIGHT, PostParams(**kw), SIGMA, SIGMA)


def pixel(cam: CameraMatrix, x: float, y: float, z: float = 0.0) -> np.ndarray:
    return cam.project([[x, y, z]])[0][0]


def step(cam: CameraMatrix, u: float, v: float) -> float:
    """Ground distance (m) between the rows v and v + 1 at column u."""
    return metres_per_pixel_nb(cam.as_row(), u, v)[0]


# -- synthetic class images -----------------------------------------------------------------


@pytest.mark.parametrize(("x", "y"), [(1.5, 0.2), (3.0, 0.4), (5.0, -0.8), (8.0, 1.0)])
def test_a_post_is_found_at_its_foot_and_ground_position(x: float, y: float) -> None:
    cam = camera(yaw=math.atan2(y, x), pitch=0.05 if x > 4 else 0.2)
    img = carpet(cam)
    paint_post(img, cam, x, y)
    rows = run(img, cam)
    assert rows.shape == (1, N_COLS)
    row = rows[0]
    u, v = pixel(cam, x, y)
    assert abs(row[Col.U] - u) < 1.0 and abs(row[Col.V] - v) < 1.0
    err = math.hypot(row[Col.X] - x, row[Col.Y] - y)
    assert err < 0.01 + 0.6 * step(cam, u, v)  # the foot is a whole pixel row
    top = pixel(cam, x, y, HEIGHT)
    if top[1] >= 0:
        assert abs(row[Col.V2] - top[1]) < 2.0 and abs(row[Col.U2] - top[0]) < 2.0
    assert row[Col.SUBTYPE] == PostSide.UNKNOWN  # no crossbar, no second post
    assert row[Col.GOAL] == -1  # both goals share the colour
    assert row[Col.VAR_XX] > 0 and row[Col.VAR_YY] > 0
    assert row[Col.SIGMA_ALPHA] == SIGMA and row[Col.TRUTH] == -1


def test_the_foot_is_the_front_of_the_post_and_the_row_its_centre() -> None:
    cam = camera(pitch=0.35)
    img = carpet(cam)
    paint_post(img, cam, 1.2, 0.0)
    row = run(img, cam)[0]
    # the lowest painted pixel sees the front of the post, 5 cm nearer than its centre
    front = pixel(cam, 1.2 - R, 0.0)
    lowest = np.flatnonzero((img == Colour.YELLOW).any(axis=1)).max()
    assert abs(lowest + 1 - front[1]) < 1.0
    assert abs(row[Col.X] - 1.2) < 0.01 + 0.6 * step(cam, *front) and abs(row[Col.Y]) < 0.01


def test_two_posts_of_a_goal_are_left_and_right() -> None:
    cam = camera(pitch=0.0)
    img = carpet(cam)
    paint_goal(img, cam, 4.0, 0.8, -0.8)
    rows = run(img, cam)
    assert len(rows) == 2
    rows = rows[np.argsort(rows[:, Col.U])]
    assert rows[0, Col.SUBTYPE] == PostSide.LEFT and rows[1, Col.SUBTYPE] == PostSide.RIGHT
    assert np.allclose(rows[:, Col.Y], [0.8, -0.8], atol=0.06)
    assert np.allclose(rows[:, Col.X], 4.0, atol=0.1)


@pytest.mark.parametrize(("y_post", "side"), [(0.8, PostSide.LEFT), (-0.8, PostSide.RIGHT)])
def test_a_single_post_gets_its_side_from_the_crossbar(y_post: float, side: PostSide) -> None:
    # the other post is out of the image: the crossbar leaves it toward the goal's middle
    y_other = y_post - 1.6 if y_post > 0 else y_post + 1.6
    cam = camera(yaw=math.atan2(y_post, 3.0) + (0.4 if y_post > 0 else -0.4), pitch=0.1)
    img = carpet(cam)
    paint_goal(img, cam, 3.0, y_post, y_other)
    rows = run(img, cam)
    assert len(rows) == 1
    assert abs(rows[0, Col.Y] - y_post) < 0.05
    assert rows[0, Col.SUBTYPE] == side


def test_a_post_without_its_foot_in_view_is_not_reported() -> None:
    cam = camera(pitch=-0.2)  # looking up: the foot of a post 1 m ahead is below the image
    img = carpet(cam)
    paint_post(img, cam, 1.0, 0.0)
    assert pixel(cam, 1.0 - R, 0.0)[1] > cam.spec.height
    assert len(run(img, cam)) == 0


def test_a_post_cut_by_the_image_side_is_placed_from_its_visible_edge() -> None:
    cam = camera(pitch=0.1)
    xy, _ = cam.pixel_to_ground([[cam.spec.width - 4.0, 150.0]])  # the base 4 px inside the right edge
    x, y = xy[0]
    img = carpet(cam)
    paint_post(img, cam, x, y)
    assert np.count_nonzero(img[140] == Colour.YELLOW) < 0.8 * 15  # part of the post (15 px wide) is cut off
    rows = run(img, cam)
    assert len(rows) == 1
    assert abs(rows[0, Col.U] - pixel(cam, x, y)[0]) < 3.0
    assert math.hypot(rows[0, Col.X] - x, rows[0, Col.Y] - y) < 0.08
    # its base centre out of the image: not reported
    xy, _ = cam.pixel_to_ground([[cam.spec.width + 3.0, 150.0]])
    img = carpet(cam)
    paint_post(img, cam, *xy[0])
    assert len(run(img, cam)) == 0


def test_white_goals_are_told_from_lines_robots_and_the_ball() -> None:
    cam = camera(pitch=0.2)
    img = carpet(cam)
    # lines: one across, one along the view (it looks like a post's foot near the camera)
    fill_ground(img, cam, [(1.0, -3.0), (1.05, -3.0), (1.05, 3.0), (1.0, 3.0)], Colour.WHITE)
    fill_ground(img, cam, [(0.3, -0.425), (6.0, -0.425), (6.0, -0.375), (0.3, -0.375)], Colour.WHITE)
    # a robot: white legs and body, grey feet, red jersey
    fill_cylinder(img, cam, (2.5, -0.9, 0.0), (2.5, -0.9, 0.58), 0.14, Colour.WHITE)
    fill_cylinder(img, cam, (2.5, -0.9, 0.0), (2.5, -0.9, 0.04), 0.14, Colour.OTHER)
    fill_cylinder(img, cam, (2.5, -0.9, 0.3), (2.5, -0.9, 0.45), 0.14, Colour.RED)
    # the ball
    fill_cylinder(img, cam, (1.8, 0.5, 0.0), (1.8, 0.5, 0.1), 0.05, Colour.WHITE)
    paint_post(img, cam, 3.5, 0.6, Colour.WHITE)
    rows = run(img, cam, WHITE)
    assert len(rows) == 1
    assert math.hypot(rows[0, Col.X] - 3.5, rows[0, Col.Y] - 0.6) < 0.01 + 0.6 * step(cam, *pixel(cam, 3.5, 0.6))


def test_a_white_post_standing_on_a_line_keeps_its_foot() -> None:
    # seen along the goal line, the line continues below the post's foot (white on white)
    cam = camera(yaw=-0.2, pitch=0.3)
    img = carpet(cam)
    fill_ground(img, cam, [(0.0, 0.025), (6.0, -1.175), (6.0, -1.225), (0.0, -0.025)], Colour.WHITE)
    x, y = 2.0, -0.4
    paint_post(img, cam, x, y, Colour.WHITE)
    rows = run(img, cam, WHITE)
    assert len(rows) == 1
    assert math.hypot(rows[0, Col.X] - x, rows[0, Col.Y] - y) < 0.06


def test_two_goal_colours_give_the_goal_and_corner_poles_are_not_posts() -> None:
    own, opp = int(Colour.BLUE), int(Colour.YELLOW)
    cam = camera(pitch=0.1)
    img = carpet(cam)
    paint_post(img, cam, 3.0, 0.8, opp)
    paint_post(img, cam, 4.0, -0.5, own)
    # a KidSize corner pole: bands yellow / blue / yellow, 0.9 m
    for z0, z1, cls in ((0.0, 0.3, opp), (0.3, 0.6, own), (0.6, 0.9, opp)):
        fill_cylinder(img, cam, (3.5, 1.8, z0), (3.5, 1.8, z1), R, cls)
    rows = run(img, cam, (own, opp))
    assert len(rows) == 2
    by_y = rows[np.argsort(rows[:, Col.Y])]
    assert by_y[0, Col.GOAL] == 0 and abs(by_y[0, Col.X] - 4.0) < 0.1  # blue: the own goal
    assert by_y[1, Col.GOAL] == 1 and abs(by_y[1, Col.X] - 3.0) < 0.08  # yellow: the opponent's


def test_a_leaning_robot_still_sees_vertical_posts() -> None:
    for roll in (-0.12, 0.12):
        cam = camera(pitch=0.1, roll=roll)
        img = carpet(cam)
        paint_goal(img, cam, 4.0, 0.8, -0.8)
        rows = run(img, cam)
        assert len(rows) == 2, roll
        assert np.allclose(np.sort(rows[:, Col.Y]), [-0.8, 0.8], atol=0.08), roll


def test_pixel_parameters_scale_with_the_image() -> None:
    out = []
    for rig in (CameraRig(), CameraRig().with_resolution(640, 480)):
        cam = camera(pitch=0.05, rig=rig)
        img = carpet(cam)
        paint_goal(img, cam, 5.0, 0.8, -0.8)
        rows = run(img, cam)
        assert len(rows) == 2
        out.append(rows[np.argsort(rows[:, Col.Y])][:, [Col.X, Col.Y]])
    assert np.allclose(out[0], out[1], atol=0.1)


def test_no_goal_colour_no_posts() -> None:
    cam = camera()
    img = carpet(cam)
    rows = run(img, cam)
    assert rows.shape == (0, N_COLS)
    blank = np.zeros((240, 320), dtype=np.uint8)  # no carpet at all
    no_field = np.full(320, 240, np.int32)
    assert len(detect_posts(blank, no_field, cam.as_row(), YELLOW, 0.1, 0.8, PostParams(), 0, 0)) == 0


# -- rendered frames ------------------------------------------------------------------------


SCENES = [  # observer (x, y, theta, head yaw, head pitch): goal views at several distances
    (2.5, 0.0, 0.0, 0.0, 0.1),
    (3.0, 1.0, -0.3, 0.0, 0.2),
    (0.0, -1.5, 0.2, 0.0, 0.05),
    (1.0, 2.0, -0.5, 0.3, 0.1),
    (-2.0, 0.5, 3.0, 0.2, 0.1),
    (3.6, -1.2, 0.4, -0.3, 0.3),
]


@pytest.mark.parametrize("scheme", ["classic", "modern"])
def test_rendered_goals_match_the_annotations(scheme: str) -> None:
    from teamsim.images import ImageRenderer
    from teamsim.percepts import Scene, SceneRobot

    ren = ImageRenderer(FIELD, scheme, CameraRig(), "default", np.random.default_rng(5))
    classifier = ColourClassifier()
    goals = YELLOW if scheme == "classic" else WHITE
    found = 0
    for x, y, th, yaw, pitch in SCENES:
        robots = [SceneRobot(0, 1, x, y, th, head_yaw=yaw, head_pitch=pitch), SceneRobot(1, 1, 4.1, 0.3, math.pi)]
        scene = Scene.build(robots, (3.4, -0.3), 2)
        img = ren.render(scene, 0)
        ann = ren.annotate(scene)[0]
        cam = ren.camera_matrix(scene, 0)
        classes = classifier.classify(img, cam)
        rows = detect_posts(
            classes, field_boundary(classes, cam, 6), cam.as_row(), goals, DIAMETER, HEIGHT, PostParams(), SIGMA, SIGMA
        )
        assert ann is not None
        offsets = np.full(N_KINDS + 1, len(rows), dtype=np.int64)
        offsets[0] = 0
        percepts = Percepts(0.0, rows, offsets, cam.as_row(), cam.spec)  # valid percept rows
        assert len(percepts.posts) == len(rows)
        for row in rows:  # every detection is an annotated post, at its foot or inside its box
            d = np.hypot(ann.posts[:, 0] - row[Col.U], ann.posts[:, 1] - row[Col.V])
            k = int(np.argmin(d))
            u0, v0, u1, v1 = ann.posts[k, 2:6]
            assert d[k] < 6 or (u0 <= row[Col.U] <= u1 and v0 <= row[Col.V] <= v1 + 3), (x, y, row[:4])
            if row[Col.SUBTYPE] != PostSide.UNKNOWN and ann.posts[k, 6] != PostSide.UNKNOWN:
                assert row[Col.SUBTYPE] == ann.posts[k, 6]
        for u, v, *_ in ann.posts:  # every annotated post with its foot in view is found
            if 8 < v < cam.spec.height - 8 and 4 < u < cam.spec.width - 4:
                assert np.min(np.hypot(rows[:, Col.U] - u, rows[:, Col.V] - v), initial=99) < 6, (x, y, u, v)
                found += 1
    assert found >= 6


def test_rendered_kidsize_goals_are_told_apart_by_colour() -> None:
    from teamsim.images import ImageRenderer
    from teamsim.percepts import Scene, SceneRobot

    field = Field(FIELD_PRESETS["kidsize"], "kidsize")
    ren = ImageRenderer(field, "kidsize", CameraRig(), "default", np.random.default_rng(2))
    classifier = ColourClassifier()
    goals = (int(Colour.BLUE), int(Colour.YELLOW))  # own goal (-x) blue, opponent's yellow
    seen = set()
    for x, y, th, yaw in (
        (0.5, 0.3, 0.0, 0.1),
        (-0.5, -0.4, math.pi, 0.0),
        (1.0, -0.8, 0.3, 0.0),
        (-1.2, 0.6, 2.8, 0.2),
    ):
        scene = Scene.build([SceneRobot(0, 1, x, y, th, head_yaw=yaw, head_pitch=0.15)], (0.0, 0.0), 1)
        img = ren.render(scene, 0)
        ann = ren.annotate(scene)[0]
        cam = ren.camera_matrix(scene, 0)
        classes = classifier.classify(img, cam)
        b = field_boundary(classes, cam, 6)
        rows = detect_posts(classes, b, cam.as_row(), goals, DIAMETER, HEIGHT, PostParams(), SIGMA, SIGMA)
        assert ann is not None and len(rows) == len(ann.posts) > 0, (x, y, len(rows), len(ann.posts))
        for row in rows:
            k = int(np.argmin(np.hypot(ann.posts[:, 0] - row[Col.U], ann.posts[:, 1] - row[Col.V])))
            truth = int(ann.posts[k, 7])
            assert row[Col.GOAL] == (0 if field.goal_posts[truth].x < 0 else 1)
            seen.add(int(row[Col.GOAL]))
    assert seen == {0, 1}


# -- bad input and parameters ---------------------------------------------------------------


def _args() -> list[object]:
    cam = camera()
    img = carpet(cam)
    return [img, field_boundary(img, cam, 6), cam.as_row(), YELLOW, DIAMETER, HEIGHT, PostParams(), SIGMA, SIGMA]


@pytest.mark.parametrize(
    ("index", "value", "message"),
    [
        (0, np.zeros((240, 320), dtype=np.float32), "uint8 class image"),
        (0, np.zeros((240, 320, 3), dtype=np.uint8), "uint8 class image"),
        (0, [[1, 2], [3, 4]], "uint8 class image"),
        (1, np.zeros(319, dtype=np.int32), "320 integers"),
        (1, np.zeros(320, dtype=np.float64), "320 integers"),
        (2, np.zeros(17), "camera row of 18"),
        (2, np.full(18, np.nan), "non-finite"),
        (3, (Colour.WHITE,), "goal_classes"),
        (3, (Colour.GREEN, Colour.GREEN), "goal_classes"),
        (3, ("white", "white"), "goal_classes"),
        (4, 0.0, "post_diameter must be a finite number > 0"),
        (5, math.inf, "goal_height"),
        (6, {"min_fill": 0.5}, "PostParams"),
        (7, -0.1, "sigma_alpha must be a finite number >= 0"),
        (8, True, "sigma_beta"),
    ],
)
def test_bad_input_is_a_clear_error(index: int, value: object, message: str) -> None:
    args = _args()
    args[index] = value
    with pytest.raises(VisionError, match=message):
        detect_posts(*args)  # type: ignore[arg-type]
    assert issubclass(VisionError, ValueError)


def test_camera_and_image_sizes_must_agree() -> None:
    args = _args()
    args[2] = CameraRig().with_resolution(640, 480).camera_matrix("upper", 0.0, 0.1).as_row()
    with pytest.raises(VisionError, match="640 x 480 pixels but classes is 320 x 240"):
        detect_posts(*args)  # type: ignore[arg-type]


def test_params_are_checked() -> None:
    with pytest.raises(ValueError, match=r"PostParams\.min_fill must be a real number in \[0, 1\], got 1.5"):
        PostParams(min_fill=1.5)
    with pytest.raises(ValueError, match=r"PostParams\.width_range must be \(low, high\)"):
        PostParams(width_range=(1.5, 0.5))
    with pytest.raises(ValueError, match=r"PostParams\.pair_distance must be \(low, high\)"):
        PostParams(pair_distance=(3.0, 1.0))
    with pytest.raises(TypeError, match=r"PostParams\.max_gap must be an integer"):
        PostParams(max_gap=1.5)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"PostParams\.separation"):
        PostParams(separation=-1.0)
    p = PostParams(min_fill=0.6)
    assert p.packed[2] == 0.6 and not p.packed.flags.writeable
    assert p == PostParams(min_fill=0.6) and p != PostParams()


def test_a_crossing_with_a_post_or_net_standing_on_it_is_dropped_and_one_on_carpet_is_kept() -> None:
    """The goal's foot meets the goal line and the net's frame in junctions no field map has;
    where the post's base is not seen, the post above the crossing tells it apart."""
    from cognition.vision.goals import not_under_posts_nb

    cam = camera(pitch=0.3)
    img = carpet(cam)
    post, free = (2.0, 0.4), (2.0, -0.4)
    paint_post(img, cam, *post)
    cross = np.array([[*post, 0.0, 0.0, 1.0, 0.0], [*free, 0.0, 0.0, 1.0, 0.0]])
    row = cam.as_row()
    white = int(Colour.WHITE)
    kept = not_under_posts_nb(cross, img, row, int(Colour.YELLOW), int(Colour.BLUE), white, R, HEIGHT)
    assert kept.shape[0] == 1 and np.allclose(kept[0, :2], free)
    # a net (white) standing just behind the crossing drops it as well
    net = carpet(cam)
    fill_cylinder(net, cam, (free[0] + 0.1, free[1], 0.0), (free[0] + 0.1, free[1], HEIGHT), 0.3, white)
    assert not_under_posts_nb(cross[1:], net, row, int(Colour.YELLOW), int(Colour.BLUE), white, R, HEIGHT).shape[0] == 0
    # a white line receding from the crossing, seen below the camera only, is no post
    line = carpet(cam)
    fill_ground(line, cam, [(free[0], free[1] - 0.025), (9.0, free[1] - 0.025), (9.0, free[1] + 0.025),
                            (free[0], free[1] + 0.025)], white)  # fmt: skip
    kept = not_under_posts_nb(cross[1:], line, row, int(Colour.YELLOW), int(Colour.BLUE), white, R, HEIGHT)
    assert kept.shape[0] == 1
