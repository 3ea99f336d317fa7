"""The field definition, which is also the robot's map.

A :class:`Field` is built from :class:`FieldDimensions` and holds every landmark a robot can
use: goal posts, straight line segments, line crossings (L, T, X), the centre circle, the
penalty marks and, on the KidSize field, corner poles.

**Team frame** (a robot's field frame): metres, origin at the field centre, +x toward the
opponent goal, +y to the left when looking along +x; angles in radians counter-clockwise
from +x, wrapped to (-pi, pi]. The own goal is at x = -length/2, the opponent goal at
x = +length/2. All line geometry runs along line *centres*.

Line crossings are derived from the segments and the circle (never typed in): at every
junction the arms leaving the point are counted (2 non-collinear -> L, 3 -> T, 4 -> X).

=========  =============  ======  ===========  ====================================
preset     field (m)      boxes   ball (m)     source
=========  =============  ======  ===========  ====================================
spl2025    9.0 x 6.0      2       0.10         SPL rules 2025
spl2013    9.0 x 6.0      1       0.065        SPL 2013 field, used by the CMU
                                               "Vision-based cognition" and DNT papers
kidsize    4.5 x 3.0      1       0.085        NimbRo multi-cue localization paper
=========  =============  ======  ===========  ====================================

The NimbRo paper gives only the KidSize field size (4.5 x 3 m), blue/yellow goals and
four corner poles; the other KidSize values follow the Humanoid League rules of that era
approximately (corner poles assumed 0.3 m outside each corner along the goal line).
Colour schemes (:class:`ColourScheme`) are separate from the geometry.

Ranges of :class:`FieldDimensions` (metres; checked when the dimensions are built, with the
rules that the boxes, circle, mark and goal fit on the field):

======================  ===========  ==========================================================
field                   range        meaning
======================  ===========  ==========================================================
length                  (0, 100]     touchline length
width                   (0, 100]     goal-line length
line_width              (0, 1]       width of the white lines
goal_area_length        (0, 50]      depth of the goal area
goal_area_width         (0, 100]     width of the goal area
penalty_area_length     (0, 50]      depth of the penalty area (None: one box only)
penalty_area_width      (0, 100]     width of the penalty area (None: one box only)
penalty_mark_distance   (0, 50]      goal line to penalty mark
penalty_mark_size       (0, 1]       size of the penalty mark
centre_mark             true/false   whether there is a centre mark
centre_circle_diameter  (0, 100]     centre circle diameter
border_strip            (0, 10]      carpet beyond the lines
goal_inner_width        (0, 100]     clear width between the posts
goal_post_diameter      (0, 1]       goal post diameter
goal_height             (0, 10]      crossbar height
goal_depth              (0, 10]      depth of the goal behind the goal line
ball_diameter           (0, 1]       ball diameter
corner_pole_offset      [0, 10]      corner poles beyond the corners (None: no poles)
corner_pole_diameter    (0, 1]       corner pole diameter
======================  ===========  ==========================================================
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from dataclasses import field as dc_field
from typing import Any, ClassVar, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from cognition.geometry import wrap_angle
from cognition.params import Ranges, check_ranges, non_negative, positive

GoalName = Literal["own", "opponent"]
CrossingKind = Literal["L", "T", "X"]
CROSSING_KINDS: tuple[CrossingKind, ...] = ("L", "T", "X")
"""Letters of the crossing kinds; ``CROSSING_KINDS[Field.crossing_kinds[i]]`` is a letter."""

_I8 = np.int8
_TOL = 1e-6  # metres; geometric tolerance for junction detection


def mirrored(x: float, y: float, theta: float) -> tuple[float, float, float]:
    """The pose symmetric to (x m, y m, theta rad) under the field's point symmetry.

    Returns (-x, -y, theta + pi) with the angle wrapped to (-pi, pi].
    """
    return (-x, -y, wrap_angle(theta + math.pi))


@dataclass(frozen=True)
class FieldDimensions:
    """Field geometry; all lengths in metres, measured as in the rule books.

    Box lengths run along x (from the goal line's centre into the field), box widths along
    y. Every length must lie in its range (module table) and the parts must fit together; a
    ``ValueError`` (``TypeError`` for a non-number) names the offending field.
    """

    length: float
    """Touchline length between goal-line centres (m)."""
    width: float
    """Goal-line length between touchline centres (m)."""
    line_width: float
    """Width of the white lines (m)."""
    goal_area_length: float
    """Depth of the goal area (the small box) into the field (m)."""
    goal_area_width: float
    """Width of the goal area along y (m)."""
    penalty_area_length: float | None
    """Depth of the penalty area (the large box) (m); None if the field has only one box."""
    penalty_area_width: float | None
    """Width of the penalty area along y (m); None if the field has only one box."""
    penalty_mark_distance: float
    """Distance from the goal line to the penalty mark's centre (m)."""
    penalty_mark_size: float
    """Size of the penalty mark (m)."""
    centre_mark: bool
    """Whether the field has a centre mark."""
    centre_circle_diameter: float
    """Diameter of the centre circle, measured at the line centre (m)."""
    border_strip: float
    """Width of the carpet outside the touchlines and goal lines (m)."""
    goal_inner_width: float
    """Clear width between the goal posts' inner edges (m)."""
    goal_post_diameter: float
    """Goal post diameter (m)."""
    goal_height: float
    """Height of the crossbar's lower edge (m)."""
    goal_depth: float
    """Depth of the goal (net) behind the goal line (m)."""
    ball_diameter: float
    """Ball diameter (m)."""
    corner_pole_offset: float | None = None
    """None: no corner poles. Otherwise each pole's centre stands this far (m, >= 0) beyond
    a field corner along the goal-line direction, i.e. at (+-length/2, +-(width/2 + offset))."""
    corner_pole_diameter: float = 0.1
    """Corner pole diameter (m); unused when there are no corner poles."""

    RANGES: ClassVar[Ranges] = {
        "length": positive(100.0),
        "width": positive(100.0),
        "line_width": positive(1.0),
        "goal_area_length": positive(50.0),
        "goal_area_width": positive(100.0),
        "penalty_area_length": positive(50.0),
        "penalty_area_width": positive(100.0),
        "penalty_mark_distance": positive(50.0),
        "penalty_mark_size": positive(1.0),
        "centre_circle_diameter": positive(100.0),
        "border_strip": positive(10.0),
        "goal_inner_width": positive(100.0),
        "goal_post_diameter": positive(1.0),
        "goal_height": positive(10.0),
        "goal_depth": positive(10.0),
        "ball_diameter": positive(1.0),
        "corner_pole_offset": non_negative(10.0),
        "corner_pole_diameter": positive(1.0),
    }

    def __post_init__(self) -> None:
        check_ranges(self)
        if (self.penalty_area_length is None) != (self.penalty_area_width is None):
            raise ValueError(
                "FieldDimensions.penalty_area_length and penalty_area_width must both be set or "
                f"both be None, got {self.penalty_area_length!r} and {self.penalty_area_width!r}"
            )
        half_l = self.length / 2
        self._require("goal_area_length", self.goal_area_length < half_l, "< length/2")
        self._require("goal_area_width", self.goal_area_width < self.width, "< width")
        deepest = self.goal_area_length
        if self.penalty_area_length is not None and self.penalty_area_width is not None:
            deepest = self.penalty_area_length
            ok_l = self.goal_area_length < self.penalty_area_length < half_l
            ok_w = self.goal_area_width < self.penalty_area_width < self.width
            self._require("penalty_area_length", ok_l, "> goal_area_length and < length/2")
            self._require("penalty_area_width", ok_w, "> goal_area_width and < width")
        radius = self.centre_circle_diameter / 2
        ok_circle = radius < self.width / 2 and radius < half_l - deepest
        self._require("centre_circle_diameter", ok_circle, "to fit between touchlines and boxes")
        self._require("penalty_mark_distance", self.penalty_mark_distance < half_l, "< length/2")
        mouth = self.goal_inner_width + 2 * self.goal_post_diameter
        self._require("goal_inner_width", mouth < self.width, "+ 2 posts < width")
        self._require("goal_depth", self.goal_depth < self.border_strip, "< border_strip")
        thin = self.line_width < min(self.goal_area_length, self.goal_area_width)
        self._require("line_width", thin, "< the goal area's sides")

    def _require(self, name: str, ok: bool, what: str) -> None:
        if not ok:
            raise ValueError(f"FieldDimensions.{name} must be {what}, got {getattr(self, name)!r}")


# fmt: off
FIELD_PRESETS: dict[str, FieldDimensions] = {
    "spl2025": FieldDimensions(
        length=9.0, width=6.0, line_width=0.05, goal_area_length=0.6, goal_area_width=2.2,
        penalty_area_length=1.65, penalty_area_width=4.0, penalty_mark_distance=1.3,
        penalty_mark_size=0.1, centre_mark=True, centre_circle_diameter=1.5, border_strip=0.7,
        goal_inner_width=1.5, goal_post_diameter=0.1, goal_height=0.8, goal_depth=0.5,
        ball_diameter=0.1,
    ),
    "spl2013": FieldDimensions(
        length=9.0, width=6.0, line_width=0.05, goal_area_length=0.6, goal_area_width=2.2,
        penalty_area_length=None, penalty_area_width=None, penalty_mark_distance=1.3,
        penalty_mark_size=0.1, centre_mark=True, centre_circle_diameter=1.2, border_strip=0.7,
        goal_inner_width=1.5, goal_post_diameter=0.1, goal_height=0.8, goal_depth=0.5,
        ball_diameter=0.065,
    ),
    "kidsize": FieldDimensions(
        length=4.5, width=3.0, line_width=0.05, goal_area_length=0.5, goal_area_width=2.0,
        penalty_area_length=None, penalty_area_width=None, penalty_mark_distance=1.5,
        penalty_mark_size=0.1, centre_mark=False, centre_circle_diameter=1.2, border_strip=0.6,
        goal_inner_width=1.5, goal_post_diameter=0.1, goal_height=0.8, goal_depth=0.4,
        ball_diameter=0.085, corner_pole_offset=0.3, corner_pole_diameter=0.1,
    ),
}
# fmt: on
"""Field presets by name (see the module docstring for sources)."""


@dataclass(frozen=True)
class GoalPost:
    """A goal post's centre (x, y in m, team frame).

    ``side`` is as seen by a robot on the field facing that goal: for the opponent goal
    (+x) left is +y, for the own goal (-x) left is -y.
    """

    x: float
    y: float
    goal: GoalName
    side: Literal["left", "right"]


@dataclass(frozen=True)
class LineSegment:
    """A straight field line from (x1, y1) to (x2, y2) along its centre (m, team frame)."""

    x1: float
    y1: float
    x2: float
    y2: float

    @property
    def length(self) -> float:
        """Segment length (m)."""
        return math.hypot(self.x2 - self.x1, self.y2 - self.y1)

    @property
    def direction(self) -> float:
        """Undirected line direction (rad) in [0, pi)."""
        a = math.atan2(self.y2 - self.y1, self.x2 - self.x1) % math.pi
        return 0.0 if a >= math.pi - 1e-12 else a

    @property
    def midpoint(self) -> tuple[float, float]:
        """Centre of the segment (m)."""
        return ((self.x1 + self.x2) / 2, (self.y1 + self.y2) / 2)

    @property
    def is_along_x(self) -> bool:
        """True if the segment is parallel to the x axis (touchlines, box fronts' sides)."""
        return abs(self.y2 - self.y1) < _TOL

    @property
    def is_along_y(self) -> bool:
        """True if the segment is parallel to the y axis (goal lines, halfway line, box fronts)."""
        return abs(self.x2 - self.x1) < _TOL


@dataclass(frozen=True)
class LineCrossing:
    """A junction of field lines at (x, y) (m, team frame).

    ``orientation`` (rad, team frame): for L the bisector of the two arms, pointing into the
    angle between them, in (-pi, pi]; for T the stem (the arm not collinear with the other
    two) pointing away from the junction, in (-pi, pi]; for X the direction of one of its
    lines modulo pi/2, in [0, pi/2).
    """

    x: float
    y: float
    kind: CrossingKind
    orientation: float


@dataclass(frozen=True)
class CentreCircle:
    """The centre circle: centre (x, y) and radius to the line centre (m, team frame)."""

    x: float
    y: float
    radius: float


@dataclass(frozen=True)
class PenaltyMark:
    """A penalty mark's centre (m, team frame) in front of the ``goal`` it belongs to."""

    x: float
    y: float
    goal: GoalName


@dataclass(frozen=True)
class CornerPole:
    """A corner pole's centre (m, team frame)."""

    x: float
    y: float


@dataclass(frozen=True, eq=False)
class Field:
    """A field map in the team frame, built from ``dims`` (see module docstring).

    ``lines`` order: touchlines (+y, -y), goal lines (own, opponent), halfway line, then each
    box's three sides (own goal first, goal area before penalty area). The numpy views are
    read-only: ``crossing_array`` (N x 3: x, y, orientation), ``crossing_kinds`` (N, int8
    index into :data:`CROSSING_KINDS`), ``line_array`` (M x 4: x1, y1, x2, y2) and
    ``post_array`` (4 x 2: x, y, in ``goal_posts`` order).
    """

    dims: FieldDimensions
    """The geometry this map is built from."""
    name: str = "custom"
    """Preset name (a key of :data:`FIELD_PRESETS`) or ``"custom"``."""
    half_length: float = dc_field(init=False, repr=False)
    """length / 2 (m)."""
    half_width: float = dc_field(init=False, repr=False)
    """width / 2 (m)."""
    goal_posts: tuple[GoalPost, ...] = dc_field(init=False, repr=False)
    """Own left, own right, opponent left, opponent right."""
    lines: tuple[LineSegment, ...] = dc_field(init=False, repr=False)
    """Straight lines along their centres (no centre circle, no marks); order as above."""
    crossings: tuple[LineCrossing, ...] = dc_field(init=False, repr=False)
    """All crossings, sorted by kind (L, T, X), then x, then y."""
    centre_circle: CentreCircle = dc_field(init=False, repr=False)
    """The centre circle (centre at the origin)."""
    penalty_marks: tuple[PenaltyMark, ...] = dc_field(init=False, repr=False)
    """Own, opponent."""
    corner_poles: tuple[CornerPole, ...] = dc_field(init=False, repr=False)
    """Empty, or the 4 poles (own side -y, own +y, opponent -y, opponent +y)."""
    crossing_array: NDArray[np.float64] = dc_field(init=False, repr=False)
    crossing_kinds: NDArray[np.int8] = dc_field(init=False, repr=False)
    line_array: NDArray[np.float64] = dc_field(init=False, repr=False)
    post_array: NDArray[np.float64] = dc_field(init=False, repr=False)

    def __post_init__(self) -> None:
        d = self.dims
        hl, hw = d.length / 2, d.width / 2
        yp = d.goal_inner_width / 2 + d.goal_post_diameter / 2
        posts = (
            GoalPost(-hl, -yp, "own", "left"),
            GoalPost(-hl, yp, "own", "right"),
            GoalPost(hl, yp, "opponent", "left"),
            GoalPost(hl, -yp, "opponent", "right"),
        )
        lines = _build_lines(d)
        circle = CentreCircle(0.0, 0.0, d.centre_circle_diameter / 2)
        xm = hl - d.penalty_mark_distance
        poles: tuple[CornerPole, ...] = ()
        if d.corner_pole_offset is not None:
            yc = hw + d.corner_pole_offset
            poles = tuple(CornerPole(sx * hl, sy * yc) for sx in (-1, 1) for sy in (-1, 1))
        crossings = _derive_crossings(lines, circle)
        values: dict[str, object] = {
            "half_length": hl,
            "half_width": hw,
            "goal_posts": posts,
            "lines": lines,
            "crossings": crossings,
            "centre_circle": circle,
            "penalty_marks": (PenaltyMark(-xm, 0.0, "own"), PenaltyMark(xm, 0.0, "opponent")),
            "corner_poles": poles,
            "crossing_array": _frozen([(c.x, c.y, c.orientation) for c in crossings], (0, 3)),
            "crossing_kinds": _frozen([CROSSING_KINDS.index(c.kind) for c in crossings], (0,), _I8),
            "line_array": _frozen([(s.x1, s.y1, s.x2, s.y2) for s in lines], (0, 4)),
            "post_array": _frozen([(p.x, p.y) for p in posts], (0, 2)),
        }
        for key, value in values.items():
            object.__setattr__(self, key, value)

    @classmethod
    def from_dimensions(cls, dims: FieldDimensions, name: str = "custom") -> Field:
        """Build a field map from arbitrary (validated) dimensions."""
        return cls(dims, name)

    def is_inside(self, x: float, y: float, margin: float = 0.0) -> bool:
        """True if (x, y) (m) lies within the outer edges of the field lines.

        A positive ``margin`` (m) enlarges the region by that much on every side, a negative
        one shrinks it.
        """
        return bool(self.inside_mask(x, y, margin))

    def inside_mask(self, x: ArrayLike, y: ArrayLike, margin: float = 0.0) -> NDArray[np.bool_]:
        """Vectorized :meth:`is_inside` over arrays of x and y (m); returns a bool array."""
        edge = self.dims.line_width / 2 + margin
        xa, ya = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        return (np.abs(xa) <= self.half_length + edge) & (np.abs(ya) <= self.half_width + edge)

    def in_goal(self, x: float, y: float, radius: float = 0.0) -> GoalName | None:
        """Which goal a disc at (x, y) (m) of ``radius`` (m, e.g. the ball's) is fully inside.

        The disc must be entirely beyond the goal line's outer edge, between the posts' inner
        edges and not behind the net (|x| <= length/2 + goal_depth). Returns None otherwise.
        """
        d = self.dims
        beyond = abs(x) - radius > self.half_length + d.line_width / 2
        between = abs(y) + radius < d.goal_inner_width / 2
        if not (beyond and between and abs(x) <= self.half_length + d.goal_depth):
            return None
        return "opponent" if x > 0 else "own"


def _frozen(rows: list[Any], empty_shape: tuple[int, ...], dtype: Any = np.float64) -> NDArray[Any]:
    arr = np.array(rows, dtype=dtype) if rows else np.zeros(empty_shape, dtype=dtype)
    arr.flags.writeable = False
    return arr


def _build_lines(d: FieldDimensions) -> tuple[LineSegment, ...]:
    hl, hw = d.length / 2, d.width / 2
    lines = [
        LineSegment(-hl, hw, hl, hw),
        LineSegment(-hl, -hw, hl, -hw),
        LineSegment(-hl, -hw, -hl, hw),
        LineSegment(hl, -hw, hl, hw),
        LineSegment(0.0, -hw, 0.0, hw),
    ]
    boxes = [(d.goal_area_length, d.goal_area_width)]
    if d.penalty_area_length is not None and d.penalty_area_width is not None:
        boxes.append((d.penalty_area_length, d.penalty_area_width))
    for sign in (-1.0, 1.0):
        gx = sign * hl
        for box_length, box_width in boxes:
            fx, by = sign * (hl - box_length), box_width / 2
            lines += [
                LineSegment(gx, by, fx, by),
                LineSegment(fx, by, fx, -by),
                LineSegment(fx, -by, gx, -by),
            ]
    return tuple(lines)


def _segment_intersection(a: LineSegment, b: LineSegment) -> tuple[float, float] | None:
    """Intersection point of two non-parallel segments (touching counts), else None."""
    ax, ay = a.x2 - a.x1, a.y2 - a.y1
    bx, by = b.x2 - b.x1, b.y2 - b.y1
    den = ax * by - ay * bx
    if abs(den) < 1e-12:
        return None
    ox, oy = b.x1 - a.x1, b.y1 - a.y1
    t = (ox * by - oy * bx) / den
    u = (ox * ay - oy * ax) / den
    ta, tb = _TOL / a.length, _TOL / b.length
    if -ta <= t <= 1 + ta and -tb <= u <= 1 + tb:
        return (a.x1 + t * ax, a.y1 + t * ay)
    return None


def _circle_intersections(s: LineSegment, c: CentreCircle) -> list[tuple[float, float]]:
    """Points where segment ``s`` meets circle ``c``."""
    dx, dy = s.x2 - s.x1, s.y2 - s.y1
    fx, fy = s.x1 - c.x, s.y1 - c.y
    qa, qb, qc = dx * dx + dy * dy, 2 * (fx * dx + fy * dy), fx * fx + fy * fy - c.radius**2
    disc = qb * qb - 4 * qa * qc
    if disc < 0:
        return []
    roots = {(-qb - math.sqrt(disc)) / (2 * qa), (-qb + math.sqrt(disc)) / (2 * qa)}
    eps = _TOL / s.length
    return [(s.x1 + t * dx, s.y1 + t * dy) for t in sorted(roots) if -eps <= t <= 1 + eps]


def _arms(px: float, py: float, lines: tuple[LineSegment, ...], c: CentreCircle) -> list[float]:
    """Directions (rad) of the distinct line arms leaving point (px, py)."""
    arms: list[float] = []
    for s in lines:
        dx, dy = s.x2 - s.x1, s.y2 - s.y1
        t = ((px - s.x1) * dx + (py - s.y1) * dy) / (dx * dx + dy * dy)
        t = min(1.0, max(0.0, t))
        if math.hypot(s.x1 + t * dx - px, s.y1 + t * dy - py) > _TOL:
            continue
        if t * s.length > _TOL:
            arms.append(math.atan2(-dy, -dx))
        if (1 - t) * s.length > _TOL:
            arms.append(math.atan2(dy, dx))
    if abs(math.hypot(px - c.x, py - c.y) - c.radius) < _TOL:
        radial = math.atan2(py - c.y, px - c.x)
        arms += [wrap_angle(radial + math.pi / 2), wrap_angle(radial - math.pi / 2)]
    distinct: list[float] = []
    for a in arms:
        if all(abs(wrap_angle(a - b)) > 1e-6 for b in distinct):
            distinct.append(a)
    return distinct


def _classify(arms: list[float]) -> tuple[CrossingKind, float] | None:
    """Kind and orientation (rad) of a junction with these arm directions, or None."""

    def opposite(a: float, b: float) -> bool:
        return abs(abs(wrap_angle(a - b)) - math.pi) < 1e-6

    if len(arms) == 2:
        if opposite(*arms):
            return None  # a straight line passing through: no junction
        bisector = math.atan2(sum(map(math.sin, arms)), sum(map(math.cos, arms)))
        return "L", wrap_angle(bisector)
    if len(arms) == 3:
        for i, stem in enumerate(arms):
            others = [a for j, a in enumerate(arms) if j != i]
            if opposite(*others):
                return "T", wrap_angle(stem)
        raise ValueError(f"junction with arms {arms} is not a T")
    if len(arms) == 4:
        quarter = math.pi / 2
        mods = [a % quarter for a in arms]
        return "X", min(0.0 if m > quarter - 1e-9 else m for m in mods)
    if len(arms) > 4:
        raise ValueError(f"junction with {len(arms)} arms is not supported")
    return None


def _derive_crossings(lines: tuple[LineSegment, ...], c: CentreCircle) -> tuple[LineCrossing, ...]:
    """All L/T/X crossings of the segments and the circle, computed geometrically."""
    candidates: list[tuple[float, float]] = []
    for s in lines:
        candidates += [(s.x1, s.y1), (s.x2, s.y2)]
    for i, a in enumerate(lines):
        for b in lines[i + 1 :]:
            p = _segment_intersection(a, b)
            if p is not None:
                candidates.append(p)
        candidates += _circle_intersections(a, c)
    points: list[tuple[float, float]] = []
    for p in candidates:
        if all(math.hypot(p[0] - q[0], p[1] - q[1]) > _TOL for q in points):
            points.append(p)
    found = []
    for px, py in points:
        result = _classify(_arms(px, py, lines, c))
        if result is not None:
            kind, orientation = result
            x, y = round(px, 9) + 0.0, round(py, 9) + 0.0
            found.append(LineCrossing(x, y, kind, orientation))
    found.sort(key=lambda k: (CROSSING_KINDS.index(k.kind), k.x, k.y))
    return tuple(found)


def make_field(name: str) -> Field:
    """The field map of preset ``name`` (a key of :data:`FIELD_PRESETS`)."""
    if name not in FIELD_PRESETS:
        raise ValueError(f"unknown field preset {name!r}; valid names: {sorted(FIELD_PRESETS)}")
    return Field(FIELD_PRESETS[name], name)


RGB = tuple[int, int, int]
"""A colour as (red, green, blue), each an int in 0..255."""


@dataclass(frozen=True)
class ColourScheme:
    """Colours of the field objects, RGB 0..255.

    ``own_goal`` / ``opponent_goal`` are the colours of the goals at -x / +x of the frame the
    scheme is applied in (for the simulator's world frame: team 0's first-half frame).
    ``team_colours`` are the jersey colours of team 0 and team 1.
    """

    name: str
    field_green: RGB
    line_white: RGB
    own_goal: RGB
    opponent_goal: RGB
    ball_primary: RGB
    """Main ball colour."""
    ball_secondary: RGB
    """Patch colour of the ball (same as primary for a single-coloured ball)."""
    team_colours: tuple[RGB, RGB]

    def __post_init__(self) -> None:
        for f in fields(self):
            if f.name == "name":
                continue
            value = getattr(self, f.name)
            rgbs = value if f.name == "team_colours" and len(value) == 2 else (value,)
            for rgb in rgbs:
                ok = isinstance(rgb, tuple) and len(rgb) == 3
                if not ok or not all(isinstance(v, int) and 0 <= v <= 255 for v in rgb):
                    raise ValueError(f"ColourScheme.{f.name} must be RGB 0..255, got {value!r}")


_GREEN, _WHITE, _BLACK = (0, 140, 40), (255, 255, 255), (0, 0, 0)
_YELLOW, _BLUE, _ORANGE = (250, 210, 0), (0, 80, 220), (255, 120, 0)
_BLUE_RED: tuple[RGB, RGB] = ((30, 60, 230), (220, 20, 30))
_CYAN_MAGENTA: tuple[RGB, RGB] = ((0, 200, 230), (230, 0, 200))

# fmt: off
COLOUR_SCHEMES: dict[str, ColourScheme] = {
    "classic": ColourScheme("classic",
                            _GREEN, _WHITE, _YELLOW, _YELLOW, _ORANGE, _ORANGE, _BLUE_RED),
    "modern": ColourScheme("modern",
                           _GREEN, _WHITE, _WHITE, _WHITE, _WHITE, _BLACK, _BLUE_RED),
    "kidsize": ColourScheme("kidsize",
                            _GREEN, _WHITE, _BLUE, _YELLOW, _ORANGE, _ORANGE, _CYAN_MAGENTA),
}
# fmt: on
"""Colour schemes: ``classic`` (2013 SPL: yellow goals, orange ball), ``modern`` (white goals,
black-and-white ball), ``kidsize`` (blue/yellow goals, orange ball, cyan/magenta teams)."""


def make_colour_scheme(name: str) -> ColourScheme:
    """The colour scheme ``name`` (a key of :data:`COLOUR_SCHEMES`)."""
    if name not in COLOUR_SCHEMES:
        raise ValueError(f"unknown colour scheme {name!r}; valid names: {sorted(COLOUR_SCHEMES)}")
    return COLOUR_SCHEMES[name]
