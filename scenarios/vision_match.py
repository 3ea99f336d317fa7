"""Matching vision percepts to ground-truth image annotations, kind by kind (``teamsim vision-eval``).

:func:`evaluate_frame` compares the :class:`~cognition.percepts.Percepts` that vision reported
for one image with the renderer's :class:`~teamsim.images.ImageAnnotations` of the same image
and returns a :class:`Tally` per kind (counts, label checks, position errors);
:func:`scenarios.vision_report.summarize` turns summed tallies into precision, recall and error
statistics and :func:`scenarios.vision_report.check_bars` checks them against the vision
issue's bars. The building blocks (``greedy_match``, ``match_points``, ``match_boxes``,
``match_lines``, ``labels_agree`` in :mod:`scenarios.vision_assign`) work on plain arrays, for
tests and for other evaluations. The frames, the run and the command are in
:mod:`scenarios.vision_eval`.

**Matching** (per frame and kind; :func:`greedy_match`: pairs in increasing pixel distance,
one-to-one; pixel tolerances are given for 320 px wide images and scale with the width):

==============  ==================================================================================
kind            a detection matches an annotation when
==============  ==================================================================================
post            its base pixel is within ``post_px`` of the annotated base or inside the
                annotated box; the side must agree when both give one (a wrong side is a false
                positive and a miss)
crossing        its pixel is within ``crossing_px`` and its type L/T/X agrees (a wrong type is a
                false positive and a miss); ``crossing_any`` is the same without the type
line            precision: both end pixels within ``line_px`` of the carrier line of the annotated
                visible pieces of one field line, and not beyond a piece's ends by more than
                3 ``line_px`` or 20 % of it (a segment may bridge a robot standing on the line,
                or run into the width of the line it meets);
                recall: an annotated piece (its part within range) longer than
                ``line_min_px`` counts, and is found when at least ``line_cover`` of it lies
                within ``line_px`` of detected segments
circle          its centre is within ``circle_m`` of the true centre on the ground; the circle
                counts for recall when at least ``circle_visible`` of it is in the image and not
                hidden (the annotation's visible points)
mark            its pixel is within ``mark_px``
ball            its centre pixel is within max(``ball_px``, the annotated image radius)
robot           its pixel (the feet) lies inside the annotated box widened by ``robot_px``;
                ``label`` is the team guess (own / opponent) where one is given
==============  ==================================================================================

**Counting.** An annotation counts for recall when its pixel lies at least ``margin_px`` inside
the image (lines: no margin, they are clipped to the image) and its true position is within
``max_distance`` of the robot (the ball: ``ball_distance``). A crossing's type is a property of
its arms, so a crossing counts for recall only when the image shows it: the first
``crossing_arm`` metres of every arm lie inside the image (with the margin), span at least
``crossing_arm_px`` pixels (a T whose bar goes on for two pixels past its stem looks like an
L), are not behind a nearer robot or goal post (their annotated boxes), and are wide enough
to be seen as a line there (the field's line width projects to at least ``line_min_width_px`` across the arm's
image, so that at least one pixel is covered by the line alone: narrower lines
blend with the carpet; at 320 x 240 a line across the view from 0.5 m of camera height
shrinks below 2 px at about 2 m, a line along the view at about 7 m). A crossing whose arms
leave the image at once, hide behind a robot or blur into the carpet is counted in
``crossing_seen``, the recall over every crossing in view, but not in
``crossing``. A detection counts for precision
when its measured position is within the same distance. Matches across the limit are neither
hits nor errors: a detection at 3.9 m of a ball at 4.1 m is a correct detection that the
recall does not ask for. Precision = matched counted detections / counted detections
(``FP`` = the rest); recall = matched counted annotations / counted annotations (``TP``;
``FN`` = the rest); both are empty (``-``) without anything to count.

**Errors** of matched pairs (detection counted), robot frame: the true position comes from the
annotation's ground-truth id (field map, scene ball, robot centre; the circle's centre), the
measured one from the percept. ``dist`` = |measured distance - true distance| (m), ``rel`` =
that / true distance, ``bearing`` = |bearing difference| (deg). Lines: the perpendicular
distance from the robot to the (infinite) line and the direction difference (deg, modulo
180). Reported as median and 90th percentile. ``label``: side (posts), type (crossings) or team
(robots) accuracy of the position matches where both sides give one, and how many those are.

======================  ==========  ============  ================================================
EvalParams              default     range         meaning
======================  ==========  ============  ================================================
crossing_px             8 px        (0, 100]      crossing tolerance
post_px                 8 px        (0, 100]      post base tolerance
ball_px                 4 px        (0, 100]      smallest ball tolerance
mark_px                 8 px        (0, 100]      penalty mark tolerance
robot_px                4 px        [0, 100]      robot box widening
line_px                 4 px        (0, 100]      line end and coverage tolerance
line_min_px             20 px       [0, 1000]     shortest annotated line piece that counts
line_cover              0.5         (0, 1]        share of a piece that must be covered
circle_m                0.3 m       (0, 5]        centre-circle tolerance on the ground
circle_visible          0.5         [0, 1]        visible share of the circle for recall
margin_px               4 px        [0, 100]      annotations this close to the border do not count
max_distance            6.0 m       (0, 100]      evaluation distance (vision's max_distance)
ball_distance           4.0 m       (0, 100]      evaluation distance of the ball
crossing_arm            0.2 m       [0, 5]        arm length a crossing must show to count for recall ...
crossing_arm_px         6 px        [0, 100]      ... as at least this many pixels
line_min_width_px       2.0 px      [0, 100]      narrowest image of a line that counts as seen
======================  ==========  ============  ================================================

**Bars** (the vision issue, stated for ``default`` images and >= 500 frames per colour
scheme): crossings precision >= 0.95, recall >= 0.80; posts precision, recall and side accuracy
>= 0.97; ball precision and recall >= 0.95 (within 4 m); circle recall >= 0.7 (half in view);
median relative distance error < 5 % (posts, crossings, circle, marks, ball).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np
from numpy.typing import NDArray

from cognition.field import Field
from cognition.params import PROBABILITY, Range, Ranges, check_ranges, non_negative, positive
from cognition.percepts import Kind, Percepts, RobotTeam
from cognition.vision.draw import percept_pixels
from scenarios.vision_assign import (
    LINE_SAMPLES,
    greedy_match,
    labels_agree,
    line_samples,
    match_boxes,
    match_lines,
    match_points,
)
from teamsim.images import ImageAnnotations
from teamsim.percepts import CIRCLE_SAMPLES, Scene

KINDS: tuple[str, ...] = (
    "post", "crossing", "crossing_any", "crossing_seen", "line", "circle", "mark", "ball", "robot"
)  # fmt: skip
"""Kinds of the evaluation (rows of the table), in order."""
LABELS = {"post": "side", "crossing": "type", "crossing_any": "type", "crossing_seen": "type", "robot": "team"}
"""What the ``label`` column checks per kind."""
BASE_WIDTH = 320.0
"""Image width (px) the pixel tolerances are given for."""
_CIRCLE_POINTS = 4 * CIRCLE_SAMPLES  # sample points of ImageAnnotations.circle over the whole circle
_DEG = 180.0 / math.pi


@dataclass(frozen=True)
class EvalParams:
    """Tolerances and counting rules of the matching (module table)."""

    crossing_px: float = 8.0
    post_px: float = 8.0
    ball_px: float = 4.0
    mark_px: float = 8.0
    robot_px: float = 4.0
    line_px: float = 4.0
    line_min_px: float = 20.0
    line_cover: float = 0.5
    circle_m: float = 0.3
    circle_visible: float = 0.5
    margin_px: float = 4.0
    max_distance: float = 6.0
    ball_distance: float = 4.0
    crossing_arm: float = 0.2
    crossing_arm_px: float = 6.0
    line_min_width_px: float = 1.5

    RANGES: ClassVar[Ranges] = {
        "crossing_px": positive(100.0),
        "post_px": positive(100.0),
        "ball_px": positive(100.0),
        "mark_px": positive(100.0),
        "robot_px": non_negative(100.0),
        "line_px": positive(100.0),
        "line_min_px": non_negative(1000.0),
        "line_cover": Range(0.0, 1.0, low_open=True),
        "circle_m": positive(5.0),
        "circle_visible": PROBABILITY,
        "margin_px": non_negative(100.0),
        "max_distance": positive(100.0),
        "ball_distance": positive(100.0),
        "crossing_arm": non_negative(5.0),
        "crossing_arm_px": non_negative(100.0),
        "line_min_width_px": non_negative(100.0),
    }

    def __post_init__(self) -> None:
        check_ranges(self)


# -- one frame -----------------------------------------------------------------------------


@dataclass
class Tally:
    """Counts and errors of one kind (one frame, or summed over frames)."""

    annotations: int = 0
    """Annotations that count for recall."""
    detections: int = 0
    """Detections that count for precision."""
    tp: int = 0
    """Counted annotations matched (recall numerator)."""
    tp_det: int = 0
    """Counted detections matched (precision numerator)."""
    label_checked: int = 0
    label_correct: int = 0
    errors: list[tuple[float, float, float]] = field(default_factory=list)
    """(true distance m, measured distance m, bearing or direction error deg) per matched pair."""
    found: list[tuple[float, bool]] = field(default_factory=list)
    """(true distance m, matched) per counted annotation (point kinds), for recall by distance."""

    @property
    def fp(self) -> int:
        return self.detections - self.tp_det

    @property
    def fn(self) -> int:
        return self.annotations - self.tp

    def add(self, other: Tally) -> None:
        self.annotations += other.annotations
        self.detections += other.detections
        self.tp += other.tp
        self.tp_det += other.tp_det
        self.label_checked += other.label_checked
        self.label_correct += other.label_correct
        self.errors.extend(other.errors)
        self.found.extend(other.found)


def _to_robot(world: NDArray[np.float64], pose: tuple[float, float, float]) -> NDArray[np.float64]:
    x, y, th = pose
    c, s = math.cos(th), math.sin(th)
    w = np.asarray(world, float).reshape(-1, 2)
    dx, dy = w[:, 0] - x, w[:, 1] - y
    return np.column_stack([c * dx + s * dy, -s * dx + c * dy])


def _wrap(a: NDArray[np.float64], period: float = 2.0 * math.pi) -> NDArray[np.float64]:
    return (a + period / 2) % period - period / 2


def _point_tally(
    det_xy: NDArray[np.float64],
    true_xy: NDArray[np.float64],
    det_to_ann: NDArray[np.int64],
    det_counted: NDArray[np.bool_],
    ann_counted: NDArray[np.bool_],
    agree: NDArray[np.bool_] | None = None,
    checked: NDArray[np.bool_] | None = None,
) -> Tally:
    """A tally from a matching; ``agree`` (per detection) turns a match into a miss and a false
    positive where a label disagrees."""
    hit = det_to_ann >= 0
    if agree is not None:
        hit &= agree
    j = det_to_ann[hit]
    t = Tally(int(ann_counted.sum()), int(det_counted.sum()))
    t.tp = int(ann_counted[j].sum())
    matched = np.zeros(len(ann_counted), dtype=np.bool_)
    matched[j] = True
    dist = np.hypot(true_xy[:, 0], true_xy[:, 1])[ann_counted]
    t.found = list(zip(dist.tolist(), matched[ann_counted].tolist(), strict=True))
    t.tp_det = int(det_counted[hit].sum())
    if checked is not None:
        t.label_checked = int(checked[det_counted].sum())
        t.label_correct = int((checked & agree)[det_counted].sum()) if agree is not None else t.label_checked
    keep = hit & det_counted
    d, tr = det_xy[keep], true_xy[det_to_ann[keep]]
    if len(d):
        dt, dm = np.hypot(tr[:, 0], tr[:, 1]), np.hypot(d[:, 0], d[:, 1])
        b = np.abs(_wrap(np.arctan2(d[:, 1], d[:, 0]) - np.arctan2(tr[:, 1], tr[:, 0]))) * _DEG
        t.errors = list(zip(dt.tolist(), dm.tolist(), b.tolist(), strict=True))
    return t


def _thickness(along: NDArray[np.float64], across: NDArray[np.float64]) -> float:
    """The image thickness (px) of a line whose image direction is ``along`` and whose two edges
    are ``across`` apart: the part of ``across`` perpendicular to ``along``."""
    n = float(np.hypot(*along))
    if n < 1e-9:
        return float(np.hypot(*across))
    return abs(float(along[0] * across[1] - along[1] * across[0])) / n


def crossings_classifiable(
    ann: ImageAnnotations,
    scene: Scene,
    field_map: Field,
    pose: tuple[float, float, float],
    p: EvalParams,
    margin: float,
) -> NDArray[np.bool_]:
    """Whether each annotated crossing shows its type in the image (module docstring, Counting)."""
    a = ann.crossings
    out = np.ones(len(a), dtype=np.bool_)
    if not len(a) or p.crossing_arm <= 0.0:
        return out
    cam = ann.camera
    s = cam.spec
    ids = a[:, 3].astype(int)
    xyo = field_map.crossing_array[ids]
    kinds = field_map.crossing_kinds[ids]
    half_w = field_map.dims.line_width / 2
    # occluders: boxes of robots and posts with their distances from the robot
    boxes, dist = [], []
    for row in ann.robots:
        boxes.append(row[2:6])
        dist.append(float(np.hypot(*_to_robot(scene.occluders[int(row[6]), :2], pose)[0])))
    for row in ann.posts:
        boxes.append(row[2:6])
        dist.append(float(np.hypot(*_to_robot(field_map.post_array[int(row[7])], pose)[0])))
    box = np.asarray(boxes, dtype=float).reshape(-1, 4)
    box_d = np.asarray(dist, dtype=float)
    for c in range(len(a)):
        x, y, o = xyo[c]
        kind = int(kinds[c])
        junction = a[c, :2]
        if kind == 0:  # L: the arms are 45 degrees either side of the bisector
            arms = (o - math.pi / 4, o + math.pi / 4)
        elif kind == 1:  # T: the stem and the two halves of the bar
            arms = (o, o + math.pi / 2, o - math.pi / 2)
        else:
            arms = (o, o + math.pi / 2, o + math.pi, o - math.pi / 2)
        for arm in arms:
            ca, sa = math.cos(arm), math.sin(arm)
            ex, ey = x + p.crossing_arm * ca, y + p.crossing_arm * sa
            # the arm's end and the line's two edges there (across the arm)
            pts = np.array([[ex, ey], [ex - half_w * sa, ey + half_w * ca], [ex + half_w * sa, ey - half_w * ca]])
            rel = _to_robot(pts, pose)
            uv, front = cam.project(np.column_stack([rel, np.zeros(3)]))
            u, v = uv[0]
            if not (
                front.all() and margin <= u <= s.width - margin and margin <= v <= s.height - margin
                and _thickness(uv[0] - junction, uv[1] - uv[2]) >= p.line_min_width_px * s.width / BASE_WIDTH
                and float(np.hypot(*(uv[0] - junction))) >= p.crossing_arm_px * s.width / BASE_WIDTH
            ):  # fmt: skip
                out[c] = False
                break
            d = float(np.hypot(*rel[0]))
            hidden = (box[:, 0] <= u) & (u <= box[:, 2]) & (box[:, 1] <= v) & (v <= box[:, 3]) & (box_d < d)
            if hidden.any():
                out[c] = False
                break
    return out


def evaluate_frame(
    percepts: Percepts,
    ann: ImageAnnotations,
    scene: Scene,
    field_map: Field,
    params: EvalParams | None = None,
    robot: int = 0,
) -> dict[str, Tally]:
    """Tallies of every kind of :data:`KINDS` for one image of robot ``robot`` (module docstring).

    The robot must be on team 0 with its team frame equal to the world frame (its annotations'
    ids then index ``field_map`` directly), as in :func:`make_frames`.
    """
    p = params or EvalParams()
    cam = ann.camera
    width, height = cam.spec.width, cam.spec.height
    k = width / BASE_WIDTH
    o = scene.observers[robot]
    pose = (float(o[0]), float(o[1]), float(o[2]))
    margin = p.margin_px * k

    def inside(uv: NDArray[np.float64]) -> NDArray[np.bool_]:
        uv = uv.reshape(-1, 2)
        with np.errstate(invalid="ignore"):
            return (
                (uv[:, 0] >= margin)
                & (uv[:, 0] <= width - margin)
                & (uv[:, 1] >= margin)
                & (uv[:, 1] <= height - margin)
            )

    def near(xy: NDArray[np.float64], limit: float) -> NDArray[np.bool_]:
        with np.errstate(invalid="ignore"):
            return np.hypot(xy[:, 0], xy[:, 1]) <= limit

    out: dict[str, Tally] = {}
    rng = p.max_distance
    # posts
    t = percepts.posts
    uv, _ = percept_pixels(percepts, Kind.POST)
    a = ann.posts
    true = _to_robot(field_map.post_array[a[:, 7].astype(int)] if len(a) else np.zeros((0, 2)), pose)
    det_to_ann, _ = match_boxes(uv, a[:, :2], a[:, 2:6], p.post_px * k, 0.0)
    agree, checked = labels_agree(t.subtype, a[:, 6].astype(np.int64), det_to_ann, 0)
    out["post"] = _point_tally(
        t.xy, true, det_to_ann, near(t.xy, rng), inside(a[:, :2]) & near(true, rng), agree, checked
    )
    # crossings
    t = percepts.crossings
    uv, _ = percept_pixels(percepts, Kind.CROSS)
    a = ann.crossings
    true = _to_robot(field_map.crossing_array[a[:, 3].astype(int), :2] if len(a) else np.zeros((0, 2)), pose)
    det_to_ann, _ = match_points(uv, a[:, :2], p.crossing_px * k)
    agree, checked = labels_agree(t.subtype, a[:, 2].astype(np.int64), det_to_ann, None)
    counted_d, in_view = near(t.xy, rng), inside(a[:, :2]) & near(true, rng)
    counted_a = in_view & crossings_classifiable(ann, scene, field_map, pose, p, margin)
    out["crossing"] = _point_tally(t.xy, true, det_to_ann, counted_d, counted_a, agree, checked)
    any_kind = _point_tally(t.xy, true, det_to_ann, counted_d, counted_a)
    any_kind.label_checked, any_kind.label_correct = out["crossing"].label_checked, out["crossing"].label_correct
    out["crossing_any"] = any_kind
    seen = _point_tally(t.xy, true, det_to_ann, counted_d, in_view, agree, checked)
    out["crossing_seen"] = seen
    out["line"] = _line_tally(percepts, ann, field_map, pose, p, k)
    out["circle"] = _circle_tally(percepts, ann, field_map, pose, p)
    # marks
    t = percepts.penalty_marks
    uv, _ = percept_pixels(percepts, Kind.MARK)
    a = ann.marks
    marks = np.array([(m.x, m.y) for m in field_map.penalty_marks], dtype=float).reshape(-1, 2)
    true = _to_robot(marks[a[:, 2].astype(int)] if len(a) else np.zeros((0, 2)), pose)
    det_to_ann, _ = match_points(uv, a[:, :2], p.mark_px * k)
    out["mark"] = _point_tally(t.xy, true, det_to_ann, near(t.xy, rng), inside(a[:, :2]) & near(true, rng))
    # ball
    t = percepts.ball
    uv, _ = percept_pixels(percepts, Kind.BALL)
    a = ann.ball
    true = _to_robot(np.repeat(scene.ball[None, :2], len(a), axis=0), pose)
    det_to_ann, _ = match_points(uv, a[:, :2], np.maximum(p.ball_px * k, a[:, 2]))
    lim = p.ball_distance
    out["ball"] = _point_tally(t.xy, true, det_to_ann, near(t.xy, lim), inside(a[:, :2]) & near(true, lim))
    # robots
    t = percepts.robots
    uv, _ = percept_pixels(percepts, Kind.ROBOT)
    a = ann.robots
    index = a[:, 6].astype(int)
    true = _to_robot(scene.occluders[index, :2] if len(a) else np.zeros((0, 2)), pose)
    team = np.where(index // scene.players_per_team == int(o[11]), int(RobotTeam.OWN), int(RobotTeam.OPPONENT))
    det_to_ann, _ = match_boxes(uv, a[:, :2], a[:, 2:6], -1.0, p.robot_px * k)
    agree, checked = labels_agree(t.subtype, team, det_to_ann, int(RobotTeam.UNKNOWN))
    tally = _point_tally(t.xy, true, det_to_ann, near(t.xy, rng), inside(a[:, :2]) & near(true, rng))
    tally.label_checked = int(checked[near(t.xy, rng)].sum())
    tally.label_correct = int((checked & agree)[near(t.xy, rng)].sum())
    out["robot"] = tally
    return out


def _line_tally(
    percepts: Percepts,
    ann: ImageAnnotations,
    field_map: Field,
    pose: tuple[float, float, float],
    p: EvalParams,
    k: float,
) -> Tally:
    t = percepts.lines
    uv, uv2 = percept_pixels(percepts, Kind.LINE)
    det = np.column_stack([uv, uv2])
    a = ann.lines
    line, covered = match_lines(det, a[:, :4], p.line_px * k, a[:, 4].astype(np.int64))
    cam = ann.camera
    # the part of each annotated piece within range: samples projected on the ground
    samples = line_samples(a[:, :4], LINE_SAMPLES).reshape(-1, 2)
    ground, ok = cam.pixel_to_ground(samples) if len(samples) else (np.zeros((0, 2)), np.zeros(0, bool))
    with np.errstate(invalid="ignore"):
        in_range = (ok & (np.hypot(ground[:, 0], ground[:, 1]) <= p.max_distance)).reshape(len(a), LINE_SAMPLES)
    length = np.hypot(a[:, 2] - a[:, 0], a[:, 3] - a[:, 1])
    n_in = in_range.sum(axis=1)
    counted = length * n_in / LINE_SAMPLES >= p.line_min_px * k
    found = (covered & in_range).sum(axis=1) >= p.line_cover * np.maximum(n_in, 1)
    with np.errstate(invalid="ignore"):
        det_counted = (np.hypot(t.x, t.y) <= p.max_distance) & (np.hypot(t.xy2[:, 0], t.xy2[:, 1]) <= p.max_distance)
    tally = Tally(int(counted.sum()), int(det_counted.sum()), int((counted & found).sum()))
    hit = (line >= 0) & det_counted
    tally.tp_det = int(hit.sum())
    if hit.any():
        la = field_map.line_array[line[hit]]
        e1, e2 = _to_robot(la[:, :2], pose), _to_robot(la[:, 2:], pose)
        dt, at = _line_distance(e1, e2)
        dm, am = _line_distance(t.xy[hit], t.xy2[hit])
        err = np.abs(_wrap(am - at, math.pi)) * _DEG
        tally.errors = list(zip(dt.tolist(), dm.tolist(), err.tolist(), strict=True))
    return tally


def _line_distance(p1: NDArray[np.float64], p2: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(perpendicular distance from the origin, direction) of the lines through p1 and p2."""
    d = p2 - p1
    length = np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-12)
    return np.abs(p1[:, 0] * d[:, 1] - p1[:, 1] * d[:, 0]) / length, np.arctan2(d[:, 1], d[:, 0])


def _circle_tally(
    percepts: Percepts, ann: ImageAnnotations, field_map: Field, pose: tuple[float, float, float], p: EvalParams
) -> Tally:
    t = percepts.circle
    c = field_map.centre_circle
    if c is None:
        return Tally(0, len(t))
    true = _to_robot(np.array([[c.x, c.y]]), pose)
    counted_a = np.array(
        [len(ann.circle) >= p.circle_visible * _CIRCLE_POINTS and np.hypot(*true[0]) <= p.max_distance]
    )
    err = np.hypot(t.x - true[0, 0], t.y - true[0, 1])
    det_to_ann, _ = greedy_match(np.where(err <= p.circle_m, err, np.inf)[:, None])
    with np.errstate(invalid="ignore"):
        counted_d = np.hypot(t.x, t.y) <= p.max_distance
    return _point_tally(t.xy, true, det_to_ann, counted_d, counted_a)
