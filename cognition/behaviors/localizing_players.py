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

from cognition.behaviors.oracle_players import OracleBrain, OracleParams
from cognition.brain import BrainContext
from cognition.localization import VARIANTS, LocalizationParams, Localizer
from cognition.oracle import OracleInput
from cognition.params import check_non_negative, check_positive
from cognition.representations import BallModel, BrainOutput, HeadRequest, RobotPose, SensorFrame
from cognition.worldmodel import OBSTACLE_MODELS
from cognition.worldmodel.beliefs import Beliefs, CognitionBeliefs
from cognition.worldmodel.goal import GoalEstimate
from cognition.worldmodel.messages import Role
from cognition.worldmodel.obstacles import ObstacleGrid, ObstacleModel, ObstacleSectors
from cognition.worldmodel.team import TeamBallEstimate, TeamState

_ROLES = {"keeper": Role.KEEPER, "strike": Role.STRIKER, "support": Role.SUPPORTER}
"""The team-message role of each body state (others send :attr:`Role.NONE`)."""


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
    Localization and world model run in a
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
        self.obstacle_model_name = obstacle_model
        self.world_model: CognitionBeliefs | None = None
        """Localization and world model on the robot's own frames (built in :meth:`reset`)."""
        self.head_state = "ball"
        self._scan_start = 0.0
        self._scan_side = 1.0

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

    # -- cognition ---------------------------------------------------------------------------
    def reset(self, context: BrainContext) -> None:
        """Remember the match facts and build a fresh world model (its localizer draws from the brain's stream)."""
        super().reset(context)
        self.world_model = CognitionBeliefs(context, self.variant, self.localization_params, self.obstacle_model_name)
        self.head_state = "ball"
        self._scan_start = 0.0
        self._scan_side = 1.0

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
            out = replace(out, motion=replace(out.motion, head=self._scan_head(frame)))
        return out

    def _payload(self, frame: SensorFrame, oracle: OracleInput) -> bytes:
        """The team message (:meth:`CognitionBeliefs.message`) with the role of the current state."""
        assert self.world_model is not None
        return self.world_model.message(_ROLES.get(self.state, Role.NONE))

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
