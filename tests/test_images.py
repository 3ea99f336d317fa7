"""Rendered camera images agree with the camera model: lines, horizon, ball size, objects."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from cognition.camera import CameraMatrix, CameraRig
from cognition.field import FIELD_PRESETS, Field, FieldDimensions, make_colour_scheme
from teamsim.image_params import ImageParams
from teamsim.images import ImageRenderer
from teamsim.percepts import Scene, SceneRobot

SPL = Field(FIELD_PRESETS["spl2025"], "spl2025")


def renderer(field: Field = SPL, scheme: str = "classic", preset: str = "ideal", size=(320, 240)) -> ImageRenderer:
    return ImageRenderer(field, scheme, CameraRig().with_resolution(*size), preset, np.random.default_rng(0))


def to_robot(world_xy: np.ndarray, pose: tuple[float, float, float], z: float = 0.0) -> np.ndarray:
    x, y, th = pose
    c, s = math.cos(th), math.sin(th)
    d = np.atleast_2d(world_xy) - [x, y]
    return np.column_stack([c * d[:, 0] + s * d[:, 1], -s * d[:, 0] + c * d[:, 1], np.full(len(d), z)])


def to_world(robot_xy: np.ndarray, pose: tuple[float, float, float]) -> np.ndarray:
    x, y, th = pose
    c, s = math.cos(th), math.sin(th)
    return np.column_stack([x + c * robot_xy[:, 0] - s * robot_xy[:, 1], y + s * robot_xy[:, 0] + c * robot_xy[:, 1]])


def is_white(img: np.ndarray) -> np.ndarray:
    return img.min(axis=-1) > 190


def random_views(n: int, seed: int) -> list[tuple[tuple[float, float, float], float, float, str]]:
    """Poses on the field and head angles that look at the ground."""
    rng = np.random.default_rng(seed)
    views = []
    for k in range(n):
        pose = (rng.uniform(-4.2, 4.2), rng.uniform(-2.8, 2.8), rng.uniform(-math.pi, math.pi))
        camera = "lower" if k % 3 == 0 else "upper"
        pitch = rng.uniform(-0.1, 0.3) if camera == "lower" else rng.uniform(0.15, 0.45)
        views.append((pose, rng.uniform(-0.8, 0.8), pitch, camera))
    return views


def single_robot_scene(pose, yaw, pitch, camera, ball=None) -> Scene:
    return Scene.build([SceneRobot(0, 1, *pose, head_yaw=yaw, head_pitch=pitch, camera=camera)], ball, 1)


def paint_distance(field: Field, xy: np.ndarray) -> np.ndarray:
    """Distance (m) from world points to the nearest paint centre line (lines, circle, marks)."""
    best = np.full(len(xy), np.inf)
    for x1, y1, x2, y2 in field.line_array:
        a, b = np.array([x1, y1]), np.array([x2, y2])
        t = np.clip(((xy - a) @ (b - a)) / np.dot(b - a, b - a), 0, 1)
        best = np.minimum(best, np.linalg.norm(xy - (a + t[:, None] * (b - a)), axis=1))
    c = field.centre_circle
    best = np.minimum(best, np.abs(np.hypot(xy[:, 0] - c.x, xy[:, 1] - c.y) - c.radius))
    half = field.dims.penalty_mark_size / 2
    marks = [(m.x, m.y) for m in field.penalty_marks] + ([(c.x, c.y)] if field.dims.centre_mark else [])
    for mx, my in marks:
        dx, dy = np.abs(xy[:, 0] - mx), np.abs(xy[:, 1] - my)
        best = np.minimum(best, np.where(dx <= half, dy, np.hypot(dx - half, dy)))
        best = np.minimum(best, np.where(dy <= half, dx, np.hypot(dx, dy - half)))
    return best


def test_line_pixels_lie_where_the_camera_model_projects_the_lines():
    ren = renderer()
    hw = SPL.dims.line_width / 2
    checked = 0
    for pose, yaw, pitch, camera in random_views(24, 1):
        scene = single_robot_scene(pose, yaw, pitch, camera)
        img = ren.render(scene, 0)
        white = is_white(img)
        goal = (img[..., 0] > 150) & (img[..., 1] > 120) & (img[..., 2] < 100)  # yellow posts may hide a line
        cam = ren.camera_matrix(scene, 0)
        for x1, y1, x2, y2 in SPL.line_array:
            t = np.linspace(0.02, 0.98, 60)[:, None]
            a, b = np.array([x1, y1]), np.array([x2, y2])
            pts = a + t * (b - a)
            normal = np.array([-(b - a)[1], (b - a)[0]]) / np.linalg.norm(b - a)
            uv, front = cam.project(to_robot(pts, pose))
            uv_l, fl = cam.project(to_robot(pts + hw * normal, pose))
            uv_r, fr = cam.project(to_robot(pts - hw * normal, pose))
            uv_n, fn = cam.project(to_robot(pts + 0.01 * (b - a) / np.linalg.norm(b - a), pose))
            along = (uv_n - uv) / np.linalg.norm(uv_n - uv, axis=1, keepdims=True)
            across = uv_l - uv_r
            width = np.abs(along[:, 0] * across[:, 1] - along[:, 1] * across[:, 0])  # perpendicular to the image line
            h, w = img.shape[:2]
            ok = front & fl & fr & fn & (width >= 2.0)
            ok &= (uv[:, 0] >= 2) & (uv[:, 0] < w - 2) & (uv[:, 1] >= 2) & (uv[:, 1] < h - 2)
            for u, v in uv[ok]:
                i, j = int(u), int(v)
                if goal[j - 2 : j + 3, i - 2 : i + 3].any():
                    continue
                assert white[j - 1 : j + 2, i - 1 : i + 2].any(), (pose, yaw, pitch, camera, (u, v))
                checked += 1
    assert checked > 300


def test_white_pixels_below_the_horizon_are_paint():
    ren = renderer()
    hw = SPL.dims.line_width / 2
    total = 0
    for pose, yaw, pitch, camera in random_views(12, 2):
        scene = single_robot_scene(pose, yaw, pitch, camera)
        img = ren.render(scene, 0)
        cam = ren.camera_matrix(scene, 0)
        jj, ii = np.nonzero(is_white(img))
        uv = np.column_stack([ii + 0.5, jj + 0.5])
        ground, valid = cam.pixel_to_ground(uv)
        below, _ = cam.pixel_to_ground(uv + np.array([0.0, 1.5]))
        near = valid & (np.linalg.norm(ground, axis=1) < 6.0)
        world = to_world(ground[near], pose)
        on_carpet = (np.abs(world[:, 0]) < SPL.half_length + 0.6) & (np.abs(world[:, 1]) < SPL.half_width + 0.6)
        foot = np.linalg.norm(ground[near] - below[near], axis=1)
        dist = paint_distance(SPL, world)
        assert np.all(dist[on_carpet] <= hw + foot[on_carpet] + 0.005), dist[on_carpet].max()
        total += int(on_carpet.sum())
    assert total > 1000


@pytest.mark.parametrize("pitch", [-0.15, 0.0, 0.12])
def test_the_horizon_is_where_the_model_says(pitch):
    # the largest field the parameters allow (100 m x 100 m, 10 m border): seen from the centre,
    # the carpet's far edge lies a few pixels below the horizon, and the green must start on
    # the row where the camera model puts that edge, with nothing green above the horizon
    dims = FieldDimensions(
        length=100.0, width=100.0, line_width=0.05, goal_area_length=0.6, goal_area_width=2.2,
        penalty_area_length=1.65, penalty_area_width=4.0, penalty_mark_distance=1.3, penalty_mark_size=0.1,
        centre_mark=True, centre_circle_diameter=1.5, border_strip=10.0, goal_inner_width=1.5,
        goal_post_diameter=0.1, goal_height=0.8, goal_depth=0.5, ball_diameter=0.1,
    )  # fmt: skip
    field = Field(dims)
    flat = dataclasses.replace(ImageParams.preset("ideal"), grass_texture=0.0)
    ren = ImageRenderer(field, "classic", CameraRig(), flat)
    scene = single_robot_scene((0.0, 0.0, 0.3), 0.0, pitch, "upper")
    img = ren.render(scene, 0).astype(int)
    cam = ren.camera_matrix(scene, 0)
    v0, v1 = cam.horizon()
    assert v0 == pytest.approx(v1)  # no roll: a horizontal horizon
    # the robot stands at x = 0 facing theta 0.3: the far edge straight ahead, in the robot frame
    reach = (field.half_length + dims.border_strip) / math.cos(0.3)
    (edge,), _ = cam.project([[reach, 0.0, 0.0]])
    assert 0.0 < edge[1] - v0 < 10.0  # just below the horizon
    green = np.abs(img - np.array(make_colour_scheme("classic").field_green)).max(axis=-1) <= 2
    rows = np.nonzero(green.any(axis=1))[0]
    assert abs(rows.min() - edge[1]) <= 1.5
    assert not green[: max(0, int(v0) - 1)].any()


@pytest.mark.parametrize(("distance", "camera"), [(0.6, "lower"), (1.0, "upper"), (2.0, "upper"), (4.0, "upper")])
def test_ball_image_radius_matches_the_model(distance, camera):
    ren = renderer()
    rig = ren.rig
    r = SPL.dims.ball_diameter / 2
    # aim the optical axis at the ball centre: find the pitch whose camera ray hits it
    pitches = np.linspace(-0.5, 0.6, 2201)
    cy = rig.spec(camera).cy
    best = min(
        pitches, key=lambda p: abs(rig.camera_matrix(camera, 0.0, p).project([[distance, 0.0, r]])[0][0, 1] - cy)
    )
    scene = single_robot_scene((0.0, 0.0, 0.0), 0.0, float(best), camera, ball=(distance, 0.0))
    img = ren.render(scene, 0).astype(int)
    cam: CameraMatrix = ren.camera_matrix(scene, 0)
    (u, v), _ = cam.project([[distance, 0.0, r]])[0][0], None
    d3 = float(np.linalg.norm(np.array([distance, 0.0, r]) - cam.position))
    f = 0.5 * (cam.spec.fx + cam.spec.fy)
    expected = f * r / math.sqrt(d3 * d3 - r * r)
    orange = (img[..., 0] > 1.6 * img[..., 1]) & (img[..., 1] > 1.5 * img[..., 2] + 5) & (img[..., 0] > 50)
    jj, ii = np.mgrid[0 : img.shape[0], 0 : img.shape[1]]
    near = np.hypot(ii + 0.5 - u, jj + 0.5 - v) < 2.0 * expected + 3
    measured = math.sqrt((orange & near).sum() / math.pi)
    assert measured == pytest.approx(expected, abs=1.0)
    ann = ren.annotate(scene)[0]
    assert ann.ball.shape == (1, 3)
    assert ann.ball[0, 2] == pytest.approx(expected, abs=1e-6)
    assert np.hypot(ann.ball[0, 0] - u, ann.ball[0, 1] - v) < 1.0


def test_occluded_features_are_absent_from_annotations():
    ren = renderer()
    mark = SPL.penalty_marks[1]
    viewer = SceneRobot(0, 1, mark.x - 2.0, 0.0, 0.0, head_pitch=0.3)
    blocker = SceneRobot(1, 1, mark.x - 0.8, 0.0, math.pi)
    free = ren.annotate(Scene.build([viewer], (mark.x - 1.0, 0.6), 1))[0]
    assert len(free.marks) == 1
    hidden_scene = Scene.build([viewer, blocker], (mark.x - 0.5, 0.0), 1)
    hidden = ren.annotate(hidden_scene)[0]
    assert len(hidden.marks) == 0
    assert len(hidden.ball) == 0  # the ball behind the robot
    assert len(hidden.robots) == 1 and hidden.robots[0, 6] == 1  # world index of team 1's player 1
    # and in the image the robot covers the mark's pixels
    img = ren.render(hidden_scene, 0).astype(int)
    bare = ren.render(Scene.build([viewer], None, 1), 0).astype(int)
    u, v = free.marks[0, :2]
    patch = (slice(int(v) - 1, int(v) + 2), slice(int(u) - 1, int(u) + 2))
    assert is_white(bare.astype(np.uint8))[patch].all()
    assert (np.abs(img - bare).max(axis=-1)[patch] > 8).all()


def test_annotated_points_are_paint_and_objects_in_the_image():
    ren = renderer(scheme="classic")
    checked = 0
    for pose, yaw, pitch, camera in random_views(30, 3):
        scene = single_robot_scene(pose, yaw, pitch, camera)
        img = ren.render(scene, 0)
        white = is_white(img)
        ann = ren.annotate(scene)[0]
        h, w = white.shape
        points = np.concatenate([ann.crossings[:, :2], ann.marks[:, :2]])
        ground, _ = ann.camera.pixel_to_ground(points)
        for (u, v), g in zip(points, ground, strict=True):
            i, j = int(u), int(v)
            if 1 <= i < w - 1 and 1 <= j < h - 1 and np.hypot(*g) < 3.0:  # lines at least ~2 px wide
                assert white[j - 1 : j + 2, i - 1 : i + 2].any()
                checked += 1
        for row in ann.posts:  # a post stands on its bottom point: goal-coloured pixels just above it
            i, j = int(row[0]), int(row[1])
            if 2 <= i < w - 2 and 3 <= j < h:
                patch = img[j - 3 : j, i - 1 : i + 2].astype(int)
                assert ((patch[..., 0] > 150) & (patch[..., 2] < 100)).any()  # yellow
                checked += 1
    assert checked > 20


def _cylinder_mask(cam: CameraMatrix, pose, centre_world, radius, height, shape) -> np.ndarray:
    """Independent ray-cylinder test of every pixel centre (robot frame)."""
    h, w = shape
    jj, ii = np.mgrid[0:h, 0:w]
    uv = np.column_stack([ii.ravel() + 0.5, jj.ravel() + 0.5])
    d = cam.rays(uv)
    o = cam.position
    c = to_robot(np.array([centre_world]), pose)[0, :2]
    px, py = o[0] - c[0], o[1] - c[1]
    a = d[:, 0] ** 2 + d[:, 1] ** 2
    b = px * d[:, 0] + py * d[:, 1]
    disc = b * b - a * (px * px + py * py - radius * radius)
    hit = disc > 0
    t = np.where(hit, (-b - np.sqrt(np.maximum(disc, 0))) / np.where(a > 0, a, 1), -1)
    z = o[2] + t * d[:, 2]
    return (hit & (t > 0) & (z >= 0) & (z <= height)).reshape(h, w)


@pytest.mark.parametrize(
    ("other", "camera", "pitch"),
    [
        ((1.2, 0.3), "upper", 0.1),
        ((0.45, -0.1), "lower", 0.0),
        ((0.25, 0.22), "upper", 0.2),
        ((0.05, 0.3), "lower", 0.4),
    ],
)
def test_robot_silhouette_matches_an_independent_ray_test(other, camera, pitch):
    """Including robots so close that their bounding box reaches behind the camera."""
    ren = renderer()
    pose = (0.0, 0.0, 0.0)
    viewer = SceneRobot(0, 1, *pose, head_yaw=0.3, head_pitch=pitch, camera=camera)
    with_robot = Scene.build([viewer, SceneRobot(1, 1, *other, 1.0)], None, 1)
    without = Scene.build([viewer], None, 1)
    a = ren.render(with_robot, 0).astype(int)
    b = ren.render(without, 0).astype(int)
    changed = np.abs(a - b).max(axis=-1) > 8
    cam = ren.camera_matrix(with_robot, 0)
    oc = with_robot.occluders[1]
    expected = _cylinder_mask(cam, pose, other, oc[2], oc[3], changed.shape)
    disagree = (changed != expected).sum()
    assert expected.sum() > 50
    assert disagree <= 0.02 * expected.sum() + 2 * np.sqrt(expected.sum())  # silhouette edge pixels only
