"""The vision pipeline: one camera image and its camera matrix in, :class:`Percepts` out.

The stages follow DNT's basic pipeline (section 3.2) with the detectors of both vision
papers, one module per stage:

==================  ===============================================  ==========================
stage               module                                           paper
==================  ===============================================  ==========================
image input         :mod:`.image` (RGB or YUV422, checks)            DNT 3.3
colour classes      :mod:`.colour` (HSV, calibrated, lookup table)   DNT 3.1, 3.5, Table 1
field boundary      :mod:`.boundary`                                 DNT 3.4
line points         :mod:`.scanlines` (method ``dnt``)               DNT 3.6.2
                    :mod:`.hough` (method ``hough``)                 NimbRo 5.1
centre circle       :mod:`.circle` (voting at the radius)            NimbRo 5.2, de Jong et al.
line segments       :mod:`.segments` (chaining, merging)             DNT 3.6.2, Algorithm 1
                    :mod:`.hough` (oriented Hough transform)         NimbRo 5.2
crossings L/T/X     :mod:`.crossings`                                DNT 3.7
goal posts          :mod:`.posts`                                    DNT 3.8
ball, robots        :mod:`.ball`, :mod:`.robots`                     NimbRo 6.1 (colour blobs)
penalty marks       :mod:`.marks`
ground projection   :mod:`.projection` (Darmstadt covariance)        DNT 3.10, Darmstadt IV.B
bird's-eye view     :mod:`.birdseye` (debug image)                   DNT 3.10
==================  ===============================================  ==========================

The result is the same :class:`~cognition.percepts.Percepts` the simulator synthesizes:
robot-frame positions (m), pixels, covariances from the Darmstadt noise model with the same
defaults, and ``truth`` -1 (vision does not know which landmark it saw). Everything after
the percepts (localization, world model, behaviors) runs unchanged on either source.

``Vision`` keeps state only for the colour calibration (a cache of lookup tables and the
latest carpet colour); one instance per camera stream.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.camera import CameraMatrix
from cognition.field import FIELD_PRESETS, ColourScheme, Field, make_colour_scheme
from cognition.percepts import N_COLS, N_KINDS, Kind, Percepts
from cognition.vision.ball import detect_ball
from cognition.vision.boundary import field_boundary
from cognition.vision.colour import ColourClassifier
from cognition.vision.crossings import crossings_nb, look_nb
from cognition.vision.dnt import dnt_lines_nb, ground_points_nb
from cognition.vision.goals import clear_of_posts_nb, cut_behind_nb, goal_lines_nb, not_under_posts_nb
from cognition.vision.hough import hough_lines
from cognition.vision.image import VisionError, as_rgb, check_camera
from cognition.vision.marks import loose_points_nb, marks_nb
from cognition.vision.params import VisionParams
from cognition.vision.posts import detect_posts
from cognition.vision.projection import sigmas
from cognition.vision.robots import detect_robots
from cognition.vision.rows import crossing_rows_nb, line_rows_nb, point_rows_nb
from cognition.vision.scanlines import line_points_nb


@dataclass(frozen=True, eq=False)
class VisionDebug:
    """Intermediate results of the latest :meth:`Vision.detect` (for drawing and tests)."""

    classes: NDArray[np.uint8]
    """Class image (H x W, :class:`~cognition.vision.colour.Colour` codes)."""
    boundary: NDArray[np.int32]
    """First field row per column."""
    points: NDArray[np.float64]
    """Line points (K x 4: u, v, run, direction) of the ``dnt`` method."""
    segments_px: NDArray[np.float64]
    """Line segments in the image (S x 4: u1, v1, u2, v2)."""
    segments_ground: NDArray[np.float64]
    """The same on the ground (S x 4, robot frame, m)."""


class Vision:
    """Detects percepts in camera images (module docstring).

    ``field`` gives the sizes vision expects (line width, circle radius, mark, post and ball
    sizes; default: the 2025 SPL field) and ``scheme`` the colours of goals, ball and jerseys
    (a :class:`ColourScheme` or its name); ``team`` is the own team's jersey index in the
    scheme (0 or 1) for the robots' team guess.
    """

    def __init__(
        self,
        params: VisionParams | None = None,
        field: Field | None = None,
        scheme: ColourScheme | str = "modern",
        team: int = 0,
    ):
        self.params = params or VisionParams()
        if not isinstance(self.params, VisionParams):
            raise TypeError(f"params must be VisionParams, got {type(self.params).__name__}")
        self.field = field or Field(FIELD_PRESETS["spl2025"], "spl2025")
        self.scheme = make_colour_scheme(scheme) if isinstance(scheme, str) else scheme
        if team not in (0, 1):
            raise ValueError(f"team must be 0 or 1 (the jersey index in the colour scheme), got {team!r}")
        self.team = team
        self.classifier = ColourClassifier(self.params.colours)
        self.debug: VisionDebug | None = None
        """Intermediate results of the latest image."""
        p = self.params
        self._goal_classes = (
            self.classifier.class_of(self.scheme.own_goal),
            self.classifier.class_of(self.scheme.opponent_goal),
        )
        """Colour classes of the scheme's two goals (own_goal, opponent_goal)."""
        self._jersey_classes = tuple(self.classifier.class_of(c) for c in self.scheme.team_colours)
        """Colour classes of the two teams' jerseys."""
        self._net_class = self.classifier.class_of(self.scheme.line_white)
        """Colour class of the goal nets (white, as the lines)."""
        self._modern_ball = self.scheme.ball_primary != self.scheme.ball_secondary
        """The ball has patches (the white-and-black SPL ball) rather than one colour."""
        self._circle = np.array(
            [p.circle_cell, p.circle_directions, p.circle_inlier, p.circle_min_points, p.circle_min_span,
             p.circle_min_coverage],
            dtype=np.float64,
        )  # fmt: skip

    def detect(
        self,
        image: NDArray[np.uint8],
        camera: CameraMatrix,
        time: float = 0.0,
        head_yaw_rate: float = 0.0,
        head_pitch_rate: float = 0.0,
        walking: bool = False,
        own_goal: int = 0,
    ) -> Percepts:
        """Percepts of one image (RGB H x W x 3 or YUV422 H x W x 2, uint8) taken with ``camera``.

        ``time`` is the exposure time (s); the head rates (rad/s) and ``walking`` set the
        reported sigmas (Darmstadt eqs. 3-6). ``own_goal`` says which goal colour of the scheme
        the robot defends (0: ``own_goal``, 1: ``opponent_goal``; it changes with the team and
        the half), so that posts of goals with different colours are told apart.
        """
        if own_goal not in (0, 1):
            raise VisionError(f"own_goal must be 0 or 1 (a goal colour of the scheme), got {own_goal!r}")
        cam = check_camera(camera)
        rgb = as_rgb(image, camera)
        p = self.params
        height, width = rgb.shape[:2]
        scale = width / 320.0
        classes = self.classifier.classify(rgb, cam)
        boundary = field_boundary(classes, cam, max(1, round(p.boundary_run * height / 240.0)))
        dims = self.field.dims
        radius = self.field.centre_circle.radius if self.field.centre_circle is not None else 0.0
        step, gap = max(1, round(p.scan_step * scale)), max(1, round(p.edge_gap * scale))
        # motion blur (px) while the shutter is open: the image moves with the head (Darmstadt IV.B)
        blur_u = abs(head_yaw_rate) * cam[12] * p.exposure
        blur_v = abs(head_pitch_rate) * cam[13] * p.exposure + (p.walking_blur * scale if walking else 0.0)
        if p.method == "dnt":
            points, seg_px, seg_ground, open_ends, cx, cy, loose = dnt_lines_nb(
                classes, boundary, cam, step, dims.line_width, gap, p.max_distance, radius, self._circle,
                np.array([p.chain_gap * scale, p.chain_tolerance * scale, p.min_white, p.min_points, p.merge_angle]),
                p.min_line_length, max(4, round(12 * scale)), blur_u, blur_v,
            )  # fmt: skip
        else:
            lines = hough_lines(classes, boundary, cam, dims.line_width, radius, p.hough)
            seg_px, seg_ground, open_ends = lines.seg_px, lines.seg_ground, lines.open_ends
            cx, cy = lines.circle
            # penalty-mark seeds: scanline points that lie on no line and not on the circle
            points = line_points_nb(classes, boundary, cam, step, dims.line_width, gap, blur_u, blur_v)
            loose = loose_points_nb(points, seg_px, cam, cx, cy, radius, p.circle_inlier, 3.0 * scale)
        sa, sb = sigmas(
            p.sigma_alpha_base, p.sigma_beta_base, p.c_tilt, p.c_pan, p.sigma_alpha_moving, p.sigma_beta_moving,
            head_pitch_rate, head_yaw_rate, walking,
        )  # fmt: skip
        goals = self._goal_classes if own_goal == 0 else self._goal_classes[::-1]
        posts = detect_posts(classes, boundary, cam, goals, dims.goal_post_diameter, dims.goal_height, p.posts, sa, sb)
        if len(posts):  # nothing behind a seen goal line is a field line
            goal_lines = goal_lines_nb(posts, seg_ground, dims.goal_inner_width + dims.goal_post_diameter)
            seg_px, seg_ground, open_ends = cut_behind_nb(
                seg_px, seg_ground, open_ends, goal_lines, cam, p.goal_behind, p.min_line_length
            )
        cross = crossings_nb(
            seg_ground, open_ends, classes, boundary, cam, p.crossing_margin, p.crossing_margin_in, p.crossing_beyond,
            p.crossing_angle, p.crossing_min_arm, 0.3, p.merge_angle, p.merge_offset, p.merge_gap, p.crossing_max_mpp,
        )  # fmt: skip
        if len(cross):
            cross = cross[np.hypot(cross[:, 0], cross[:, 1]) <= p.crossing_max_distance * math.sqrt(scale)]
        if len(posts):
            cross = clear_of_posts_nb(cross, posts, p.post_clearance)
        if len(cross):  # and where a post is seen standing on it, though its base is not
            cross = not_under_posts_nb(
                cross, classes, cam, goals[0], goals[1], self._net_class, dims.goal_post_diameter / 2, dims.goal_height
            )
        if math.isfinite(cx):
            cross = _circle_crossings_nb(cross, cx, cy, radius, seg_ground, cam, p.max_distance, classes, boundary)
        marks = marks_nb(
            classes, points, loose, cam, dims.penalty_mark_size, p.mark_tolerance, p.mark_min_green,
            max(1, round(p.mark_min_px * scale)),
        )  # fmt: skip
        self.debug = VisionDebug(classes, boundary, points, seg_px, seg_ground)
        tables: list[NDArray[np.float64]] = [_EMPTY] * N_KINDS
        tables[Kind.POST] = posts
        tables[Kind.CROSS] = crossing_rows_nb(cross, cam, sa, sb)
        tables[Kind.BALL] = detect_ball(
            rgb, classes, boundary, cam, dims.ball_diameter / 2, self._modern_ball, p.ball, sa, sb
        )
        tables[Kind.ROBOT] = detect_robots(
            classes, boundary, cam, self._jersey_classes, self.team, p.robot_radius, p.obstacles, sa, sb
        )
        tables[Kind.LINE] = line_rows_nb(seg_px, seg_ground, cam, sa, sb)
        if math.isfinite(cx):
            tables[Kind.CIRCLE] = point_rows_nb(np.array([[cx, cy]]), _no_pixels(1), 0.0, cam, sa, sb)
        if len(marks):
            xy, ok = ground_points_nb(cam, marks, p.mark_max_distance)
            tables[Kind.MARK] = point_rows_nb(xy[ok], np.ascontiguousarray(marks[ok, :2]), 0.0, cam, sa, sb)
        rows = np.concatenate(tables)
        offsets = np.zeros(N_KINDS + 1, dtype=np.int64)
        offsets[1:] = np.cumsum([len(t) for t in tables])
        return Percepts(time, rows, offsets, cam, camera.spec)


_EMPTY = np.zeros((0, N_COLS))


def _no_pixels(n: int) -> NDArray[np.float64]:
    """NaN pixels: the row builders project the ground points."""
    return np.full((n, 2), np.nan)


@nb.njit(cache=True)
def _circle_crossings_nb(
    cross: NDArray[np.float64],
    cx: float,
    cy: float,
    radius: float,
    seg_ground: NDArray[np.float64],
    cam: NDArray[np.float64],
    max_distance: float,
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """``cross`` (C x 6) plus the X crossings where a line through the circle's centre (the
    halfway line) meets the circle; the circle's X replaces whatever the segments made there."""
    extra = np.empty((2, 6))
    n_extra = 0
    for k in range(seg_ground.shape[0]):
        x1, y1, x2, y2 = seg_ground[k, 0], seg_ground[k, 1], seg_ground[k, 2], seg_ground[k, 3]
        length = math.hypot(x2 - x1, y2 - y1)
        if length < 0.3:
            continue
        dx, dy = (x2 - x1) / length, (y2 - y1) / length
        if abs((cx - x1) * dy - (cy - y1) * dx) > 0.15:
            continue
        for s in (-1.0, 1.0):
            px, py = cx + s * radius * dx, cy + s * radius * dy
            # it must be in view and on white (a robot may stand on it)
            if look_nb(classes, boundary, cam, px, py) == 1 and math.hypot(px, py) <= max_distance:
                extra[n_extra, 0] = px
                extra[n_extra, 1] = py
                extra[n_extra, 2] = 2.0
                extra[n_extra, 3] = math.atan2(dy, dx) % (0.5 * math.pi)
                extra[n_extra, 4] = 1.0
                extra[n_extra, 5] = 0.0
                n_extra += 1
        break
    if n_extra == 0:
        return cross
    keep = np.ones(cross.shape[0], dtype=np.bool_)
    for k in range(cross.shape[0]):
        for e in range(n_extra):
            if math.hypot(cross[k, 0] - extra[e, 0], cross[k, 1] - extra[e, 1]) <= 0.3:
                keep[k] = False
    return np.concatenate((cross[keep], extra[:n_extra]))
