"""Parameters of the Monte Carlo localization family (one frozen dataclass, defaults from the papers).

Units: metres, radians, seconds. "d" is the measured distance (m) of an observation.

=========================  ==============  ==========================================================
parameter                  default         source / meaning
=========================  ==============  ==========================================================
particles                  300             particle count (CMU: at most 300)
sigma_mx                   0.3             CMU Alg. 2: translation noise sd per m of reported motion
sigma_mtheta               0.4             CMU Alg. 2: rotation noise sd per rad of reported turn
sigma_mytheta              3.0 rad/m       CMU Alg. 2: rotation noise sd per m of sidestep (0.003/mm)
motion_floor               0.002, 0.004    minimum noise per frame (m, rad) so that a standing
                                           robot's particles keep some diversity
post_sigma                 0.30 + 0.175 d  CMU III.C.1: distance sd of goal posts (m)
post_sigma_bearing         10 + 1.25 d deg CMU III.C.1: bearing sd of goal posts
corner_sigma               0.10 + 0.25 d   CMU III.C.2: distance sd of crossings; bearing 10 deg
corner_sigma_orientation   10 deg          CMU III.C.2: sd of the crossing's orientation
line_sigma                 0.40 + 0.5 d    CMU III.C.3: distance sd of the nearest line point
line_sigma_bearing         30 deg          CMU III.C.3
line_sigma_orientation     10 deg          CMU III.C.3
line_min_length            0.10            CMU III.C.3: shorter line segments are dropped
line_floor                 0.9             CMU III.C.3: added to every line likelihood
circle_sigma               0.10 + 0.10 d   CMU III.C.4; bearing 10 deg
mark_sigma                 0.10 + 0.25 d   penalty marks (not in CMU; as crossings); bearing 10 deg
line_model                 nearest         ``nearest`` (CMU) or ``hough`` (NimbRo eq. 7)
hough_sigmas               0.1, 10 deg, ...NimbRo eq. 7: sigma of rho, theta, mean u, spread sigma(u)
confidence                 0.95            NimbRo eq. 9: p = (1 - c) + c p for every observation
adaptive                   False           Darmstadt VI: distance and bearing sd from each
                                           percept's covariance instead of the tables
resample_jitter            1.5 cm, 1.8 deg CMU III.D: noise on resampled particles (x, y; theta): the
                                           paper's 8 cm and 10 deg as the spread per second
                                           when resampling at 30 Hz (8 cm / sqrt(30)); the
                                           paper's values per frame diffuse a 30 Hz filter by
                                           ~0.45 m/s and triple the tracking error
resample_interval          0.0 s           resample at most this often (0: on every observation)
alpha_slow, alpha_fast     0.005, 0.1      DNT 4.4 (Thrun): averaging rates of w_slow, w_fast
injection_max              0.3             largest share of particles injected in one update
reset_probability          0.1             CMU III.D: chance that a resampled particle comes from vision
min_particles              150             the adaptive count never goes below
                                           min(min_particles, particles); the count is
                                           ceil(floor / evidence per observation), the CMU
                                           rule that fewer particles are drawn as the weights
                                           grow (with a floor of 50, 3% of match frames were off
                                           by > 3 m: too few particles to keep the right mode)
reset_from_any_feature     False           DNT 4.5: also reset from one random feature of any kind
maturing_threshold         7               Darmstadt VI: consecutive consistent frames a candidate
                                           pose needs before it may replace particles (at 3,
                                           wrong candidates matured on line-only frames and a
                                           walking robot's error rose to 1.5 m; 7 gives 0.14 m)
maturing_candidates        40              candidate poses kept while maturing
maturing_consistency       0.3             a frame counts as consistent with a candidate when the
                                           per-observation likelihood (no floors) reaches this
cluster_radius             0.40            CMU III.E: particles within this of the best form the pose
jump_weight                0.2             CMU III.E: below this cluster weight the pose jumps
lost_spread                0.5             CMU III.E: weighted position sd (m) above which the robot is lost
return_rule                spl2025         penalty return positions (``spl2025`` or ``spl2010``)
placement_sigma            0.15, 10 deg    spread of particles at known placement positions
=========================  ==============  ==========================================================
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from cognition.params import check_choice, check_non_negative, check_positive, check_probability, from_mapping

LINE_MODELS = ("nearest", "hough")
RETURN_RULES = ("spl2025", "spl2010")
_DEG = math.pi / 180.0


@dataclass(frozen=True)
class LocalizationParams:
    """Tuning of every localization variant (table in the module docstring)."""

    particles: int = 300
    sigma_mx: float = 0.3
    sigma_mtheta: float = 0.4
    sigma_mytheta: float = 3.0
    motion_floor_xy: float = 0.002
    motion_floor_theta: float = 0.004
    post_sigma_min: float = 0.30
    post_sigma_rate: float = 0.175
    post_sigma_bearing_min: float = 10.0 * _DEG
    post_sigma_bearing_rate: float = 1.25 * _DEG
    corner_sigma_min: float = 0.10
    corner_sigma_rate: float = 0.25
    corner_sigma_bearing: float = 10.0 * _DEG
    corner_sigma_orientation: float = 10.0 * _DEG
    line_sigma_min: float = 0.40
    line_sigma_rate: float = 0.5
    line_sigma_bearing: float = 30.0 * _DEG
    line_sigma_orientation: float = 10.0 * _DEG
    line_min_length: float = 0.10
    line_floor: float = 0.9
    circle_sigma_min: float = 0.10
    circle_sigma_rate: float = 0.10
    circle_sigma_bearing: float = 10.0 * _DEG
    mark_sigma_min: float = 0.10
    mark_sigma_rate: float = 0.25
    mark_sigma_bearing: float = 10.0 * _DEG
    line_model: str = "nearest"
    hough_sigma_rho: float = 0.10
    hough_sigma_theta: float = 10.0 * _DEG
    hough_sigma_u: float = 0.30
    hough_sigma_spread: float = 0.20
    confidence: float = 0.95
    adaptive: bool = False
    resample_jitter_xy: float = 0.08 / math.sqrt(30.0)
    resample_jitter_theta: float = 10.0 * _DEG / math.sqrt(30.0)
    resample_interval: float = 0.0
    alpha_slow: float = 0.005
    alpha_fast: float = 0.1
    injection_max: float = 0.3
    reset_probability: float = 0.1
    min_particles: int = 150
    reset_from_any_feature: bool = False
    maturing_threshold: int = 7
    maturing_candidates: int = 40
    maturing_consistency: float = 0.3
    cluster_radius: float = 0.40
    jump_weight: float = 0.2
    lost_spread: float = 0.5
    return_rule: str = "spl2025"
    placement_sigma_xy: float = 0.15
    placement_sigma_theta: float = 10.0 * _DEG

    def __post_init__(self) -> None:
        o = "LocalizationParams"
        for name in ("particles", "min_particles", "maturing_threshold", "maturing_candidates"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int) or v < 1:
                raise ValueError(f"{o}.{name} must be an integer >= 1, got {v!r}")
        if self.particles > 100_000:
            raise ValueError(f"{o}.particles must be at most 100000, got {self.particles}")
        check_positive(
            o,
            post_sigma_min=self.post_sigma_min,
            post_sigma_bearing_min=self.post_sigma_bearing_min,
            corner_sigma_min=self.corner_sigma_min,
            corner_sigma_bearing=self.corner_sigma_bearing,
            corner_sigma_orientation=self.corner_sigma_orientation,
            line_sigma_min=self.line_sigma_min,
            line_sigma_bearing=self.line_sigma_bearing,
            line_sigma_orientation=self.line_sigma_orientation,
            circle_sigma_min=self.circle_sigma_min,
            circle_sigma_bearing=self.circle_sigma_bearing,
            mark_sigma_min=self.mark_sigma_min,
            mark_sigma_bearing=self.mark_sigma_bearing,
            hough_sigma_rho=self.hough_sigma_rho,
            hough_sigma_theta=self.hough_sigma_theta,
            hough_sigma_u=self.hough_sigma_u,
            hough_sigma_spread=self.hough_sigma_spread,
            cluster_radius=self.cluster_radius,
            lost_spread=self.lost_spread,
        )
        check_non_negative(
            o,
            sigma_mx=self.sigma_mx,
            sigma_mtheta=self.sigma_mtheta,
            sigma_mytheta=self.sigma_mytheta,
            motion_floor_xy=self.motion_floor_xy,
            motion_floor_theta=self.motion_floor_theta,
            post_sigma_rate=self.post_sigma_rate,
            post_sigma_bearing_rate=self.post_sigma_bearing_rate,
            corner_sigma_rate=self.corner_sigma_rate,
            line_sigma_rate=self.line_sigma_rate,
            circle_sigma_rate=self.circle_sigma_rate,
            mark_sigma_rate=self.mark_sigma_rate,
            line_min_length=self.line_min_length,
            line_floor=self.line_floor,
            resample_jitter_xy=self.resample_jitter_xy,
            resample_jitter_theta=self.resample_jitter_theta,
            resample_interval=self.resample_interval,
            placement_sigma_xy=self.placement_sigma_xy,
            placement_sigma_theta=self.placement_sigma_theta,
        )
        check_probability(
            o,
            confidence=self.confidence,
            alpha_slow=self.alpha_slow,
            alpha_fast=self.alpha_fast,
            injection_max=self.injection_max,
            reset_probability=self.reset_probability,
            maturing_consistency=self.maturing_consistency,
            jump_weight=self.jump_weight,
        )
        if self.alpha_slow >= self.alpha_fast:
            raise ValueError(f"{o}: alpha_slow ({self.alpha_slow}) must be below alpha_fast ({self.alpha_fast})")
        check_choice(o, "line_model", self.line_model, LINE_MODELS)
        check_choice(o, "return_rule", self.return_rule, RETURN_RULES)
        for name in ("adaptive", "reset_from_any_feature"):
            if not isinstance(getattr(self, name), bool):
                raise ValueError(f"{o}.{name} must be true or false, got {getattr(self, name)!r}")

    @classmethod
    def from_mapping(cls, data: dict[str, Any]) -> LocalizationParams:
        """Build from a plain mapping (scenario file, JSON); unknown keys are an error."""
        return from_mapping(cls, data)

    @property
    def floor_particles(self) -> int:
        """The smallest particle count of the adaptive ``reset`` variant: min(min_particles, particles)."""
        return min(self.min_particles, self.particles)
