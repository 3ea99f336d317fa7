"""Odometry: the walking engine's report of its own motion, with realistic errors.

The robot's walking engine integrates the steps it *planned*; the body's *actual* motion
differs (slippage, collisions, being pushed). Following the error sources that the CMU paper
(Sec. III.B, Algorithm 2) and the Darmstadt paper (Sec. II, odometry) describe, the report
is the planned motion with

* translational noise proportional to the distance travelled on each axis,
* rotational noise proportional to the rotation,
* extra rotational noise for sideways steps (sidesteps are "especially non-straight"),
* a slow systematic drift: a per-robot rotation bias per metre walked and a per-robot
  scale error of the step length, drawn once per robot.

Ground truth (:class:`TrueOdometry`) and the report (:class:`cognition.representations.
OdometryReading`) are different types; only the report reaches a brain. All motions are in
the robot frame of the previous cognition frame (dx forward m, dy left m, dtheta rad).

=========================  =======  =========  =========================================================
parameter                  default  range      meaning
=========================  =======  =========  =========================================================
trans_noise                0.08     [0, 10]    sigma of dx (dy) per metre of |dx| (|dy|)
rot_noise                  0.10     [0, 10]    sigma of dtheta per radian of |dtheta|
sideways_rot_noise         0.20     [0, 100]   sigma of dtheta (rad) per metre of |dy|
drift_sigma                0.03     [0, 10]    sigma of the per-robot rotation bias (rad per metre walked)
scale_sigma                0.03     [0, 1]     sigma of the per-robot relative step-length error
=========================  =======  =========  =========================================================

Every value is checked against its range when the parameters are built
(:func:`cognition.params.check_ranges`).

The filter-side motion model (CMU: sigma 0.3 / 0.4) is deliberately larger than these
values, as both papers recommend modelling odometry worse than it is.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from cognition.records import fast_init
from cognition.representations import OdometryReading
from teamsim.params import Ranges, check_ranges, non_negative


@fast_init
@dataclass(frozen=True)
class TrueOdometry:
    """The body's actual motion since the previous cognition frame (simulator truth)."""

    dx: float
    dy: float
    dtheta: float


@dataclass(frozen=True)
class OdometryParams:
    """Error model of the reported odometry (see module table)."""

    trans_noise: float = 0.08
    rot_noise: float = 0.10
    sideways_rot_noise: float = 0.20
    drift_sigma: float = 0.03
    scale_sigma: float = 0.03

    RANGES: ClassVar[Ranges] = {
        "trans_noise": non_negative(10.0),
        "rot_noise": non_negative(10.0),
        "sideways_rot_noise": non_negative(100.0),
        "drift_sigma": non_negative(10.0),
        "scale_sigma": non_negative(1.0),
    }

    def __post_init__(self) -> None:
        check_ranges(self)


_REPORTS_PER_DRAW = 256
"""Reports whose noise :class:`OdometryModel` draws from its generator at once."""


class OdometryModel:
    """Turns one robot's planned motion into its noisy odometry report.

    The systematic part (rotation drift per metre, step-length scale) is drawn once at
    construction from ``rng``; the random part is drawn on every :meth:`report`.
    """

    def __init__(self, params: OdometryParams, rng: np.random.Generator):
        self.params = params
        self.rng = rng
        self.drift = float(rng.normal(0.0, params.drift_sigma))
        """Rotation bias (rad per metre walked) of this robot."""
        self.scale = 1.0 + float(rng.normal(0.0, params.scale_sigma))
        """Step-length scale factor of this robot."""
        self._normals: list[float] = []
        """Standard normals drawn ahead from ``rng`` (four per report), used in order."""
        self._next = 0

    def report(self, planned: tuple[float, float, float]) -> OdometryReading:
        """The odometry a robot reports for the planned motion ``(dx, dy, dtheta)``."""
        p = self.params
        dx, dy, dth = planned
        i = self._next
        if i == len(self._normals):
            # the same numbers, in the same order, as four draws per report (the stream is this
            # robot's own), for a fraction of the cost of a numpy call per report
            self._normals = self.rng.standard_normal(4 * _REPORTS_PER_DRAW).tolist()
            i = 0
        n0, n1, n2, n3 = self._normals[i : i + 4]
        self._next = i + 4
        dist = math.hypot(dx, dy)
        rx = dx * self.scale + n0 * p.trans_noise * abs(dx)
        ry = dy * self.scale + n1 * p.trans_noise * abs(dy)
        rth = dth + n2 * p.rot_noise * abs(dth) + n3 * p.sideways_rot_noise * abs(dy) + self.drift * dist
        return OdometryReading(rx, ry, rth)  # dx, dy, dtheta
