"""Multi-hypothesis ball with confidences (CMU paper, Sec. IV.A).

A visible ball overrides everything: it becomes the one own hypothesis with confidence 1.
Otherwise the model keeps ranked hypotheses, each with a confidence in [0, 1]:

* **own** hypotheses (from the robot's vision) live in the **robot frame** and are moved
  by the odometry; their confidence decays with time and with the robot's own walking
  and turning (odometry noise makes the remembered place less certain);
* **team** hypotheses (from teammates' messages) live in the **team frame** and do not
  decay with the robot's walking, only with time;
* **negative information**: while a hypothesis lies in the camera's view (projected into
  the current image, within ``view_distance``) and no ball is seen, its confidence falls
  fast (``negative_per_second``).

The best hypothesis is thresholded into CMU's three levels: ``valid`` (confidence at
least ``valid_level``), ``suspicious`` (at least ``suspicious_level``: the behavior should
look there, the model's active-gaze request) and ``invalid``.

======================  =======  ==========  ========================================================
HypothesisParams        default  range       meaning
======================  =======  ==========  ========================================================
decay_per_second        0.08     [0, 100]    confidence an own hypothesis loses per second
walk_decay_per_metre    0.3      [0, 100]    ... per metre the robot walks
turn_decay_per_radian   0.1      [0, 100]    ... per radian the robot turns
team_decay_per_second   0.08     [0, 100]    confidence a team hypothesis loses per second
negative_per_second     2.0      [0, 1000]   loss per second while in view and not seen
view_distance           4.0      (0, 100]    only hypotheses nearer than this (m) count as in view
valid_level             0.6      [0, 1]      least confidence of a ``valid`` ball
suspicious_level        0.3      [0, 1]      least confidence of a ``suspicious`` ball (<= valid_level)
merge_distance          0.3      (0, 100]    team hypotheses this near (m) an own one reinforce it
max_team_age            2.0      [0, 3600]   teammates' balls older than this (s) are ignored
======================  =======  ==========  ========================================================

Every value is checked against its range when the parameters are built
(:func:`cognition.params.check_ranges`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import ClassVar

from cognition.camera import view_sees
from cognition.params import PROBABILITY, Ranges, check_ranges, non_negative, positive
from cognition.percepts import Col, Kind, Percepts
from cognition.records import fast_init
from cognition.representations import BallLevel, RobotPose, SensorFrame
from cognition.worldmodel.messages import TeamMessage

_X, _Y = int(Col.X), int(Col.Y)
_BALL = int(Kind.BALL)


def _heading(pose: RobotPose | None) -> tuple[float, float]:
    """cos and sin of the pose's heading ((1, 0) without a pose)."""
    return (1.0, 0.0) if pose is None else (math.cos(pose.theta), math.sin(pose.theta))


@dataclass(frozen=True)
class HypothesisParams:
    """Confidence dynamics (per second, per metre walked, per radian turned)."""

    decay_per_second: float = 0.08
    walk_decay_per_metre: float = 0.3
    turn_decay_per_radian: float = 0.1
    team_decay_per_second: float = 0.08
    negative_per_second: float = 2.0
    view_distance: float = 4.0
    """Only hypotheses nearer than this (m) count as in view (a far ball may be missed)."""
    valid_level: float = 0.6
    suspicious_level: float = 0.3
    merge_distance: float = 0.3
    """Team hypotheses closer than this (m) to an own one reinforce it instead."""
    max_team_age: float = 2.0
    """Teammates' balls older than this (s since they saw it) are ignored."""

    RANGES: ClassVar[Ranges] = {
        "decay_per_second": non_negative(100.0),
        "walk_decay_per_metre": non_negative(100.0),
        "turn_decay_per_radian": non_negative(100.0),
        "team_decay_per_second": non_negative(100.0),
        "negative_per_second": non_negative(1000.0),
        "view_distance": positive(100.0),
        "valid_level": PROBABILITY,
        "suspicious_level": PROBABILITY,
        "merge_distance": positive(100.0),
        "max_team_age": non_negative(3600.0),
    }

    def __post_init__(self) -> None:
        check_ranges(self)
        if self.suspicious_level > self.valid_level:
            raise ValueError(
                f"HypothesisParams.suspicious_level ({self.suspicious_level}) must not exceed valid_level "
                f"({self.valid_level})"
            )


@dataclass
class Hypothesis:
    """One possible ball position: robot frame for ``own``, team frame for ``team``."""

    x: float
    y: float
    confidence: float
    source: str  # "own" or "team"
    sender: int = 0


@fast_init
@dataclass(frozen=True)
class BallBelief:
    """The best hypothesis (robot frame, m) with its level and the active-gaze request."""

    x: float
    y: float
    confidence: float
    level: BallLevel
    source: str
    """``vision`` (seen now), ``own``, ``team`` or ``none``."""
    look_at: tuple[float, float] | None
    """Where the head should look (robot frame) when the ball is suspicious, else ``None``."""


class BallHypotheses:
    """The CMU multi-hypothesis ball of one robot (module docstring)."""

    def __init__(self, params: HypothesisParams | None = None):
        self.params = params or HypothesisParams()
        self.hypotheses: list[Hypothesis] = []
        self.time: float | None = None

    def update(self, frame: SensorFrame, pose: RobotPose | None = None, team: Sequence[TeamMessage] = ()) -> BallBelief:
        """One frame; ``pose`` converts team hypotheses; ``team``: messages received this frame."""
        p = self.params
        time = frame.time
        dt = 0.0 if self.time is None else time - self.time
        dt = dt if dt > 0.0 else 0.0  # max(0.0, dt)
        self.time = time
        percepts = frame.percepts
        seen = False
        bx = by = 0.0
        if percepts is not None:
            lo, hi = percepts.span(_BALL)
            seen = hi > lo
            if seen:
                bx, by = percepts.table_and_offsets[0][lo, _X : _Y + 1].tolist()
        cs = _heading(pose)
        team_decay = p.team_decay_per_second * dt
        for h in self.hypotheses:
            if h.source == "team":
                h.confidence -= team_decay
        if seen:  # the visible ball overrides: it is the one own hypothesis, and the answer
            self.hypotheses = [h for h in self.hypotheses if h.source == "team"]
            self.hypotheses.append(Hypothesis(bx, by, 1.0, "own"))
        else:
            o = frame.odometry
            odx, ody, odth = o.dx, o.dy, o.dtheta
            c, s = math.cos(odth), math.sin(odth)
            walk = math.hypot(odx, ody) * p.walk_decay_per_metre + abs(odth) * p.turn_decay_per_radian
            own_loss = p.decay_per_second * dt + walk
            for h in self.hypotheses:
                if h.source == "own":
                    x, y = h.x - odx, h.y - ody
                    h.x, h.y = c * x + s * y, -s * x + c * y
                    h.confidence -= own_loss
            self._negative(percepts, pose, dt, cs)
        if team:
            self._teammates(team, pose)
        self.hypotheses = [h for h in self.hypotheses if h.confidence > 0.0]
        return self._belief(pose, seen, cs)

    # -- pieces ----------------------------------------------------------------------------
    @staticmethod
    def _relative(h: Hypothesis, pose: RobotPose | None, cs: tuple[float, float]) -> tuple[float, float] | None:
        """``h`` in the robot frame (m); ``cs``: cos and sin of the pose's heading (unused for own
        hypotheses); ``None`` for a team hypothesis without a pose."""
        if h.source == "own":
            return h.x, h.y
        if pose is None:
            return None
        c, s = cs
        dx, dy = h.x - pose.x, h.y - pose.y
        return c * dx + s * dy, -s * dx + c * dy

    def _negative(self, percepts: Percepts | None, pose: RobotPose | None, dt: float, cs: tuple[float, float]) -> None:
        """Hypotheses in view but not seen lose confidence fast; ``cs``: cos and sin of the
        pose's heading (:func:`_heading`). The camera view (as floats) is only asked for when there are
        hypotheses."""
        if not self.hypotheses or percepts is None:
            return
        cam = percepts.camera_view
        if cam is None:
            return
        view, loss = self.params.view_distance, self.params.negative_per_second * dt
        c, s = cs
        for h in self.hypotheses:
            if h.source == "own":  # robot frame already (:meth:`_relative`, written out)
                rx, ry = h.x, h.y
            elif pose is None:
                continue
            else:
                dx, dy = h.x - pose.x, h.y - pose.y
                rx, ry = c * dx + s * dy, -s * dx + c * dy
            if math.hypot(rx, ry) > view:
                continue
            if view_sees(cam, rx, ry, 0.05):
                h.confidence -= loss

    def _teammates(self, team: Sequence[TeamMessage], pose: RobotPose | None) -> None:
        p = self.params
        max_age, decay = p.max_team_age, p.team_decay_per_second
        hyps = self.hypotheses
        for m in team:
            if not m.ball_valid or m.penalized or m.ball_age > max_age:
                continue
            conf = m.ball_confidence  # max(0.0, min(1.0, c)) as the comparisons those builtins make
            conf = conf if conf < 1.0 else 1.0
            conf = (conf if conf > 0.0 else 0.0) - decay * m.ball_age
            player = m.player
            for i, h in enumerate(hyps):  # at most one hypothesis per teammate: the latest, last
                if h.sender == player and h.source == "team":
                    del hyps[i]
                    h.x, h.y, h.confidence = m.ball_x, m.ball_y, conf
                    hyps.append(h)
                    break
            else:
                hyps.append(Hypothesis(m.ball_x, m.ball_y, conf, "team", player))

    def _belief(self, pose: RobotPose | None, seen: bool, cs: tuple[float, float]) -> BallBelief:
        """The most confident hypothesis that can be placed in the robot frame (the first of
        equals in list order), an own one when the ball is seen; ``cs``: cos and sin of the
        pose's heading (:func:`_heading`)."""
        p = self.params
        best = None
        any_source = pose is not None and not seen  # else own hypotheses only
        for h in self.hypotheses:
            if (any_source or h.source == "own") and (best is None or h.confidence > best.confidence):
                best = h
        if best is None:
            return BallBelief(0.0, 0.0, 0.0, "invalid", "none", None)
        rel = self._relative(best, pose, cs)
        assert rel is not None
        conf = best.confidence
        level: BallLevel = (
            "valid" if conf >= p.valid_level else ("suspicious" if conf >= p.suspicious_level else "invalid")
        )
        source = "vision" if seen else best.source
        look = rel if level == "suspicious" else None
        return BallBelief(rel[0], rel[1], conf, level, source, look)
