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

import numpy as np
from numpy.typing import NDArray

from cognition.camera import CameraMatrix
from cognition.field import FIELD_PRESETS, ColourScheme, Field, make_colour_scheme
from cognition.percepts import Percepts
from cognition.vision import assemble as asm
from cognition.vision.ball import ball_rows
from cognition.vision.boundary import field_boundary
from cognition.vision.colour import ColourClassifier
from cognition.vision.dnt import dnt_lines_nb
from cognition.vision.hough import hough_lines
from cognition.vision.image import VisionError, as_rgb, check_camera
from cognition.vision.marks import loose_points_nb
from cognition.vision.params import VisionParams
from cognition.vision.posts import post_rows
from cognition.vision.projection import sigmas
from cognition.vision.robots import robot_rows
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
        self._sizes: dict[int, tuple[int, int, NDArray[np.float64], int, float, NDArray[np.float64]]] = {}
        """Per image width: the parameters scaled to it (:meth:`_size_params`)."""
        self._modern_ball = self.scheme.ball_primary != self.scheme.ball_secondary
        """The ball has patches (the white-and-black SPL ball) rather than one colour."""
        self._circle = np.array(
            [p.circle_cell, p.circle_directions, p.circle_inlier, p.circle_min_points, p.circle_min_span,
             p.circle_min_coverage, p.circle_vote_every],
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
        size = self._sizes.get(width)
        if size is None:
            size = self._sizes[width] = self._size_params(width)
        step, gap, chain, probe, run, prm = size
        classes = self.classifier.classify(rgb, cam)
        boundary = field_boundary(classes, cam, max(1, round(run * height / 240.0)))
        dims = self.field.dims
        radius = prm[asm.A_CIRCLE_RADIUS]
        # motion blur (px) while the shutter is open: the image moves with the head (Darmstadt IV.B)
        blur_u = abs(head_yaw_rate) * cam[12] * p.exposure
        blur_v = abs(head_pitch_rate) * cam[13] * p.exposure + (p.walking_blur * width / 320.0 if walking else 0.0)
        if p.method == "dnt":
            points, seg_px, seg_ground, open_ends, cx, cy, loose = dnt_lines_nb(
                classes, boundary, cam, step, dims.line_width, gap, p.max_distance, radius, self._circle, chain,
                p.min_line_length, probe, blur_u, blur_v,
            )  # fmt: skip
        else:
            lines = hough_lines(classes, boundary, cam, dims.line_width, radius, p.hough)
            seg_px, seg_ground, open_ends = lines.seg_px, lines.seg_ground, lines.open_ends
            cx, cy = lines.circle
            # penalty-mark seeds: scanline points that lie on no line and not on the circle
            points = line_points_nb(classes, boundary, cam, step, dims.line_width, gap, blur_u, blur_v)
            loose = loose_points_nb(points, seg_px, cam, cx, cy, radius, p.circle_inlier, 3.0 * width / 320.0)
        sa, sb = sigmas(
            p.sigma_alpha_base, p.sigma_beta_base, p.c_tilt, p.c_pan, p.sigma_alpha_moving, p.sigma_beta_moving,
            head_pitch_rate, head_yaw_rate, walking,
        )  # fmt: skip
        goals = self._goal_classes if own_goal == 0 else self._goal_classes[::-1]
        posts = post_rows(classes, boundary, cam, goals, dims.goal_post_diameter, dims.goal_height, p.posts, sa, sb)
        ball = ball_rows(rgb, classes, boundary, cam, dims.ball_diameter / 2, self._modern_ball, p.ball, sa, sb)
        robots = robot_rows(
            classes, boundary, cam, self._jersey_classes, self.team, p.robot_radius, p.obstacles, sa, sb
        )
        rows, offsets, seg_px, seg_ground = asm.assemble_nb(
            classes, boundary, cam, points, loose, seg_px, seg_ground, open_ends, cx, cy, posts, ball, robots,
            goals[0], goals[1], self._net_class, prm, sa, sb,
        )  # fmt: skip
        self.debug = VisionDebug(classes, boundary, points, seg_px, seg_ground)
        return Percepts(time, rows, offsets, cam, camera.spec)

    def _size_params(self, width: int) -> tuple[int, int, NDArray[np.float64], int, float, NDArray[np.float64]]:
        """What :meth:`detect` needs for images ``width`` pixels wide: scan step and edge gap
        (px), the chaining parameters (:func:`~cognition.vision.dnt.dnt_lines_nb`), the ends'
        probe length (px), the boundary's run and the parameter vector of
        :func:`~cognition.vision.assemble.assemble_nb` (pixel sizes scaled from 320 px)."""
        p = self.params
        dims = self.field.dims
        scale = width / 320.0
        chain = np.array([p.chain_gap * scale, p.chain_tolerance * scale, p.min_white, p.min_points, p.merge_angle])
        values = {
            asm.A_GOAL_WIDTH: dims.goal_inner_width + dims.goal_post_diameter, asm.A_GOAL_BEHIND: p.goal_behind,
            asm.A_MIN_LINE: p.min_line_length, asm.A_MARGIN: p.crossing_margin, asm.A_MARGIN_IN: p.crossing_margin_in,
            asm.A_BEYOND: p.crossing_beyond, asm.A_ANGLE: p.crossing_angle, asm.A_MIN_ARM: p.crossing_min_arm,
            asm.A_MERGE_ANGLE: p.merge_angle, asm.A_MERGE_OFFSET: p.merge_offset, asm.A_MERGE_GAP: p.merge_gap,
            asm.A_MAX_MPP: p.crossing_max_mpp, asm.A_CROSS_MAX: p.crossing_max_distance * math.sqrt(scale),
            asm.A_POST_CLEARANCE: p.post_clearance, asm.A_POST_RADIUS: dims.goal_post_diameter / 2,
            asm.A_GOAL_HEIGHT: dims.goal_height, asm.A_MAX_DISTANCE: p.max_distance,
            asm.A_CIRCLE_RADIUS: self.field.centre_circle.radius if self.field.centre_circle is not None else 0.0,
            asm.A_MARK_SIZE: dims.penalty_mark_size, asm.A_MARK_TOL: p.mark_tolerance,
            asm.A_MARK_GREEN: p.mark_min_green, asm.A_MARK_PX: max(1, round(p.mark_min_px * scale)),
            asm.A_MARK_MAX: p.mark_max_distance,
        }  # fmt: skip
        prm = np.zeros(asm.A_N)
        for k, value in values.items():
            prm[k] = value
        step, gap = max(1, round(p.scan_step * scale)), max(1, round(p.edge_gap * scale))
        return step, gap, chain, max(4, round(12 * scale)), p.boundary_run, prm
