"""The Kalman ball as a module: percepts, odometry and teammates in, a :class:`BallModel` out.

Wraps the functional core of :mod:`cognition.worldmodel.kalman_ball` (Darmstadt paper,
Sec. V) for one robot. Each frame:

1. predict over the time since the previous frame (rolling friction), then carry the state
   into the new robot frame with the odometry;
2. camera update from the ball percept nearest to the prediction (Mahalanobis gate: a
   percept far outside it is rejected, and :data:`RESTART_AFTER` rejections in a row
   restart the filter at the latest one: the ball was moved); sigmas from the
   percept (``adaptive``) or fixed angles, size-based distance fused (eqs. 8-15);
3. without an own sighting, once the own position variance exceeds ``team_threshold``:
   update from the teammate whose ball estimate is least uncertain, converted from the team
   frame with the own pose estimate, its covariance multiplied by ``team_inflation``
   (Darmstadt V.B).

Levels (CMU IV.A): ``valid`` while the position sd is below ``valid_sigma``, ``suspicious``
below ``suspicious_sigma``, else ``invalid``.

Given ``limits`` (the largest abs(x), abs(y) of the carpet plus a margin, team frame, m:
:func:`cognition.worldmodel.team.carpet_limits`), a state whose field position lies beyond them
is put back on the limit and loses its velocity across it: the boards stop a real ball, and
without this a teammate's report of a fast ball could carry the estimate tens of metres away.

A state that is no longer finite (whatever produced it) is dropped instead of published: the
model then reports no ball (``invalid``, source ``none``) until the next sighting or team
ball, never a NaN ball; a teammate's report that would make the measurement non-finite is
skipped.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from cognition.percepts import N_COLS, Kind, Percepts
from cognition.representations import BallLevel, BallModel, RobotPose, SensorFrame
from cognition.worldmodel.kalman_ball import KalmanBallParams, own_frame_nb, publish_nb, update
from cognition.worldmodel.messages import TeamMessage

GATE = 25.0
"""Mahalanobis distance squared beyond which a percept is rejected."""
RESTART_AFTER = 5
"""Consecutive rejected percepts after which the filter restarts at the latest (the ball moved)."""
VALID_SIGMA = 0.5
"""Position sd (m) below which the ball is ``valid``."""
SUSPICIOUS_SIGMA = 1.5
"""Position sd (m) below which the ball is ``suspicious`` (else ``invalid``)."""
_BALL = int(Kind.BALL)
_TEAM_VELOCITY_VAR = 1.0  # (m/s)^2: the message carries no velocity covariance
_NO_ROWS = np.zeros((0, N_COLS))
"""No ball percept rows (kept writable: a read-only array would compile :func:`own_frame_nb` again)."""


_UNKNOWN_COV = np.eye(4) * 1e6
_UNKNOWN_COV.flags.writeable = False
"""The covariance of no ball (shared, read-only)."""


class KalmanBallModel:
    """One robot's Kalman ball (module docstring); ``ball_radius`` in m from the field map,
    ``limits`` the largest abs(x), abs(y) (m, team frame) of a ball, ``None`` for no limit."""

    def __init__(
        self, ball_radius: float, params: KalmanBallParams | None = None, limits: tuple[float, float] | None = None
    ):
        self.params = params or KalmanBallParams()
        self.ball_radius = float(ball_radius)
        self.limits = limits
        self.x: NDArray[np.float64] | None = None
        self.p: NDArray[np.float64] | None = None
        self.last_seen = -math.inf
        self.time: float | None = None
        self.source = "none"
        self._status = np.zeros(2, dtype=np.int64)
        """(1 if the compiled frame is given a state, consecutive rejected percepts) (:func:`own_frame_nb`)."""
        self._out = np.zeros(3)
        """Position sd and field position of the published state (:func:`publish_nb`)."""

    def update(self, frame: SensorFrame, pose: RobotPose | None = None, team: Sequence[TeamMessage] = ()) -> BallModel:
        """One frame (robot frame results; ``pose`` only for field coordinates and team balls)."""
        prm = self.params
        dt = 0.0 if self.time is None else max(0.0, frame.time - self.time)
        self.time = frame.time
        had = self.x is not None and self.p is not None
        rows, foot_x, foot_y, height, focal = self._ball_rows(frame.percepts)
        seen = False
        if had or rows.shape[0]:
            if not had:  # the first sighting fills fresh arrays
                self.x, self.p = np.zeros(4), np.zeros((4, 4))
            self._status[0] = 1 if had else 0
            o = frame.odometry
            seen = own_frame_nb(
                self.x, self.p, self._status, dt, prm.rolling_deceleration, prm.accel_sigma, o.dx, o.dy, o.dtheta, rows,
                foot_x, foot_y, height, focal, self.ball_radius, prm.fixed_sigma if prm.sigma_mode == "fixed" else -1.0,
                prm.size_sigma_px, prm.sigmas_at_prediction, GATE, RESTART_AFTER, prm.initial_velocity_sigma**2,
            )  # fmt: skip
            if had:
                self.source = "prediction"
            if seen:
                self.last_seen = frame.time
                self.source = "vision"
        if not seen and pose is not None and team and self._needs_team():
            self._team(pose, team)
        return self._output(pose)

    # -- updates ---------------------------------------------------------------------------
    def _ball_rows(self, percepts: Percepts | None) -> tuple[NDArray[np.float64], float, float, float, float]:
        """This frame's ball percept rows (none without percepts or a camera matrix), the camera's
        foot (x, y, m, robot frame), its height above the ball centre (m) and focal length (px)."""
        if percepts is None or percepts.camera is None:
            return _NO_ROWS, 0.0, 0.0, 0.0, 0.0
        table, offsets = percepts.table_and_offsets
        lo, hi = int(offsets[_BALL]), int(offsets[_BALL + 1])
        if hi == lo:
            return _NO_ROWS, 0.0, 0.0, 0.0, 0.0
        cam = percepts.camera
        foot = cam.position  # distances are from the camera's foot
        focal = 0.5 * (cam.spec.fx + cam.spec.fy)
        return table[lo:hi], float(foot[0]), float(foot[1]), cam.height - self.ball_radius, focal

    def _needs_team(self) -> bool:
        return self.p is None or float(self.p[0, 0] + self.p[1, 1]) > self.params.team_threshold

    def _team(self, pose: RobotPose, team: Sequence[TeamMessage]) -> None:
        mates = [m for m in team if m.ball_valid and not m.penalized]
        if not mates:
            return
        best = min(mates, key=lambda m: m.ball_cov_xx + m.ball_cov_yy)
        c, s = math.cos(pose.theta), math.sin(pose.theta)
        rot = np.array([[c, s], [-s, c]])  # team frame -> robot frame
        z = np.zeros(4)
        z[:2] = rot @ np.array([best.ball_x - pose.x, best.ball_y - pose.y])
        z[2:] = rot @ np.array([best.ball_vx, best.ball_vy])
        cov = np.array([[best.ball_cov_xx, best.ball_cov_xy], [best.ball_cov_xy, best.ball_cov_yy]])
        r = np.zeros((4, 4))
        r[:2, :2] = rot @ cov @ rot.T + pose.covariance[:2, :2]
        r[2:, 2:] = np.eye(2) * _TEAM_VELOCITY_VAR
        r *= self.params.team_inflation
        if not (np.isfinite(z).all() and np.isfinite(r).all()):
            return  # a report (or an own pose) no update can use
        if self.x is None or self.p is None:
            self.x, self.p = z, r
        else:
            self.x, self.p = update(self.x, self.p, z, r)
        self.source = "team"

    # -- output ----------------------------------------------------------------------------
    def _output(self, pose: RobotPose | None) -> BallModel:
        """Keep the state on the carpet (given ``limits`` and a pose) and publish it
        (:func:`publish_nb`); a state that is not finite is dropped (module docstring)."""
        if self.x is not None and self.p is not None:
            lim = self.limits if self.limits is not None else (-1.0, -1.0)
            has_pose = pose is not None
            px, py, pth = (pose.x, pose.y, pose.theta) if pose is not None else (0.0, 0.0, 0.0)
            if not publish_nb(self.x, self.p, has_pose, px, py, pth, lim[0], lim[1], self._out):
                self.x = self.p = None  # NaN would read as a certain ball (max(0, nan) is 0)
                self.source = "none"
        if self.x is None or self.p is None:
            return BallModel(0.0, 0.0, 0.0, 0.0, _UNKNOWN_COV, math.nan, math.nan, math.inf, "invalid", "none")
        x0, x1, x2, x3 = self.x.tolist()
        sd, fx, fy = self._out.tolist()
        level: BallLevel = "valid" if sd < VALID_SIGMA else ("suspicious" if sd < SUSPICIOUS_SIGMA else "invalid")
        age = (self.time or 0.0) - self.last_seen
        p = self.p.copy()  # the state is updated in place; the output keeps this frame's covariance
        p.flags.writeable = False
        return BallModel(x0, x1, x2, x3, p, fx, fy, age, level, self.source)  # type: ignore[arg-type]
