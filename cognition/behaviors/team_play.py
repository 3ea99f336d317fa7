"""Scripted team play on beliefs: roles from teammates' messages and one state machine per robot.

:class:`ScriptedBrain` reads only its :class:`~cognition.worldmodel.beliefs.Beliefs` (the
cognition stack on its own sensor frames, or the oracle providers in ``truth`` mode) and acts
with the skills of :mod:`cognition.behaviors.skills`. Roles (:func:`assign_role`): player 1
keeps goal; of the active field players, the one nearest to the ball strikes (teammates'
positions come from their messages; the current striker gets a ``striker_bonus`` so that the
role does not flicker); of the rest, the one nearest to the own goal defends, the others
support. CMU IV.B describes the striker's kick (goal model when close, pose when far).

=========  ===================================================================================
state      behaviour
=========  ===================================================================================
stand      INITIAL, SET, FINISHED, penalised, fallen or carried: do nothing
position   READY: walk to the kickoff position
keeper     PLAYING, player 1: between ball and goal; clears a close ball
striker    PLAYING, nearest to the ball: approach, align, kick toward the goal
defender   PLAYING: between the ball and the own goal
supporter  PLAYING: a spot behind and beside the ball
wait       PLAYING during the opponent's kickoff or set play: keep away from the ball
=========  ===================================================================================

The head runs :class:`~cognition.behaviors.head_control.HeadControl` (ball, active gaze, scans).
With cognition beliefs the robot sends team messages (pose, ball, role), spreading the team's
budget over the game (:func:`message_due`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import ClassVar

from cognition.behaviors.head_control import HeadControl, HeadParams
from cognition.behaviors.message_budget import message_due
from cognition.behaviors.skills import SkillParams, Skills
from cognition.brain import BrainContext, think_by_stages
from cognition.gamestate import GameStateId, SetPlay
from cognition.oracle import OracleInput
from cognition.pipeline import CognitionConfig
from cognition.representations import BrainOutput, MotionRequest, RobotPose, SensorFrame
from cognition.worldmodel.beliefs import Beliefs, CognitionBeliefs, Teammate
from cognition.worldmodel.messages import Role

STRIKER_BONUS = 0.3
"""Metres the current striker's distance to the ball is shortened by when roles are compared."""


_READY, _PLAYING, _NO_SET_PLAY, _KEEPER = GameStateId.READY, GameStateId.PLAYING, SetPlay.NONE, Role.KEEPER
_ROLE_STATES = {Role.STRIKER: "striker", Role.DEFENDER: "defender"}
"""Enum members and the role -> state table as module names: in CPython 3.11 reading a member off
its class (``GameStateId.READY``) costs about 0.1 us, a module name a tenth of that (the same objects)."""


def assign_role(b: Beliefs, current: Role = Role.NONE, own_goal_x: float = -4.5, bonus: float = STRIKER_BONUS) -> Role:
    """This robot's role from its beliefs (module docstring); ``own_goal_x`` in m, team frame."""
    if b.player_number == 1:
        return Role.KEEPER
    ball = b.best_ball()
    if ball is None:
        return Role.SUPPORTER
    bx, by = ball

    def ball_dist(x: float, y: float) -> float:
        return math.hypot(bx - x, by - y)

    mine = ball_dist(b.pose.x, b.pose.y) - (bonus if current == Role.STRIKER else 0.0)
    mates = [m for m in b.teammates if m.active and m.number != 1]
    striker: Teammate | None = None
    best = mine
    for m in mates:
        d = ball_dist(m.x, m.y) - (bonus if m.role == Role.STRIKER else 0.0)
        best_number = b.player_number if striker is None else striker.number
        if d < best - 1e-9 or (abs(d - best) <= 1e-9 and m.number < best_number):
            striker, best = m, d
    if striker is None:
        return Role.STRIKER
    return _back_role(b, [m for m in mates if m is not striker], own_goal_x)


def _back_role(b: Beliefs, backs: list[Teammate], own_goal_x: float) -> Role:
    """Of the non-strikers (this robot and ``backs``), the one nearest the own goal defends, the others support."""
    own = math.hypot(b.pose.x - own_goal_x, b.pose.y)
    for m in backs:
        d = math.hypot(m.x - own_goal_x, m.y)
        if d < own - 1e-9 or (abs(d - own) <= 1e-9 and m.number < b.player_number):
            return Role.SUPPORTER
    return Role.DEFENDER


class ScriptedBrain:
    """The scripted player (module docstring) on the beliefs of ``cognition`` (default: the full
    stack, :class:`~cognition.pipeline.CognitionConfig`; :data:`~cognition.pipeline.TRUTH`: the
    oracle providers, a baseline)."""

    def __init__(
        self,
        cognition: CognitionConfig | None = None,
        skill_params: SkillParams | None = None,
        head_params: HeadParams | None = None,
        message_interval: float = 1.0,
    ):
        self.cognition = cognition or CognitionConfig()
        """Which provider fills each slot of the cognition frame."""
        self.skill_params = skill_params
        self.head_params = head_params
        self.message_interval = message_interval
        self.uses_oracle = self.cognition.reads_ground_truth
        self.context: BrainContext | None = None
        self.provider: CognitionBeliefs | None = None
        self.beliefs: Beliefs | None = None
        """The latest beliefs."""
        self.pose: RobotPose | None = None
        """The latest pose estimate (cognition beliefs only; the match records its error)."""
        self.role = Role.NONE
        self.state = "stand"
        self._frame: SensorFrame | None = None
        self._motion = MotionRequest()
        self._message: bytes | None = None
        self._on_truth = self.cognition.beliefs == "truth"

    def reset(self, context: BrainContext) -> None:
        """Build the cognition frame, skills and head control for a new match."""
        self.context = context
        self.provider = CognitionBeliefs(context, self.cognition)
        self.skills = Skills(context, self.skill_params)
        self.head = HeadControl(context, self.head_params)
        self.beliefs = None
        self.pose = None
        self.role = Role.NONE
        self.state = "stand"
        self._last_message = -1e9
        self._stage_runs: dict[str, Callable[[], None]] = self.provider.stage_calls()
        """What each stage calls: the cognition frame's modules on its blackboard, then ours."""
        self._stage_runs.update({"behaviour": self._behave, "team message out": self._message_out})
        self._stages = self.provider.stages + self.BEHAVIOUR_STAGES
        self._runs = tuple(self._stage_runs[stage] for stage in self._stages)

    def rejected_inputs(self) -> dict[str, int]:
        """Sensor inputs the cognition stack could not use, by kind (none on truth beliefs)."""
        return self.provider.rejected_inputs() if self.provider is not None else {}

    # -- the frame, stage by stage (:class:`cognition.brain.StagedBrain`) ----------------------
    BEHAVIOUR_STAGES: ClassVar[tuple[str, ...]] = ("behaviour", "team message out")

    @property
    def stages(self) -> tuple[str, ...]:
        """The modules of one frame: the cognition frame's, then behaviour and the team message."""
        if self.provider is None:
            raise RuntimeError("ScriptedBrain.stages read before reset()")
        return self._stages

    def think(self, frame: SensorFrame, oracle: OracleInput | None) -> BrainOutput:
        """Update the beliefs, choose the state, act (every stage of :attr:`stages` in order)."""
        return think_by_stages(self, frame, oracle)

    def begin(self, frame: SensorFrame, oracle: OracleInput | None) -> None:
        """Start a frame."""
        if self.provider is None or self.context is None:
            raise RuntimeError("ScriptedBrain.think called before reset()")
        self._frame = frame
        self._message = None
        self.provider.begin(frame, oracle)

    def run_stage(self, stage: str) -> None:
        """Run the module ``stage`` of :attr:`stages` on the current frame."""
        self._stage_runs[stage]()

    def stage_runs(self) -> tuple[Callable[[], None], ...]:
        """The stages of :attr:`stages` as calls without arguments, in order (:func:`~cognition.brain.stage_runs`)."""
        return self._runs

    def finish(self) -> BrainOutput:
        """The motion request and team message of the frame."""
        return BrainOutput(self._motion, self._message)  # motion, message

    def _behave(self) -> None:
        assert self.provider is not None
        b = self.provider.finish()
        if not self._on_truth:
            self.pose = b.pose
        self.beliefs = b
        self.state = self._transition(b)
        motion = self._act(b)
        self._motion = MotionRequest(motion.walk, motion.kick, self.head.request(b))

    def _message_out(self) -> None:
        assert self.context is not None
        frame = self._frame
        if not self._on_truth and message_due(
            frame.game, self.context.team_number, self.context.players_per_team, frame.time,
            self._last_message, self.message_interval,
        ):  # fmt: skip
            self._last_message = frame.time
            self._message = self.provider.message(self.role)

    def _transition(self, b: Beliefs) -> str:
        assert self.context is not None
        g = b.game
        if b.penalty or b.fallen or b.picked_up:
            return "stand"
        if g.state == _READY:
            return "position"
        if g.state != _PLAYING:
            return "stand"
        self.role = assign_role(b, self.role, -self.context.field.half_length)
        if self.role == _KEEPER:
            return "keeper"
        ours = g.kicking_team == self.context.team_number
        if not ours and (g.set_play != _NO_SET_PLAY or g.secondary_time > 0):
            return "wait"
        return _ROLE_STATES.get(self.role, "supporter")

    def _act(self, b: Beliefs) -> MotionRequest:
        assert self.context is not None
        s, sk = self.state, self.skills
        if s == "position":
            return sk.go_to_kickoff(b, b.game.kicking_team == self.context.team_number)
        if s == "keeper":
            return sk.keeper(b)
        if s == "striker":
            return sk.kick_to_goal(b)
        if s == "defender":
            return sk.defend(b)
        if s == "supporter":
            return sk.support(b, self.context.player_number)
        if s == "wait":
            return sk.keep_away(b)
        return sk.stand(b)
