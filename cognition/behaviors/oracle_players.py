"""Scripted oracle players (goalkeeper, striker, supporters) that read ground truth.

These brains exist so that a full match can be played before the real cognition stack
(localization, world model) is in place, and later as a ground-truth baseline. They read
the :class:`~cognition.oracle.OracleInput` (team frame) and nothing else of the truth.

Each brain is an explicit state machine (DESIGN principle 10):

==========  ==================================================================
state       behaviour
==========  ==================================================================
stand       INITIAL, SET, FINISHED, penalised, fallen or carried: do nothing
position    READY: walk to the predefined kickoff position of the player
keeper      PLAYING, player 1: stay between ball and goal; clear a close ball
strike      PLAYING, the field player nearest to the ball: approach behind the
            ball, align, kick toward the opponent goal
support     PLAYING, other field players: hold a spot relative to the ball,
            clear of teammates
wait        PLAYING while the opponent has a kickoff or set play: keep 0.8 m
            away from the ball
==========  ==================================================================

Team messages: each player broadcasts a small status (number, x, y, theta) at a rate that
spreads the team's remaining message budget over the remaining game time.

====================  =======  ==========  =======================================================
OracleParams          default  range       meaning
====================  =======  ==========  =======================================================
approach_distance     0.22     (0, 10]     where the striker lines up behind the ball (m)
kick_distance         0.26     (0, 10]     largest robot-ball centre distance of a kick (m)
kick_bearing          0.35     (0, pi]     largest |bearing| to the ball of a kick (rad)
keep_away             0.8      (0, 100]    distance kept from the ball in the opponent's set play (m)
min_message_interval  1.0      [0, 3600]   least time between two status messages (s)
outside_allowance     0.1      [0, 10]     how far beyond the field lines a target may lie (m)
personal_space        0.45     (0, 100]    targets are kept this far from other robots (m)
====================  =======  ==========  =======================================================

Every value is checked against its range when the parameters are built
(:func:`cognition.params.check_ranges`).
"""

from __future__ import annotations

import math
import struct
from dataclasses import dataclass
from typing import ClassVar

from cognition.behaviors.message_budget import message_due
from cognition.brain import BrainContext
from cognition.gamestate import GameStateId, SetPlay
from cognition.geometry import wrap_angle
from cognition.oracle import OracleInput, OraclePose
from cognition.params import Ranges, check_ranges, non_negative, positive
from cognition.positions import kickoff_position
from cognition.representations import (
    BrainOutput,
    HeadRequest,
    KickRequest,
    MotionRequest,
    SensorFrame,
    WalkRequest,
)

STATUS_FORMAT = struct.Struct("<Bfff")
"""Status message: player number, x (m), y (m), theta (rad) in the team frame."""


@dataclass(frozen=True)
class OracleParams:
    """Tuning of the scripted players."""

    approach_distance: float = 0.22
    """Distance behind the ball (m, centre to centre) where the striker lines up."""
    kick_distance: float = 0.26
    """Largest robot-to-ball centre distance at which the striker kicks (m)."""
    kick_bearing: float = 0.35
    """Largest |bearing| to the ball at which the striker kicks (rad)."""
    keep_away: float = 0.8
    """Distance kept from the ball during the opponent's kickoff or set play (m)."""
    min_message_interval: float = 1.0
    """Never send status messages more often than this (s)."""
    outside_allowance: float = 0.1
    """How far beyond the field lines (m) a target may lie; leaving the field is penalised."""
    personal_space: float = 0.45
    """Targets are kept this far (m, centre to centre) from other robots."""

    RANGES: ClassVar[Ranges] = {
        "approach_distance": positive(10.0),
        "kick_distance": positive(10.0),
        "kick_bearing": positive(math.pi),
        "keep_away": positive(100.0),
        "min_message_interval": non_negative(3600.0),
        "outside_allowance": non_negative(10.0),
        "personal_space": positive(100.0),
    }

    def __post_init__(self) -> None:
        check_ranges(self)


class OracleBrain:
    """A scripted SPL player driven by ground truth (see the module docstring)."""

    uses_oracle = True

    def __init__(self, params: OracleParams | None = None):
        self.params = params or OracleParams()
        self.context: BrainContext | None = None
        self.state = "stand"
        self._last_message = -1e9

    def reset(self, context: BrainContext) -> None:
        """Remember the match facts and forget earlier matches."""
        self.context = context
        self.state = "stand"
        self._last_message = -1e9

    # -- decisions -------------------------------------------------------------------------
    def think(self, frame: SensorFrame, oracle: OracleInput | None) -> BrainOutput:
        """One frame: choose the state, then act on it."""
        if self.context is None:
            raise RuntimeError("OracleBrain.think called before reset()")
        if oracle is None:
            raise ValueError("OracleBrain needs the oracle input (uses_oracle is True)")
        self.state = self._transition(frame, oracle)
        motion = getattr(self, f"_act_{self.state}")(frame, oracle)
        return BrainOutput(motion=motion, message=self._message(frame, oracle))

    def _transition(self, frame: SensorFrame, oracle: OracleInput) -> str:
        game = frame.game
        if frame.penalty or frame.fallen or frame.picked_up:
            return "stand"
        if game.state == GameStateId.READY:
            return "position"
        if game.state != GameStateId.PLAYING:
            return "stand"
        assert self.context is not None
        if self.context.player_number == 1:
            return "keeper"
        ours = game.kicking_team == self.context.team_number
        kickoff_wait = game.set_play == SetPlay.NONE and game.secondary_time > 0 and not ours
        set_play_wait = game.set_play != SetPlay.NONE and not ours
        if kickoff_wait or set_play_wait:
            return "wait"
        return "strike" if self._nearest_to_ball(oracle) else "support"

    def _nearest_to_ball(self, oracle: OracleInput) -> bool:
        def dist(p: OraclePose) -> float:
            return math.hypot(p.x - oracle.ball_x, p.y - oracle.ball_y)

        me = dist(oracle.self_pose)
        for mate in oracle.teammates:
            if not mate.active or mate.fallen or mate.number == 1:
                continue
            d = dist(mate)
            if d < me - 1e-9 or (abs(d - me) <= 1e-9 and mate.number < oracle.self_pose.number):
                return False
        return True

    # -- actions ---------------------------------------------------------------------------
    def _head(self, oracle: OracleInput) -> HeadRequest:
        me = oracle.self_pose
        bearing = wrap_angle(math.atan2(oracle.ball_y - me.y, oracle.ball_x - me.x) - me.theta)
        return HeadRequest(yaw=max(-1.5, min(1.5, bearing)), pitch=0.3)

    def _act_stand(self, frame: SensorFrame, oracle: OracleInput) -> MotionRequest:
        return MotionRequest(head=self._head(oracle))

    def _act_position(self, frame: SensorFrame, oracle: OracleInput) -> MotionRequest:
        assert self.context is not None
        kicking = frame.game.kicking_team == self.context.team_number
        target = kickoff_position(self.context.field, self.context.player_number, kicking)
        return MotionRequest(walk=self._walk_to(oracle, target, avoid=True), head=self._head(oracle))

    def _act_keeper(self, frame: SensorFrame, oracle: OracleInput) -> MotionRequest:
        assert self.context is not None
        f = self.context.field
        goal_x = -f.half_length
        bx, by = oracle.ball_x, oracle.ball_y
        near_goal = bx < goal_x + f.dims.goal_area_length + 0.6 and abs(by) < f.dims.goal_area_width / 2 + 0.4
        if near_goal:
            return self._strike(oracle)
        # stand on the line from the goal centre to the ball, inside the goal area
        half_goal = f.dims.goal_inner_width / 2
        ang = math.atan2(by, bx - goal_x)
        x = goal_x + 0.35 * math.cos(ang) + 0.1
        y = max(-half_goal + 0.1, min(half_goal - 0.1, 0.6 * math.sin(ang)))
        heading = math.atan2(by - y, bx - x)
        return MotionRequest(walk=self._walk_to(oracle, (x, y, heading)), head=self._head(oracle))

    def _act_strike(self, frame: SensorFrame, oracle: OracleInput) -> MotionRequest:
        return self._strike(oracle)

    def _strike(self, oracle: OracleInput) -> MotionRequest:
        assert self.context is not None
        p = self.params
        me = oracle.self_pose
        bx, by = oracle.ball_x, oracle.ball_y
        aim = self._feasible_aim(bx, by)
        dist = math.hypot(bx - me.x, by - me.y)
        bearing = wrap_angle(math.atan2(by - me.y, bx - me.x) - me.theta)
        aim_rel = wrap_angle(aim - me.theta)
        if dist < p.kick_distance and abs(bearing) < p.kick_bearing and abs(aim_rel) < 0.6:
            return MotionRequest(kick=KickRequest(direction=aim_rel, strength=1.0), head=self._head(oracle))
        behind = (
            bx - p.approach_distance * math.cos(aim),
            by - p.approach_distance * math.sin(aim),
            aim,
        )
        if dist < 0.45:
            # close: line up behind the ball with small steps, facing the aim direction
            walk = self._walk_to(oracle, behind, final_heading_radius=1.0, gain=1.5)
        else:
            # far: go around the ball if it lies between the robot and its line-up point
            walk = self._walk_to(oracle, behind, avoid=True)
        return MotionRequest(walk=walk, head=self._head(oracle))

    def _feasible_aim(self, bx: float, by: float) -> float:
        """Aim at the goal if the line-up spot behind the ball is reachable, else up the field."""
        assert self.context is not None
        f = self.context.field
        d = self.params.approach_distance
        for tx, ty in ((f.half_length + 0.2, 0.0), (f.half_length / 2, 0.0), (0.0, 0.0), (-f.half_length, 0.0)):
            aim = math.atan2(ty - by, tx - bx)
            sx, sy = bx - d * math.cos(aim), by - d * math.sin(aim)
            if (
                abs(sx) <= f.half_length + self.params.outside_allowance
                and abs(sy) <= f.half_width + self.params.outside_allowance
            ):
                return aim
        return math.atan2(-by, -bx)

    def _act_support(self, frame: SensorFrame, oracle: OracleInput) -> MotionRequest:
        assert self.context is not None
        f = self.context.field
        n = self.context.player_number
        bx, by = oracle.ball_x, oracle.ball_y
        offsets = {2: (-2.0, -0.8), 4: (-1.0, 1.2), 5: (-1.2, -1.4), 6: (-2.2, 0.9), 7: (-0.6, 2.0)}
        ox, oy = offsets.get(n, (-1.5, 0.0))
        x = max(-f.half_length + 0.8, min(f.half_length - 0.8, bx + ox))
        y = max(-f.half_width + 0.3, min(f.half_width - 0.3, by * 0.5 + oy * f.dims.width / 6.0))
        heading = math.atan2(by - y, bx - x)
        return MotionRequest(walk=self._walk_to(oracle, (x, y, heading), avoid=True), head=self._head(oracle))

    def _act_wait(self, frame: SensorFrame, oracle: OracleInput) -> MotionRequest:
        me = oracle.self_pose
        bx, by = oracle.ball_x, oracle.ball_y
        dx, dy = me.x - bx, me.y - by
        d = math.hypot(dx, dy)
        keep = self.params.keep_away
        if d >= keep:
            return self._act_support(frame, oracle) if d > keep + 0.3 else MotionRequest(head=self._head(oracle))
        ux, uy = (dx / d, dy / d) if d > 1e-6 else (-1.0, 0.0)
        target = (bx + ux * (keep + 0.2), by + uy * (keep + 0.2), math.atan2(-uy, -ux))
        return MotionRequest(walk=self._walk_to(oracle, target), head=self._head(oracle))

    # -- motion primitives -----------------------------------------------------------------
    def _walk_to(
        self,
        oracle: OracleInput,
        target: tuple[float, float, float],
        avoid: bool = False,
        final_heading_radius: float = 0.4,
        gain: float = 1.0,
    ) -> WalkRequest:
        """Walk command (robot frame) toward a team-frame target pose."""
        me = oracle.self_pose
        tx, ty, tth = target
        if avoid:
            tx, ty = self._avoid(oracle, me, tx, ty)
        assert self.context is not None
        f = self.context.field
        if avoid:
            tx, ty = self._free_spot(oracle, me, tx, ty)
        # stay (almost) inside the field lines: leaving the field is penalised
        lim_x = f.half_length + self.params.outside_allowance
        lim_y = f.half_width + self.params.outside_allowance
        tx = max(-lim_x, min(lim_x, tx))
        ty = max(-lim_y, min(lim_y, ty))
        dx, dy = tx - me.x, ty - me.y
        dist = math.hypot(dx, dy)
        c, s = math.cos(me.theta), math.sin(me.theta)
        fx, fy = c * dx + s * dy, -s * dx + c * dy
        if dist > final_heading_radius:
            heading_err = wrap_angle(math.atan2(dy, dx) - me.theta)
        else:
            heading_err = wrap_angle(tth - me.theta)
        if dist < 0.03 and abs(heading_err) < 0.05:
            return WalkRequest()
        slow = 1.0 if abs(heading_err) < 0.6 or dist < final_heading_radius else 0.3
        return WalkRequest(
            forward=gain * 1.2 * fx * slow,
            left=gain * 1.2 * fy * slow,
            turn=2.0 * heading_err,
        )

    def _free_spot(self, oracle: OracleInput, me: OraclePose, tx: float, ty: float) -> tuple[float, float]:
        """Move a target out of other robots' personal space so nobody is pushed."""
        space = self.params.personal_space
        for p in (*oracle.teammates, *oracle.opponents):
            if not p.active:
                continue
            dx, dy = tx - p.x, ty - p.y
            d = math.hypot(dx, dy)
            if d >= space:
                continue
            if d < 1e-6:
                dx, dy, d = me.x - p.x, me.y - p.y, max(1e-6, math.hypot(me.x - p.x, me.y - p.y))
            tx, ty = p.x + dx / d * space, p.y + dy / d * space
        return tx, ty

    def _avoid(self, oracle: OracleInput, me: OraclePose, tx: float, ty: float) -> tuple[float, float]:
        """Bend the target away from nearby robots (and the ball when walking around it)."""
        ax, ay = tx - me.x, ty - me.y
        obstacles = [(p.x, p.y, 0.5) for p in (*oracle.teammates, *oracle.opponents) if p.active]
        obstacles.append((oracle.ball_x, oracle.ball_y, 0.35))
        for ox, oy, radius in obstacles:
            rx, ry = ox - me.x, oy - me.y
            d = math.hypot(rx, ry)
            if d < 1e-6 or d > radius + 0.3:
                continue
            along = (rx * ax + ry * ay) / (math.hypot(ax, ay) or 1.0)
            if along <= 0 or math.hypot(ax, ay) < d:
                continue
            # step sideways, to the side of the path the obstacle is not on
            side = 1.0 if (ax * ry - ay * rx) < 0 else -1.0
            nx, ny = -ry / d * side, rx / d * side
            push = radius + 0.3 - d + 0.2
            ax, ay = ax + nx * push * 2.0, ay + ny * push * 2.0
        return me.x + ax, me.y + ay

    # -- team messages ---------------------------------------------------------------------
    def _message(self, frame: SensorFrame, oracle: OracleInput) -> bytes | None:
        if not self._send_now(frame):
            return None
        self._last_message = frame.time
        return self._payload(frame, oracle)

    def _send_now(self, frame: SensorFrame) -> bool:
        """Whether to send now (:func:`~cognition.behaviors.message_budget.message_due`: the team's
        remaining budget spread over the remaining game time, never faster than the minimum interval)."""
        assert self.context is not None
        c = self.context
        return message_due(
            frame.game, c.team_number, c.players_per_team, frame.time, self._last_message,
            self.params.min_message_interval,
        )  # fmt: skip

    def _payload(self, frame: SensorFrame, oracle: OracleInput) -> bytes:
        """The status message (:data:`STATUS_FORMAT`)."""
        assert self.context is not None
        me = oracle.self_pose
        return STATUS_FORMAT.pack(self.context.player_number, me.x, me.y, me.theta)
