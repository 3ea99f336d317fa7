"""Goal model from the two posts seen during a head scan (CMU paper, Sec. IV.B).

Vision's bearings to goal posts are accurate; its distances are not (a post may be reported
at 1.5 or 2 times its distance), but a scale error is common to both posts of one scan. So
the goal is rebuilt from the two bearings and the *ratio* of the distances: with the posts
at d_L u_L and d_R u_R (u unit vectors along the bearings, robot frame) and d_L = q d_R,
the known post separation w fixes d_R = w / |q u_L - u_R|.

:class:`GoalModel` keeps post detections during a scan, carried along with the odometry, and
merges detections of the same post (bearing within ``merge_angle``) into tracks whose
confidence grows with every detection. The two most confident tracks are the posts; the
one with the larger bearing is the left post. Positions in the **robot frame** (m, rad).

==================  ========  ==========  ====================================================
GoalModelParams     default   range       meaning
==================  ========  ==========  ====================================================
merge_angle         5 deg     (0, pi]     detections within this bearing of a track join it (rad)
confidence_gain     0.25      (0, 1]      confidence a track gains per detection
decay_per_second    0.2       (0, 100]    confidence a track loses per second
==================  ========  ==========  ====================================================

The post separation given to :class:`GoalModel` lies in (0, 100] m. Every value is checked
against its range when the parameters are built (:func:`cognition.params.check_ranges`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import NDArray

from cognition.params import Ranges, check_number, check_ranges, positive
from cognition.percepts import Col, Kind, Percepts
from cognition.records import fast_init

_TAU = 2 * math.pi
_POST = int(Kind.POST)
_X, _Y = int(Col.X), int(Col.Y)


@fast_init
@dataclass(frozen=True)
class GoalEstimate:
    """The goal as the robot sees it (robot frame)."""

    centre_x: float
    """Goal centre between the posts (m)."""
    centre_y: float
    left: tuple[float, float]
    """Left post (m)."""
    right: tuple[float, float]
    """Right post (m)."""
    facing: float
    """Direction from the goal centre into the field (rad): the goal's normal toward the robot."""
    confidence: float
    """Of the weaker post track, in [0, 1]."""


def goal_from_posts(
    bearing_left: float, distance_left: float, bearing_right: float, distance_right: float, separation: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Left and right post positions (robot frame, m) from accurate bearings (rad) and the
    ratio of the measured distances, scaled so that the posts are ``separation`` m apart."""
    lx, ly, rx, ry = _posts_xy(bearing_left, distance_left, bearing_right, distance_right, separation)
    return np.array([lx, ly]), np.array([rx, ry])


def _posts_xy(
    bearing_left: float, distance_left: float, bearing_right: float, distance_right: float, separation: float
) -> tuple[float, float, float, float]:
    """:func:`goal_from_posts` as plain floats (left x, y, right x, y; m)."""
    if not (distance_left > 0 and distance_right > 0 and separation > 0):
        raise ValueError("post distances and separation must be > 0")
    ulx, uly = math.cos(bearing_left), math.sin(bearing_left)
    urx, ury = math.cos(bearing_right), math.sin(bearing_right)
    q = distance_left / distance_right
    gap = math.hypot(q * ulx - urx, q * uly - ury)
    if gap < 1e-9:
        raise ValueError("the two posts lie on one bearing; the goal is not determined")
    d_right = separation / gap
    return q * d_right * ulx, q * d_right * uly, d_right * urx, d_right * ury


@dataclass(frozen=True)
class GoalModelParams:
    """Tuning of the goal model."""

    merge_angle: float = math.radians(5.0)
    """Detections within this bearing of a track belong to it (rad)."""
    confidence_gain: float = 0.25
    """Confidence a track gains per detection (saturates at 1)."""
    decay_per_second: float = 0.2
    """Confidence lost per second (the scan ages)."""

    RANGES: ClassVar[Ranges] = {
        "merge_angle": positive(math.pi),
        "confidence_gain": positive(1.0),
        "decay_per_second": positive(100.0),
    }

    def __post_init__(self) -> None:
        check_ranges(self)


class GoalModel:
    """Goal-post tracks over a scan; :meth:`estimate` gives the goal (module docstring)."""

    def __init__(self, separation: float, params: GoalModelParams | None = None):
        check_number("GoalModel", "separation", separation, positive(100.0))
        self.separation = separation
        self.params = params or GoalModelParams()
        self._tracks: list[list[float]] = []  # x, y, confidence, mean distance-scale samples

    def move_robot(self, dx: float, dy: float, dtheta: float, dt: float) -> None:
        """Carry the tracks into the new robot frame and age them (``dx``, ``dy`` m and
        ``dtheta`` rad: the robot's motion in its old frame; ``dt`` s); faded tracks are dropped."""
        if not self._tracks:
            return
        c, s = math.cos(dtheta), math.sin(dtheta)
        decay = self.params.decay_per_second * dt
        keep = []
        for x, y, confidence, n in self._tracks:
            confidence -= decay
            if confidence > 0.0:
                x, y = x - dx, y - dy
                keep.append([c * x + s * y, -s * x + c * y, confidence, n])
        self._tracks = keep

    def add(self, x: float, y: float) -> None:
        """One post detection at (x, y) (robot frame, m)."""
        b = math.atan2(y, x)
        merge = self.params.merge_angle
        for t in self._tracks:
            tx, ty, confidence, n = t
            if abs(math.remainder(math.atan2(ty, tx) - b, _TAU)) <= merge:
                t[0], t[1] = (tx * n + x) / (n + 1), (ty * n + y) / (n + 1)
                t[2] = min(1.0, confidence + self.params.confidence_gain)
                t[3] = n + 1
                return
        self._tracks.append([x, y, self.params.confidence_gain, 1.0])

    def add_percepts(self, percepts: Percepts | None) -> None:
        """All post detections of one image."""
        if percepts is None:
            return
        lo, hi = percepts.span(_POST)
        if hi != lo:
            for x, y in percepts.table_and_offsets[0][lo:hi, _X : _Y + 1].tolist():
                self.add(x, y)

    def estimate(self) -> GoalEstimate | None:
        """The goal from the two most confident post tracks, or ``None`` with fewer than two."""
        tracks = self._tracks
        if len(tracks) < 2:
            return None
        a: list[float] | None = None  # the two most confident; of equals the first in track order
        b: list[float] | None = None
        for t in tracks:
            if a is None or t[2] > a[2]:
                a, b = t, a
            elif b is None or t[2] > b[2]:
                b = t
        assert a is not None and b is not None
        ba, bb = math.atan2(a[1], a[0]), math.atan2(b[1], b[0])
        if math.remainder(ba - bb, _TAU) > 0:  # the left post has the larger bearing
            (lx, ly, lc, _), bl, (rx, ry, rc, _), br = a, ba, b, bb
        else:
            (lx, ly, lc, _), bl, (rx, ry, rc, _), br = b, bb, a, ba
        try:
            plx, ply, prx, pry = _posts_xy(bl, math.hypot(lx, ly), br, math.hypot(rx, ry), self.separation)
        except ValueError:
            return None
        cx, cy = 0.5 * (plx + prx), 0.5 * (ply + pry)
        nx, ny = -(pry - ply), prx - plx  # perpendicular to the goal line
        if -(nx * cx + ny * cy) < 0.0:  # point it toward the robot's side of the goal line
            nx, ny = -nx, -ny
        confidence = rc if rc < lc else lc  # min(lc, rc)
        return GoalEstimate(cx, cy, (plx, ply), (prx, pry), math.atan2(ny, nx), confidence)
