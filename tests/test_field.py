"""Tests for cognition.field: presets, derived landmarks, helpers and colour schemes."""

from __future__ import annotations

import dataclasses
import math
from collections import Counter

import numpy as np
import pytest

from cognition.field import (
    COLOUR_SCHEMES,
    CROSSING_KINDS,
    FIELD_PRESETS,
    Field,
    FieldDimensions,
    LineCrossing,
    LineSegment,
    make_colour_scheme,
    make_field,
    mirrored,
)


def angle_diff(a: float, b: float) -> float:
    return abs(math.remainder(a - b, 2 * math.pi))


def crossing_at(field: Field, x: float, y: float) -> LineCrossing:
    hits = [c for c in field.crossings if math.isclose(c.x, x) and math.isclose(c.y, y)]
    assert len(hits) == 1, f"expected one crossing at ({x}, {y}), got {hits}"
    return hits[0]


def points(field: Field, kind: str) -> set[tuple[float, float]]:
    return {(round(c.x, 6), round(c.y, 6)) for c in field.crossings if c.kind == kind}


def on_segment(s: LineSegment, x: float, y: float, tol: float = 1e-6) -> bool:
    dx, dy = s.x2 - s.x1, s.y2 - s.y1
    t = min(1.0, max(0.0, ((x - s.x1) * dx + (y - s.y1) * dy) / (dx * dx + dy * dy)))
    return math.hypot(s.x1 + t * dx - x, s.y1 + t * dy - y) < tol


@pytest.fixture(params=sorted(FIELD_PRESETS))
def any_field(request: pytest.FixtureRequest) -> Field:
    return make_field(request.param)


@pytest.mark.parametrize(
    ("name", "expected"),
    [
        ("spl2025", {"L": 12, "T": 10, "X": 2}),
        ("spl2013", {"L": 8, "T": 6, "X": 2}),
        ("kidsize", {"L": 8, "T": 6, "X": 2}),
    ],
)
def test_crossing_counts(name: str, expected: dict[str, int]) -> None:
    field = make_field(name)
    assert Counter(c.kind for c in field.crossings) == expected
    assert field.crossing_array.shape == (sum(expected.values()), 3)
    kinds = Counter(CROSSING_KINDS[k] for k in field.crossing_kinds)
    assert kinds == expected


@pytest.mark.parametrize(("name", "n_lines"), [("spl2025", 17), ("spl2013", 11), ("kidsize", 11)])
def test_line_counts(name: str, n_lines: int) -> None:
    # 2 touchlines + 2 goal lines + halfway + 3 sides per box
    field = make_field(name)
    assert len(field.lines) == n_lines
    assert field.line_array.shape == (n_lines, 4)


def test_common_landmark_counts(any_field: Field) -> None:
    assert len(any_field.goal_posts) == 4
    assert any_field.post_array.shape == (4, 2)
    assert len(any_field.penalty_marks) == 2
    assert {m.goal for m in any_field.penalty_marks} == {"own", "opponent"}


def test_spl2025_crossing_positions() -> None:
    field = make_field("spl2025")
    corners = {(sx * 4.5, sy * 3.0) for sx in (-1, 1) for sy in (-1, 1)}
    goal_area = {(sx * 3.9, sy * 1.1) for sx in (-1, 1) for sy in (-1, 1)}
    penalty_area = {(sx * 2.85, sy * 2.0) for sx in (-1, 1) for sy in (-1, 1)}
    assert points(field, "L") == corners | goal_area | penalty_area
    ts = {(sx * 4.5, sy * w) for sx in (-1, 1) for sy in (-1, 1) for w in (1.1, 2.0)}
    assert points(field, "T") == ts | {(0.0, 3.0), (0.0, -3.0)}
    assert points(field, "X") == {(0.0, 0.75), (0.0, -0.75)}


def test_spl2025_crossing_orientations() -> None:
    field = make_field("spl2025")
    assert angle_diff(crossing_at(field, 4.5, 3.0).orientation, -3 * math.pi / 4) < 1e-9
    assert angle_diff(crossing_at(field, -4.5, -3.0).orientation, math.pi / 4) < 1e-9
    # goal-area corner at (3.9, 1.1): arms toward +x and -y
    assert angle_diff(crossing_at(field, 3.9, 1.1).orientation, -math.pi / 4) < 1e-9
    assert angle_diff(crossing_at(field, 0.0, 3.0).orientation, -math.pi / 2) < 1e-9
    assert angle_diff(crossing_at(field, 0.0, -3.0).orientation, math.pi / 2) < 1e-9
    assert angle_diff(crossing_at(field, 4.5, 1.1).orientation, math.pi) < 1e-9
    assert angle_diff(crossing_at(field, -4.5, 1.1).orientation, 0.0) < 1e-9
    for c in field.crossings:
        if c.kind == "X":
            assert 0.0 <= c.orientation < math.pi / 2
            assert c.orientation == pytest.approx(0.0)
        else:
            assert -math.pi < c.orientation <= math.pi


def test_crossings_lie_on_lines_or_circle(any_field: Field) -> None:
    circle = any_field.centre_circle
    for c in any_field.crossings:
        n_lines = sum(on_segment(s, c.x, c.y) for s in any_field.lines)
        on_circle = abs(math.hypot(c.x - circle.x, c.y - circle.y) - circle.radius) < 1e-6
        assert n_lines + on_circle >= 2, c
        if c.kind == "X":
            assert on_circle and n_lines == 1


def test_crossings_point_symmetric(any_field: Field) -> None:
    def key(x: float, y: float, kind: str) -> tuple[float, float, str]:
        return (round(x, 6) + 0.0, round(y, 6) + 0.0, kind)

    original = {key(c.x, c.y, c.kind) for c in any_field.crossings}
    flipped = {key(-c.x, -c.y, c.kind) for c in any_field.crossings}
    assert original == flipped
    # orientations rotate by pi under the symmetry (X crossings: unchanged modulo pi/2)
    for c in any_field.crossings:
        if c.kind in "LT":
            twin = crossing_at(any_field, -c.x, -c.y)
            assert angle_diff(twin.orientation, c.orientation + math.pi) < 1e-9


def test_goal_posts_identity(any_field: Field) -> None:
    d = any_field.dims
    posts = {(p.goal, p.side): p for p in any_field.goal_posts}
    assert len(posts) == 4
    assert posts["opponent", "left"].y > 0 and posts["opponent", "right"].y < 0
    assert posts["own", "left"].y < 0 and posts["own", "right"].y > 0
    y_post = d.goal_inner_width / 2 + d.goal_post_diameter / 2
    for p in any_field.goal_posts:
        assert p.x == pytest.approx(d.length / 2 if p.goal == "opponent" else -d.length / 2)
        assert abs(p.y) == pytest.approx(y_post)
    np.testing.assert_allclose(any_field.post_array, [(p.x, p.y) for p in any_field.goal_posts])


def test_spl2025_values() -> None:
    field = make_field("spl2025")
    assert field.name == "spl2025"
    assert (field.half_length, field.half_width) == (4.5, 3.0)
    assert field.centre_circle.radius == pytest.approx(0.75)
    marks = {m.goal: (m.x, m.y) for m in field.penalty_marks}
    assert marks["own"] == pytest.approx((-3.2, 0.0))
    assert marks["opponent"] == pytest.approx((3.2, 0.0))
    assert field.corner_poles == ()
    assert field.dims.centre_mark
    assert abs(field.goal_posts[2].y) == pytest.approx(0.8)


def test_spl2013_values() -> None:
    field = make_field("spl2013")
    assert field.dims.penalty_area_length is None and field.dims.penalty_area_width is None
    assert field.centre_circle.radius == pytest.approx(0.6)
    assert sorted(m.x for m in field.penalty_marks) == pytest.approx([-3.2, 3.2])
    assert field.dims.ball_diameter == pytest.approx(0.065)
    assert points(field, "X") == {(0.0, 0.6), (0.0, -0.6)}
    assert field.corner_poles == ()


def test_kidsize_values() -> None:
    field = make_field("kidsize")
    assert (field.dims.length, field.dims.width) == (4.5, 3.0)
    assert not field.dims.centre_mark
    assert len(field.corner_poles) == 4
    for pole in field.corner_poles:
        assert not field.is_inside(pole.x, pole.y)
        assert abs(pole.x) == pytest.approx(2.25) and abs(pole.y) > 1.5
    assert {(np.sign(p.x), np.sign(p.y)) for p in field.corner_poles} == {(sx, sy) for sx in (-1, 1) for sy in (-1, 1)}
    assert sorted(m.x for m in field.penalty_marks) == pytest.approx([-0.75, 0.75])
    corners = {(sx * 2.25, sy * 1.5) for sx in (-1, 1) for sy in (-1, 1)}
    assert corners <= points(field, "L")


def test_line_segment_helpers() -> None:
    s = LineSegment(0.0, 3.0, 0.0, -3.0)
    assert s.length == pytest.approx(6.0)
    assert s.direction == pytest.approx(math.pi / 2)
    assert s.is_along_y and not s.is_along_x
    assert s.midpoint == pytest.approx((0.0, 0.0))
    t = LineSegment(4.5, 1.0, -4.5, 1.0)
    assert t.direction == pytest.approx(0.0) and t.is_along_x
    for seg in make_field("spl2025").lines:
        assert 0.0 <= seg.direction < math.pi
        assert seg.is_along_x != seg.is_along_y


def test_is_inside_and_mask() -> None:
    field = make_field("spl2025")
    assert field.is_inside(0.0, 0.0)
    assert field.is_inside(4.52, 3.02)  # on the outer half of the corner lines
    assert not field.is_inside(4.53, 0.0)
    assert field.is_inside(4.6, 0.0, margin=0.1)
    assert not field.is_inside(4.4, 0.0, margin=-0.2)
    mask = field.inside_mask(np.array([0.0, 5.0, -4.5]), np.array([0.0, 0.0, -3.0]))
    assert mask.tolist() == [True, False, True]


def test_in_goal() -> None:
    field = make_field("spl2025")
    assert field.in_goal(4.7, 0.0) == "opponent"
    assert field.in_goal(-4.7, 0.3) == "own"
    assert field.in_goal(4.5, 0.0) is None  # on the goal line
    assert field.in_goal(4.56, 0.0, radius=0.05) is None  # ball still touches the line
    assert field.in_goal(4.6, 0.0, radius=0.05) == "opponent"
    assert field.in_goal(4.7, 0.8) is None  # beside the goal
    assert field.in_goal(5.2, 0.0) is None  # behind the net
    assert field.in_goal(0.0, 0.0) is None


def test_mirrored() -> None:
    x, y, th = mirrored(1.0, -2.0, 0.5)
    assert (x, y) == (-1.0, 2.0)
    assert th == pytest.approx(0.5 - math.pi)
    assert mirrored(0.0, 0.0, 0.0)[2] == pytest.approx(math.pi)
    assert mirrored(0.0, 0.0, math.pi)[2] == pytest.approx(0.0)
    assert -math.pi < mirrored(0.0, 0.0, -math.pi / 2 + 2 * math.pi)[2] <= math.pi


def test_arrays_are_read_only() -> None:
    field = make_field("spl2025")
    with pytest.raises(ValueError):
        field.crossing_array[0, 0] = 1.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        field.half_length = 1.0  # type: ignore[misc]


def test_from_dimensions_custom() -> None:
    dims = dataclasses.replace(FIELD_PRESETS["spl2025"], length=10.0, width=7.0)
    field = Field.from_dimensions(dims)
    assert field.name == "custom"
    assert crossing_at(field, 5.0, 3.5).kind == "L"
    assert Counter(c.kind for c in field.crossings) == {"L": 12, "T": 10, "X": 2}


def test_unknown_preset() -> None:
    with pytest.raises(ValueError, match="spl2025") as info:
        make_field("spl1999")
    for name in FIELD_PRESETS:
        assert name in str(info.value)


@pytest.mark.parametrize(
    ("changes", "culprit"),
    [
        ({"length": -9.0}, "length"),
        ({"width": math.nan}, "width"),
        ({"goal_area_width": 7.0}, "goal_area_width"),
        ({"penalty_area_width": 2.0}, "penalty_area_width"),
        ({"penalty_area_length": None}, "penalty_area_length"),
        ({"centre_circle_diameter": 6.5}, "centre_circle_diameter"),
        ({"corner_pole_offset": -0.1}, "corner_pole_offset"),
        ({"ball_diameter": 0.0}, "ball_diameter"),
    ],
)
def test_bad_dimensions(changes: dict[str, object], culprit: str) -> None:
    with pytest.raises(ValueError, match=culprit):
        dataclasses.replace(FIELD_PRESETS["spl2025"], **changes)  # type: ignore[arg-type]


def test_field_dimensions_direct_construction() -> None:
    kwargs = {f.name: getattr(FIELD_PRESETS["spl2013"], f.name) for f in dataclasses.fields(FieldDimensions)}
    assert FieldDimensions(**kwargs) == FIELD_PRESETS["spl2013"]
    with pytest.raises(ValueError, match=r"length.*-1\.0"):
        FieldDimensions(**{**kwargs, "length": -1.0})
    with pytest.raises(TypeError, match=r"FieldDimensions\.centre_mark must be true or false, got 1"):
        FieldDimensions(**{**kwargs, "centre_mark": 1})
    with pytest.raises(ValueError, match=r"ColourScheme\.line_white"):
        dataclasses.replace(COLOUR_SCHEMES["classic"], line_white=(255, 255, 256))


def test_colour_schemes() -> None:
    classic = make_colour_scheme("classic")
    assert classic.own_goal == classic.opponent_goal
    r, g, b = classic.own_goal
    assert r > 200 and g > 150 and b < 80  # yellow
    r, g, b = classic.ball_primary
    assert r > 200 and 60 < g < 180 and b < 60  # orange
    assert classic.ball_secondary == classic.ball_primary
    modern = make_colour_scheme("modern")
    assert modern.own_goal == modern.opponent_goal == (255, 255, 255)
    assert {modern.ball_primary, modern.ball_secondary} == {(255, 255, 255), (0, 0, 0)}
    kidsize = make_colour_scheme("kidsize")
    assert kidsize.own_goal != kidsize.opponent_goal
    for scheme in COLOUR_SCHEMES.values():
        assert len(scheme.team_colours) == 2
        assert scheme.team_colours[0] != scheme.team_colours[1]


def test_unknown_colour_scheme() -> None:
    with pytest.raises(ValueError, match="classic") as info:
        make_colour_scheme("neon")
    assert "modern" in str(info.value) and "kidsize" in str(info.value)
