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

from cognition.camera import VIEW_FX, VIEW_FY, VIEW_X, VIEW_Y, VIEW_Z
from cognition.percepts import N_COLS, Kind, Percepts
from cognition.representations import BallLevel, BallModel, RobotPose, SensorFrame
from cognition.worldmodel.kalman_ball import (
    FRAME_PUBLISHED,
    FRAME_SEEN,
    FRAME_TEAM,
    KalmanBallParams,
    frame_nb,
    publish_nb,
    update,
)
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


def _no_ball() -> BallModel:
    """The ball model of no ball (``invalid``, source ``none``)."""
    return BallModel(0.0, 0.0, 0.0, 0.0, _UNKNOWN_COV, math.nan, math.nan, math.inf, "invalid", "none")


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
        self._consts_of: KalmanBallParams | None = None
        self._consts: tuple[float, float, float, float, bool, float, float] = (0.0, 0.0, 0.0, 0.0, False, 0.0, 0.0)
        """The kernel's view of ``params`` (:meth:`_kernel_constants`), for the params object ``_consts_of``."""

    def update(self, frame: SensorFrame, pose: RobotPose | None = None, team: Sequence[TeamMessage] = ()) -> BallModel:
        """One frame (robot frame results; ``pose`` only for field coordinates and team balls)."""
        time = frame.time
        dt = 0.0 if self.time is None else time - self.time
        dt = dt if dt > 0.0 else 0.0  # max(0.0, dt)
        self.time = time
        x, p = self.x, self.p
        had = x is not None and p is not None
        rows, foot_x, foot_y, height, focal = self._ball_rows(frame.percepts)
        if not (had or rows.shape[0]):  # no state and nothing seen: at most a teammate's ball
            if pose is not None and team and self._needs_team():
                self._team(pose, team)
            return self._output(pose)
        if x is None or p is None:  # the first sighting fills fresh arrays
            self.x, self.p = x, p = np.zeros(4), np.zeros((4, 4))
        status = self._status
        status[0] = 1 if had else 0
        deceleration, accel_sigma, fixed_sigma, size_px, at_prediction, velocity_var, threshold = (
            self._kernel_constants()
        )
        lim_x, lim_y = self.limits if self.limits is not None else (-1.0, -1.0)
        px, py, pth = (pose.x, pose.y, pose.theta) if pose is not None else (0.0, 0.0, 0.0)
        o = frame.odometry
        flags = frame_nb(
            x, p, status, dt, deceleration, accel_sigma, o.dx, o.dy, o.dtheta, rows, foot_x, foot_y, height, focal,
            self.ball_radius, fixed_sigma, size_px, at_prediction, GATE, RESTART_AFTER, velocity_var,
            threshold if pose is not None and team else -1.0, pose is not None, px, py, pth, lim_x, lim_y, self._out,
        )  # fmt: skip
        if had:
            self.source = "prediction"
        if flags & FRAME_SEEN:
            self.last_seen = time
            self.source = "vision"
        if flags & FRAME_TEAM:  # not seen and uncertain: a teammate's ball, then publish
            assert pose is not None  # only asked for with a pose
            self._team(pose, team)
            return self._output(pose)
        return self._published(flags & FRAME_PUBLISHED != 0)

    def _kernel_constants(self) -> tuple[float, float, float, float, bool, float, float]:
        """The arguments of :func:`frame_nb` that come from ``params`` alone: rolling
        deceleration (m/s^2), acceleration sd (m/s^1.5), fixed angular sd (rad; -1 in ``adaptive``
        mode), image radius sd (px), sigmas at the prediction, velocity variance of a new ball
        ((m/s)^2), team threshold (m^2). Worked out again only when ``params`` is replaced (it is
        frozen)."""
        prm = self.params
        if prm is not self._consts_of:
            self._consts = (
                prm.rolling_deceleration, prm.accel_sigma, prm.fixed_sigma if prm.sigma_mode == "fixed" else -1.0,
                prm.size_sigma_px, prm.sigmas_at_prediction, prm.initial_velocity_sigma**2, prm.team_threshold,
            )  # fmt: skip
            self._consts_of = prm
        return self._consts

    # -- updates ---------------------------------------------------------------------------
    def _ball_rows(self, percepts: Percepts | None) -> tuple[NDArray[np.float64], float, float, float, float]:
        """This frame's ball percept rows (none without percepts or a camera matrix), the camera's
        foot (x, y, m, robot frame), its height above the ball centre (m) and focal length (px).

        The camera view (:attr:`~cognition.percepts.Percepts.camera_view`) is only asked for when
        there are ball rows."""
        if percepts is None:
            return _NO_ROWS, 0.0, 0.0, 0.0, 0.0
        lo, hi = percepts.span(_BALL)
        if hi == lo:
            return _NO_ROWS, 0.0, 0.0, 0.0, 0.0
        cam = percepts.camera_view
        if cam is None:
            return _NO_ROWS, 0.0, 0.0, 0.0, 0.0
        # distances are from the camera's foot; the focal length is the mean of the spec's two
        height, focal = cam[VIEW_Z] - self.ball_radius, 0.5 * (cam[VIEW_FX] + cam[VIEW_FY])
        return percepts.table_and_offsets[0][lo:hi], cam[VIEW_X], cam[VIEW_Y], height, focal

    def _needs_team(self) -> bool:
        """Whether the own position variance (trace, m^2) exceeds ``team_threshold`` (or there is no state)."""
        p = self.p
        if p is None:
            return True
        p00, p11 = p.item(0, 0), p.item(1, 1)  # Python floats
        return p00 + p11 > self.params.team_threshold

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
        x, p = self.x, self.p
        if x is None or p is None:
            return _no_ball()
        lim_x, lim_y = self.limits if self.limits is not None else (-1.0, -1.0)
        if pose is not None:
            return self._published(publish_nb(x, p, True, pose.x, pose.y, pose.theta, lim_x, lim_y, self._out))
        return self._published(publish_nb(x, p, False, 0.0, 0.0, 0.0, lim_x, lim_y, self._out))

    def _published(self, finite: bool) -> BallModel:
        """The ball model of the state just published (:func:`publish_nb`: position sd and field
        position in ``_out``); with ``finite`` false the state is dropped and there is no ball."""
        x, p = self.x, self.p
        if not finite or x is None or p is None:
            self.x = self.p = None  # NaN would read as a certain ball (max(0, nan) is 0)
            self.source = "none"
            return _no_ball()
        x0, x1, x2, x3 = x.tolist()
        sd, fx, fy = self._out.tolist()
        level: BallLevel = "valid" if sd < VALID_SIGMA else ("suspicious" if sd < SUSPICIOUS_SIGMA else "invalid")
        age = (self.time or 0.0) - self.last_seen
        p = p.copy()  # the state is updated in place; the output keeps this frame's covariance
        p.setflags(write=False)  # cheaper than through p.flags
        return BallModel(x0, x1, x2, x3, p, fx, fy, age, level, self.source)  # type: ignore[arg-type]
