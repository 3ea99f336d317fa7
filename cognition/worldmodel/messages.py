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

Accepted content (checked when a :class:`TeamMessage` is built and when one is unpacked; every
float must be finite):

==========================  ======================  ==============================================
field                       accepted                why this bound
==========================  ======================  ==============================================
player                      1..7                    SPL team sizes
flags, role                 the bits above, Role    nothing else is defined
x, y, ball_x, ball_y        within +-100 m          wire limit (:data:`MAX_POSITION`); the receiver
                                                    (:class:`~cognition.worldmodel.team.TeamState`)
                                                    also wants them on the carpet plus a margin
theta                       within +-4 rad          pi plus float32 rounding (:data:`MAX_ANGLE`)
ball_vx, ball_vy            within +-50 m/s         far beyond any kick (:data:`MAX_BALL_SPEED`)
pose_std                    0..100 m                a larger sd says nothing more (:data:`MAX_POSE_STD`)
ball_age                    0..1e9 s                1e9 s stands for "never seen" (:data:`MAX_BALL_AGE`)
ball_cov_xx, ball_cov_yy    0..100 m^2              a 10 m sd says nothing more (:data:`MAX_BALL_VARIANCE`)
ball_cov_xy                 xy^2 <= xx yy (1+1e-6)  positive semi-definite, with float32 slack
ball_confidence             0..1                    a probability
==========================  ======================  ==============================================

:func:`unpack` rejects anything else with :class:`MalformedMessageError`, whose ``reason`` is one
of :data:`REJECT_REASONS` (``format``: not bytes, wrong size, magic or version; ``checksum``;
``non_finite``; ``out_of_range``; ``covariance``: not positive semi-definite), so a corrupt,
truncated or absurd packet can never crash a receiving robot or poison its world model.
Building a :class:`TeamMessage` with such content raises the same error (a ``ValueError``).
Floats travel as float32: a message that came out of :func:`unpack` packs to the same bytes
again.
"""

from __future__ import annotations

import binascii
import math
import numbers
import struct
from dataclasses import dataclass
from enum import IntEnum

from cognition.gamestate import TEAM_MESSAGE_MAX_BYTES
from cognition.records import fast_init

MAGIC = b"TS"
VERSION = 1
_BODY = struct.Struct("<2sBBBB3ff4ff3fH")
_CRC = struct.Struct("<H")
SIZE = _BODY.size + _CRC.size
"""Bytes of a packed message."""
assert SIZE <= TEAM_MESSAGE_MAX_BYTES

FALLEN, PENALIZED, LOST, BALL_VALID = 1, 2, 4, 8
MAX_POSITION = 100.0
"""Largest absolute coordinate (m) the message carries; the receiver checks the carpet itself."""
MAX_ANGLE = 4.0
"""Largest absolute heading (rad): pi with room for float32 rounding."""
MAX_BALL_SPEED = 50.0
"""Largest absolute ball velocity component (m/s)."""
MAX_POSE_STD = 100.0
"""Largest pose standard deviation (m)."""
MAX_BALL_AGE = 1.0e9
"""Largest ball age (s); the default, for a ball never seen."""
MAX_BALL_VARIANCE = 100.0
"""Largest ball position variance (m^2)."""
_PSD_SLACK = 1e-6

REJECT_REASONS = ("format", "checksum", "non_finite", "out_of_range", "covariance")
"""Reasons :func:`unpack` gives for a rejected packet (:attr:`MalformedMessageError.reason`)."""


class MalformedMessageError(ValueError):
    """A packet, or the content of a message being built, is not a valid team message."""

    def __init__(self, message: str, reason: str):
        super().__init__(message)
        self.reason = reason
        """Why: one of :data:`REJECT_REASONS`."""


class Role(IntEnum):
    """The role a player intends to play."""

    NONE = 0
    KEEPER = 1
    STRIKER = 2
    SUPPORTER = 3
    DEFENDER = 4


@fast_init
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
        _validate(self)

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
            self.ball_x, self.ball_y, self.ball_vx, self.ball_vy, self.ball_age,
            self.ball_cov_xx, self.ball_cov_xy, self.ball_cov_yy, round(self.ball_confidence * 65535),
        )  # fmt: skip
        return body + _CRC.pack(binascii.crc_hqx(body, 0xFFFF))


def unpack(data: bytes) -> TeamMessage:
    """Decode a packet; :class:`MalformedMessageError` names what is wrong with an invalid one
    and gives the reason (:data:`REJECT_REASONS`)."""
    if not isinstance(data, bytes | bytearray | memoryview):
        raise MalformedMessageError(f"team message must be bytes, got {type(data).__name__}", "format")
    data = bytes(data)
    if len(data) != SIZE:
        raise MalformedMessageError(f"team message has {len(data)} bytes, expected {SIZE}", "format")
    body = data[: _BODY.size]
    (crc,) = _CRC.unpack(data[_BODY.size :])
    if binascii.crc_hqx(body, 0xFFFF) != crc:
        raise MalformedMessageError("team message checksum mismatch (corrupted)", "checksum")
    (magic, version, player, flags, role, x, y, th, pstd, bx, by, bvx, bvy, age, cxx, cxy, cyy, conf) = _BODY.unpack(
        body
    )
    if magic != MAGIC:
        raise MalformedMessageError(f"team message magic is {magic!r}, expected {MAGIC!r}", "format")
    if version != VERSION:
        raise MalformedMessageError(f"team message version {version} is not supported (expected {VERSION})", "format")
    if flags & ~(FALLEN | PENALIZED | LOST | BALL_VALID):
        raise MalformedMessageError(f"team message has unknown flag bits {flags:#x}", "out_of_range")
    if role not in Role._value2member_map_:
        raise MalformedMessageError(f"team message role {role} is unknown", "out_of_range")
    return TeamMessage(
        player=player, x=x, y=y, theta=th, pose_std=pstd, ball_x=bx, ball_y=by, ball_vx=bvx, ball_vy=bvy,
        ball_age=age, ball_cov_xx=cxx, ball_cov_xy=cxy, ball_cov_yy=cyy, ball_confidence=conf / 65535,
        ball_valid=bool(flags & BALL_VALID), role=Role(role), fallen=bool(flags & FALLEN),
        penalized=bool(flags & PENALIZED), lost=bool(flags & LOST),
    )  # fmt: skip


_FLOATS = ("x", "y", "theta", "pose_std", "ball_x", "ball_y", "ball_vx", "ball_vy", "ball_age", "ball_cov_xx",
           "ball_cov_xy", "ball_cov_yy", "ball_confidence")  # fmt: skip
_SYMMETRIC = (
    (("x", "y", "ball_x", "ball_y"), MAX_POSITION, "m"),
    (("theta",), MAX_ANGLE, "rad"),
    (("ball_vx", "ball_vy"), MAX_BALL_SPEED, "m/s"),
)
_NON_NEGATIVE = (
    (("pose_std",), MAX_POSE_STD, "m"),
    (("ball_age",), MAX_BALL_AGE, "s"),
    (("ball_cov_xx", "ball_cov_yy"), MAX_BALL_VARIANCE, "m^2"),
    (("ball_confidence",), 1.0, ""),
)


def _validate(m: TeamMessage) -> None:
    """Raise :class:`MalformedMessageError` naming the first field of ``m`` outside the ranges of
    the module docstring."""
    if isinstance(m.player, bool) or not isinstance(m.player, int) or not 1 <= m.player <= 7:
        raise MalformedMessageError(f"TeamMessage.player must be an integer in 1..7, got {m.player!r}", "out_of_range")
    for name in _FLOATS:
        v = getattr(m, name)
        if isinstance(v, bool) or not isinstance(v, numbers.Real):
            raise MalformedMessageError(f"TeamMessage.{name} must be a number, got {v!r}", "out_of_range")
        if not math.isfinite(v):
            raise MalformedMessageError(f"TeamMessage.{name} must be finite, got {v!r}", "non_finite")
    for names, limit, unit in _SYMMETRIC:
        for name in names:
            v = getattr(m, name)
            if abs(v) > limit:
                raise MalformedMessageError(
                    f"TeamMessage.{name} must be in [-{limit:g}, {limit:g}] {unit}, got {v!r}", "out_of_range"
                )
    for names, limit, unit in _NON_NEGATIVE:
        for name in names:
            v = getattr(m, name)
            if not 0.0 <= v <= limit:
                raise MalformedMessageError(
                    f"TeamMessage.{name} must be in [0, {limit:g}] {unit}".rstrip() + f", got {v!r}", "out_of_range"
                )
    if m.ball_cov_xy * m.ball_cov_xy > m.ball_cov_xx * m.ball_cov_yy * (1.0 + _PSD_SLACK):
        raise MalformedMessageError(
            f"TeamMessage ball covariance must be positive semi-definite (xy^2 <= xx * yy), got xx="
            f"{m.ball_cov_xx!r}, xy={m.ball_cov_xy!r}, yy={m.ball_cov_yy!r}",
            "covariance",
        )
    if not isinstance(m.role, Role):
        raise MalformedMessageError(f"TeamMessage.role must be a Role, got {m.role!r}", "out_of_range")
