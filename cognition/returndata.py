"""The status packet a robot sends to the GameController: RoboCupGameControlReturnData v4.

Every robot on an SPL field tells the GameController that it is alive, at 0.5 to 2 Hz, by
UDP unicast to port 3939 (:data:`cognition.gamestate.GAMECONTROLLER_RETURN_PORT`); the
GameController shows the robots online and, in its monitor, where each robot believes it is
and where it believes the ball is. This module mirrors the official C struct (header
``"RGrt"``, struct version 4, 32 bytes, little-endian, no padding) field for field:

==========  ========  ============  =============================================================
offset      C type    field         meaning and what :meth:`ReturnData.unpack` accepts
==========  ========  ============  =============================================================
0           char[4]   header        ``b"RGrt"``
4           uint8     version       4
5           uint8     playerNum     player number, 1..20 (``MAX_NUM_PLAYERS``)
6           uint8     teamNum       GameController team number, 0..255
7           uint8     fallen        1 fallen, 0 can play (nothing else)
8           float[3]  pose          x, y (mm) and theta (rad) in the robot's team frame: origin at
                                    the centre, +x toward the goal the robot attacks, theta
                                    counter-clockwise from +x; finite
20          float     ballAge       seconds since the robot last saw the ball, -1 if it never
                                    did; finite and >= -1
24          float[2]  ball          ball position relative to the robot (mm): +x forward, +y to the
                                    left; finite
==========  ========  ============  =============================================================

The floats are IEEE-754 single precision on the wire, so a value read back is the float32
nearest to what was packed (under 0.06 mm at 1 km). The official GameController rejects only
NaN in the float fields; this decoder also rejects infinities and ball ages below -1, which no
robot can mean. :meth:`ReturnData.unpack` raises ``ValueError`` naming the first problem
(length, header, version, or field with the value found); :meth:`ReturnData.pack` checks the
same ranges and raises ``ValueError`` (``TypeError`` for a value of the wrong type), so what
is packed always decodes again.
"""

from __future__ import annotations

import math
import operator
import struct
from dataclasses import dataclass

from cognition.gamestate import MAX_NUM_PLAYERS
from cognition.representations import BallModel, RobotPose

RETURN_HEADER = b"RGrt"
RETURN_VERSION = 4
_LAYOUT = struct.Struct("<4sBBBBffffff")
RETURN_PACKET_SIZE = _LAYOUT.size
"""Bytes of one status packet (32)."""
BALL_NEVER_SEEN = -1.0
"""``ball_age`` of a robot that has not seen the ball yet (s)."""
_FLOAT32_MAX = 3.4028234663852886e38


@dataclass(frozen=True)
class ReturnData:
    """One robot's status packet (RoboCupGameControlReturnData v4), in the units of the wire."""

    player_number: int
    """Player number, 1..20."""
    team_number: int
    """GameController team number, 0..255."""
    fallen: bool = False
    """Whether the robot lies on the ground."""
    x: float = 0.0
    """Own position estimate, team frame (mm)."""
    y: float = 0.0
    """Own position estimate, team frame (mm)."""
    theta: float = 0.0
    """Own heading estimate, team frame (rad, counter-clockwise from +x)."""
    ball_age: float = BALL_NEVER_SEEN
    """Seconds since the robot last saw the ball; :data:`BALL_NEVER_SEEN` (-1) if never."""
    ball_x: float = 0.0
    """Ball position relative to the robot, forward (mm)."""
    ball_y: float = 0.0
    """Ball position relative to the robot, to the left (mm)."""

    def pack(self) -> bytes:
        """The 32 little-endian bytes of the C struct; ``ValueError`` (``TypeError``) names a
        field outside the ranges of the module table."""
        _check(self)
        return _LAYOUT.pack(
            RETURN_HEADER,
            RETURN_VERSION,
            operator.index(self.player_number),
            operator.index(self.team_number),
            1 if self.fallen else 0,
            self.x,
            self.y,
            self.theta,
            self.ball_age,
            self.ball_x,
            self.ball_y,
        )

    @classmethod
    def unpack(cls, data: bytes) -> ReturnData:
        """Parse one status packet; ``ValueError`` names what is wrong with a malformed one."""
        if not isinstance(data, bytes | bytearray | memoryview):
            raise TypeError(f"ReturnData packet must be bytes, got {type(data).__name__}")
        if len(data) != RETURN_PACKET_SIZE:
            raise ValueError(f"ReturnData packet must be {RETURN_PACKET_SIZE} bytes, got {len(data)}")
        header, version, player, team, fallen, x, y, theta, age, bx, by = _LAYOUT.unpack(data)
        if header != RETURN_HEADER:
            raise ValueError(f"ReturnData header must be {RETURN_HEADER!r}, got {header!r}")
        if version != RETURN_VERSION:
            raise ValueError(f"ReturnData version must be {RETURN_VERSION}, got {version}")
        if fallen not in (0, 1):
            raise ValueError(f"ReturnData.fallen must be 0 or 1, got {fallen}")
        out = cls(player, team, fallen == 1, x, y, theta, age, bx, by)
        _check(out)
        return out


def status_packet(
    player_number: int, team_number: int, fallen: bool, pose: RobotPose | None, ball: BallModel | None
) -> ReturnData:
    """The status a robot reports from its beliefs: ``pose`` (team frame, m and rad) and ``ball``
    (robot frame, m; its ``age`` in s) converted to the wire's millimetres.

    A robot without a pose estimate reports the origin; one that has never seen the ball (no
    ball model, ``source`` ``"none"`` or a non-finite age) reports :data:`BALL_NEVER_SEEN` and
    the ball at its feet. Non-finite estimates are reported as unknown in the same way instead
    of making the packet invalid."""
    x = y = theta = 0.0
    if pose is not None and math.isfinite(pose.x) and math.isfinite(pose.y) and math.isfinite(pose.theta):
        x, y, theta = _mm(pose.x), _mm(pose.y), math.remainder(pose.theta, math.tau)
    age, bx, by = BALL_NEVER_SEEN, 0.0, 0.0
    seen = ball is not None and ball.source != "none" and math.isfinite(ball.age) and ball.age >= 0.0
    if seen and ball is not None and math.isfinite(ball.x) and math.isfinite(ball.y):
        age, bx, by = min(float(ball.age), _FLOAT32_MAX), _mm(ball.x), _mm(ball.y)
    return ReturnData(int(player_number), int(team_number), bool(fallen), x, y, theta, age, bx, by)


def _mm(metres: float) -> float:
    """Metres as millimetres, clipped to the float32 range."""
    return max(-_FLOAT32_MAX, min(_FLOAT32_MAX, float(metres) * 1000.0))


def _check(r: ReturnData) -> None:
    """``ValueError`` (``TypeError``) naming the first field of ``r`` outside the module table."""
    for name, low, high in (("player_number", 1, MAX_NUM_PLAYERS), ("team_number", 0, 255)):
        value = getattr(r, name)
        try:
            v = operator.index(value)
        except TypeError:
            raise TypeError(f"ReturnData.{name} must be an integer, got {value!r}") from None
        if not low <= v <= high:
            raise ValueError(f"ReturnData.{name} must be in {low}..{high}, got {value!r}")
    if not isinstance(r.fallen, bool):
        raise TypeError(f"ReturnData.fallen must be a bool, got {r.fallen!r}")
    for name in ("x", "y", "theta", "ball_age", "ball_x", "ball_y"):
        value = getattr(r, name)
        if not isinstance(value, int | float) or isinstance(value, bool):
            raise TypeError(f"ReturnData.{name} must be a number, got {value!r}")
        if not math.isfinite(value) or abs(value) > _FLOAT32_MAX:
            raise ValueError(f"ReturnData.{name} must be a finite float32, got {value!r}")
    if r.ball_age < BALL_NEVER_SEEN:
        raise ValueError(f"ReturnData.ball_age must be -1 (never seen) or more, got {r.ball_age!r}")
