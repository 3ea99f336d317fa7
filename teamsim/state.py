"""Ground-truth snapshot types of the simulated world.

These are the simulator's own types: they never reach a brain (only the oracle input,
:mod:`cognition.oracle`, carries truth, and it is built from these explicitly).

All poses are in the **world frame**: metres and radians, origin at the field centre, x
along the field toward the goal that team 0 attacks in the first half, y to the left of x,
theta counter-clockwise from +x and wrapped to (-pi, pi].
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class RobotTruth:
    """True state of one robot (world frame)."""

    team: int
    """Team index: 0 (home) or 1 (away)."""
    number: int
    """Player number, 1-based; number 1 is the goalkeeper."""
    x: float
    """Position (m, world frame)."""
    y: float
    """Position (m, world frame)."""
    theta: float
    """Heading (rad, world frame)."""
    vx: float = 0.0
    """Velocity (m/s, world frame)."""
    vy: float = 0.0
    """Velocity (m/s, world frame)."""
    fallen: bool = False
    """The robot lies on the ground and is getting up."""
    penalized: bool = False
    """The robot is removed from the field by a penalty."""
    picked_up: bool = False
    """The robot's feet are off the ground (carried by a referee)."""
    head_yaw: float = 0.0
    """Head yaw relative to the torso (rad)."""


@dataclass(frozen=True)
class WorldSnapshot:
    """Everything true about the world at one instant."""

    time: float
    """Simulated time since the start of the match (s)."""
    robots: tuple[RobotTruth, ...]
    """All robots, team 0 first, each team in player-number order."""
    ball_x: float
    """Ball centre (m, world frame)."""
    ball_y: float
    """Ball centre (m, world frame)."""
    ball_vx: float = 0.0
    """Ball velocity (m/s, world frame)."""
    ball_vy: float = 0.0
    """Ball velocity (m/s, world frame)."""

    def robot(self, team: int, number: int) -> RobotTruth:
        """The robot with this team index and player number."""
        for r in self.robots:
            if r.team == team and r.number == number:
                return r
        raise KeyError(f"no robot {number} in team {team}")
