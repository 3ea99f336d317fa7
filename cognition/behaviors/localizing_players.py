"""Scripted players that act on their own localization estimate instead of their true pose.

:class:`LocalizingBrain` is the :class:`~cognition.behaviors.oracle_players.OracleBrain` with
one input swapped: each frame it runs a localization variant
(:func:`cognition.localization.make_localizer`) on its sensor frame and plays with the
estimated own pose. The ball, teammates and opponents still come from the oracle input
(``uses_oracle`` stays ``True``) until a world model provides them. The ``oracle`` variant is
the one exception that reads the true own pose, as a baseline.

Body states are the oracle players' (stand, position, keeper, strike, support, wait), decided
and carried out with the estimated pose. The brain also runs the world model of
:mod:`cognition.worldmodel` (Kalman ball, ball hypotheses, teammates' reports, team ball,
72-sector obstacles, goal model; the play does not use it yet) and sends
:class:`~cognition.worldmodel.messages.TeamMessage` reports with its estimated pose and
ball, spreading the team's message budget over the game.
The head has its own small state machine, so that the camera sees landmarks:

=====  =====================================================================================
state  behaviour
=====  =====================================================================================
ball   look at the ball (bearing from the estimated pose), as the oracle players do
scan   sweep the head yaw between ``-scan_yaw`` and ``+scan_yaw`` (rad) at ``scan_pitch``,
       starting on the side the head points to; entered while the estimate is ``lost``
       and for ``scan_duration`` seconds every ``scan_period`` seconds (shifted per
       player so that the team does not look away from the ball all at once)
=====  =====================================================================================

=================  =======  ========================================================
HeadScanParams     default  meaning
=================  =======  ========================================================
scan_period        5.0      seconds between the starts of two routine scans
scan_duration      1.0      length of one sweep from one side to the other (s)
scan_yaw           1.4      sweep amplitude (rad, both sides)
scan_pitch         0.3      head pitch while scanning (rad, positive looks down)
scan_speed         4.0      maximum head speed requested while scanning (rad/s)
player_offset      0.7      the routine scan of player n starts n * offset s later
=================  =======  ========================================================
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from cognition.behaviors.oracle_players import OracleBrain, OracleParams
from cognition.brain import BrainContext
from cognition.localization import VARIANTS, LocalizationParams, Localizer, make_localizer
from cognition.oracle import OracleInput
from cognition.params import check_non_negative, check_positive
from cognition.representations import BallModel, BrainOutput, HeadRequest, RobotPose, SensorFrame
from cognition.worldmodel import OBSTACLE_MODELS, make_obstacle_model
from cognition.worldmodel.ball import KalmanBallModel
from cognition.worldmodel.goal import GoalEstimate, GoalModel
from cognition.worldmodel.hypotheses import BallBelief, BallHypotheses
from cognition.worldmodel.messages import Role, TeamMessage
from cognition.worldmodel.obstacles import ObstacleGrid, ObstacleModel, ObstacleSectors
from cognition.worldmodel.team import TeamBallEstimate, TeamState, rotate_covariance, team_ball


@dataclass(frozen=True)
class HeadScanParams:
    """When and how the head scans for landmarks (table in the module docstring)."""

    scan_period: float = 5.0
    scan_duration: float = 1.0
    scan_yaw: float = 1.4
    scan_pitch: float = 0.3
    scan_speed: float = 4.0
    player_offset: float = 0.7

    def __post_init__(self) -> None:
        o = "HeadScanParams"
        check_positive(o, scan_period=self.scan_period, scan_duration=self.scan_duration, scan_speed=self.scan_speed)
        check_non_negative(o, scan_yaw=self.scan_yaw, player_offset=self.player_offset)
        if not math.isfinite(self.scan_pitch):
            raise ValueError(f"{o}.scan_pitch must be a finite number, got {self.scan_pitch!r}")
        if self.scan_duration > self.scan_period:
            raise ValueError(
                f"{o}.scan_duration ({self.scan_duration}) must not exceed scan_period ({self.scan_period})"
            )


class LocalizingBrain(OracleBrain):
    """A scripted player that localizes with ``variant`` and acts on the estimate.

    ``params`` tune the localization, ``oracle_params`` the scripted play, ``scan_params``
    the head scans; ``obstacle_model`` names the obstacle model (``sectors`` or ``grid``).
    ``localizer`` and ``pose`` (the latest :class:`~cognition.representations.RobotPose`,
    team frame) exist after :meth:`reset`.
    """

    uses_oracle = True

    def __init__(
        self,
        variant: str,
        params: LocalizationParams | None = None,
        oracle_params: OracleParams | None = None,
        scan_params: HeadScanParams | None = None,
        obstacle_model: str = "sectors",
    ):
        if variant not in VARIANTS:
            raise ValueError(f"unknown localization variant {variant!r}; valid: {list(VARIANTS)}")
        if obstacle_model not in OBSTACLE_MODELS:
            raise ValueError(f"unknown obstacle model {obstacle_model!r}; valid: {list(OBSTACLE_MODELS)}")
        super().__init__(oracle_params)
        self.variant = variant
        self.localization_params = params or LocalizationParams()
        self.scan_params = scan_params or HeadScanParams()
        self.localizer: Localizer | None = None
        """The robot's localizer (built in :meth:`reset`)."""
        self.pose: RobotPose | None = None
        """The latest pose estimate (team frame; ``None`` before :meth:`reset`)."""
        self.ball_model: KalmanBallModel | None = None
        """The Kalman ball (robot frame), fed with percepts, odometry and teammates' reports."""
        self.hypotheses = BallHypotheses()
        """The CMU multi-hypothesis ball."""
        self.team = TeamState(1)
        """Teammates' latest reports."""
        self.obstacle_model_name = obstacle_model
        self.obstacles: ObstacleGrid | ObstacleSectors = make_obstacle_model(obstacle_model)
        """The obstacle model chosen by name (robot frame)."""
        self.goal_model: GoalModel | None = None
        """Goal-post tracks over head scans (CMU IV.B)."""
        self.goal: GoalEstimate | None = None
        self.ball: BallModel | None = None
        self.belief: BallBelief | None = None
        self.team_ball: TeamBallEstimate | None = None
        self.obstacle_model: ObstacleModel | None = None
        self.head_state = "ball"
        self._scan_start = 0.0
        self._scan_side = 1.0

    def reset(self, context: BrainContext) -> None:
        """Remember the match facts and build a fresh localizer from the brain's random stream."""
        super().reset(context)
        rng = context.rng if context.rng is not None else np.random.default_rng(context.player_number)
        self.localizer = make_localizer(
            self.variant,
            context.field,
            params=self.localization_params,
            rng=rng,
            player_number=context.player_number,
            players_per_team=context.players_per_team,
        )
        self.pose = self.localizer.pose
        self.ball_model = KalmanBallModel(0.5 * context.field.dims.ball_diameter)
        self.hypotheses = BallHypotheses()
        self.team = TeamState(context.player_number)
        self.obstacles = make_obstacle_model(self.obstacle_model_name)
        self.obstacle_model = None
        dims = context.field.dims
        self.goal_model = GoalModel(dims.goal_inner_width + dims.goal_post_diameter)
        self.goal = None
        self.ball = None
        self.belief = None
        self.team_ball = None
        self.head_state = "ball"
        self._scan_start = 0.0
        self._scan_side = 1.0

    def think(self, frame: SensorFrame, oracle: OracleInput | None) -> BrainOutput:
        """Localize, then play the oracle players' game with the estimated own pose."""
        if self.context is None or self.localizer is None:
            raise RuntimeError("LocalizingBrain.think called before reset()")
        if oracle is None:
            raise ValueError("LocalizingBrain needs the oracle input for the ball and the other robots")
        me = oracle.self_pose
        truth = (me.x, me.y, me.theta) if self.variant == "oracle" else None
        pose = self.localizer.update(frame, truth)
        self.pose = pose
        mates = self.team.update(frame)
        assert self.ball_model is not None
        self.ball = self.ball_model.update(frame, pose, mates)
        self.belief = self.hypotheses.update(frame, pose, mates)
        self.team_ball = team_ball(self.ball, pose, self.context.player_number, mates)
        self.obstacle_model = self.obstacles.update(frame.time, frame.odometry, frame.percepts)
        assert self.goal_model is not None
        o = frame.odometry
        self.goal_model.move_robot(o.dx, o.dy, o.dtheta, 1.0 / self.context.cognition_hz)
        self.goal_model.add_percepts(frame.percepts)
        self.goal = self.goal_model.estimate()
        believed = replace(oracle, self_pose=replace(me, x=pose.x, y=pose.y, theta=pose.theta))
        out = super().think(frame, believed)
        self.head_state = self._head_transition(frame, pose)
        if self.head_state == "scan":
            out = replace(out, motion=replace(out.motion, head=self._scan_head(frame)))
        return out

    def _payload(self, frame: SensorFrame, oracle: OracleInput) -> bytes:
        """The team message (:mod:`cognition.worldmodel.messages`): the estimated pose, the own
        Kalman ball in the team frame, the role, and the fallen, penalised and lost flags."""
        assert self.context is not None and self.pose is not None
        pose, ball = self.pose, self.ball
        role = {"keeper": Role.KEEPER, "strike": Role.STRIKER, "support": Role.SUPPORTER}.get(self.state, Role.NONE)
        fields: dict[str, object] = {}
        if ball is not None and ball.level != "invalid" and math.isfinite(ball.field_x):
            c, s = math.cos(pose.theta), math.sin(pose.theta)
            cxx, cxy, cyy = rotate_covariance(ball.covariance, pose.theta)
            fields = {
                "ball_x": _clip(ball.field_x, 99.0), "ball_y": _clip(ball.field_y, 99.0),
                "ball_vx": _clip(c * ball.vx - s * ball.vy, 49.0), "ball_vy": _clip(s * ball.vx + c * ball.vy, 49.0),
                "ball_age": min(ball.age, 1e6), "ball_cov_xx": cxx, "ball_cov_xy": cxy, "ball_cov_yy": cyy,
                "ball_confidence": 1.0 if ball.level == "valid" else 0.5, "ball_valid": True,
            }  # fmt: skip
        msg = TeamMessage(
            player=self.context.player_number, x=_clip(pose.x, 99.0), y=_clip(pose.y, 99.0), theta=pose.theta,
            pose_std=min(pose.position_std, 1e6), role=role, fallen=frame.fallen, penalized=bool(frame.penalty),
            lost=pose.lost, **fields,  # type: ignore[arg-type]
        )  # fmt: skip
        return msg.pack()

    # -- head ------------------------------------------------------------------------------
    def _head_transition(self, frame: SensorFrame, pose: RobotPose) -> str:
        assert self.context is not None
        p = self.scan_params
        phase = (frame.time - self.context.player_number * p.player_offset) % p.scan_period
        wanted = "scan" if pose.lost or phase < p.scan_duration else "ball"
        if wanted == "scan" and self.head_state != "scan":
            self._scan_start = frame.time
            self._scan_side = 1.0 if frame.head.yaw >= 0.0 else -1.0
        return wanted

    def _scan_head(self, frame: SensorFrame) -> HeadRequest:
        """Triangle sweep: from ``side * scan_yaw`` to the other side in ``scan_duration``, and back."""
        p = self.scan_params
        u = max(0.0, frame.time - self._scan_start) / p.scan_duration
        leg = math.floor(u)
        frac = u - leg
        pos = frac if leg % 2 == 0 else 1.0 - frac
        yaw = self._scan_side * p.scan_yaw * (1.0 - 2.0 * pos)
        return HeadRequest(yaw=yaw, pitch=p.scan_pitch, speed=p.scan_speed)


def _clip(v: float, limit: float) -> float:
    """``v`` limited to [-limit, limit] (the message's ranges)."""
    return max(-limit, min(limit, float(v)))
