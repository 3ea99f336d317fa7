"""Parameters of the Monte Carlo localization family (one frozen dataclass, defaults from the papers).

Units: metres, radians, seconds. "d" is the measured distance (m) of an observation.

=========================  ==============  =============  ==========================================================
parameter                  default         range          source / meaning
=========================  ==============  =============  ==========================================================
particles                  300             [1, 100000]    particle count (CMU: at most 300)
sigma_mx                   0.3             [0, 10]        CMU Alg. 2: translation noise sd per m of reported motion
sigma_mtheta               0.4             [0, 10]        CMU Alg. 2: rotation noise sd per rad of reported turn
sigma_mytheta              3.0 rad/m       [0, 100]       CMU Alg. 2: rotation noise sd per m of sidestep (0.003/mm)
motion_floor_xy            0.002 m         [0, 1]         minimum noise per frame so that a standing robot's
motion_floor_theta         0.004 rad       [0, pi]        particles keep some diversity
post_sigma_min             0.30 m          (0, 100]       CMU III.C.1: distance sd of goal posts is
post_sigma_rate            0.175           [0, 10]        min + rate d
post_sigma_bearing_min     10 deg          (0, pi]        CMU III.C.1: bearing sd of goal posts is
post_sigma_bearing_rate    1.25 deg/m      [0, pi]        min + rate d
corner_sigma_min           0.10 m          (0, 100]       CMU III.C.2: distance sd of crossings is
corner_sigma_rate          0.25            [0, 10]        min + rate d
corner_sigma_bearing       10 deg          (0, pi]        CMU III.C.2: bearing sd of crossings
corner_sigma_orientation   10 deg          (0, pi]        CMU III.C.2: sd of the crossing's orientation
partial_crossings          0.1             [0, 1]         weight of explaining a crossing seen as a lesser kind by a
                                                          larger one (a T by an X, an L by a T or an X: seen in
                                                          part); 0: never, as in the paper (not in the paper;
                                                          :mod:`~cognition.localization.sensor`)
line_sigma_min             0.40 m          (0, 100]       CMU III.C.3: distance sd of the nearest line point is
line_sigma_rate            0.5             [0, 10]        min + rate d
line_sigma_bearing         30 deg          (0, pi]        CMU III.C.3
line_sigma_orientation     10 deg          (0, pi]        CMU III.C.3
line_min_length            0.10 m          [0, 100]       CMU III.C.3: shorter line segments are dropped
line_floor                 0.9             [0, 100]       CMU III.C.3: added to every line likelihood
circle_sigma_min           0.10 m          (0, 100]       CMU III.C.4: distance sd of the centre circle is
circle_sigma_rate          0.10            [0, 10]        min + rate d
circle_sigma_bearing       10 deg          (0, pi]        CMU III.C.4
mark_sigma_min             0.10 m          (0, 100]       penalty marks (not in CMU; as crossings): distance sd
mark_sigma_rate            0.25            [0, 10]        min + rate d
mark_sigma_bearing         10 deg          (0, pi]        penalty marks' bearing sd
line_model                 nearest                        ``nearest`` (CMU) or ``hough`` (NimbRo eq. 7)
hough_sigma_rho            0.1 m           (0, 100]       NimbRo eq. 7: sigma of rho,
hough_sigma_theta          10 deg          (0, pi]        of theta,
hough_sigma_u              0.3 m           (0, 100]       of the mean u
hough_sigma_spread         0.2 m           (0, 100]       and of the spread sigma(u)
confidence                 0.95            [0, 1]         NimbRo eq. 9: p = (1 - c) + c p for every observation
adaptive                   False           true/false     Darmstadt VI: distance and bearing sd from each
                                                          percept's covariance instead of the tables
resample_jitter_xy         1.5 cm          [0, 10]        CMU III.D: noise on resampled particles (x, y; theta): the
resample_jitter_theta      1.8 deg         [0, pi]        paper's 8 cm and 10 deg as the spread per second
                                                          when resampling at 30 Hz (8 cm / sqrt(30)); the
                                                          paper's values per frame diffuse a 30 Hz filter by
                                                          ~0.45 m/s and triple the tracking error
resample_interval          0.0 s           [0, 3600]      resample at most this often (0: on every observation)
alpha_slow                 0.005           [0, 1]         DNT 4.4 (Thrun): averaging rates of w_slow
alpha_fast                 0.1             [0, 1]         and w_fast (alpha_slow < alpha_fast)
injection_max              0.3             [0, 1]         largest share of particles injected in one update
reset_probability          0.1             [0, 1]         CMU III.D: chance that a resampled particle comes from vision
min_particles              150             [1, 100000]    the adaptive count never goes below
                                                          min(min_particles, particles); the count is
                                                          ceil(floor / evidence per observation), the CMU
                                                          rule that fewer particles are drawn as the weights
                                                          grow (with a floor of 50, 3% of match frames were off
                                                          by > 3 m: too few particles to keep the right mode)
kld                        False           true/false     KLD-sampling (Fox 2003, :mod:`.kld`): while tracking, a
                                                          resampling draws as many particles as the posterior's
                                                          spread needs (replaces the variant's count); lost,
                                                          injecting or relocalizing, it draws them all
kld_epsilon                0.1             (0, 1]         the bound on the Kullback-Leibler distance
kld_z                      2.326           (0, 10]        upper quantile of the standard normal (delta 0.01)
kld_bin_xy                 0.25 m          (0, 10]        KLD bin size in x and y
kld_bin_theta              10 deg          (0, pi]        KLD bin size in theta
kld_min_particles          60              [1, 100000]    the KLD count never goes below min(this, particles)
reset_from_any_feature     False           true/false     DNT 4.5: also reset from one random feature of any kind
maturing_threshold         7               [1, 10000]     Darmstadt VI: consistent frames with a landmark that a
                                                          candidate pose needs before it may replace particles
                                                          (frames of lines only keep it but add nothing: lines
                                                          fit too many poses; at 3 frames of any kind a walking
                                                          robot's error rose to 1.5 m)
maturing_candidates        40              [1, 10000]     candidate poses kept while maturing
maturing_consistency       0.3             [0, 1]         a frame counts as consistent with a candidate when the
                                                          per-observation likelihood (no floors) reaches this
maturing_beat_estimate     True            true/false     a matured candidate replaces particles only when it
                                                          explained the observations better than the filter's
                                                          estimate (not in the paper; :mod:`.maturing`)
maturing_margin            0.5             [0, 100]       by this much: its per-observation log-likelihood minus
                                                          the estimate's, averaged over its kept frames
cluster_radius             0.40 m          (0, 100]       CMU III.E: particles within this of the best form the pose
jump_weight                0.2             [0, 1]         CMU III.E: below this cluster weight the pose jumps
                                                          to the heaviest particle's cluster, if that is heavier
lost_spread                0.5 m           (0, 100]       CMU III.E: weighted position sd above which the robot is lost
return_rule                spl2025                        penalty return positions (``spl2025`` or ``spl2010``)
penalty_prior              true            true/false     CMU III.A.3: a robot returning from a penalty puts its
                                                          particles at the return positions (the game
                                                          controller's prior); false keeps its belief from before
                                                          the penalty and relocalizes from percepts alone
field_lines                true            true/false     use the painted-line features (crossings, lines, centre
                                                          circle, penalty marks); false leaves goal posts and
                                                          poles only, as in NimbRo's localization without lines
                                                          (NimbRo Sec. 5, Table 2)
placement_sigma_xy         0.15 m          [0, 10]        spread of particles at known placement positions
placement_sigma_theta      10 deg          [0, pi]
relocalize_seconds         3.0 s           [0, 600]       safety net of every particle variant (not in the papers,
                                                          see :mod:`~cognition.localization.particle_filter`):
                                                          the window it judges; 0 turns it off (the papers'
                                                          plain variants)
relocalize_log_likelihood  -6.0            (-10000, 0)    an observation is unexplained when the log of its mean
                                                          likelihood under the particles (no floors) is below
                                                          this
relocalize_share           0.4             [0, 1]         random poses are injected when this share of the
                                                          window's observations was unexplained. Measured share
                                                          with -6 (1 v 1 walking, 8 recordings): at most 0.21
                                                          while localized (default and harsh percepts), median
                                                          0.40 while lost after a kidnapping; 5 v 5 harsh: 95 %
                                                          of windows below 0.38 while localized
relocalize_weight          0.01            (0, 1]         weight of an injected pose relative to a resampled
                                                          particle
=========================  ==============  =============  ==========================================================

Every value is checked against its range when the parameters are built
(:func:`cognition.params.check_ranges`): the sizes (particles, candidates) are bounded so that
a typo cannot exhaust the memory, and a value outside its range, a non-number, NaN or infinity
raises an error naming the field.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

from cognition.params import (
    PROBABILITY,
    Range,
    Ranges,
    check_choice,
    check_ranges,
    from_mapping,
    non_negative,
    positive,
)

LINE_MODELS = ("nearest", "hough")
RETURN_RULES = ("spl2025", "spl2010")
MAX_PARTICLES = 100_000
"""Largest particle count (``particles``, ``min_particles``): a few MB of particles per robot."""
MAX_CANDIDATES = 10_000
"""Largest number of maturing candidate poses (``maturing_candidates``)."""
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
    partial_crossings: float = 0.1
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
    kld: bool = False
    kld_epsilon: float = 0.1
    kld_z: float = 2.326
    kld_bin_xy: float = 0.25
    kld_bin_theta: float = 10.0 * _DEG
    kld_min_particles: int = 60
    reset_from_any_feature: bool = False
    maturing_threshold: int = 7
    maturing_candidates: int = 40
    maturing_consistency: float = 0.3
    maturing_beat_estimate: bool = True
    maturing_margin: float = 0.5
    cluster_radius: float = 0.40
    jump_weight: float = 0.2
    lost_spread: float = 0.5
    return_rule: str = "spl2025"
    penalty_prior: bool = True
    field_lines: bool = True
    placement_sigma_xy: float = 0.15
    placement_sigma_theta: float = 10.0 * _DEG
    relocalize_seconds: float = 3.0
    relocalize_log_likelihood: float = -6.0
    relocalize_share: float = 0.4
    relocalize_weight: float = 0.01

    RANGES: ClassVar[Ranges] = {
        "particles": Range(1, MAX_PARTICLES),
        "sigma_mx": non_negative(10.0),
        "sigma_mtheta": non_negative(10.0),
        "sigma_mytheta": non_negative(100.0),
        "motion_floor_xy": non_negative(1.0),
        "motion_floor_theta": non_negative(math.pi),
        "post_sigma_min": positive(100.0),
        "post_sigma_rate": non_negative(10.0),
        "post_sigma_bearing_min": positive(math.pi),
        "post_sigma_bearing_rate": non_negative(math.pi),
        "corner_sigma_min": positive(100.0),
        "corner_sigma_rate": non_negative(10.0),
        "corner_sigma_bearing": positive(math.pi),
        "corner_sigma_orientation": positive(math.pi),
        "partial_crossings": PROBABILITY,
        "line_sigma_min": positive(100.0),
        "line_sigma_rate": non_negative(10.0),
        "line_sigma_bearing": positive(math.pi),
        "line_sigma_orientation": positive(math.pi),
        "line_min_length": non_negative(100.0),
        "line_floor": non_negative(100.0),
        "circle_sigma_min": positive(100.0),
        "circle_sigma_rate": non_negative(10.0),
        "circle_sigma_bearing": positive(math.pi),
        "mark_sigma_min": positive(100.0),
        "mark_sigma_rate": non_negative(10.0),
        "mark_sigma_bearing": positive(math.pi),
        "hough_sigma_rho": positive(100.0),
        "hough_sigma_theta": positive(math.pi),
        "hough_sigma_u": positive(100.0),
        "hough_sigma_spread": positive(100.0),
        "confidence": PROBABILITY,
        "resample_jitter_xy": non_negative(10.0),
        "resample_jitter_theta": non_negative(math.pi),
        "resample_interval": non_negative(3600.0),
        "alpha_slow": PROBABILITY,
        "alpha_fast": PROBABILITY,
        "injection_max": PROBABILITY,
        "reset_probability": PROBABILITY,
        "min_particles": Range(1, MAX_PARTICLES),
        "kld_epsilon": Range(0.0, 1.0, low_open=True),
        "kld_z": positive(10.0),
        "kld_bin_xy": positive(10.0),
        "kld_bin_theta": positive(math.pi),
        "kld_min_particles": Range(1, MAX_PARTICLES),
        "maturing_threshold": Range(1, 10_000),
        "maturing_candidates": Range(1, MAX_CANDIDATES),
        "maturing_consistency": PROBABILITY,
        "maturing_margin": Range(0.0, 100.0),
        "cluster_radius": positive(100.0),
        "jump_weight": PROBABILITY,
        "lost_spread": positive(100.0),
        "placement_sigma_xy": non_negative(10.0),
        "placement_sigma_theta": non_negative(math.pi),
        "relocalize_seconds": non_negative(600.0),
        "relocalize_log_likelihood": Range(-10_000.0, 0.0, low_open=True, high_open=True),
        "relocalize_share": PROBABILITY,
        "relocalize_weight": Range(0.0, 1.0, low_open=True),
    }

    def __post_init__(self) -> None:
        check_ranges(self)
        o = "LocalizationParams"
        if self.alpha_slow >= self.alpha_fast:
            raise ValueError(f"{o}: alpha_slow ({self.alpha_slow}) must be below alpha_fast ({self.alpha_fast})")
        check_choice(o, "line_model", self.line_model, LINE_MODELS)
        check_choice(o, "return_rule", self.return_rule, RETURN_RULES)

    @classmethod
    def from_mapping(cls, data: dict[str, Any]) -> LocalizationParams:
        """Build from a plain mapping (scenario file, JSON); unknown keys are an error."""
        return from_mapping(cls, data)

    @property
    def floor_particles(self) -> int:
        """The smallest particle count of the adaptive ``reset`` variant: min(min_particles, particles)."""
        return min(self.min_particles, self.particles)
