"""Matching vision percepts to ground-truth image annotations, kind by kind (``teamsim vision-eval``).

:func:`evaluate_frame` compares the :class:`~cognition.percepts.Percepts` that vision reported
for one image with the renderer's :class:`~teamsim.images.ImageAnnotations` of the same image
and returns a :class:`Tally` per kind (counts, label checks, position errors);
:func:`summarize` turns summed tallies into precision, recall and error statistics and
:func:`check_bars` checks them against the vision issue's bars. The building blocks
(:func:`greedy_match`, :func:`match_points`, :func:`match_boxes`, :func:`match_lines`,
:func:`labels_agree`) work on plain arrays, for tests and for other evaluations. The frames,
the run and the command are in :mod:`scenarios.vision_eval`.

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

import itertools
import math
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from cognition.field import Field
from cognition.params import PROBABILITY, Range, Ranges, check_ranges, non_negative, positive
from cognition.percepts import Kind, Percepts, RobotTeam
from cognition.vision.draw import percept_pixels
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
_LINE_SAMPLES = 32
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


# -- matching ------------------------------------------------------------------------------


def greedy_match(cost: NDArray[np.float64]) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """One-to-one pairs of detections (rows) and annotations (columns) by increasing ``cost``;
    an infinite or NaN cost forbids the pair. Returns (annotation of each detection, detection
    of each annotation), -1 where unmatched."""
    c = np.asarray(cost, dtype=np.float64)
    n, m = c.shape
    det = np.full(n, -1, dtype=np.int64)
    ann = np.full(m, -1, dtype=np.int64)
    if n == 0 or m == 0:
        return det, ann
    flat = np.where(np.isfinite(c), c, np.inf).ravel()
    order = np.argsort(flat, kind="stable")
    for f in order[: int(np.isfinite(flat).sum())]:
        i, j = divmod(int(f), m)
        if det[i] < 0 and ann[j] < 0:
            det[i], ann[j] = j, i
    return det, ann


def _distances(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """Pixel distances (n x m) between points a (n x 2) and b (m x 2); NaN where undefined."""
    return np.hypot(a[:, None, 0] - b[None, :, 0], a[:, None, 1] - b[None, :, 1])


def match_points(
    det_uv: NDArray[np.float64], ann_uv: NDArray[np.float64], tolerance: float | NDArray[np.float64]
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Greedy matching of pixels within ``tolerance`` (px; a scalar or one per annotation)."""
    d = _distances(np.asarray(det_uv, float).reshape(-1, 2), np.asarray(ann_uv, float).reshape(-1, 2))
    tol = np.broadcast_to(np.asarray(tolerance, dtype=float), d.shape[1:])
    with np.errstate(invalid="ignore"):
        return greedy_match(np.where(d <= tol[None, :], d, np.inf))


def match_boxes(
    det_uv: NDArray[np.float64], ann_uv: NDArray[np.float64], boxes: NDArray[np.float64], tolerance: float, widen: float
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Greedy matching by pixel distance to ``ann_uv``, allowed within ``tolerance`` of it or inside
    the annotation's box (u0, v0, u1, v1) widened by ``widen`` px on every side."""
    p = np.asarray(det_uv, float).reshape(-1, 2)
    b = np.asarray(boxes, float).reshape(-1, 4)
    d = _distances(p, np.asarray(ann_uv, float).reshape(-1, 2))
    with np.errstate(invalid="ignore"):
        inside = (
            (p[:, None, 0] >= b[None, :, 0] - widen) & (p[:, None, 0] <= b[None, :, 2] + widen)
            & (p[:, None, 1] >= b[None, :, 1] - widen) & (p[:, None, 1] <= b[None, :, 3] + widen)
        )  # fmt: skip
        return greedy_match(np.where((d <= tolerance) | inside, np.nan_to_num(d, nan=1e9), np.inf))


def labels_agree(
    det_label: NDArray[np.int64], ann_label: NDArray[np.int64], det_to_ann: NDArray[np.int64], unknown: int | None
) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """(agree, checked) per detection: ``checked`` where the detection is matched and both labels
    are known (not ``unknown``); ``agree`` is True unless checked and different."""
    matched = det_to_ann >= 0
    a = np.where(matched, np.asarray(ann_label)[np.maximum(det_to_ann, 0)] if len(ann_label) else -1, -1)
    d = np.asarray(det_label)
    checked = matched & ((d != unknown) & (a != unknown) if unknown is not None else matched)
    return ~checked | (d == a), checked


def _segment_distance(p: NDArray[np.float64], seg: NDArray[np.float64]) -> NDArray[np.float64]:
    """Distances (n x m) from points p (n x 2) to segments seg (m x 4: u1, v1, u2, v2)."""
    a, ab = seg[None, :, :2], seg[None, :, 2:] - seg[None, :, :2]
    rel = p[:, None, :] - a
    t = np.clip((rel * ab).sum(-1) / np.maximum((ab * ab).sum(-1), 1e-12), 0.0, 1.0)
    return np.linalg.norm(rel - t[..., None] * ab, axis=-1)


def _carrier_distance(p: NDArray[np.float64], seg: NDArray[np.float64], tolerance: float) -> NDArray[np.float64]:
    """Distances (n x m) from points p (n x 2) to the carrier lines of segments seg (m x 4),
    infinite where a point lies farther than max(3 tolerance, 20 % of the segment) beyond its
    ends along it."""
    a, ab = seg[None, :, :2], seg[None, :, 2:] - seg[None, :, :2]
    length = np.maximum(np.linalg.norm(ab, axis=-1), 1e-9)
    rel = p[:, None, :] - a
    along = (rel * ab).sum(-1) / length
    across = np.abs(rel[..., 0] * ab[..., 1] - rel[..., 1] * ab[..., 0]) / length
    slack = np.maximum(3.0 * tolerance, 0.2 * length)
    return np.where((along >= -slack) & (along <= length + slack), across, np.inf)


def match_lines(
    det_seg: NDArray[np.float64],
    ann_seg: NDArray[np.float64],
    tolerance: float,
    ann_ids: NDArray[np.int64] | None = None,
    samples: int = _LINE_SAMPLES,
) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
    """(line id of each detected segment, or -1; covered samples per annotated piece).

    Pieces with the same id (``ann_ids``, default: each piece its own id) are pieces of one
    straight line (split where robots hide it). A detected segment (u1, v1, u2, v2) lies on
    the line whose pieces are nearest to both its ends when both are within ``tolerance`` px of
    their carrier lines, no farther than max(3 ``tolerance``, 20 % of the piece) beyond the
    piece (a segment bridging a robot in front of a line is on that line; one running into the
    width of a line it meets at a crossing too). Each annotated
    piece is sampled at ``samples`` points; a sample is covered when it is within
    ``tolerance`` of a detected segment.
    """
    det = np.asarray(det_seg, float).reshape(-1, 4)
    ann = np.asarray(ann_seg, float).reshape(-1, 4)
    ids = np.arange(len(ann)) if ann_ids is None else np.asarray(ann_ids, dtype=np.int64)
    line = np.full(len(det), -1, dtype=np.int64)
    covered = np.zeros((len(ann), samples), dtype=np.bool_)
    if len(det) == 0 or len(ann) == 0:
        return line, covered
    names = np.unique(ids)
    same = ids[None, :] == names[:, None]  # (lines x pieces)
    ends = []
    for end in (det[:, :2], det[:, 2:]):
        d = np.nan_to_num(_carrier_distance(end, ann, tolerance), nan=np.inf)
        ends.append(np.where(same[None], d[:, None, :], np.inf).min(axis=2))  # (det x lines)
    worst = np.maximum(*ends)
    best = np.argmin(worst, axis=1)
    ok = worst[np.arange(len(det)), best] <= tolerance
    line[ok] = names[best[ok]]
    pts = _line_samples(ann, samples).reshape(-1, 2)
    with np.errstate(invalid="ignore"):
        covered = (_segment_distance(pts, det) <= tolerance).any(axis=1).reshape(len(ann), samples)
    return line, covered


def _line_samples(seg: NDArray[np.float64], samples: int) -> NDArray[np.float64]:
    """``samples`` points (m x samples x 2) evenly inside each segment (cell centres)."""
    t = (np.arange(samples) + 0.5) / samples
    return seg[:, None, :2] + t[None, :, None] * (seg[:, None, 2:] - seg[:, None, :2])


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
    samples = _line_samples(a[:, :4], _LINE_SAMPLES).reshape(-1, 2)
    ground, ok = cam.pixel_to_ground(samples) if len(samples) else (np.zeros((0, 2)), np.zeros(0, bool))
    with np.errstate(invalid="ignore"):
        in_range = (ok & (np.hypot(ground[:, 0], ground[:, 1]) <= p.max_distance)).reshape(len(a), _LINE_SAMPLES)
    length = np.hypot(a[:, 2] - a[:, 0], a[:, 3] - a[:, 1])
    n_in = in_range.sum(axis=1)
    counted = length * n_in / _LINE_SAMPLES >= p.line_min_px * k
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


# -- summary -------------------------------------------------------------------------------


def summarize(tally: Tally) -> dict[str, float | int | None]:
    """The figures of one kind: counts, precision, recall, error medians and 90th percentiles
    (None where there is nothing to compute them from)."""
    e = np.asarray(tally.errors, dtype=float).reshape(-1, 3)
    dist = np.abs(e[:, 1] - e[:, 0])
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = dist / e[:, 0]
    rel = rel[np.isfinite(rel)]

    def q(a: NDArray[np.float64], level: float) -> float | None:
        return float(np.quantile(a, level)) if len(a) else None

    return {
        "annotations": tally.annotations,
        "detections": tally.detections,
        "tp": tally.tp,
        "fp": tally.fp,
        "fn": tally.fn,
        "precision": tally.tp_det / tally.detections if tally.detections else None,
        "recall": tally.tp / tally.annotations if tally.annotations else None,
        "matched": len(e),
        "distance_error_median_m": q(dist, 0.5),
        "distance_error_p90_m": q(dist, 0.9),
        "relative_distance_error_median": q(rel, 0.5),
        "relative_distance_error_p90": q(rel, 0.9),
        "bearing_error_median_deg": q(e[:, 2], 0.5),
        "bearing_error_p90_deg": q(e[:, 2], 0.9),
        "label_accuracy": tally.label_correct / tally.label_checked if tally.label_checked else None,
        "label_checked": tally.label_checked,
        "recall_by_distance": _recall_bins(tally.found),
    }


DISTANCE_BINS = (0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0)
"""Bin edges (m) of ``recall_by_distance`` in metrics.json."""


def _recall_bins(found: list[tuple[float, bool]]) -> list[dict[str, Any]]:
    """Recall per true-distance bin of :data:`DISTANCE_BINS` (point kinds; empty for lines)."""
    f = np.asarray(found, dtype=float).reshape(-1, 2)
    out = []
    for lo, hi in itertools.pairwise(DISTANCE_BINS):
        sel = (f[:, 0] >= lo) & (f[:, 0] < hi)
        n = int(sel.sum())
        out.append({"from_m": lo, "to_m": hi, "annotations": n, "recall": float(f[sel, 1].mean()) if n else None})
    return out if len(f) else []


BARS: tuple[tuple[str, str, str, float], ...] = (
    ("crossing", "precision", ">=", 0.95),
    ("crossing", "recall", ">=", 0.80),
    ("post", "precision", ">=", 0.97),
    ("post", "recall", ">=", 0.97),
    ("post", "label_accuracy", ">=", 0.97),
    ("ball", "precision", ">=", 0.95),
    ("ball", "recall", ">=", 0.95),
    ("circle", "recall", ">=", 0.70),
    *((k, "relative_distance_error_median", "<", 0.05) for k in ("post", "crossing", "circle", "mark", "ball")),
)
"""(kind, figure, comparison, bound) of the vision issue (module docstring)."""


def check_bars(kinds: dict[str, dict[str, Any]]) -> list[dict[str, Any]]:
    """Each bar with the measured value and whether it holds (a missing value does not)."""
    out = []
    for kind, name, op, bound in BARS:
        value = kinds[kind][name]
        ok = value is not None and (value >= bound if op == ">=" else value < bound)
        out.append({"kind": kind, "figure": name, "op": op, "bound": bound, "value": value, "ok": bool(ok)})
    return out


def format_table(kinds: dict[str, dict[str, Any]]) -> str:
    """The table of one method (one row per kind of :data:`KINDS`)."""

    def f(v: Any, spec: str, scale: float = 1.0) -> str:
        return format(v * scale, spec) if v is not None else "-".rjust(int(spec.split(".")[0]))

    head = (
        f"{'kind':13s}{'ann':>6s}{'det':>6s}{'TP':>6s}{'FP':>5s}{'FN':>5s}{'prec':>7s}{'recall':>7s}"
        f"{'dist med':>9s}{'p90':>6s}{'rel med':>8s}{'p90':>6s}{'brg med':>8s}{'p90':>6s}  label"
    )
    lines = [head, "-" * len(head)]
    for name in KINDS:
        s = kinds[name]
        label = "-"
        if s["label_accuracy"] is not None:
            label = f"{LABELS.get(name, 'label')} {s['label_accuracy']:.3f} ({s['label_checked']})"
        lines.append(
            f"{name:13s}{s['annotations']:6d}{s['detections']:6d}{s['tp']:6d}{s['fp']:5d}{s['fn']:5d}"
            f"{f(s['precision'], '7.3f')}{f(s['recall'], '7.3f')}"
            f"{f(s['distance_error_median_m'], '9.3f')}{f(s['distance_error_p90_m'], '6.2f')}"
            f"{f(s['relative_distance_error_median'], '8.3f')}{f(s['relative_distance_error_p90'], '6.3f')}"
            f"{f(s['bearing_error_median_deg'], '8.2f')}{f(s['bearing_error_p90_deg'], '6.2f')}  {label}"
        )
    lines.append(
        "dist: |measured - true distance| (m), rel: the same / true distance, brg: bearing error (deg), median and "
        "90th percentile; lines: distance to the line and direction error"
    )
    return "\n".join(lines)


def format_recall_by_distance(kinds: dict[str, dict[str, Any]]) -> str:
    """Recall per true-distance bin (:data:`DISTANCE_BINS`) of the kinds with annotations."""
    edges = DISTANCE_BINS
    head = "recall by true distance (m): " + " ".join(f"{a:g}-{b:g}".rjust(7) for a, b in itertools.pairwise(edges))
    lines = [head]
    for name in KINDS:
        bins = kinds[name]["recall_by_distance"]
        if name == "crossing_any" or not bins:
            continue
        cells = [("-" if b["recall"] is None else f"{b['recall']:.2f}").rjust(7) for b in bins]
        lines.append(f"  {name:27s}" + " ".join(cells))
    return "\n".join(lines)
