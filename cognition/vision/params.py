"""Parameters of the vision pipeline (:class:`VisionParams`), defaults from the papers.

Pixel sizes are given for a 320 x 240 image (DNT 3.3 worked at that resolution, QVGA) and
scale with the image width; ground sizes are metres, angles radians.

======================  ===============  =============  ===================================================
parameter               default          range          meaning
======================  ===============  =============  ===================================================
method                  dnt              dnt, hough     line method: DNT scanlines and chaining (3.6) or
                                                        NimbRo oriented points and Hough transform (5.1-5.2)
colours                 ColourParams()                  colour classes and calibration (:mod:`.colour`)
hough                   HoughParams()                   the ``hough`` line method (:mod:`.hough`)
posts                   PostParams()                    goal posts (:mod:`.posts`)
ball                    BallParams()                    the ball (:mod:`.ball`)
obstacles               ObstacleParams()                robots as obstacles (:mod:`.robots`)
robot_radius            0.14 m           (0, 1]         robots' body radius (their centre lies behind the feet)
exposure                0.008 s          [0, 0.2]       the camera's shutter time: head rates blur lines by
                                                        rate x focal length x exposure pixels
walking_blur            1 px             [0, 100]       vertical shake of the image while walking (px at 320)
scan_step               4 px             [1, 64]        scanline spacing (DNT: every 5-10 px)
boundary_run            6 px             [1, 100]       green run that starts the field (DNT 3.4), at 240 rows
edge_gap                3 px             [1, 20]        pixels allowed between green and a line's white
chain_gap               12 px            [1, 100]       farthest link between two points of a chain
chain_tolerance         1.5 px           (0, 20]        rms distance of a chain's points from its line (eq. 1)
min_white               0.7              [0, 1]         white ratio of a link (DNT: "usually 1.0")
min_points              4                [2, 100]       points of a reported segment
merge_angle             6 deg            [0, pi/2]      direction difference of segments that may merge
min_line_length         0.10 m           [0, 100]       shorter segments (on the ground) are dropped
max_distance            6.0 m            (0, 100]       features farther away (on the ground) are dropped
crossing_margin         0.4 m            (0, 5]         a junction this far beyond a line's end is "at the end"
crossing_margin_in      0.3 m            (0, 5]         ... and this far inside it (or 6 px; DNT 3.7)
crossing_beyond         0.1 m            (0, 5]         the image is read this far past a junction (and to 2x)
crossing_angle          20 deg           (0, pi/4]      allowed deviation from a right angle
crossing_min_arm        0.15 m           (0, 10]        shortest line that forms a crossing
crossing_max_mpp        0.08 m           (0, 10]        ground metres per pixel along a line at a junction
crossing_max_distance   3.5 m            (0, 100]       farther junctions are not reported: a line across the view
                                                        is thinner than 1.5 px beyond about 3 m at 320 x 240 (it
                                                        thins with the square of the distance: the limit grows
                                                        with the square root of the image width)
merge_offset            0.06 m           (0, 5]         pieces of one line: offset from its carrier (+ 3 % of
                                                        the distance) ...
merge_gap               0.8 m            [0, 10]        ... and gap between them (SPL lines never continue one
                                                        another across a gap)
goal_behind             0.05 m           [0, 5]         lines are cut this far behind a seen goal line (:mod:`.goals`)
post_clearance          0.2 m            [0, 5]         no crossing this close to a seen post's base
circle_cell             0.05 m           (0, 1]         vote grid of the centre circle (NimbRo: 6 cm)
circle_directions       32               [4, 360]       votes per point on the ring
circle_inlier           0.08 m           (0, 1]         distance from the circle of its points
circle_min_points       8                [3, 1000]      inliers of an accepted circle
circle_min_span         90 deg           [0, 2pi]       arc the inliers must cover
circle_min_coverage     0.85             [0, 1]         share of the projected circle's visible points on white
circle_vote_every       2                [1, 16]        every n-th line point votes (all are fitted)
mark_tolerance          0.6              (0, 5]         relative size error of a penalty mark blob
mark_min_green          0.8              [0, 1]         green share of the ring around a mark
mark_max_distance       3.0 m            (0, 100]       farther blobs are not marks (a 10 cm mark is then about
                                                        2 px tall at 320 x 240, as thin as broken far lines)
mark_min_px             2                [1, 100]       smallest height and width of a mark blob (px at 320)
sigma_alpha_base        1 deg            [0, pi/2]      Darmstadt eq. 3: base sigma about the pitch axis
sigma_beta_base         1 deg            [0, pi/2]      Darmstadt eq. 4: base sigma about the yaw axis
c_tilt                  0.03 s           [0, 10]        eq. 5: sigma_alpha grows by c_tilt x |pitch rate|
c_pan                   0.03 s           [0, 10]        eq. 5: sigma_beta grows by c_pan x |yaw rate|
sigma_alpha_moving      3 deg            [0, pi/2]      eq. 6: added to sigma_alpha while walking
sigma_beta_moving       2 deg            [0, pi/2]      eq. 6: added to sigma_beta while walking
======================  ===============  =============  ===================================================

The noise-model defaults are those of the synthesized percepts (``PerceptParams``), so
vision percepts carry the covariance the simulator's percepts would report.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import ClassVar, Literal

from cognition.params import Range, Ranges, check_ranges, non_negative, positive
from cognition.vision.ball import BallParams
from cognition.vision.colour import ColourParams
from cognition.vision.hough import HoughParams
from cognition.vision.posts import PostParams
from cognition.vision.robots import ObstacleParams

_DEG = math.pi / 180.0
_ANGLE = Range(0.0, math.pi / 2)

METHODS: tuple[str, ...] = ("dnt", "hough")
"""The line methods by name."""


@dataclass(frozen=True)
class VisionParams:
    """All parameters of :class:`cognition.vision.Vision` (module table)."""

    method: Literal["dnt", "hough"] = "dnt"
    colours: ColourParams = field(default_factory=ColourParams)
    hough: HoughParams = field(default_factory=HoughParams)
    posts: PostParams = field(default_factory=PostParams)
    ball: BallParams = field(default_factory=BallParams)
    obstacles: ObstacleParams = field(default_factory=ObstacleParams)
    robot_radius: float = 0.14
    exposure: float = 0.008
    walking_blur: float = 1.0
    scan_step: int = 4
    boundary_run: int = 6
    edge_gap: int = 3
    chain_gap: float = 12.0
    chain_tolerance: float = 1.5
    min_white: float = 0.7
    min_points: int = 4
    merge_angle: float = 6.0 * _DEG
    min_line_length: float = 0.10
    max_distance: float = 6.0
    crossing_margin: float = 0.4
    crossing_margin_in: float = 0.3
    crossing_beyond: float = 0.1
    crossing_angle: float = 20.0 * _DEG
    crossing_min_arm: float = 0.15
    crossing_max_mpp: float = 0.08
    crossing_max_distance: float = 3.5
    merge_offset: float = 0.06
    merge_gap: float = 0.8
    goal_behind: float = 0.05
    post_clearance: float = 0.2
    circle_cell: float = 0.05
    circle_directions: int = 32
    circle_inlier: float = 0.08
    circle_min_points: int = 8
    circle_min_span: float = 90.0 * _DEG
    circle_min_coverage: float = 0.85
    circle_vote_every: int = 2
    mark_tolerance: float = 0.6
    mark_min_green: float = 0.8
    mark_max_distance: float = 3.0
    mark_min_px: int = 2
    sigma_alpha_base: float = 1.0 * _DEG
    sigma_beta_base: float = 1.0 * _DEG
    c_tilt: float = 0.03
    c_pan: float = 0.03
    sigma_alpha_moving: float = 3.0 * _DEG
    sigma_beta_moving: float = 2.0 * _DEG

    RANGES: ClassVar[Ranges] = {
        "robot_radius": positive(1.0),
        "exposure": non_negative(0.2),
        "walking_blur": non_negative(100.0),
        "scan_step": Range(1, 64),
        "boundary_run": Range(1, 100),
        "edge_gap": Range(1, 20),
        "chain_gap": Range(1.0, 100.0),
        "chain_tolerance": positive(20.0),
        "min_white": Range(0.0, 1.0),
        "min_points": Range(2, 100),
        "merge_angle": _ANGLE,
        "min_line_length": non_negative(100.0),
        "max_distance": positive(100.0),
        "crossing_margin": positive(5.0),
        "crossing_margin_in": positive(5.0),
        "crossing_beyond": positive(5.0),
        "merge_offset": positive(5.0),
        "merge_gap": non_negative(10.0),
        "goal_behind": non_negative(5.0),
        "post_clearance": non_negative(5.0),
        "crossing_angle": Range(0.0, math.pi / 4, low_open=True),
        "crossing_min_arm": positive(10.0),
        "crossing_max_mpp": positive(10.0),
        "crossing_max_distance": positive(100.0),
        "circle_cell": positive(1.0),
        "circle_directions": Range(4, 360),
        "circle_inlier": positive(1.0),
        "circle_min_points": Range(3, 1000),
        "circle_min_span": Range(0.0, 2 * math.pi),
        "circle_min_coverage": Range(0.0, 1.0),
        "circle_vote_every": Range(1, 16),
        "mark_tolerance": positive(5.0),
        "mark_min_green": Range(0.0, 1.0),
        "mark_max_distance": positive(100.0),
        "mark_min_px": Range(1, 100),
        "sigma_alpha_base": _ANGLE,
        "sigma_beta_base": _ANGLE,
        "c_tilt": non_negative(10.0),
        "c_pan": non_negative(10.0),
        "sigma_alpha_moving": _ANGLE,
        "sigma_beta_moving": _ANGLE,
    }

    def __post_init__(self) -> None:
        check_ranges(self)
