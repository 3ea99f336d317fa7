"""The oracle input: ground truth, handed only to brains that declare ``uses_oracle``.

Everything here is expressed in the receiving robot's **team frame** (metres, radians;
origin at the field centre, +x toward the opponent goal), so an oracle brain never needs to
know which side its team plays on. This is the only path by which truth reaches
``cognition``; regular brains receive ``None`` instead.
"""

from __future__ import annotations

from dataclasses import dataclass

from cognition.records import fast_init


@fast_init
@dataclass(frozen=True)
class OraclePose:
    """A robot's true pose in the receiver's team frame."""

    number: int
    """Player number (1-based)."""
    x: float
    """Position (m)."""
    y: float
    """Position (m)."""
    theta: float
    """Heading (rad)."""
    active: bool = True
    """False while the robot is penalised (removed from the field)."""
    fallen: bool = False


@fast_init
@dataclass(frozen=True)
class OracleInput:
    """Ground truth for an oracle brain (team frame of the receiving robot)."""

    self_pose: OraclePose
    teammates: tuple[OraclePose, ...]
    """All other robots of the own team."""
    opponents: tuple[OraclePose, ...]
    ball_x: float
    """Ball position (m)."""
    ball_y: float
    ball_vx: float
    """Ball velocity (m/s)."""
    ball_vy: float
