"""Scripted players that act on their own localization estimate instead of their true pose.

:class:`LocalizingBrain` is the :class:`~cognition.behaviors.oracle_players.OracleBrain` with
one input swapped: each frame it runs a localization variant
(:func:`cognition.localization.make_localizer`) on its sensor frame and plays with the
estimated own pose. The ball, teammates and opponents still come from the oracle input
(``uses_oracle`` stays ``True``) until a world model provides them. The ``oracle`` variant is
the one exception that reads the true own pose, as a baseline.

Body states are the oracle players' (stand, position, keeper, strike, support, wait), decided
and carried out with the estimated pose. Localization and the world model of
:mod:`cognition.worldmodel` (Kalman ball, ball hypotheses, teammates' reports, team ball,
obstacles, goal model; the play does not use it yet) run in a
:class:`~cognition.worldmodel.beliefs.CognitionBeliefs`; the brain sends its
:class:`~cognition.worldmodel.messages.TeamMessage` reports with the estimated pose and
ball, spreading the team's message budget over the game.
The head has its own small state machine, so that the camera sees landmarks:

=====  =====================================================================================
state  behaviour
=====  =====================================================================================
ball   look at the ball (bearing from the estimated pose), as the oracle players do
scan   sweep the head yaw (robot frame) between ``-scan_yaw`` and ``+scan_yaw`` (rad) at
       ``scan_pitch``, starting on the side the head points to (its measured yaw); entered
       while the estimate is ``lost`` and for ``scan_duration`` s every ``scan_period`` s
       (player n shifted by n * ``player_offset`` s so that the team does not look away from
       the ball all at once)
=====  =====================================================================================

The scan is the scripted players' :class:`~cognition.behaviors.head_control.HeadSweep`, tuned
by the ``scan_*`` and ``player_offset`` fields of
:class:`~cognition.behaviors.head_control.HeadParams` (table and defaults in
:mod:`cognition.behaviors.head_control`); the other fields are not read here.
"""

from __future__ import annotations

from dataclasses import replace

from cognition.behaviors.head_control import HeadParams, HeadSweep
from cognition.behaviors.oracle_players import OracleBrain, OracleParams
from cognition.brain import BrainContext
from cognition.localization import VARIANTS, LocalizationParams, Localizer
from cognition.oracle import OracleInput
from cognition.representations import BallModel, BrainOutput, RobotPose, SensorFrame
from cognition.vision import VisionParams
from cognition.worldmodel import OBSTACLE_MODELS
from cognition.worldmodel.beliefs import Beliefs, CognitionBeliefs
from cognition.worldmodel.goal import GoalEstimate
from cognition.worldmodel.messages import Role
from cognition.worldmodel.obstacles import ObstacleGrid, ObstacleModel, ObstacleSectors
from cognition.worldmodel.team import TeamBallEstimate, TeamState

_ROLES = {"keeper": Role.KEEPER, "strike": Role.STRIKER, "support": Role.SUPPORTER}
"""The team-message role of each body state (others send :attr:`Role.NONE`)."""


class LocalizingBrain(OracleBrain):
    """A scripted player that localizes with ``variant`` and acts on the estimate.

    ``params`` tune the localization, ``oracle_params`` the scripted play, ``head_params``
    the head scans (only its ``scan_*`` and ``player_offset`` fields); ``obstacle_model``
    names the obstacle model (``sectors`` or ``grid``). Localization and world model run in a
    :class:`~cognition.worldmodel.beliefs.CognitionBeliefs` (``world_model``, built in
    :meth:`reset`); ``beliefs`` is its latest :class:`~cognition.worldmodel.beliefs.Beliefs`
    and the other world-model attributes are read-only views of it (``None`` before
    :meth:`reset`).
    """

    uses_oracle = True

    def __init__(
        self,
        variant: str,
        params: LocalizationParams | None = None,
        oracle_params: OracleParams | None = None,
        head_params: HeadParams | None = None,
        obstacle_model: str = "sectors",
        vision: VisionParams | None = None,
    ):
        if variant not in VARIANTS:
            raise ValueError(f"unknown localization variant {variant!r}; valid: {list(VARIANTS)}")
        if obstacle_model not in OBSTACLE_MODELS:
            raise ValueError(f"unknown obstacle model {obstacle_model!r}; valid: {list(OBSTACLE_MODELS)}")
        super().__init__(oracle_params)
        self.variant = variant
        self.localization_params = params or LocalizationParams()
        self.head_params = head_params or HeadParams()
        self.obstacle_model_name = obstacle_model
        self.vision = vision
        self.world_model: CognitionBeliefs | None = None
        """Localization and world model on the robot's own frames (built in :meth:`reset`)."""
        self.head_state = "ball"
        """The head's state: ``ball`` or ``scan`` (module docstring)."""
        self.sweep = HeadSweep(self.head_params)
        """The landmark scan: routine timing and the yaw sweep."""

    # -- read-only views of the world model -------------------------------------------------
    @property
    def beliefs(self) -> Beliefs | None:
        """The latest beliefs (frames in :mod:`cognition.worldmodel.beliefs`; ``None`` before the first frame)."""
        return self.world_model.latest if self.world_model is not None else None

    @property
    def localizer(self) -> Localizer | None:
        """The robot's localizer (``None`` before :meth:`reset`)."""
        return self.world_model.localizer if self.world_model is not None else None

    @property
    def pose(self) -> RobotPose | None:
        """The latest pose estimate (team frame; the localizer's initial pose before the first frame)."""
        return self.world_model.localizer.pose if self.world_model is not None else None

    @property
    def ball(self) -> BallModel | None:
        """The Kalman ball (robot and team frame) of the latest frame."""
        b = self.beliefs
        return b.ball if b is not None else None

    @property
    def team_ball(self) -> TeamBallEstimate | None:
        """The team's fused ball (team frame) of the latest frame."""
        b = self.beliefs
        return b.team_ball if b is not None else None

    @property
    def goal(self) -> GoalEstimate | None:
        """The goal seen in the latest head scans (robot frame)."""
        b = self.beliefs
        return b.goal if b is not None else None

    @property
    def team(self) -> TeamState | None:
        """Teammates' latest reports."""
        return self.world_model.team if self.world_model is not None else None

    @property
    def obstacles(self) -> ObstacleGrid | ObstacleSectors | None:
        """The obstacle model chosen by name (robot frame)."""
        return self.world_model.obstacles if self.world_model is not None else None

    @property
    def obstacle_model(self) -> ObstacleModel | None:
        """The obstacle model's output of the latest frame (robot frame)."""
        return self.world_model.obstacle_model if self.world_model is not None else None

    def rejected_inputs(self) -> dict[str, int]:
        """Sensor inputs the world model could not use, by kind (:meth:`CognitionBeliefs.rejected_inputs`)."""
        return self.world_model.rejected_inputs() if self.world_model is not None else {}

    # -- cognition ---------------------------------------------------------------------------
    def reset(self, context: BrainContext) -> None:
        """Remember the match facts and build a fresh world model (its localizer draws from the brain's stream)."""
        super().reset(context)
        self.world_model = CognitionBeliefs(
            context, self.variant, self.localization_params, self.obstacle_model_name, vision=self.vision
        )
        self.head_state = "ball"
        self.sweep = HeadSweep(self.head_params)

    def think(self, frame: SensorFrame, oracle: OracleInput | None) -> BrainOutput:
        """Localize, then play the oracle players' game with the estimated own pose."""
        if self.context is None or self.world_model is None:
            raise RuntimeError("LocalizingBrain.think called before reset()")
        if oracle is None:
            raise ValueError("LocalizingBrain needs the oracle input for the ball and the other robots")
        me = oracle.self_pose
        pose = self.world_model.update(frame, (me.x, me.y, me.theta)).pose
        believed = replace(oracle, self_pose=replace(me, x=pose.x, y=pose.y, theta=pose.theta))
        out = super().think(frame, believed)
        self.head_state = self._head_transition(frame, pose)
        if self.head_state == "scan":
            out = replace(out, motion=replace(out.motion, head=self.sweep.request(frame.time)))
        return out

    def _payload(self, frame: SensorFrame, oracle: OracleInput) -> bytes:
        """The team message (:meth:`CognitionBeliefs.message`) with the role of the current state."""
        assert self.world_model is not None
        return self.world_model.message(_ROLES.get(self.state, Role.NONE))

    # -- head ------------------------------------------------------------------------------
    def _head_transition(self, frame: SensorFrame, pose: RobotPose) -> str:
        """``scan`` while lost or a routine scan is due, else ``ball``; a new scan starts on the measured yaw's side."""
        assert self.context is not None
        wanted = "scan" if pose.lost or self.sweep.routine_due(frame.time, self.context.player_number) else "ball"
        if wanted == "scan" and self.head_state != "scan":
            self.sweep.begin(frame.time, frame.head.yaw)
        return wanted
