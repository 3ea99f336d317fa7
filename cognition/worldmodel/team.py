"""Teammates' reports and the team ball.

:class:`TeamState` reads the team messages a robot received each frame
(:mod:`cognition.worldmodel.messages`), keeps the latest valid one per teammate with the
time it arrived, drops the ones older than ``max_age`` and counts what it rejected, in total
(``rejected``) and by reason (``rejected_by_reason``): a malformed or absurd packet never
reaches the rest of the brain. A message is accepted only if :func:`~cognition.worldmodel
.messages.unpack` accepts it (finite values, sane covariances and uncertainties: the table in
that module) and, beyond that:

============  ================================================================================
reason        the message is rejected when
============  ================================================================================
format        it is not a team message of this format (size, magic, version)
checksum      its CRC does not match (corrupted)
non_finite    a float is NaN or infinite
out_of_range  a field is outside its range (player, flags, role, speeds, uncertainties, ...)
covariance    the ball covariance is not positive semi-definite
sender        its player number is not its sender's, or it is the receiver's own number
off_field     the pose or the ball lies beyond the carpet (field plus border strip) by more
              than ``margin`` (1 m by default): abs(x) > half length + border + margin or
              abs(y) > half width + border + margin
============  ================================================================================

:func:`team_ball` fuses the own ball and the teammates' balls in the team frame. Each
estimate counts with the inverse of its covariance, the ball covariance plus the
reporter's pose variance (a poorly localized robot puts the ball in the wrong place),
grown with the age of the report (``age_variance_per_second``; the ball may have moved).
The fused mean is the information-weighted mean. This is the team-ball idea of the
Darmstadt paper (Sec. V.B) applied to all teammates at once. Estimates without a finite
position or a finite, positive-definite covariance are left out. Thin, correlated ellipses
can put the information-weighted mean far beyond every estimate; given ``limits`` (the
:attr:`TeamState.limits` of the carpet plus margin) the fused mean is clipped into them, so
that the team ball always lies where a ball can be.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from cognition.field import Field
from cognition.records import fast_init
from cognition.representations import BallModel, RobotPose, SensorFrame
from cognition.worldmodel.messages import REJECT_REASONS, MalformedMessageError, TeamMessage, unpack

TEAM_REJECT_REASONS = (*REJECT_REASONS, "sender", "off_field")
"""Every reason :class:`TeamState` counts a rejected message under (module docstring)."""


@fast_init
@dataclass(frozen=True)
class TeamBallEstimate:
    """The team's ball (team frame, m) with its 2 x 2 covariance and who contributed."""

    x: float
    y: float
    cov_xx: float
    cov_xy: float
    cov_yy: float
    contributors: tuple[int, ...]
    """Player numbers whose estimates were fused (the own number included)."""


def carpet_limits(field: Field, margin: float = 1.0) -> tuple[float, float]:
    """Largest abs(x) and abs(y) (m, team frame) of anything on the carpet (the field plus its
    border strip) or at most ``margin`` (m) beyond it."""
    border = field.dims.border_strip + float(margin)
    return (field.half_length + border, field.half_width + border)


class TeamState:
    """The latest valid message of every teammate (see the module docstring).

    ``field`` gives the carpet (half length, half width and border strip, m); ``margin`` (m)
    is how far beyond it a reported pose or ball may lie; ``max_age`` (s) is how long a
    teammate's latest message counts."""

    def __init__(self, own_number: int, field: Field, max_age: float = 3.0, margin: float = 1.0):
        if not (isinstance(max_age, int | float) and 0.0 < max_age < math.inf):
            raise ValueError(f"TeamState.max_age must be a positive finite number of seconds, got {max_age!r}")
        if not (isinstance(margin, int | float) and 0.0 <= margin < math.inf):
            raise ValueError(f"TeamState.margin must be a non-negative finite distance (m), got {margin!r}")
        self.own_number = own_number
        self.max_age = float(max_age)
        self.limits = carpet_limits(field, margin)
        """Largest accepted abs(x) and abs(y) (m, team frame) of a reported pose or ball."""
        self.latest: dict[int, tuple[float, TeamMessage]] = {}
        """Player number -> (time received, message)."""
        self.rejected = 0
        """Packets that were not valid team messages (all reasons)."""
        self.rejected_by_reason: dict[str, int] = {}
        """Rejected packets per reason (:data:`TEAM_REJECT_REASONS`); only reasons that occurred."""

    def update(self, frame: SensorFrame) -> list[TeamMessage]:
        """Read this frame's messages; returns the current (not too old) teammates' messages."""
        time = frame.time
        for m in frame.messages:
            try:
                msg = unpack(m.payload)
            except MalformedMessageError as e:
                self._reject(e.reason)
                continue
            if msg.player != m.sender or msg.player == self.own_number:
                self._reject("sender")  # a report under a wrong name
                continue
            if not self.on_carpet(msg):
                self._reject("off_field")
                continue
            self.latest[msg.player] = (time, msg)
        latest, max_age = self.latest, self.max_age
        for received, _ in latest.values():
            if not time - received <= max_age:  # one is too old: keep the others, in their order
                self.latest = latest = {k: v for k, v in latest.items() if time - v[0] <= max_age}
                break
        return [msg for _, msg in latest.values()]

    def on_carpet(self, msg: TeamMessage) -> bool:
        """Whether the message's pose and ball both lie within :attr:`limits`."""
        lx, ly = self.limits
        return abs(msg.x) <= lx and abs(msg.y) <= ly and abs(msg.ball_x) <= lx and abs(msg.ball_y) <= ly

    def _reject(self, reason: str) -> None:
        self.rejected += 1
        self.rejected_by_reason[reason] = self.rejected_by_reason.get(reason, 0) + 1


def rotate_covariance(p: NDArray[np.float64], theta: float) -> tuple[float, float, float]:
    """(xx, xy, yy) of the upper-left 2 x 2 block of ``p`` rotated by ``theta`` (rad): a
    robot-frame position covariance expressed in the team frame of a robot heading ``theta``."""
    c, s = math.cos(theta), math.sin(theta)
    a, b, d = p.item(0, 0), p.item(0, 1), p.item(1, 1)  # Python floats, without a slice and a list
    return (
        c * c * a - 2 * c * s * b + s * s * d,
        c * s * (a - d) + (c * c - s * s) * b,
        s * s * a + 2 * c * s * b + c * c * d,
    )


def _information(
    bx: float, by: float, cxx: float, cxy: float, cyy: float, extra: float
) -> tuple[float, float, float, float, float] | None:
    """One estimate's terms of the fused sums: its information matrix (xx, xy, yy) and
    information vector (x, y), for a ball at (``bx``, ``by``) with covariance (``cxx``,
    ``cxy``, ``cyy``) plus ``extra`` on both diagonal entries (m, m^2, team frame); ``None`` for
    a degenerate, infinitely uncertain or non-finite estimate (left out of the fusion)."""
    a, b, d = cxx + extra, cxy, cyy + extra
    det = a * d - b * b
    if not (det > 1e-12 and math.isfinite(det) and a > 0.0 and math.isfinite(bx) and math.isfinite(by)):
        return None
    ia, ib, idd = d / det, -b / det, a / det
    return ia, ib, idd, ia * bx + ib * by, ib * bx + idd * by


def team_ball(
    own: BallModel | None,
    own_pose: RobotPose | None,
    own_number: int,
    mates: Sequence[TeamMessage],
    age_variance_per_second: float = 0.25,
    limits: tuple[float, float] | None = None,
    terms: dict[int, tuple[TeamMessage, float, tuple[float, float, float, float, float] | None]] | None = None,
) -> TeamBallEstimate | None:
    """Information-weighted fusion of the own and the teammates' balls (team frame).

    ``limits``: largest abs(x) and abs(y) (m) of the fused mean (module docstring); ``None``
    leaves it unclipped. ``terms``: a memo the caller keeps from frame to frame (``None``: none).
    A teammate's message (frozen) adds the same information to the sums in every frame it
    counts, so its terms are computed once per message and ``age_variance_per_second`` (keyed by
    the message's ``id``, checked by identity) and added in the same order as without the memo:
    the result is the same to the bit."""
    ix = ixy = iy = 0.0  # summed information matrix
    vx = vy = 0.0  # summed information vector
    who: list[int] = []
    if own is not None and own_pose is not None and own.level != "invalid" and math.isfinite(own.field_x):
        cov = own_pose.covariance
        c00, c11 = cov.item(0, 0), cov.item(1, 1)  # Python floats
        # own ball covariance rotated into the team frame, plus the pose's position variance
        cxx, cxy, cyy = rotate_covariance(own.covariance, own_pose.theta)
        extra = 0.5 * (c00 + c11) + age_variance_per_second * own.age
        own_terms = _information(own.field_x, own.field_y, cxx, cxy, cyy, extra)
        if own_terms is not None:  # the own estimate first
            ia, ib, idd, tx, ty = own_terms
            ix, ixy, iy = ix + ia, ixy + ib, iy + idd
            vx += tx
            vy += ty
            who.append(own_number)
    for m in mates:
        if not m.ball_valid or m.penalized:
            continue
        memo = None if terms is None else terms.get(id(m))
        if memo is not None and memo[0] is m and memo[1] == age_variance_per_second:
            mate_terms = memo[2]
        else:
            extra = m.pose_std**2 + age_variance_per_second * m.ball_age
            mate_terms = _information(m.ball_x, m.ball_y, m.ball_cov_xx, m.ball_cov_xy, m.ball_cov_yy, extra)
            if terms is not None:
                terms[id(m)] = (m, age_variance_per_second, mate_terms)
        if mate_terms is None:
            continue
        ia, ib, idd, tx, ty = mate_terms
        ix, ixy, iy = ix + ia, ixy + ib, iy + idd
        vx += tx
        vy += ty
        who.append(m.player)
    if not who:
        return None
    det = ix * iy - ixy * ixy
    if not (det > 0.0 and math.isfinite(det)):  # a sum of positive-definite terms: only by underflow
        return None
    cxx, cxy, cyy = iy / det, -ixy / det, ix / det
    x, y = cxx * vx + cxy * vy, cxy * vx + cyy * vy
    if limits is not None:
        lx, ly = limits
        # min(max(v, -l), l) as the comparisons those builtins make (a tenth of their cost)
        x = -lx if -lx > x else x
        x = lx if lx < x else x
        y = -ly if -ly > y else y
        y = ly if ly < y else y
    return TeamBallEstimate(x, y, cxx, cxy, cyy, tuple(who))
