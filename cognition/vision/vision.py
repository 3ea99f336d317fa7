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

:meth:`Vision.detect` checks the input and calibrates the colours in Python; all stages
after that run in one compiled call (:mod:`.frame`).

``Vision`` keeps state only for the colour calibration (a cache of lookup tables and the
latest carpet colour) and, per image size, the parameters of the compiled frame; one
instance per camera stream.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from cognition.camera import CameraMatrix
from cognition.field import FIELD_PRESETS, ColourScheme, Field, make_colour_scheme
from cognition.percepts import Percepts
from cognition.vision.colour import ColourClassifier
from cognition.vision.frame import BAD_CAMERA, frame_config, frame_nb
from cognition.vision.image import VisionError, as_rgb, check_camera
from cognition.vision.params import VisionParams
from cognition.vision.projection import sigmas


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
        self._configs: dict[tuple[int, int], NDArray[np.float64]] = {}
        """Per image size (width, height): the configuration of the compiled frame (:func:`frame_config`)."""

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
        cfg = self._configs.get((width, height))
        if cfg is None:
            cfg = self._configs[width, height] = self._config(width, height)
        table = self.classifier.lut(self.classifier.calibrate(rgb, cam))
        # motion blur (px) while the shutter is open: the image moves with the head (Darmstadt IV.B)
        blur_u = abs(head_yaw_rate) * cam[12] * p.exposure
        blur_v = abs(head_pitch_rate) * cam[13] * p.exposure + (p.walking_blur * width / 320.0 if walking else 0.0)
        sa, sb = sigmas(
            p.sigma_alpha_base, p.sigma_beta_base, p.c_tilt, p.c_pan, p.sigma_alpha_moving, p.sigma_beta_moving,
            head_pitch_rate, head_yaw_rate, walking,
        )  # fmt: skip
        classes = np.empty((height, width), dtype=np.uint8)
        boundary = np.empty(width, dtype=np.int32)
        status, rows, offsets, points, seg_px, seg_ground, invalid = frame_nb(
            rgb, cam, table, cfg, classes, boundary, own_goal, blur_u, blur_v, sa, sb
        )
        if status == BAD_CAMERA:
            raise ValueError("cam must be a finite camera row with positive focal lengths")
        self.debug = VisionDebug(classes, boundary, points, seg_px, seg_ground)
        if invalid >= 0:  # the checks of the constructor name the row
            return Percepts(time, rows, offsets, cam, camera.spec)
        return Percepts.of_checked_rows(time, rows, offsets, cam, camera.spec)

    def _config(self, width: int, height: int) -> NDArray[np.float64]:
        """The configuration of the compiled frame for images of ``width`` x ``height`` pixels."""
        goals = self._goal_classes
        classes = (goals[0], goals[1], self._net_class, *self._jersey_classes)
        return frame_config(self.params, self.field, classes, self._modern_ball, self.team, width, height)
