"""Parameters of percept synthesis: noise, detection, false positives, latency.

The angular noise follows the Darmstadt paper (Kohlbrecher & von Stryk, section IV.B,
eqs. 3-6): for the angle ``alpha`` around the pitch axis and ``beta`` around the yaw axis,

    sigma = sigma_base + c * |head rate| + (sigma_moving if the robot walks else 0)

with ``c_tilt`` acting on the head pitch rate (alpha) and ``c_pan`` on the yaw rate (beta).
Detection rates, maximum distances and false-positive rates of the ``default`` preset come
from B-Human's oracle percept configuration (ball 0.9 up to 5 m, lines 0.6 up to 5 m,
centre circle 0.2 up to 3.5 m, goal posts 0.9 up to 8 m, penalty mark 0.8 up to 2.5 m,
robots 0.6 up to 4 m, ball false positives 0.0005, penalty-mark false positives 0.005);
the angular sigmas are NAO-scale values in the range the Darmstadt comparison spans
(fixed 5 and 15 degrees in its Table I).

=========================  ===============  ===========  ===============================================
parameter                  default          range        meaning
=========================  ===============  ===========  ===============================================
sigma_alpha_base           1.0 deg          [0, pi/2]    base sigma around the pitch axis (eq. 3)
sigma_beta_base            1.0 deg          [0, pi/2]    base sigma around the yaw axis (eq. 4)
c_tilt                     0.03 s           [0, 10]      head-motion factors (eq. 5): sigma += c |rate|,
c_pan                      0.03 s           [0, 10]      tilt on the pitch rate, pan on the yaw rate
sigma_alpha_moving         3.0 deg          [0, pi/2]    added while walking (eq. 6)
sigma_beta_moving          2.0 deg          [0, pi/2]    added while walking (eq. 6)
shared_noise_fraction      0.5              [0, 1]       share of the angular variance common to all
                                                         percepts of one image (camera-pose error)
reported_sigma             adaptive                      sigmas written into the percepts: ``adaptive``
                                                         (the model above) or ``fixed`` (Table I style)
fixed_sigma                5 deg            [0, pi/2]    the reported sigma in ``fixed`` mode
orientation_sigma          5 deg            [0, pi]      noise of crossing orientations
ball_radius_sigma_px       0.6 px           [0, 100]     noise of the ball's image radius
post ... pole              Detection                     per kind: rate, full_range, max_range (below)
circle_min_visible         0.25             [0, 1]       visible fraction of the circle needed
min_line_length            0.10 m           [0, 100]     shorter line pieces are not reported
head_speed_detection       0.1 s/rad        [0, 100]     detection / (1 + k |head rate|)
walking_detection          0.9              [0, 1]       detection factor while walking
ball_speed_detection       0.15 s/m         [0, 100]     ball detection / (1 + k |ball speed|)
max_occlusion              0.5              [0, 1]       objects hidden more than this are not seen
phantom_crossing_rate      0.02             [0, 1]       false crossings per image
phantom_mark_rate          0.005            [0, 1]       false penalty marks per image
background_post_rate       0.01             [0, 1]       false posts beyond the field per image
feet_ball_rate             0.01             [0, 1]       false ball at a seen robot's feet, per robot
false_ball_rate            0.0005           [0, 1]       false ball anywhere on the seen ground per image
crossing_confusion         0.1              [0, 1]       probability of reporting the wrong L/T/X type
robot_team_unknown         0.1              [0, 1]       robot percepts without a team guess
robot_team_wrong           0.03             [0, 1]       robot percepts with the wrong team (the two
                                                         shares add up to at most 1)
latency                    0.04 s           [0, 2]       image capture to sensor frame
robot_height               0.58 m           (0, 3]       standing robot (occludes everything behind)
fallen_height              0.20 m           [0, 3]       lying robot (short shadow)
=========================  ===============  ===========  ===============================================

Detection probability of a visible feature at ground distance ``d`` from the camera:
``rate`` up to ``full_range``, falling linearly to 0 at ``max_range``, times the motion
factors and, for the ball, posts and robots, the visible (not occluded) fraction.

The ranges apply to the true distance; a detected feature is reported wherever its noisy
angles project it, however far (a walking robot with its head sweeping reported a crossing
3.1 m away at 57 m: seen 9 degrees below the horizon, it came out at 0.5; the reported
covariance says how uncertain such a reading is). Dropping landmarks measured beyond ``max_range``, as a vision
module's distance limits do, was tried on 2026-11-28 and left out: it removes the far side of
the noise only, so the kept measurements are biased nearer, and two 10-minute 5 v 5 matches
(``maturing``, seeds 0 and 1) localized worse, 0.170 and 0.156 m against 0.120 and 0.130 m.

=========================  ===========  ==================================================
Detection                  range        meaning
=========================  ===========  ==================================================
rate                       [0, 1]       detection probability up to ``full_range``
full_range                 (0, 100]     distance (m) up to which ``rate`` applies
max_range                  (0, 100]     distance (m) from which nothing is detected;
                                        ``max_range >= full_range``
=========================  ===========  ==================================================

Every value is checked against its range when the parameters are built
(:func:`cognition.params.check_ranges`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace
from typing import ClassVar

import numpy as np
from numpy.typing import NDArray

from teamsim.params import PROBABILITY, Ranges, check_choice, check_ranges, non_negative, positive

_DEG = math.pi / 180.0


@dataclass(frozen=True)
class Detection:
    """Detection rate of one percept kind as a function of distance (m)."""

    rate: float = 1.0
    """Probability of detecting a visible feature up to ``full_range``."""
    full_range: float = 5.0
    """Distance up to which ``rate`` applies (m)."""
    max_range: float = 6.0
    """Distance from which the feature is never detected (m); linear in between."""

    RANGES: ClassVar[Ranges] = {"rate": PROBABILITY, "full_range": positive(100.0), "max_range": positive(100.0)}

    def __post_init__(self) -> None:
        check_ranges(self)
        if self.max_range < self.full_range:
            raise ValueError(f"Detection.max_range ({self.max_range}) must be >= full_range ({self.full_range})")

    def probability(self, distance: float) -> float:
        """Detection probability at ``distance`` (m), before motion and occlusion factors."""
        if distance <= self.full_range:
            return self.rate
        if distance >= self.max_range:
            return 0.0
        return self.rate * (self.max_range - distance) / (self.max_range - self.full_range)


_KINDS = ("post", "cross", "line", "circle", "mark", "ball", "robot", "pole")


@dataclass(frozen=True)
class PerceptParams:
    """All parameters of percept synthesis (see the module table); presets in ``PRESETS``."""

    sigma_alpha_base: float = 1.0 * _DEG
    sigma_beta_base: float = 1.0 * _DEG
    c_tilt: float = 0.03
    c_pan: float = 0.03
    sigma_alpha_moving: float = 3.0 * _DEG
    sigma_beta_moving: float = 2.0 * _DEG
    shared_noise_fraction: float = 0.5
    reported_sigma: str = "adaptive"
    fixed_sigma: float = 5.0 * _DEG
    orientation_sigma: float = 5.0 * _DEG
    ball_radius_sigma_px: float = 0.6
    post: Detection = field(default_factory=lambda: Detection(0.9, 6.0, 8.0))
    cross: Detection = field(default_factory=lambda: Detection(0.6, 3.0, 4.5))
    line: Detection = field(default_factory=lambda: Detection(0.6, 4.0, 5.0))
    circle: Detection = field(default_factory=lambda: Detection(0.2, 2.5, 3.5))
    mark: Detection = field(default_factory=lambda: Detection(0.8, 2.0, 3.0))
    ball: Detection = field(default_factory=lambda: Detection(0.9, 4.5, 5.5))
    robot: Detection = field(default_factory=lambda: Detection(0.6, 3.5, 4.5))
    pole: Detection = field(default_factory=lambda: Detection(0.9, 4.0, 6.0))
    circle_min_visible: float = 0.25
    min_line_length: float = 0.10
    head_speed_detection: float = 0.1
    walking_detection: float = 0.9
    ball_speed_detection: float = 0.15
    max_occlusion: float = 0.5
    phantom_crossing_rate: float = 0.02
    phantom_mark_rate: float = 0.005
    background_post_rate: float = 0.01
    feet_ball_rate: float = 0.01
    false_ball_rate: float = 0.0005
    crossing_confusion: float = 0.1
    robot_team_unknown: float = 0.1
    robot_team_wrong: float = 0.03
    latency: float = 0.04
    robot_height: float = 0.58
    fallen_height: float = 0.20

    PRESETS: ClassVar[dict[str, PerceptParams]]

    RANGES: ClassVar[Ranges] = {
        "sigma_alpha_base": non_negative(math.pi / 2),
        "sigma_beta_base": non_negative(math.pi / 2),
        "c_tilt": non_negative(10.0),
        "c_pan": non_negative(10.0),
        "sigma_alpha_moving": non_negative(math.pi / 2),
        "sigma_beta_moving": non_negative(math.pi / 2),
        "shared_noise_fraction": PROBABILITY,
        "fixed_sigma": non_negative(math.pi / 2),
        "orientation_sigma": non_negative(math.pi),
        "ball_radius_sigma_px": non_negative(100.0),
        "circle_min_visible": PROBABILITY,
        "min_line_length": non_negative(100.0),
        "head_speed_detection": non_negative(100.0),
        "walking_detection": PROBABILITY,
        "ball_speed_detection": non_negative(100.0),
        "max_occlusion": PROBABILITY,
        "phantom_crossing_rate": PROBABILITY,
        "phantom_mark_rate": PROBABILITY,
        "background_post_rate": PROBABILITY,
        "feet_ball_rate": PROBABILITY,
        "false_ball_rate": PROBABILITY,
        "crossing_confusion": PROBABILITY,
        "robot_team_unknown": PROBABILITY,
        "robot_team_wrong": PROBABILITY,
        "latency": non_negative(2.0),
        "robot_height": positive(3.0),
        "fallen_height": non_negative(3.0),
    }

    def __post_init__(self) -> None:
        check_ranges(self)
        check_choice("PerceptParams", "reported_sigma", self.reported_sigma, ("adaptive", "fixed"))
        if self.robot_team_unknown + self.robot_team_wrong > 1.0:
            raise ValueError("PerceptParams.robot_team_unknown + robot_team_wrong must not exceed 1")

    @classmethod
    def preset(cls, name: str) -> PerceptParams:
        """A named preset: ``ideal``, ``default`` or ``harsh``."""
        if name not in cls.PRESETS:
            raise ValueError(f"unknown PerceptParams preset {name!r}; valid presets: {sorted(cls.PRESETS)}")
        return cls.PRESETS[name]

    def sigmas(self, pitch_rate: float, yaw_rate: float, walking: bool) -> tuple[float, float]:
        """True angular sigmas (alpha, beta) in rad for this head motion (rad/s) and gait (eqs. 3-6)."""
        sa = self.sigma_alpha_base + self.c_tilt * abs(pitch_rate) + (self.sigma_alpha_moving if walking else 0.0)
        sb = self.sigma_beta_base + self.c_pan * abs(yaw_rate) + (self.sigma_beta_moving if walking else 0.0)
        return sa, sb

    def motion_factor(self, pitch_rate: float, yaw_rate: float, walking: bool) -> float:
        """Detection factor for camera motion (head rates in rad/s, walking)."""
        f = 1.0 / (1.0 + self.head_speed_detection * math.hypot(pitch_rate, yaw_rate))
        return f * (self.walking_detection if walking else 1.0)

    def to_vector(self) -> NDArray[np.float64]:
        """The parameters as the flat vector the compiled kernel reads (order of ``VECTOR_FIELDS``)."""
        values: list[float] = []
        for name in VECTOR_FIELDS:
            kind, _, attr = name.partition(".")
            if attr:
                values.append(float(getattr(getattr(self, kind), attr)))
            elif name == "reported_fixed":
                values.append(1.0 if self.reported_sigma == "fixed" else 0.0)
            else:
                values.append(float(getattr(self, name)))
        return np.asarray(values, dtype=np.float64)


VECTOR_FIELDS: tuple[str, ...] = tuple(
    [f.name for f in fields(PerceptParams) if f.name not in _KINDS and f.name != "reported_sigma"]
    + ["reported_fixed"]
    + [f"{k}.{a}" for k in _KINDS for a in ("rate", "full_range", "max_range")]
)
"""Names of the entries of :meth:`PerceptParams.to_vector`, in order."""

_IDEAL_DETECTION = Detection(1.0, 30.0, 30.0)

PerceptParams.PRESETS = {
    "ideal": PerceptParams(
        sigma_alpha_base=0.0,
        sigma_beta_base=0.0,
        c_tilt=0.0,
        c_pan=0.0,
        sigma_alpha_moving=0.0,
        sigma_beta_moving=0.0,
        shared_noise_fraction=0.0,
        orientation_sigma=0.0,
        ball_radius_sigma_px=0.0,
        **{k: _IDEAL_DETECTION for k in _KINDS},
        circle_min_visible=0.1,
        head_speed_detection=0.0,
        walking_detection=1.0,
        ball_speed_detection=0.0,
        phantom_crossing_rate=0.0,
        phantom_mark_rate=0.0,
        background_post_rate=0.0,
        feet_ball_rate=0.0,
        false_ball_rate=0.0,
        crossing_confusion=0.0,
        robot_team_unknown=0.0,
        robot_team_wrong=0.0,
        latency=0.0,
    ),
    "default": PerceptParams(),
}
_d = PerceptParams()
PerceptParams.PRESETS["harsh"] = replace(
    _d,
    sigma_alpha_base=2.0 * _DEG,
    sigma_beta_base=2.0 * _DEG,
    c_tilt=0.06,
    c_pan=0.06,
    sigma_alpha_moving=6.0 * _DEG,
    sigma_beta_moving=4.0 * _DEG,
    shared_noise_fraction=0.6,
    orientation_sigma=10.0 * _DEG,
    ball_radius_sigma_px=1.2,
    **{
        k: Detection(getattr(_d, k).rate * 0.7, getattr(_d, k).full_range * 0.75, getattr(_d, k).max_range * 0.75)
        for k in _KINDS
    },
    head_speed_detection=0.25,
    walking_detection=0.75,
    ball_speed_detection=0.3,
    phantom_crossing_rate=0.08,
    phantom_mark_rate=0.02,
    background_post_rate=0.04,
    feet_ball_rate=0.04,
    false_ball_rate=0.002,
    crossing_confusion=0.2,
    robot_team_unknown=0.2,
    robot_team_wrong=0.08,
    latency=0.08,
)
del _d
