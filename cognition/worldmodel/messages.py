"""The team message: what a robot tells its teammates, packed into at most 128 bytes.

SPL robots share their state by UDP broadcast within the team, at most 128 bytes per
message and 1200 messages per game (see :mod:`cognition.gamestate`). A
:class:`TeamMessage` carries the sender's pose estimate and its quality, its ball estimate
with age and covariance (the Darmstadt paper, Sec. V.B: teammates' ball states in field
coordinates), its role intention and its fallen, penalised and lost flags.

Wire format (little-endian, :data:`SIZE` = 58 bytes; all positions in the sender's **team
frame**, m, rad, s):

======  ======  ==========  ================================================================
offset  bytes   type        content
======  ======  ==========  ================================================================
0       2       2s          magic ``b"TS"``
2       1       B           format version (:data:`VERSION`)
3       1       B           sender's player number (1..7)
4       1       B           flags: 1 fallen, 2 penalised, 4 pose lost, 8 ball valid
5       1       B           role intention (:class:`Role`)
6       12      3f          pose x, y (m), theta (rad)
18      4       f           pose quality: position standard deviation (m)
22      16      4f          ball x, y (m), vx, vy (m/s)
38      4       f           ball age: seconds since the sender last saw the ball itself
42      12      3f          ball position covariance xx, xy, yy (m^2)
54      2       H           ball confidence in [0, 1] times 65535
56      2       H           CRC-16/CCITT of bytes 0..55
======  ======  ==========  ================================================================

:func:`unpack` rejects anything else with :class:`MalformedMessageError` (wrong size, magic,
version, checksum, player number, role, non-finite or out-of-range values), so a corrupt or
truncated packet can never crash a receiving robot. Floats travel as float32: a message
that came out of :func:`unpack` packs to the same bytes again.
"""

from __future__ import annotations

import binascii
import math
import struct
from dataclasses import dataclass
from enum import IntEnum

from cognition.gamestate import TEAM_MESSAGE_MAX_BYTES

MAGIC = b"TS"
VERSION = 1
_BODY = struct.Struct("<2sBBBB3ff4ff3fH")
_CRC = struct.Struct("<H")
SIZE = _BODY.size + _CRC.size
"""Bytes of a packed message."""
assert SIZE <= TEAM_MESSAGE_MAX_BYTES

FALLEN, PENALIZED, LOST, BALL_VALID = 1, 2, 4, 8
_MAX_POSITION = 100.0  # m: anything beyond this is not a soccer field
_MAX_SPEED = 50.0  # m/s


class MalformedMessageError(ValueError):
    """A received packet is not a valid team message."""


class Role(IntEnum):
    """The role a player intends to play."""

    NONE = 0
    KEEPER = 1
    STRIKER = 2
    SUPPORTER = 3
    DEFENDER = 4


@dataclass(frozen=True)
class TeamMessage:
    """One robot's report to its team (team frame; fields as in the module docstring)."""

    player: int
    x: float = 0.0
    y: float = 0.0
    theta: float = 0.0
    pose_std: float = 1.0
    ball_x: float = 0.0
    ball_y: float = 0.0
    ball_vx: float = 0.0
    ball_vy: float = 0.0
    ball_age: float = 1e9
    ball_cov_xx: float = 1.0
    ball_cov_xy: float = 0.0
    ball_cov_yy: float = 1.0
    ball_confidence: float = 0.0
    ball_valid: bool = False
    role: Role = Role.NONE
    fallen: bool = False
    penalized: bool = False
    lost: bool = False

    def __post_init__(self) -> None:
        _validate(self, ValueError)

    def pack(self) -> bytes:
        """The wire format (:data:`SIZE` bytes)."""
        flags = (
            (FALLEN if self.fallen else 0)
            | (PENALIZED if self.penalized else 0)
            | (LOST if self.lost else 0)
            | (BALL_VALID if self.ball_valid else 0)
        )
        body = _BODY.pack(
            MAGIC, VERSION, self.player, flags, int(self.role), self.x, self.y, self.theta, self.pose_std,
            self.ball_x, self.ball_y, self.ball_vx, self.ball_vy, min(self.ball_age, 3.0e38),
            self.ball_cov_xx, self.ball_cov_xy, self.ball_cov_yy, round(self.ball_confidence * 65535),
        )  # fmt: skip
        return body + _CRC.pack(binascii.crc_hqx(body, 0xFFFF))


def unpack(data: bytes) -> TeamMessage:
    """Decode a packet; :class:`MalformedMessageError` names what is wrong with an invalid one."""
    if not isinstance(data, bytes | bytearray | memoryview):
        raise MalformedMessageError(f"team message must be bytes, got {type(data).__name__}")
    data = bytes(data)
    if len(data) != SIZE:
        raise MalformedMessageError(f"team message has {len(data)} bytes, expected {SIZE}")
    body = data[: _BODY.size]
    (crc,) = _CRC.unpack(data[_BODY.size :])
    if binascii.crc_hqx(body, 0xFFFF) != crc:
        raise MalformedMessageError("team message checksum mismatch (corrupted)")
    (magic, version, player, flags, role, x, y, th, pstd, bx, by, bvx, bvy, age, cxx, cxy, cyy, conf) = _BODY.unpack(
        body
    )
    if magic != MAGIC:
        raise MalformedMessageError(f"team message magic is {magic!r}, expected {MAGIC!r}")
    if version != VERSION:
        raise MalformedMessageError(f"team message version {version} is not supported (expected {VERSION})")
    if flags & ~(FALLEN | PENALIZED | LOST | BALL_VALID):
        raise MalformedMessageError(f"team message has unknown flag bits {flags:#x}")
    if role not in Role._value2member_map_:
        raise MalformedMessageError(f"team message role {role} is unknown")
    try:
        return TeamMessage(
            player=player, x=x, y=y, theta=th, pose_std=pstd, ball_x=bx, ball_y=by, ball_vx=bvx, ball_vy=bvy,
            ball_age=age, ball_cov_xx=cxx, ball_cov_xy=cxy, ball_cov_yy=cyy, ball_confidence=conf / 65535,
            ball_valid=bool(flags & BALL_VALID), role=Role(role), fallen=bool(flags & FALLEN),
            penalized=bool(flags & PENALIZED), lost=bool(flags & LOST),
        )  # fmt: skip
    except ValueError as e:
        raise MalformedMessageError(f"team message content is invalid: {e}") from None


def _validate(m: TeamMessage, error: type[Exception]) -> None:
    if isinstance(m.player, bool) or not isinstance(m.player, int) or not 1 <= m.player <= 7:
        raise error(f"TeamMessage.player must be an integer in 1..7, got {m.player!r}")
    for name in ("x", "y", "ball_x", "ball_y"):
        v = getattr(m, name)
        if not math.isfinite(v) or abs(v) > _MAX_POSITION:
            raise error(f"TeamMessage.{name} must be finite and within {_MAX_POSITION} m, got {v!r}")
    for name in ("ball_vx", "ball_vy"):
        v = getattr(m, name)
        if not math.isfinite(v) or abs(v) > _MAX_SPEED:
            raise error(f"TeamMessage.{name} must be finite and within {_MAX_SPEED} m/s, got {v!r}")
    if not math.isfinite(m.theta) or abs(m.theta) > 4.0:
        raise error(f"TeamMessage.theta must be an angle in [-pi, pi] (rad), got {m.theta!r}")
    for name in ("pose_std", "ball_age", "ball_cov_xx", "ball_cov_yy"):
        v = getattr(m, name)
        if not v >= 0.0 or math.isnan(v):
            raise error(f"TeamMessage.{name} must be >= 0, got {v!r}")
    if not math.isfinite(m.ball_cov_xy) or m.ball_cov_xy * m.ball_cov_xy > m.ball_cov_xx * m.ball_cov_yy * (1 + 1e-6):
        raise error("TeamMessage ball covariance must be positive semi-definite")
    if not 0.0 <= m.ball_confidence <= 1.0:
        raise error(f"TeamMessage.ball_confidence must be in [0, 1], got {m.ball_confidence!r}")
