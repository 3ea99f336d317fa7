"""Teammates' reports and the team ball.

:class:`TeamState` reads the team messages a robot received each frame
(:mod:`cognition.worldmodel.messages`), keeps the latest valid one per teammate with the
time it arrived, drops the ones older than ``max_age`` and counts what it rejected: a
malformed packet never reaches the rest of the brain.

:func:`team_ball` fuses the own ball and the teammates' balls in the team frame. Each
estimate counts with the inverse of its covariance, the ball covariance plus the
reporter's pose variance (a poorly localized robot puts the ball in the wrong place),
grown with the age of the report (``age_variance_per_second``; the ball may have moved).
The fused mean is the information-weighted mean. This is the team-ball idea of the
Darmstadt paper (Sec. V.B) applied to all teammates at once.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from cognition.representations import BallModel, RobotPose, SensorFrame
from cognition.worldmodel.messages import MalformedMessageError, TeamMessage, unpack


@dataclass(frozen=True)
class TeamBallEstimate:
    """The team's ball (team frame, m) with its 2 x 2 covariance and who contributed."""

    x: float
    y: float
    cov_xx: float
    cov_xy: float
    cov_yy: float
    contributors: tuple[int, ...]
    """Player numbers whose estimates were fused (the own number included)."""


class TeamState:
    """The latest valid message of every teammate (see the module docstring)."""

    def __init__(self, own_number: int, max_age: float = 3.0):
        self.own_number = own_number
        self.max_age = max_age
        self.latest: dict[int, tuple[float, TeamMessage]] = {}
        """Player number -> (time received, message)."""
        self.rejected = 0
        """Packets that were not valid team messages."""

    def update(self, frame: SensorFrame) -> list[TeamMessage]:
        """Read this frame's messages; returns the current (not too old) teammates' messages."""
        for m in frame.messages:
            try:
                msg = unpack(m.payload)
            except MalformedMessageError:
                self.rejected += 1
                continue
            if msg.player != m.sender or msg.player == self.own_number:
                self.rejected += 1  # a report under a wrong name
                continue
            self.latest[msg.player] = (frame.time, msg)
        self.latest = {k: v for k, v in self.latest.items() if frame.time - v[0] <= self.max_age}
        return [msg for _, msg in self.latest.values()]


def rotate_covariance(p: NDArray[np.float64], theta: float) -> tuple[float, float, float]:
    """(xx, xy, yy) of the upper-left 2 x 2 block of ``p`` rotated by ``theta`` (rad): a
    robot-frame position covariance expressed in the team frame of a robot heading ``theta``."""
    c, s = math.cos(theta), math.sin(theta)
    a, b, d = float(p[0, 0]), float(p[0, 1]), float(p[1, 1])
    return (
        c * c * a - 2 * c * s * b + s * s * d,
        c * s * (a - d) + (c * c - s * s) * b,
        s * s * a + 2 * c * s * b + c * c * d,
    )


def team_ball(
    own: BallModel | None,
    own_pose: RobotPose | None,
    own_number: int,
    mates: Sequence[TeamMessage],
    age_variance_per_second: float = 0.25,
) -> TeamBallEstimate | None:
    """Information-weighted fusion of the own and the teammates' balls (team frame)."""
    ix = ixy = iy = 0.0  # summed information matrix
    vx = vy = 0.0  # summed information vector
    who: list[int] = []

    def add(bx: float, by: float, cxx: float, cxy: float, cyy: float, extra: float, number: int) -> None:
        nonlocal ix, ixy, iy, vx, vy
        a, b, d = cxx + extra, cxy, cyy + extra
        det = a * d - b * b
        if not (det > 1e-12 and math.isfinite(det)):  # degenerate or infinitely uncertain
            return
        ia, ib, idd = d / det, -b / det, a / det
        ix, ixy, iy = ix + ia, ixy + ib, iy + idd
        vx += ia * bx + ib * by
        vy += ib * bx + idd * by
        who.append(number)

    if own is not None and own_pose is not None and own.level != "invalid" and math.isfinite(own.field_x):
        c = own_pose.covariance
        # own ball covariance rotated into the team frame, plus the pose's position variance
        cxx, cxy, cyy = rotate_covariance(own.covariance, own_pose.theta)
        add(own.field_x, own.field_y, cxx, cxy, cyy, 0.5 * (c[0, 0] + c[1, 1]) + age_variance_per_second * own.age,
            own_number)  # fmt: skip
    for m in mates:
        if not m.ball_valid or m.penalized:
            continue
        extra = m.pose_std**2 + age_variance_per_second * m.ball_age
        add(m.ball_x, m.ball_y, m.ball_cov_xx, m.ball_cov_xy, m.ball_cov_yy, extra, m.player)
    if not who:
        return None
    det = ix * iy - ixy * ixy
    cxx, cxy, cyy = iy / det, -ixy / det, ix / det
    return TeamBallEstimate(cxx * vx + cxy * vy, cxy * vx + cyy * vy, cxx, cxy, cyy, tuple(who))
