"""Beliefs: everything a behavior or a policy may read about the world, from one provider.

A behavior never reads the sensor frame's raw contents or the ground truth directly; it reads a
:class:`Beliefs`. Two providers make one per cognition frame, so that the same behavior or
policy runs on real cognition or on the truth (DESIGN "data flow": the ``truth`` mode swaps
localization and world model for oracle providers):

=====================  ============================================================================
provider               what it runs
=====================  ============================================================================
CognitionBeliefs       a localization variant (:func:`cognition.localization.make_localizer`), the
                       Kalman ball (Darmstadt V), the CMU ball hypotheses (IV.A, for active gaze),
                       teammates' messages and the team ball, the goal model (CMU IV.B) and an
                       obstacle model (Darmstadt VII); it also writes the robot's team message
TruthBeliefs           reads the :class:`~cognition.oracle.OracleInput`: exact pose, ball, robots
=====================  ============================================================================

Input the robot cannot trust never reaches a model: :class:`CognitionBeliefs` first runs the
frame through :class:`~cognition.inputs.InputCheck` (non-finite or implausible odometry
becomes no motion) and the team messages through :class:`~cognition.worldmodel.team.TeamState`
(invalid ones are dropped); :meth:`CognitionBeliefs.rejected_inputs` counts both by kind.

Frames: ``pose`` and ``team_ball`` and ``teammates`` are in the **team frame** (m, rad; +x
toward the opponent goal); ``ball`` holds robot-frame (``x, y, vx, vy``) and team-frame
(``field_x, field_y``) values; ``goal``, ``obstacles`` and ``look_at`` are in the **robot
frame** (m, +x forward, +y left).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import ClassVar, Literal

import numpy as np
from numpy.typing import NDArray

from cognition.brain import BrainContext
from cognition.gamestate import GameControlData
from cognition.geometry import wrap_angle
from cognition.inputs import InputCheck, merge_counts
from cognition.localization import VARIANTS, LocalizationParams, Localizer, make_localizer
from cognition.oracle import OracleInput
from cognition.representations import BallModel, RobotPose, SensorFrame
from cognition.vision import Vision, VisionParams
from cognition.worldmodel.ball import KalmanBallModel
from cognition.worldmodel.goal import GoalEstimate, GoalModel
from cognition.worldmodel.hypotheses import BallHypotheses
from cognition.worldmodel.kalman_ball import KalmanBallParams
from cognition.worldmodel.messages import MAX_POSE_STD, Role, TeamMessage
from cognition.worldmodel.obstacles import ObstacleGrid, ObstacleModel, ObstacleSectors
from cognition.worldmodel.team import TeamBallEstimate, TeamState, carpet_limits, rotate_covariance, team_ball

_EMPTY2 = np.zeros((0, 2))
_EMPTY3 = np.zeros((0, 3))
_EMPTY1 = np.zeros(0)
_ZERO3 = np.zeros((3, 3))
_ZERO4 = np.zeros((4, 4))
for _a in (_EMPTY2, _EMPTY3, _EMPTY1, _ZERO3, _ZERO4):
    _a.setflags(write=False)  # shared by every truth belief


@dataclass(frozen=True)
class Teammate:
    """What a robot knows of one teammate (team frame), from its latest message or the oracle."""

    number: int
    """Player number (1-based)."""
    x: float
    """Position (m, team frame)."""
    y: float
    theta: float
    """Heading (rad, team frame)."""
    age: float
    """Seconds since this information was sent (0 for the oracle)."""
    role: Role = Role.NONE
    fallen: bool = False
    penalized: bool = False
    ball_x: float = math.nan
    """The teammate's ball (m, team frame), NaN when it has none."""
    ball_y: float = math.nan

    @property
    def active(self) -> bool:
        """On the field and standing."""
        return not self.penalized and not self.fallen


@dataclass(frozen=True)
class Beliefs:
    """One robot's beliefs after one cognition frame (frames in the module docstring)."""

    time: float
    """Game time of the frame (s)."""
    player_number: int
    game: GameControlData
    """The latest GameController packet."""
    penalty: int
    """Own penalty code (0: playing)."""
    fallen: bool
    picked_up: bool
    pose: RobotPose
    """Own pose estimate (team frame) with covariance and the ``lost`` flag."""
    ball: BallModel
    """The own ball (robot and team frame), with its level ``valid``/``suspicious``/``invalid`` and age."""
    team_ball: TeamBallEstimate | None
    """The team's fused ball (team frame), ``None`` when nobody has one."""
    goal: GoalEstimate | None
    """The goal seen in the latest head scans (robot frame), ``None`` when no two posts are tracked."""
    teammates: tuple[Teammate, ...]
    obstacles: NDArray[np.float64] = field(default_factory=lambda: _EMPTY2)
    """K x 2 obstacle positions (robot frame, m)."""
    look_at: tuple[float, float] | None = None
    """Active gaze: a suspicious ball hypothesis (robot frame, m) the world model asks to check."""
    source: Literal["cognition", "truth"] = "cognition"

    @classmethod
    def of_frame(
        cls,
        frame: SensorFrame,
        player_number: int,
        pose: RobotPose,
        ball: BallModel,
        team_ball: TeamBallEstimate | None,
        goal: GoalEstimate | None,
        teammates: tuple[Teammate, ...],
        obstacles: NDArray[np.float64],
        look_at: tuple[float, float] | None,
        source: Literal["cognition", "truth"],
    ) -> Beliefs:
        """Beliefs with time, game state, penalty and body signals taken from ``frame``."""
        return cls(
            frame.time, player_number, frame.game, frame.penalty, frame.fallen, frame.picked_up,
            pose, ball, team_ball, goal, teammates, obstacles, look_at, source,
        )  # fmt: skip

    def to_robot(self, x: float, y: float) -> tuple[float, float]:
        """A team-frame point (m) in the robot frame of the estimated pose."""
        p = self.pose
        dx, dy = x - p.x, y - p.y
        c, s = math.cos(p.theta), math.sin(p.theta)
        return (c * dx + s * dy, -s * dx + c * dy)

    def to_field(self, x: float, y: float) -> tuple[float, float]:
        """A robot-frame point (m) in the team frame of the estimated pose."""
        p = self.pose
        c, s = math.cos(p.theta), math.sin(p.theta)
        return (p.x + c * x - s * y, p.y + s * x + c * y)

    def best_ball(self) -> tuple[float, float] | None:
        """The ball to play (team frame, m): the own ball while it is ``valid``, else the team ball,
        else the own ``suspicious`` ball; ``None`` when nobody knows where it is."""
        b = self.ball
        if b.level == "valid" and math.isfinite(b.field_x):
            return (b.field_x, b.field_y)
        if self.team_ball is not None:
            return (self.team_ball.x, self.team_ball.y)
        if b.level == "suspicious" and math.isfinite(b.field_x):
            return (b.field_x, b.field_y)
        return None


class CognitionBeliefs:
    """The full stack on the robot's own sensor frames (see the module table).

    ``variant`` names the localization (:data:`cognition.localization.VARIANTS`); the
    ``oracle`` variant needs the true pose passed to :meth:`update`. ``obstacle_model`` is
    ``sectors`` or ``grid``; ``ball_params`` tunes the Kalman ball (its observation noise model,
    Darmstadt V). Frames that carry a camera image instead of percepts go through the vision
    pipeline first (:class:`cognition.vision.Vision` with ``vision``, the colours and jersey of
    the context), so everything after it runs on the same percepts either way.

    :attr:`localization_cpu_seconds` sums the CPU time (s, this thread) of the localizer's
    updates, so that a study can report the cost of a variant per update.
    """

    def __init__(
        self,
        context: BrainContext,
        variant: str = "maturing",
        params: LocalizationParams | None = None,
        obstacle_model: str = "sectors",
        ball_params: KalmanBallParams | None = None,
        vision: VisionParams | None = None,
    ):
        from cognition.worldmodel import OBSTACLE_MODELS, make_obstacle_model

        if variant not in VARIANTS:
            raise ValueError(f"unknown localization variant {variant!r}; valid: {list(VARIANTS)}")
        if obstacle_model not in OBSTACLE_MODELS:
            raise ValueError(f"unknown obstacle model {obstacle_model!r}; valid: {list(OBSTACLE_MODELS)}")
        self.context = context
        self.variant = variant
        rng = context.rng if context.rng is not None else np.random.default_rng(context.player_number)
        self.localizer: Localizer = make_localizer(
            variant,
            context.field,
            params=params or LocalizationParams(),
            rng=rng,
            player_number=context.player_number,
            players_per_team=context.players_per_team,
        )
        self.ball_model = KalmanBallModel(
            0.5 * context.field.dims.ball_diameter, ball_params, limits=carpet_limits(context.field)
        )
        self.hypotheses = BallHypotheses()
        self.team = TeamState(context.player_number, context.field)
        self.obstacles: ObstacleGrid | ObstacleSectors = make_obstacle_model(obstacle_model)
        dims = context.field.dims
        self.goal_model = GoalModel(dims.goal_inner_width + dims.goal_post_diameter)
        self.latest: Beliefs | None = None
        """The beliefs of the latest frame (``None`` before the first)."""
        self.obstacle_model: ObstacleModel | None = None
        """The obstacle model's latest output (robot frame)."""
        self.inputs = InputCheck("cognition")
        """Counts the sensor input replaced before any model saw it (:mod:`cognition.inputs`)."""
        self.localization_cpu_seconds = 0.0
        """CPU time (s, this thread) spent in the localizer's updates so far."""
        self.vision_params = vision or VisionParams()
        self.vision: Vision | None = None
        """The vision pipeline, built at the first frame that carries a camera image."""
        # the representations of the current frame, written and read by the stages in order
        self._frame: SensorFrame
        self._true_pose: tuple[float, float, float] | None = None
        self._pose: RobotPose
        self._mates: list[TeamMessage] = []
        self._ball_now: BallModel
        self._look_at: tuple[float, float] | None = None
        self._team_ball_now: TeamBallEstimate | None = None
        self._goal_now: GoalEstimate | None = None

    def rejected_inputs(self) -> dict[str, int]:
        """Inputs dropped so far, by kind: odometry (:mod:`cognition.inputs`), the localizer's
        own checks, and team messages (``team_message_<reason>``, :mod:`cognition.worldmodel.team`)."""
        return merge_counts(
            self.inputs.rejected,
            self.localizer.rejected_inputs(),
            {f"team_message_{reason}": n for reason, n in self.team.rejected_by_reason.items()},
        )

    # -- the frame, stage by stage -----------------------------------------------------------
    STAGES: ClassVar[tuple[str, ...]] = (
        "input check", "vision", "localization", "team messages", "ball model", "ball hypotheses", "team ball",
        "obstacles", "goal model", "beliefs",
    )  # fmt: skip
    """The modules of one frame, in order (:meth:`run_stage`); ``vision`` does nothing on a frame
    that carries percepts."""

    def update(self, frame: SensorFrame, true_pose: tuple[float, float, float] | None = None) -> Beliefs:
        """Run localization and the world model on one frame (``true_pose``: only for ``oracle``):
        :meth:`begin`, every stage of :data:`STAGES` in order, :meth:`finish`."""
        self.begin(frame, true_pose)
        for stage in self.STAGES:
            self.run_stage(stage)
        return self.finish()

    def begin(self, frame: SensorFrame, true_pose: tuple[float, float, float] | None = None) -> None:
        """Start a frame; the stages then read and write its representations on this object."""
        self._frame = frame
        self._true_pose = true_pose

    def run_stage(self, stage: str) -> None:
        """Run the module ``stage`` (one of :data:`STAGES`, in order) on the current frame."""
        _STAGE_METHODS[stage](self)

    def finish(self) -> Beliefs:
        """The beliefs of the frame (after the ``beliefs`` stage)."""
        assert self.latest is not None
        return self.latest

    def _input_check(self) -> None:
        self._frame = self.inputs.frame(self._frame)

    def _vision(self) -> None:
        if self._frame.percepts is None and self._frame.image is not None:
            self._frame = self._see(self._frame)

    def _localize(self) -> None:
        started = time.thread_time()
        self._pose = self.localizer.update(self._frame, self._true_pose if self.variant == "oracle" else None)
        self.localization_cpu_seconds += time.thread_time() - started

    def _team_messages(self) -> None:
        self._mates = self.team.update(self._frame)

    def _ball(self) -> None:
        self._ball_now = self.ball_model.update(self._frame, self._pose, self._mates)

    def _ball_hypotheses(self) -> None:
        self._look_at = self.hypotheses.update(self._frame, self._pose, self._mates).look_at

    def _team_ball(self) -> None:
        self._team_ball_now = team_ball(
            self._ball_now, self._pose, self.context.player_number, self._mates, limits=self.team.limits
        )

    def _obstacles(self) -> None:
        f = self._frame
        self.obstacle_model = self.obstacles.update(f.time, f.odometry, f.percepts)

    def _goal(self) -> None:
        o = self._frame.odometry
        self.goal_model.move_robot(o.dx, o.dy, o.dtheta, 1.0 / self.context.cognition_hz)
        self.goal_model.add_percepts(self._frame.percepts)
        self._goal_now = self.goal_model.estimate()

    def _beliefs(self) -> None:
        frame = self._frame
        received = {number: t for number, (t, _) in self.team.latest.items()}
        teammates = tuple(
            Teammate(
                number=m.player, x=m.x, y=m.y, theta=m.theta, age=max(0.0, frame.time - received[m.player]),
                role=m.role, fallen=m.fallen, penalized=m.penalized,
                ball_x=m.ball_x if m.ball_valid else math.nan, ball_y=m.ball_y if m.ball_valid else math.nan,
            )
            for m in sorted(self._mates, key=lambda m: m.player)
        )  # fmt: skip
        assert self.obstacle_model is not None
        self.latest = Beliefs.of_frame(
            frame, self.context.player_number, self._pose, self._ball_now, self._team_ball_now, self._goal_now,
            teammates, self.obstacle_model.obstacles, self._look_at, "cognition",
        )  # fmt: skip

    def _see(self, frame: SensorFrame) -> SensorFrame:
        """The frame with the percepts its camera image shows (the image observation path)."""
        if self.vision is None:
            c = self.context
            self.vision = Vision(self.vision_params, c.field, c.colours or "modern", c.team)
        image = frame.image
        assert image is not None
        o = frame.odometry
        # the home team (0) defends the scheme's own_goal colour in the first half; sides switch at half time
        own_goal = int((self.context.team == 1) != (frame.game.first_half == 0))
        percepts = self.vision.detect(
            image.pixels, image.camera, image.time, frame.head.yaw_rate, frame.head.pitch_rate,
            walking=o.dx != 0.0 or o.dy != 0.0 or o.dtheta != 0.0, own_goal=own_goal,
        )  # fmt: skip
        return replace(frame, percepts=percepts)

    def message(self, role: Role = Role.NONE) -> bytes:
        """The team message (:mod:`cognition.worldmodel.messages`) of the latest beliefs: the
        estimated pose, the own Kalman ball in the team frame, the role and the flags."""
        b = self.latest
        if b is None:
            raise RuntimeError("CognitionBeliefs.message called before the first update()")
        pose, ball = b.pose, b.ball
        fields: dict[str, object] = {}
        if ball.level != "invalid" and math.isfinite(ball.field_x):
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
            pose_std=min(pose.position_std, MAX_POSE_STD), role=role, fallen=b.fallen, penalized=bool(b.penalty),
            lost=pose.lost, **fields,  # type: ignore[arg-type]
        )  # fmt: skip
        return msg.pack()


_STAGE_METHODS: dict[str, Callable[[CognitionBeliefs], None]] = {
    "input check": CognitionBeliefs._input_check,
    "vision": CognitionBeliefs._vision,
    "localization": CognitionBeliefs._localize,
    "team messages": CognitionBeliefs._team_messages,
    "ball model": CognitionBeliefs._ball,
    "ball hypotheses": CognitionBeliefs._ball_hypotheses,
    "team ball": CognitionBeliefs._team_ball,
    "obstacles": CognitionBeliefs._obstacles,
    "goal model": CognitionBeliefs._goal,
    "beliefs": CognitionBeliefs._beliefs,
}
"""The method of each stage of :data:`CognitionBeliefs.STAGES`."""
assert tuple(_STAGE_METHODS) == CognitionBeliefs.STAGES


class TruthBeliefs:
    """Beliefs read from the oracle input: the true pose (zero covariance), the true ball (always
    ``valid``, age 0), every robot, and the opponent goal from the field map."""

    def __init__(self, context: BrainContext):
        self.context = context
        f = context.field
        half_goal = 0.5 * (f.dims.goal_inner_width + f.dims.goal_post_diameter)
        self._goal = (f.half_length, half_goal)
        self.latest: Beliefs | None = None
        self._pending: tuple[SensorFrame, OracleInput | None] | None = None

    STAGES: ClassVar[tuple[str, ...]] = ("truth beliefs",)
    """The one module of a frame (:meth:`update` as a stage)."""

    def begin(self, frame: SensorFrame, oracle: OracleInput | None) -> None:
        """Start a frame (stage interface of :class:`CognitionBeliefs`)."""
        self._pending = (frame, oracle)

    def run_stage(self, stage: str) -> None:
        if stage != "truth beliefs":
            raise ValueError(f"TruthBeliefs has no stage {stage!r}; stages: {list(self.STAGES)}")
        assert self._pending is not None
        self.update(*self._pending)

    def finish(self) -> Beliefs:
        assert self.latest is not None
        return self.latest

    def update(self, frame: SensorFrame, oracle: OracleInput | None) -> Beliefs:
        """Turn this frame's oracle input into beliefs."""
        if oracle is None:
            raise ValueError("TruthBeliefs needs the oracle input (the brain must set uses_oracle = True)")
        me = oracle.self_pose
        pose = RobotPose(me.x, me.y, me.theta, _ZERO3, False, 0, _EMPTY3, _EMPTY1, "truth")
        c, s = math.cos(me.theta), math.sin(me.theta)
        dx, dy = oracle.ball_x - me.x, oracle.ball_y - me.y
        bvx, bvy = oracle.ball_vx, oracle.ball_vy
        ball = BallModel(
            x=c * dx + s * dy, y=-s * dx + c * dy, vx=c * bvx + s * bvy, vy=-s * bvx + c * bvy,
            covariance=_ZERO4, field_x=oracle.ball_x, field_y=oracle.ball_y, age=0.0,
            level="valid", source="vision",
        )  # fmt: skip
        gx, gy = self._goal
        left = (c * (gx - me.x) + s * (gy - me.y), -s * (gx - me.x) + c * (gy - me.y))
        right = (c * (gx - me.x) + s * (-gy - me.y), -s * (gx - me.x) + c * (-gy - me.y))
        goal = GoalEstimate(
            centre_x=0.5 * (left[0] + right[0]), centre_y=0.5 * (left[1] + right[1]), left=left, right=right,
            facing=wrap_angle(math.pi - me.theta), confidence=1.0,
        )  # fmt: skip
        teammates = tuple(
            Teammate(number=m.number, x=m.x, y=m.y, theta=m.theta, age=0.0, fallen=m.fallen, penalized=not m.active)
            for m in oracle.teammates
        )
        others = [
            (c * (p.x - me.x) + s * (p.y - me.y), -s * (p.x - me.x) + c * (p.y - me.y))
            for p in (*oracle.teammates, *oracle.opponents)
            if p.active
        ]
        obstacles = np.array(others) if others else _EMPTY2
        number = self.context.player_number
        tb = TeamBallEstimate(oracle.ball_x, oracle.ball_y, 0.0, 0.0, 0.0, (number,))
        self.latest = Beliefs.of_frame(frame, number, pose, ball, tb, goal, teammates, obstacles, None, "truth")
        return self.latest


def _clip(v: float, limit: float) -> float:
    """``v`` limited to [-limit, limit] (the message's ranges)."""
    return max(-limit, min(limit, float(v)))
