"""What a behaviour or a policy reads about the world: :class:`Beliefs` (the ``beliefs``
representation of :mod:`cognition.pipeline`) and what it knows of each :class:`Teammate`.

Frames: ``pose`` and ``team_ball`` and ``teammates`` are in the **team frame** (m, rad; +x
toward the opponent goal); ``ball`` holds robot-frame (``x, y, vx, vy``) and team-frame
(``field_x, field_y``) values; ``goal``, ``obstacles`` and ``look_at`` are in the **robot
frame** (m, +x forward, +y left). :mod:`cognition.worldmodel.beliefs` makes them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from cognition.gamestate import GameControlData
from cognition.records import fast_init
from cognition.representations import BallModel, RobotPose, SensorFrame
from cognition.worldmodel.goal import GoalEstimate
from cognition.worldmodel.messages import Role
from cognition.worldmodel.team import TeamBallEstimate

_EMPTY2 = np.zeros((0, 2))
_EMPTY2.setflags(write=False)


@fast_init
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


@fast_init
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
