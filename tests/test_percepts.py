"""Percept synthesis: visibility, occlusion, labels and crossing types on every field preset."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from cognition.field import CROSSING_KINDS, FIELD_PRESETS, Field, make_field
from cognition.geometry import wrap_angle
from cognition.percepts import Kind, PostSide
from teamsim.percept_params import PerceptParams
from teamsim.percepts import PerceptSynthesizer, Scene, SceneRobot

IDEAL = PerceptParams.preset("ideal")


def synth(field: Field, params: PerceptParams = IDEAL, seed: int = 0) -> PerceptSynthesizer:
    return PerceptSynthesizer(field, params, np.random.default_rng(seed))


def see(syn: PerceptSynthesizer, robots: list[SceneRobot], ball: tuple[float, float] | None = None, ppt: int = 5):
    """Percepts of the first robot in ``robots``."""
    first = robots[0]
    return syn.synthesize(Scene.build(robots, ball, ppt))[first.team * ppt + first.number - 1]


def to_robot(pose: tuple[float, float, float], x: float, y: float) -> tuple[float, float]:
    """World point -> robot frame of ``pose``."""
    px, py, th = pose
    c, s = math.cos(th), math.sin(th)
    return c * (x - px) + s * (y - py), -s * (x - px) + c * (y - py)


def observer(x: float, y: float, theta: float, **kw: object) -> SceneRobot:
    return SceneRobot(0, 2, x, y, theta, **kw)  # type: ignore[arg-type]


def test_centre_spot_upper_camera_sees_opponent_goal() -> None:
    f = make_field("spl2025")
    p = see(synth(f), [observer(0.0, 0.0, 0.0)], ball=(2.0, 0.3))
    posts = {int(t): int(s) for t, s in zip(p.posts.truth, p.posts.subtype, strict=True)}
    assert posts == {2: PostSide.LEFT, 3: PostSide.RIGHT}  # opponent left (+y) and right
    seen = {(round(x, 6), round(y, 6), CROSSING_KINDS[k]) for x, y, k in zip(*_truth_crossings(f, p), strict=True)}
    expected = {(3.9, 1.1, "L"), (3.9, -1.1, "L"), (4.5, 1.1, "T"), (4.5, -1.1, "T"), (4.5, 2.0, "T"), (4.5, -2.0, "T")}
    assert seen == expected  # penalty-box L's (bearing 35 deg) and corners (34 deg) lie outside the 27 deg half angle
    assert list(p.penalty_marks.truth) == [1]
    assert len(p.circle) == 0  # the circle's front arc (0.75 m) is below the upper camera's view (~1.2 m)
    assert len(p.ball) == 1 and np.allclose(p.ball.xy[0], (2.0, 0.3), atol=1e-9)


def _truth_crossings(f: Field, p) -> tuple[list[float], list[float], list[int]]:
    ids = p.crossings.truth
    return [f.crossings[i].x for i in ids], [f.crossings[i].y for i in ids], list(p.crossings.subtype)


def test_centre_spot_lower_camera_sees_the_circle() -> None:
    f = make_field("spl2025")
    p = see(synth(f), [observer(0.0, 0.0, 0.0, camera="lower")])
    assert len(p.circle) == 1
    assert np.allclose(p.circle.xy[0], (0.0, 0.0), atol=1e-9)
    assert len(p.posts) == 0  # the lower camera looks at the ground in front of the feet


def _world_landmarks(f: Field) -> dict[Kind, np.ndarray]:
    return {
        Kind.POST: f.post_array,
        Kind.CROSS: f.crossing_array[:, :2],
        Kind.MARK: np.array([(m.x, m.y) for m in f.penalty_marks]),
    }


@pytest.mark.parametrize("name", sorted(FIELD_PRESETS))
def test_reported_landmarks_are_in_front_and_inside_the_image(name: str) -> None:
    """Random poses and head angles: every reported landmark projects into the image (ideal: exact)."""
    f = make_field(name)
    syn = synth(f)
    rng = np.random.default_rng(7)
    landmarks = _world_landmarks(f)
    reported = 0
    for _ in range(300):
        hl, hw = f.half_length, f.half_width
        pose = (rng.uniform(-hl, hl), rng.uniform(-hw, hw), rng.uniform(-3, 3))
        cam = "upper" if rng.random() < 0.6 else "lower"
        yaw, pitch = rng.uniform(-1.5, 1.5), rng.uniform(-0.4, 0.5)
        p = see(syn, [observer(*pose, head_yaw=yaw, head_pitch=pitch, camera=cam)])
        cm = p.camera
        assert cm is not None
        for kind, pts in landmarks.items():
            t = p.table(kind)
            for i, (mx, my) in zip(t.truth, t.xy, strict=True):
                x, y = to_robot(pose, *pts[i])
                assert math.hypot(mx - x, my - y) < 1e-9  # ideal: no measurement error
                uv, front = cm.project([[x, y, 0.0]])
                assert front[0] and cm.in_image(uv)[0]
                reported += 1
        for line in p.lines.rows:
            ends = np.array([[line[0], line[1], 0.0], [line[4], line[5], 0.0]])
            uv, front = cm.project(ends)
            assert front.all()
            assert np.all((uv >= -1e-6) & (uv <= (cm.spec.width + 1e-6, cm.spec.height + 1e-6)))
            assert math.hypot(line[4] - line[0], line[5] - line[1]) >= IDEAL.min_line_length - 1e-9
            _assert_on_field_line(f, pose, line)
    assert reported > 100


def _assert_on_field_line(f: Field, pose: tuple[float, float, float], row: np.ndarray) -> None:
    x1, y1, x2, y2 = f.line_array[int(row[16])]
    for rx, ry in ((row[0], row[1]), (row[4], row[5])):
        c, s = math.cos(pose[2]), math.sin(pose[2])
        wx, wy = pose[0] + c * rx - s * ry, pose[1] + s * rx + c * ry
        cross = (x2 - x1) * (wy - y1) - (y2 - y1) * (wx - x1)
        assert abs(cross) / math.hypot(x2 - x1, y2 - y1) < 1e-9
        lo, hi = min(x1, x2) - 1e-9, max(x1, x2) + 1e-9
        assert lo <= wx <= hi


def test_landmarks_behind_the_camera_are_never_reported() -> None:
    f = make_field("spl2025")
    # facing the own goal from the centre: nothing of the opponent half may appear
    p = see(synth(f), [observer(0.5, 0.0, math.pi)])
    for kind, pts in _world_landmarks(f).items():
        for i in p.table(kind).truth:
            assert pts[i][0] < 0.5
    assert set(p.posts.truth) == {0, 1}


def test_a_robot_hides_the_post_behind_it_but_a_lying_robot_does_not() -> None:
    f = make_field("spl2025")
    syn = synth(f)
    me = observer(2.0, 0.0, 0.0)
    free = see(syn, [me])
    assert set(free.posts.truth) == {2, 3}
    blocker = (2.0 + 1.5, 0.8 * 1.5 / 2.5)  # on the line of sight to the left post (4.5, 0.8), 1.5 m ahead
    standing = SceneRobot(1, 3, *blocker, math.pi)
    hidden = see(syn, [me, standing])
    assert set(hidden.posts.truth) == {3}
    assert PostSide(int(hidden.posts.subtype[0])) != PostSide.UNKNOWN  # crossbar still tells the side
    lying = SceneRobot(1, 3, *blocker, math.pi, fallen=True)
    assert set(see(syn, [me, lying]).posts.truth) == {2, 3}  # a lying robot's shadow ends before the goal
    robots = see(syn, [me, standing]).robots
    assert list(robots.truth) == [5 + 3 - 1] and list(robots.subtype) == [2]  # opponent #3, team guessed right


def test_a_robot_in_front_of_a_line_splits_it() -> None:
    f = make_field("spl2025")
    syn = synth(f)
    me = observer(2.0, 0.0, math.pi / 2, head_pitch=0.1)  # looking at the +y touchline, 3 m away
    whole = [row for row in see(syn, [me]).lines.rows if int(row[16]) == 0]
    assert len(whole) == 1
    split = [row for row in see(syn, [me, SceneRobot(1, 1, 2.0, 1.5, 0.0)]).lines.rows if int(row[16]) == 0]
    assert len(split) == 2
    # the gap is the robot's shadow: around world x = 2 (robot-frame y = -(x - 2))
    inner = sorted([max(r[1], r[5]) for r in split] + [min(r[1], r[5]) for r in split])
    gap_lo, gap_hi = inner[1], inner[2]
    assert gap_lo < 0.0 < gap_hi and gap_hi - gap_lo < 0.8


def _post_label_expected(f: Field, pose, cam, i: int) -> PostSide:
    """The stated rule, evaluated with the public camera model: known iff partner or crossbar in view."""
    posts = f.goal_posts
    me = posts[i]
    partner = next(p for j, p in enumerate(posts) if p.goal == me.goal and j != i)
    h = f.dims.goal_height
    px, py = to_robot(pose, me.x, me.y)
    qx, qy = to_robot(pose, partner.x, partner.y)
    uv, front = cam.project([[px, py, 0.0], [qx, qy, 0.0]])
    if front[1] and cam.in_image(uv[1:])[0]:
        return PostSide.LEFT if uv[1, 0] > uv[0, 0] else PostSide.RIGHT
    k = min(0.3 / math.hypot(qx - px, qy - py), 0.5)
    bar = cam.project([[px, py, h], [px + k * (qx - px), py + k * (qy - py), h]])[0]
    if cam.in_image(bar).all():
        return PostSide.LEFT if bar[1, 0] > bar[0, 0] else PostSide.RIGHT
    return PostSide.UNKNOWN


@pytest.mark.parametrize("name", sorted(FIELD_PRESETS))
def test_post_side_rule_for_every_post(name: str) -> None:
    f = make_field(name)
    syn = synth(f)
    for i, post in enumerate(f.goal_posts):
        inward = 1.0 if post.goal == "own" else -1.0  # direction from the goal line into the field
        labels = set()
        for dist in (1.5, 2.5, 3.5):
            for lateral in np.linspace(-1.2, 1.2, 9):
                x, y = post.x + inward * dist, post.y + lateral
                base = math.atan2(post.y - y, post.x - x)
                for off in np.linspace(-0.5, 0.5, 11):  # sweep the post across the image and beyond
                    pose = (x, y, base + off)
                    p = see(syn, [observer(*pose)])
                    rows = [k for k, t in enumerate(p.posts.truth) if t == i]
                    if not rows:
                        continue
                    got = PostSide(int(p.posts.subtype[rows[0]]))
                    expected = _post_label_expected(f, pose, p.camera, i)
                    assert got == expected, (name, i, pose)
                    if got != PostSide.UNKNOWN:
                        assert got.name.lower() == post.side  # on the field side the image label is the true side
                    labels.add(got)
        assert labels == {PostSide.UNKNOWN, PostSide(1 if post.side == "left" else 2)}, (name, i, labels)


@pytest.mark.parametrize("name", sorted(FIELD_PRESETS))
@pytest.mark.parametrize("mirrored", [False, True])
def test_every_crossing_is_reported_with_its_type_and_orientation(name: str, mirrored: bool) -> None:
    f = make_field(name)
    syn = synth(f)
    for i, c in enumerate(f.crossings):
        if c.kind == "X":
            direction = math.atan2(-c.y, -c.x) if (c.x, c.y) != (0.0, 0.0) else 0.0
            direction += math.pi  # stand outside, away from the centre
        else:
            direction = c.orientation
        x, y = c.x + 1.5 * math.cos(direction), c.y + 1.5 * math.sin(direction)
        heading = wrap_angle(direction + math.pi)
        team, sign = (1, -1.0) if mirrored else (0, 1.0)
        robot = SceneRobot(team, 2, x, y, heading, head_pitch=0.3, team_sign=sign)
        p = see(syn, [robot])
        # the observer's own map is mirrored when its team frame is: ids refer to that map
        target = min(
            range(len(f.crossings)),
            key=lambda j: math.hypot(f.crossings[j].x - sign * c.x, f.crossings[j].y - sign * c.y),
        )
        rows = [k for k, t in enumerate(p.crossings.truth) if t == target]
        assert len(rows) == 1, (name, i, c)
        k = rows[0]
        assert CROSSING_KINDS[int(p.crossings.subtype[k])] == c.kind
        rel = c.orientation - heading
        got = p.crossings.orientation[k]
        if c.kind == "X":
            assert abs((rel - got + math.pi / 4) % (math.pi / 2) - math.pi / 4) < 1e-9
            assert 0.0 <= got < math.pi / 2
        else:
            assert abs(wrap_angle(rel - got)) < 1e-9
        assert np.allclose(p.crossings.xy[k], to_robot((x, y, heading), c.x, c.y), atol=1e-9)


def test_mirrored_observer_gets_ids_of_its_own_map() -> None:
    f = make_field("spl2025")
    syn = synth(f)
    # team 1 in the first half: its team frame is the world rotated by pi; at world (1, 0) facing +x
    # it stands in its own half facing its own goal (team-frame posts 0 and 1 = own left/right)
    p = see(syn, [SceneRobot(1, 2, 1.0, 0.0, 0.0, team_sign=-1.0)])
    assert set(p.posts.truth) == {0, 1}
    assert list(p.penalty_marks.truth) == [0]


def test_unusable_camera_gives_no_percepts() -> None:
    f = make_field("spl2025")
    syn = synth(f)
    p = see(syn, [observer(0.0, 0.0, 0.0, sees=False)], ball=(1.5, 0.0))
    assert len(p) == 0 and p.camera is None


def test_ball_image_radius_gives_size_based_distance() -> None:
    f = make_field("spl2025")
    r = f.dims.ball_diameter / 2
    for d in (0.8, 2.0, 4.0):
        p = see(synth(f), [observer(0.0, 0.0, 0.0, head_pitch=0.35)], ball=(d, 0.0))
        assert len(p.ball) == 1
        cam = p.camera
        c = cam.position
        dist3 = math.sqrt((d - c[0]) ** 2 + c[1] ** 2 + (r - c[2]) ** 2)
        f_mean = 0.5 * (cam.spec.fx + cam.spec.fy)
        assert p.ball.radius_px[0] == pytest.approx(f_mean * r / math.sqrt(dist3**2 - r**2), rel=1e-12)
        assert p.ball_distance_from_size(r)[0] == pytest.approx(dist3, rel=1e-9)


def test_false_positives_only_when_configured() -> None:
    f = make_field("spl2025")
    noisy = replace(
        PerceptParams.preset("harsh"), phantom_crossing_rate=1.0, background_post_rate=1.0, feet_ball_rate=1.0
    )
    syn = synth(f, noisy, seed=3)
    me = observer(0.0, 0.0, 0.0, head_pitch=0.1)
    other = SceneRobot(1, 4, 2.0, -0.3, math.pi)
    phantom = {"cross": 0, "post": 0, "ball": 0}
    for _ in range(200):
        p = see(syn, [me, other])
        phantom["cross"] += int(np.sum(p.crossings.truth < 0))
        phantom["post"] += int(np.sum(p.posts.truth < 0))
        phantom["ball"] += int(np.sum(p.ball.truth < 0))
    assert all(v > 50 for v in phantom.values()), phantom
    ideal = synth(f)
    for _ in range(50):
        p = see(ideal, [me, other])
        assert np.all(p.rows[:, 16] >= 0)
