"""Beliefs: everything a behavior or a policy may read about the world, and the frame that makes them.

A behavior never reads the sensor frame's raw contents or the ground truth directly; it reads a
:class:`Beliefs`, the ``beliefs`` representation of the cognition pipeline
(:mod:`cognition.pipeline`). :class:`CognitionBeliefs` runs one robot's planned modules
(:mod:`cognition.modules`) on a blackboard and hands out their beliefs, so that the same
behavior or policy runs on real cognition or on the truth (DESIGN "data flow": the ``truth``
mode swaps localization and world model for oracle providers). The ``beliefs`` slot has two
providers, both here:

=====================  ============================================================================
provider               what it does
=====================  ============================================================================
``cognition``          :class:`BeliefsModule`: assembles the frame's robot pose (a localization
                       variant), Kalman ball (Darmstadt V), ball hypotheses (CMU IV.A, for active
                       gaze), teammates and team ball, goal (CMU IV.B) and obstacles (Darmstadt
                       VII); :meth:`CognitionBeliefs.message` writes the robot's team message
``truth``              :class:`TruthModule` (:class:`TruthBeliefs`): reads the
                       :class:`~cognition.oracle.OracleInput`: exact pose, ball, robots
=====================  ============================================================================

Input the robot cannot trust never reaches a model: the pipeline first runs the frame through
:class:`~cognition.inputs.InputCheck` (non-finite or implausible odometry
becomes no motion) and the team messages through :class:`~cognition.worldmodel.team.TeamState`
(invalid ones are dropped); :meth:`CognitionBeliefs.rejected_inputs` counts both by kind.

Frames: ``pose`` and ``team_ball`` and ``teammates`` are in the **team frame** (m, rad; +x
toward the opponent goal); ``ball`` holds robot-frame (``x, y, vx, vy``) and team-frame
(``field_x, field_y``) values; ``goal``, ``obstacles`` and ``look_at`` are in the **robot
frame** (m, +x forward, +y left).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import partial
from operator import attrgetter
from typing import TypeVar

import numpy as np

from cognition.brain import BrainContext
from cognition.geometry import wrap_angle
from cognition.inputs import merge_counts
from cognition.localization import Localizer
from cognition.modules import (
    MODULES,
    BallModule,
    Blackboard,
    GoalModule,
    HypothesesModule,
    InputCheckModule,
    LocalizationModule,
    Module,
    ModuleFactory,
    ObstacleModule,
    TeamBallModule,
    TeamMessagesModule,
    VisionModule,
)
from cognition.oracle import OracleInput
from cognition.pipeline import DECLARATIONS, CognitionConfig, plan
from cognition.representations import BallModel, RobotPose, SensorFrame
from cognition.vision import Vision
from cognition.worldmodel.ball import KalmanBallModel
from cognition.worldmodel.goal import GoalEstimate, GoalModel
from cognition.worldmodel.hypotheses import BallHypotheses
from cognition.worldmodel.messages import MAX_POSE_STD, Role, TeamMessage
from cognition.worldmodel.obstacles import ObstacleGrid, ObstacleModel, ObstacleSectors
from cognition.worldmodel.representations import Beliefs, Teammate
from cognition.worldmodel.team import TeamBallEstimate, TeamState, rotate_covariance

M = TypeVar("M")

_BY_PLAYER = attrgetter("player")
"""Sort key of team messages: the sender's player number."""
_EMPTY2 = np.zeros((0, 2))
_EMPTY3 = np.zeros((0, 3))
_EMPTY1 = np.zeros(0)
_ZERO3 = np.zeros((3, 3))
_ZERO4 = np.zeros((4, 4))
for _a in (_EMPTY2, _EMPTY3, _EMPTY1, _ZERO3, _ZERO4):
    _a.setflags(write=False)  # shared by every truth belief


class CognitionBeliefs:
    """One robot's cognition frame: the modules :func:`cognition.pipeline.plan` picks for its
    :class:`~cognition.pipeline.CognitionConfig`, run in order on a shared blackboard.

    With the default configuration that is the full stack of the module table (input check,
    vision on camera images, localization, team messages, Kalman ball, ball hypotheses, team
    ball, obstacles, goal model, beliefs); with ``beliefs="truth"`` it is the one oracle
    provider (:class:`TruthBeliefs`). The context's ``observation`` says what the frames carry;
    a configuration that needs what they do not carry is a :class:`~cognition.pipeline.PipelineError`
    here. :attr:`stages` names the modules of a frame, in order (:meth:`run_stage`).
    """

    def __init__(self, context: BrainContext, config: CognitionConfig | None = None):
        self.context = context
        self.config = config or CognitionConfig()
        planned = plan(self.config, context.observation)
        self.stages: tuple[str, ...] = tuple(d.stage for d in planned)
        """The modules of one frame, in the order they run."""
        self.modules: dict[str, Module] = {}
        for d in planned:
            slot = _SLOT_OF[d.stage]
            self.modules[d.stage] = MODULES[(slot, self.config.provider(slot))](context, self.config)
        """Every module of the frame by stage name."""
        self.board = Blackboard()
        """The representations of the current frame."""
        self.latest: Beliefs | None = None
        """The beliefs of the latest frame (``None`` before the first)."""

    # -- the modules, for callers that inspect them (``None`` when the configuration has none) --
    def _module(self, stage: str, kind: type[M]) -> M | None:
        m = self.modules.get(stage)
        return m if isinstance(m, kind) else None

    @property
    def variant(self) -> str:
        """The localization variant (``truth`` on truth beliefs)."""
        return "truth" if self.config.beliefs == "truth" else self.config.localization

    @property
    def localizer(self) -> Localizer | None:
        """The localization variant's localizer (``None`` on truth beliefs)."""
        m = self._module("localization", LocalizationModule)
        return m.localizer if m is not None else None

    @property
    def localization_cpu_seconds(self) -> float:
        """CPU time (s, this thread) spent in the localizer's updates so far (0 without one)."""
        m = self._module("localization", LocalizationModule)
        return m.cpu_seconds if m is not None else 0.0

    @property
    def ball_model(self) -> KalmanBallModel | None:
        m = self._module("ball model", BallModule)
        return m.model if m is not None else None

    @property
    def hypotheses(self) -> BallHypotheses | None:
        m = self._module("ball hypotheses", HypothesesModule)
        return m.model if m is not None else None

    @property
    def team(self) -> TeamState | None:
        m = self._module("team messages", TeamMessagesModule)
        return m.team if m is not None else None

    @property
    def obstacles(self) -> ObstacleGrid | ObstacleSectors | None:
        m = self._module("obstacles", ObstacleModule)
        return m.model if m is not None else None

    @property
    def obstacle_model(self) -> ObstacleModel | None:
        """The obstacle model's latest output (robot frame)."""
        return self.board.obstacles

    @property
    def goal_model(self) -> GoalModel | None:
        m = self._module("goal model", GoalModule)
        return m.model if m is not None else None

    @property
    def vision(self) -> Vision | None:
        """The vision pipeline (built at the first frame that carries a camera image)."""
        m = self._module("vision", VisionModule)
        return m.vision if m is not None else None

    def rejected_inputs(self) -> dict[str, int]:
        """Inputs dropped so far, by kind: odometry (:mod:`cognition.inputs`), the localizer's
        own checks, and team messages (``team_message_<reason>``, :mod:`cognition.worldmodel.team`)."""
        check = self._module("input check", InputCheckModule)
        loc = self._module("localization", LocalizationModule)
        team = self.team
        return merge_counts(
            check.check.rejected if check is not None else {},
            loc.localizer.rejected_inputs() if loc is not None else {},
            {f"team_message_{reason}": n for reason, n in team.rejected_by_reason.items()} if team is not None else {},
        )

    # -- the frame, stage by stage -----------------------------------------------------------
    def update(self, frame: SensorFrame, ground_truth: OracleInput | None = None) -> Beliefs:
        """One frame: :meth:`begin`, every stage of :attr:`stages` in order, :meth:`finish`.
        ``ground_truth`` reaches only the declared oracle providers."""
        self.begin(frame, ground_truth)
        for stage in self.stages:
            self.run_stage(stage)
        return self.finish()

    def begin(self, frame: SensorFrame, ground_truth: OracleInput | None = None) -> None:
        """Start a frame; the stages then read and write the blackboard."""
        self.board.start(frame, ground_truth)

    def run_stage(self, stage: str) -> None:
        """Run the module ``stage`` (one of :attr:`stages`, in order) on the current frame."""
        self.modules[stage].run(self.board)

    def stage_calls(self) -> dict[str, Callable[[], None]]:
        """Each stage of :attr:`stages`, in order, as a call without arguments: its module's
        ``run`` bound to the blackboard (what :meth:`run_stage` does, without looking it up),
        for brains that run the stages themselves."""
        return {stage: partial(self.modules[stage].run, self.board) for stage in self.stages}

    def finish(self) -> Beliefs:
        """The beliefs of the frame (after the last stage)."""
        b = self.board.beliefs
        assert b is not None
        self.latest = b
        return b

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


class BeliefsModule:
    """``beliefs`` = ``cognition``: the frame's representations assembled into one :class:`Beliefs`."""

    def __init__(self, context: BrainContext, config: CognitionConfig) -> None:
        self.player_number = context.player_number

    def run(self, board: Blackboard) -> None:
        frame = board.frame
        heard = board.heard or {}
        now = frame.time
        teammates = tuple(
            Teammate(  # number, x, y, theta, age (max(0, now - heard), as a comparison), role, fallen, penalized, ball
                m.player, m.x, m.y, m.theta, a if (a := now - heard[m.player]) > 0.0 else 0.0, m.role, m.fallen,
                m.penalized, m.ball_x if m.ball_valid else math.nan, m.ball_y if m.ball_valid else math.nan,
            )
            for m in sorted(board.teammates or (), key=_BY_PLAYER)
        )  # fmt: skip
        assert board.pose is not None and board.ball is not None
        obstacles = board.obstacles.obstacles if board.obstacles is not None else _EMPTY2
        board.beliefs = Beliefs.of_frame(
            frame, self.player_number, board.pose, board.ball, board.team_ball, board.goal,
            teammates, obstacles, board.look_at, "cognition",
        )  # fmt: skip


class TruthModule:
    """``beliefs`` = ``truth``: the oracle provider (:class:`TruthBeliefs`) on the ground truth."""

    def __init__(self, context: BrainContext, config: CognitionConfig) -> None:
        self.truth = TruthBeliefs(context)

    def run(self, board: Blackboard) -> None:
        board.beliefs = self.truth.update(board.frame, board.ground_truth)


class TruthBeliefs:
    """Beliefs read from the oracle input: the true pose (zero covariance), the true ball (always
    ``valid``, age 0), every robot, and the opponent goal from the field map."""

    def __init__(self, context: BrainContext):
        self.context = context
        f = context.field
        half_goal = 0.5 * (f.dims.goal_inner_width + f.dims.goal_post_diameter)
        self._goal = (f.half_length, half_goal)
        self.latest: Beliefs | None = None

    def update(self, frame: SensorFrame, oracle: OracleInput | None) -> Beliefs:
        """Turn this frame's oracle input into beliefs."""
        if oracle is None:
            raise ValueError("TruthBeliefs needs the oracle input (the brain must set uses_oracle = True)")
        me = oracle.self_pose
        mx, my, mth = me.x, me.y, me.theta
        pose = RobotPose(mx, my, mth, _ZERO3, False, 0, _EMPTY3, _EMPTY1, "truth")
        c, s = math.cos(mth), math.sin(mth)
        bx, by = oracle.ball_x, oracle.ball_y
        dx, dy = bx - mx, by - my
        bvx, bvy = oracle.ball_vx, oracle.ball_vy
        ball = BallModel(
            c * dx + s * dy, -s * dx + c * dy, c * bvx + s * bvy, -s * bvx + c * bvy, _ZERO4, bx, by, 0.0,
            "valid", "vision",
        )  # fmt: skip
        gx, gy = self._goal
        left = (c * (gx - mx) + s * (gy - my), -s * (gx - mx) + c * (gy - my))
        right = (c * (gx - mx) + s * (-gy - my), -s * (gx - mx) + c * (-gy - my))
        goal = GoalEstimate(
            0.5 * (left[0] + right[0]), 0.5 * (left[1] + right[1]), left, right, wrap_angle(math.pi - mth), 1.0
        )
        mates = oracle.teammates
        none = Role.NONE
        teammates = tuple([Teammate(m.number, m.x, m.y, m.theta, 0.0, none, m.fallen, not m.active) for m in mates])
        others = [
            (c * (p.x - mx) + s * (p.y - my), -s * (p.x - mx) + c * (p.y - my))
            for group in (mates, oracle.opponents)
            for p in group
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


_CLASSES: dict[str, ModuleFactory] = {
    "input check": InputCheckModule,
    "vision": VisionModule,
    "localization": LocalizationModule,
    "team messages": TeamMessagesModule,
    "ball": BallModule,
    "hypotheses": HypothesesModule,
    "team_ball": TeamBallModule,
    "obstacles": ObstacleModule,
    "goal": GoalModule,
}
"""The class of every built-in slot but ``beliefs`` (each builds the provider its configuration names)."""
MODULES.update({(slot, name): cls for slot, cls in _CLASSES.items() for name in DECLARATIONS[slot]})
MODULES[("beliefs", "cognition")] = BeliefsModule
MODULES[("beliefs", "truth")] = TruthModule
assert set(MODULES) == {(slot, name) for slot, opts in DECLARATIONS.items() for name in opts}

_SLOT_OF: dict[str, str] = {d.stage: slot for slot, opts in DECLARATIONS.items() for d in opts.values()}
"""The slot of every stage name."""
