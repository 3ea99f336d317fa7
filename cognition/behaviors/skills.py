"""Reusable soccer skills on :class:`~cognition.worldmodel.beliefs.Beliefs`.

A skill turns the current beliefs into one :class:`~cognition.representations.MotionRequest`
(walk or kick). Skills hold no game logic: the scripted team play
(:mod:`cognition.behaviors.team_play`) and the discrete macro-actions of a policy
(:mod:`cognition.behaviors.actions`) decide which skill runs. Every skill returns the default
:class:`~cognition.representations.HeadRequest`; the caller sets the head
(:class:`~cognition.behaviors.head_control.HeadControl`, re-exported here).

Frames: targets are poses in the **team frame** (m, rad; +x toward the opponent goal);
``Beliefs.obstacles``, ``Beliefs.goal`` and the own ball's ``x, y`` are in the **robot
frame**. Ball skills work on the ball in both frames: the own ball while it is ``valid``,
else ``Beliefs.best_ball()`` through the pose. When nobody knows where the ball is, ball
skills turn on the spot (search); the goalkeeper goes home instead.

=============  =================================================================================
skill          what the robot does
=============  =================================================================================
walk_to        walk to a team-frame pose; with ``avoid`` bend around robots and the ball and keep
               the target out of other robots' personal space
go_to_ball     walk to the line-up spot ``approach_distance`` behind the ball, facing the aim of
               :meth:`Skills.kick_to_goal`, going round the ball when on its wrong side; no kick
kick_to_goal   approach, align and kick toward the opponent goal. The aim comes from the goal model
               (robot frame, posts seen in head scans) when the goal is nearer than
               ``close_to_goal`` and the model is confident and roughly where the pose puts the
               opponent goal, and from the pose otherwise: the CMU paper, Sec. IV.B, uses the goal
               model for accuracy close to the goal and the pose when far, where long kicks scatter
               anyway. Near the lines the aim falls back to points up the field whose line-up spot
               lies inside the field
pass_to        kick toward a teammate (``None``: the best-placed active teammate ahead of the ball;
               none: :meth:`Skills.kick_to_goal`), strength from the distance and the ball's
               rolling deceleration
defend         stand on the line from the own goal centre (x = -half length) to the ball,
               ``defend_distance`` in front of the goal (closer to the goal when the ball is)
keeper         goalkeeper: on the goal-ball line inside the goal area; kicks a ball away that
               comes near the goal
support        hold a spot relative to the ball (per player number), clear of teammates
keep_away      opponent kickoff or set play: step out to ``keep_away`` from the ball, else stand
               facing it
go_to_kickoff  READY: walk to the predefined kickoff position (:mod:`cognition.positions`)
stand          stand still
=============  =================================================================================

No pushing: every walk drops the part of its velocity that drives toward an obstacle closer
than ``contact_distance`` (robot frame), and targets stay inside the field lines plus
``outside_allowance`` (leaving the field is penalised).

=====================  =======  ==========  ======================================================================
SkillParams            default  range       meaning
=====================  =======  ==========  ======================================================================
approach_distance      0.22     (0, 10]     line-up distance behind the ball (m, centre to centre; < kick_distance)
kick_distance          0.29     (0, 10]     largest robot-ball distance at which a kick is started (m, centre to
                                            centre; the kick connects up to 0.31 m, :mod:`teamsim.robot`)
kick_bearing           0.35     (0, pi]     largest |bearing| of the ball at which a kick is started (rad)
kick_alignment         0.6      (0, pi]     largest |aim - heading| at which a kick is started (rad)
side_kick              1.0      (0, pi]     largest |aim - heading| of a side kick, used when the line-up spot
                                            straight behind the ball is off limits (ball at a corner or a line);
                                            the robot's kick reaches 1.05 rad (:mod:`teamsim.robot`)
keep_away              0.8      (0, 100]    distance kept from the ball in the opponent's kickoff or set play (m)
personal_space         0.45     (0, 100]    walk targets are kept this far from other robots (m, centre to centre)
outside_allowance      0.1      [0, 10]     how far beyond the field lines a target may lie (m); a robot of
                                            radius 0.14 m leaves the field (penalised) past 0.165 m
close_to_goal          2.5      (0, 100]    goal distance (m) below which the goal model aims the kick
goal_confidence        0.5      [0, 1]      least goal-model confidence to aim with it
goal_gate              1.5      (0, 100]    the goal model must lie within this of the opponent goal by the pose (m)
defend_distance        1.2      (0, 100]    the defender's distance in front of the own goal centre (m)
contact_distance       0.4      (0, 100]    obstacles nearer than this (m) are never walked toward
search_turn            0.8      (0, 20]     turn rate while searching for the ball (rad/s)
kick_speed             3.0      (0, 20]     ball speed of a full-strength kick the pass assumes (m/s)
ball_deceleration      1.0      (0, 100]    rolling deceleration of the ball the pass assumes (m/s^2)
pass_min               0.8      (0, 100]    teammates from this far from the ball (m) ...
pass_max               4.0      (0, 100]    ... up to this far can receive a pass (pass_min < pass_max)
pass_lead              0.3      [0, 100]    a pass goes this far ahead of the receiver, toward the goal (m)
=====================  =======  ==========  ======================================================================

Every value is checked against its range when the parameters are built
(:func:`cognition.params.check_ranges`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

from cognition.behaviors.head_control import HeadControl, HeadParams
from cognition.brain import BrainContext
from cognition.geometry import wrap_angle
from cognition.params import PROBABILITY, Ranges, check_ranges, non_negative, positive
from cognition.positions import kickoff_position
from cognition.representations import KickRequest, MotionRequest, WalkRequest
from cognition.worldmodel.beliefs import Beliefs, Teammate

__all__ = ["HeadControl", "HeadParams", "SkillParams", "Skills"]

Ball = tuple[float, float, float, float]
"""The ball to play: team-frame x, y and robot-frame x, y (m)."""

_OBSTACLE_RADIUS = 0.5
"""Radius (m) of the robots the walk bends around (:func:`_bend`)."""
_SUPPORT_OFFSETS: dict[int, tuple[float, float]] = {
    2: (-2.0, -0.8),
    3: (-1.5, 0.0),
    4: (-1.0, 1.2),
    5: (-1.2, -1.4),
    6: (-2.2, 0.9),
    7: (-0.6, 2.0),
}
"""Supporting spot per player number relative to the ball (x m; y in sixths of the field width)."""


@dataclass(frozen=True)
class SkillParams:
    """Tuning of the skills (table in the module docstring)."""

    approach_distance: float = 0.22
    kick_distance: float = 0.29
    kick_bearing: float = 0.35
    kick_alignment: float = 0.6
    side_kick: float = 1.0
    keep_away: float = 0.8
    personal_space: float = 0.45
    outside_allowance: float = 0.1
    close_to_goal: float = 2.5
    goal_confidence: float = 0.5
    goal_gate: float = 1.5
    defend_distance: float = 1.2
    contact_distance: float = 0.4
    search_turn: float = 0.8
    kick_speed: float = 3.0
    ball_deceleration: float = 1.0
    pass_min: float = 0.8
    pass_max: float = 4.0
    pass_lead: float = 0.3

    RANGES: ClassVar[Ranges] = {
        "approach_distance": positive(10.0),
        "kick_distance": positive(10.0),
        "kick_bearing": positive(math.pi),
        "kick_alignment": positive(math.pi),
        "side_kick": positive(math.pi),
        "keep_away": positive(100.0),
        "personal_space": positive(100.0),
        "outside_allowance": non_negative(10.0),
        "close_to_goal": positive(100.0),
        "goal_confidence": PROBABILITY,
        "goal_gate": positive(100.0),
        "defend_distance": positive(100.0),
        "contact_distance": positive(100.0),
        "search_turn": positive(20.0),
        "kick_speed": positive(20.0),
        "ball_deceleration": positive(100.0),
        "pass_min": positive(100.0),
        "pass_max": positive(100.0),
        "pass_lead": non_negative(100.0),
    }

    def __post_init__(self) -> None:
        check_ranges(self)
        o = "SkillParams"
        if self.approach_distance >= self.kick_distance:
            raise ValueError(
                f"{o}.approach_distance ({self.approach_distance}) must be below kick_distance ({self.kick_distance}): "
                "the line-up spot must be within kicking range"
            )
        if self.pass_min >= self.pass_max:
            raise ValueError(f"{o}.pass_min ({self.pass_min}) must be below pass_max ({self.pass_max})")


class Skills:
    """The skills of one robot (module docstring); plain-Python math, no state but a cache."""

    def __init__(self, context: BrainContext, params: SkillParams | None = None) -> None:
        self.context = context
        self.params = params or SkillParams()
        f = context.field
        self._hl, self._hw = f.half_length, f.half_width
        self._lim_x = f.half_length + self.params.outside_allowance
        self._lim_y = f.half_width + self.params.outside_allowance
        self._cached: Beliefs | None = None
        self._obstacles: list[list[float]] = []
        self._bend_near: list[tuple[float, float, float]] = []
        """The obstacles :func:`_bend` can bend around (within ``_OBSTACLE_RADIUS + 0.3`` m), as its entries."""
        self._touching: list[tuple[float, float]] = []
        """The obstacles within ``contact_distance`` (the walk does not push into them)."""

    # -- walking ---------------------------------------------------------------------------
    def walk_to(self, b: Beliefs, target: tuple[float, float, float], avoid: bool = True) -> WalkRequest:
        """Walk toward ``target`` (x m, y m, theta rad; team frame), inside the field.

        With ``avoid`` the path bends around other robots and the ball, and the target is kept
        out of other robots' personal space.
        """
        tx, ty, tth = target
        fx, fy = b.to_robot(self._clamp_x(tx), self._clamp_y(ty))
        return self._walk(b, fx, fy, wrap_angle(tth - b.pose.theta), avoid)

    def stand(self, b: Beliefs) -> MotionRequest:
        """Stand still."""
        return MotionRequest()

    def go_to_kickoff(self, b: Beliefs, kicking: bool) -> MotionRequest:
        """READY: walk to the own kickoff position (``kicking``: the own team kicks off)."""
        target = kickoff_position(self.context.field, b.player_number, kicking)
        return MotionRequest(self.walk_to(b, target))

    # -- the ball ----------------------------------------------------------------------------
    def go_to_ball(self, b: Beliefs) -> MotionRequest:
        """Walk to the line-up spot behind the ball, facing the goal aim; never kicks."""
        ball = self.ball(b)
        if ball is None:
            return self.search(b)
        return MotionRequest(self._approach(b, ball, self.goal_aim(b, ball)))

    def kick_to_goal(self, b: Beliefs) -> MotionRequest:
        """Approach, align and kick toward the opponent goal (aim: :meth:`goal_aim`)."""
        ball = self.ball(b)
        if ball is None:
            return self.search(b)
        return self._play(b, ball, self.goal_aim(b, ball), 1.0)

    def pass_to(self, b: Beliefs, number: int | None = None) -> MotionRequest:
        """Kick toward teammate ``number`` (``None``: :meth:`pass_receiver`); without one, kick to goal."""
        ball = self.ball(b)
        if ball is None:
            return self.search(b)
        if number is None:
            mate = self.pass_receiver(b, ball)
        else:
            mate = next((m for m in b.teammates if m.number == number and m.active), None)
        if mate is None:
            return self.kick_to_goal(b)
        bx, by = ball[0], ball[1]
        tx, ty = self._clamp_x(mate.x + self.params.pass_lead), mate.y
        aim = math.atan2(ty - by, tx - bx)
        if self.lineup_heading(bx, by, aim) is None:
            return self.kick_to_goal(b)
        p = self.params
        dist = math.hypot(tx - bx, ty - by)
        strength = math.sqrt(2.0 * p.ball_deceleration * dist) / p.kick_speed
        return self._play(b, ball, wrap_angle(aim - b.pose.theta), max(0.2, min(1.0, strength)))

    def pass_receiver(self, b: Beliefs, ball: Ball | None = None) -> Teammate | None:
        """The best-placed active field player ahead of the ball (team frame) within pass range:
        the one furthest up the field, less a quarter of its distance from the ball."""
        ball = ball or self.ball(b)
        if ball is None:
            return None
        p = self.params
        bx, by = ball[0], ball[1]
        best, score = None, -math.inf
        for m in b.teammates:
            if not m.active or m.number == 1 or m.x < bx + 0.3 or m.age > 5.0:
                continue
            d = math.hypot(m.x - bx, m.y - by)
            if p.pass_min <= d <= p.pass_max and m.x - 0.25 * d > score:
                best, score = m, m.x - 0.25 * d
        return best

    def defend(self, b: Beliefs) -> MotionRequest:
        """Stand on the own-goal-to-ball line, ``defend_distance`` in front of the own goal centre."""
        ball = self.ball(b)
        if ball is None:
            return self.search(b)
        gx = -self._hl
        bx, by = ball[0], ball[1]
        vx, vy = bx - gx, by
        length = math.hypot(vx, vy) or 1.0
        d = min(self.params.defend_distance, max(0.3, length - 0.5))
        x, y = gx + vx / length * d, vy / length * d
        return MotionRequest(self.walk_to(b, (x, y, math.atan2(by - y, bx - x))))

    def keeper(self, b: Beliefs) -> MotionRequest:
        """Goalkeeper: stay between the ball and the goal inside the goal area; clear a close ball."""
        f = self.context.field
        goal_x = -self._hl
        ball = self.ball(b)
        if ball is None:
            return MotionRequest(self.walk_to(b, (goal_x + 0.35, 0.0, 0.0)))
        bx, by = ball[0], ball[1]
        if bx < goal_x + f.dims.goal_area_length + 0.6 and abs(by) < f.dims.goal_area_width / 2 + 0.4:
            return self.kick_to_goal(b)
        half_goal = f.dims.goal_inner_width / 2
        ang = math.atan2(by, bx - goal_x)
        x = goal_x + 0.35 * math.cos(ang) + 0.1
        y = max(-half_goal + 0.1, min(half_goal - 0.1, 0.6 * math.sin(ang)))
        return MotionRequest(self.walk_to(b, (x, y, math.atan2(by - y, bx - x)), avoid=False))

    def support(self, b: Beliefs, number: int) -> MotionRequest:
        """Hold the supporting spot of player ``number`` relative to the ball, clear of teammates."""
        ball = self.ball(b)
        if ball is None:
            return self.search(b)
        x, y, th = self.support_spot(b, ball, number)
        return MotionRequest(self.walk_to(b, (x, y, th)))

    def support_spot(self, b: Beliefs, ball: Ball, number: int) -> tuple[float, float, float]:
        """The supporting pose of player ``number`` (team frame), moved out of teammates' space."""
        bx, by = ball[0], ball[1]
        ox, oy = _SUPPORT_OFFSETS.get(number, (-1.5, 0.0))
        x = max(-self._hl + 0.8, min(self._hl - 0.8, bx + ox))
        y = max(-self._hw + 0.3, min(self._hw - 0.3, by * 0.5 + oy * self._hw / 3.0))
        space = self.params.personal_space
        for m in b.teammates:
            if not m.active:
                continue
            dx, dy = x - m.x, y - m.y
            d = math.hypot(dx, dy)
            if d < space:
                dx, dy, d = (dx, dy, d) if d > 1e-6 else (0.0, 1.0, 1.0)
                x, y = m.x + dx / d * space, m.y + dy / d * space
        return (x, y, math.atan2(by - y, bx - x))

    def keep_away(self, b: Beliefs) -> MotionRequest:
        """Opponent kickoff or set play: step out to ``keep_away`` from the ball, else stand facing it."""
        ball = self.ball(b)
        if ball is None:
            return self.search(b)
        rx, ry = ball[2], ball[3]
        d = math.hypot(rx, ry)
        keep = self.params.keep_away
        if d >= keep:
            turn = math.atan2(ry, rx)
            return MotionRequest() if abs(turn) < 0.3 else MotionRequest(walk=WalkRequest(turn=2.0 * turn))
        ux, uy = (-rx / d, -ry / d) if d > 1e-6 else (-1.0, 0.0)  # away from the ball, robot frame
        tx, ty = rx + ux * (keep + 0.2), ry + uy * (keep + 0.2)
        fx, fy = b.to_field(tx, ty)
        th = b.pose.theta + math.atan2(-uy, -ux)
        return MotionRequest(self.walk_to(b, (fx, fy, th), avoid=False))

    def clear_of_ball(self, b: Beliefs, target: tuple[float, float, float]) -> tuple[float, float, float]:
        """``target`` (team frame) moved out to ``keep_away`` + 0.2 m from the ball (if known)."""
        ball = self.ball(b)
        if ball is None:
            return target
        bx, by = ball[0], ball[1]
        x, y, _ = target
        dx, dy = x - bx, y - by
        d = math.hypot(dx, dy)
        keep = self.params.keep_away + 0.2
        if d >= keep:
            return target
        dx, dy, d = (dx, dy, d) if d > 1e-6 else (-1.0, 0.0, 1.0)
        x, y = bx + dx / d * keep, by + dy / d * keep
        return (x, y, math.atan2(by - y, bx - x))

    def search(self, b: Beliefs) -> MotionRequest:
        """Turn on the spot toward where the ball was last seen (left if never)."""
        ball = b.ball
        side = -1.0 if math.isfinite(ball.y) and ball.y < 0.0 else 1.0
        return MotionRequest(walk=WalkRequest(turn=side * self.params.search_turn))

    # -- where the ball is and where it should go ---------------------------------------------------
    def ball(self, b: Beliefs) -> Ball | None:
        """The ball to play (team x, y; robot x, y; m), ``None`` when nobody knows."""
        own = b.ball
        if own.level == "valid" and math.isfinite(own.field_x):
            return (own.field_x, own.field_y, own.x, own.y)
        best = b.best_ball()
        if best is None:
            return None
        rx, ry = b.to_robot(*best)
        return (best[0], best[1], rx, ry)

    def goal_aim(self, b: Beliefs, ball: Ball) -> float:
        """Kick direction toward the opponent goal (rad, **robot frame**), from the ball.

        From the goal model when it is close, confident and plausible (CMU IV.B), else from
        the pose with :meth:`feasible_aim`.
        """
        p = self.params
        g = b.goal
        bx, by, rx, ry = ball
        th = b.pose.theta
        if g is not None and g.confidence >= p.goal_confidence and math.hypot(g.centre_x, g.centre_y) < p.close_to_goal:
            gx, gy = b.to_field(g.centre_x, g.centre_y)
            if math.hypot(gx - self._hl, gy) < p.goal_gate:
                aim = math.atan2(g.centre_y - ry, g.centre_x - rx)
                if self.lineup_heading(bx, by, aim + th) is not None:
                    return aim
        return wrap_angle(self.feasible_aim(bx, by) - th)

    def feasible_aim(self, bx: float, by: float) -> float:
        """Aim (rad, team frame) from the ball at (bx, by) (team frame): at the opponent goal if
        the robot can line up for it (:meth:`lineup_heading`), else at points further back up
        the field, else toward the centre of the field; at a corner, where none of these can be
        reached, the reachable direction nearest to the goal (along the goal line toward the goal
        mouth: the robot must stay inside the field limits)."""
        hl = self._hl
        for tx in (hl + 0.2, hl / 2, 0.0):
            aim = math.atan2(-by, tx - bx)
            if self.lineup_heading(bx, by, aim) is not None:
                return aim
        goal = math.atan2(-by, hl + 0.2 - bx)
        for k in range(1, 64):
            for aim in (goal + 0.05 * k, goal - 0.05 * k):
                if self.lineup_heading(bx, by, aim) is not None:
                    return wrap_angle(aim)
        return math.atan2(-by, -bx)

    def lineup_heading(self, bx: float, by: float, aim: float) -> float | None:
        """Heading (rad, team frame) to line up with for a kick toward ``aim`` (team frame) of the
        ball at (bx, by): the aim itself if the spot ``approach_distance`` behind the ball lies
        within the field limits, else the heading nearest to it, at most ``side_kick`` away, whose
        spot does (a side kick); ``None`` if there is none."""
        if self._feasible(bx, by, aim):
            return aim
        step = 0.05
        for k in range(1, int(self.params.side_kick / step) + 1):
            for heading in (aim - k * step, aim + k * step):
                if self._feasible(bx, by, heading):
                    return wrap_angle(heading)
        return None

    # -- internals -----------------------------------------------------------------------------------
    def _feasible(self, bx: float, by: float, aim: float) -> bool:
        d = self.params.approach_distance
        return abs(bx - d * math.cos(aim)) <= self._lim_x and abs(by - d * math.sin(aim)) <= self._lim_y

    def _play(self, b: Beliefs, ball: Ball, aim: float, strength: float) -> MotionRequest:
        """Kick toward ``aim`` (rad, robot frame) when in position, else approach the line-up spot
        (:meth:`lineup_heading`; straight behind the ball, or beside it for a side kick)."""
        p = self.params
        bx, by, rx, ry = ball
        th = b.pose.theta
        heading = self.lineup_heading(bx, by, aim + th)
        side = 0.0 if heading is None else abs(wrap_angle(aim + th - heading))
        tolerance = p.kick_alignment if side < 1e-9 else min(p.side_kick, side) + 0.15
        seen = b.ball.level == "valid"
        if (
            seen
            and rx * rx + ry * ry < p.kick_distance * p.kick_distance
            and abs(math.atan2(ry, rx)) < p.kick_bearing
            and abs(aim) < tolerance
        ):
            return MotionRequest(kick=KickRequest(direction=aim, strength=strength))
        approach = aim if heading is None else wrap_angle(heading - th)
        return MotionRequest(self._approach(b, ball, approach))

    def _approach(self, b: Beliefs, ball: Ball, aim: float) -> WalkRequest:
        """Walk to the line-up spot behind the ball for ``aim`` (rad, robot frame).

        Far: with obstacle avoidance (the ball is one); close and behind the ball: straight in,
        turning to the aim early; close and on the wrong side: to a spot beside the ball first.
        """
        d = self.params.approach_distance
        rx, ry = ball[2], ball[3]
        ca, sa = math.cos(aim), math.sin(aim)
        sx, sy = rx - d * ca, ry - d * sa
        dist = math.hypot(rx, ry)
        if dist >= 0.45:
            return self._walk(b, sx, sy, aim, avoid=True)
        along = -(rx * ca + ry * sa)  # robot position along the aim, from the ball (< 0: behind)
        if along > -0.08:
            lateral = rx * sa - ry * ca  # robot position across the aim, from the ball
            side = 1.0 if lateral >= 0.0 else -1.0
            back = 0.25 if along < 0.1 else 0.0
            wx, wy = rx - back * ca - side * 0.4 * sa, ry - back * sa + side * 0.4 * ca
            return self._walk(b, wx, wy, math.atan2(ry, rx), avoid=False, final_radius=0.2, gain=1.2, ball=0.22)
        return self._walk(b, sx, sy, aim, avoid=False, final_radius=1.0, gain=1.5)

    def _clamp_x(self, x: float) -> float:
        lim = self._lim_x  # max(-lim, min(lim, x)) as comparisons
        x = x if x < lim else lim
        return x if x > -lim else -lim

    def _clamp_y(self, y: float) -> float:
        lim = self._lim_y  # max(-lim, min(lim, y)) as comparisons
        y = y if y < lim else lim
        return y if y > -lim else -lim

    def _obstacle_list(self, b: Beliefs) -> list[list[float]]:
        """The beliefs' obstacles (robot frame) as lists of two Python floats (cached per
        beliefs), and with them the two subsets :meth:`_walk` loops over: those near enough for
        :func:`_bend` to act on (it skips the others without changing the target) and those
        within the contact distance. Both keep the obstacles' order, so the walk is the same to
        the bit. One pass: ``math.hypot`` only for obstacles whose squared distance can be
        within reach (a bound a little above reach squared: hypot and the square root of the
        sum differ in the last bit at most)."""
        if self._cached is not b:
            self._cached = b
            obstacles = self._obstacles = b.obstacles.tolist()  # Python floats
            reach = _OBSTACLE_RADIUS + 0.3  # as _bend compares
            maybe2 = reach * reach * (1.0 + 1e-9)
            contact2 = self.params.contact_distance * self.params.contact_distance
            near: list[tuple[float, float, float]] = []
            touching: list[tuple[float, float]] = []
            for x, y in obstacles:
                r2 = x * x + y * y
                if r2 <= maybe2 and not ((d := math.hypot(x, y)) < 1e-6 or d > reach):
                    near.append((x, y, _OBSTACLE_RADIUS))
                if 1e-12 < r2 < contact2:
                    touching.append((x, y))
            self._bend_near, self._touching = near, touching
        return self._obstacles

    def _walk(
        self,
        b: Beliefs,
        fx: float,
        fy: float,
        heading: float,
        avoid: bool,
        final_radius: float = 0.4,
        gain: float = 1.0,
        ball: float = 0.0,
    ) -> WalkRequest:
        """Walk command toward the robot-frame point (fx, fy) with final heading ``heading``
        (rad, relative to the current one). ``avoid``: bend around robots and the ball (radius
        0.35 m) and keep out of personal space; ``ball`` > 0: bend around the ball with that radius."""
        p = self.params
        obstacles = self._obstacle_list(b)
        if avoid or ball > 0.0:
            bend: list[tuple[float, float, float]] = self._bend_near.copy() if avoid else []
            own = self.ball(b)
            if own is not None:
                bend.append((own[2], own[3], ball if ball > 0.0 else 0.35))
            fx, fy = _bend(bend, fx, fy)
            if avoid:
                fx, fy = _free_spot(obstacles, fx, fy, p.personal_space)
            tx, ty = b.to_field(fx, fy)
            if abs(tx) > self._lim_x or abs(ty) > self._lim_y:
                fx, fy = b.to_robot(self._clamp_x(tx), self._clamp_y(ty))
        dist = math.hypot(fx, fy)
        err = math.atan2(fy, fx) if dist > final_radius else heading
        if dist < 0.03 and abs(err) < 0.05:
            return WalkRequest()
        k = gain * 1.2 * (1.0 if abs(err) < 0.6 or dist < final_radius else 0.3)
        fwd, left = k * fx, k * fy
        for ox, oy in self._touching:  # within the contact distance (:meth:`_obstacle_list`)
            d = math.sqrt(ox * ox + oy * oy)
            ux, uy = ox / d, oy / d
            v = fwd * ux + left * uy
            if v > 0.0:
                fwd, left = fwd - v * ux, left - v * uy
        fwd, left = self._stay_inside(b, fwd, left)
        return WalkRequest(fwd, left, 2.0 * err)  # forward, left, turn

    def _stay_inside(self, b: Beliefs, fwd: float, left: float) -> tuple[float, float]:
        """Drop the part of a walk (robot frame, m/s) that leads further out once the robot is at
        the field limits: blocked by a goal post or a robot, the walk would slide it off the field."""
        x, y, th = b.pose.x, b.pose.y, b.pose.theta
        c, s = math.cos(th), math.sin(th)
        vx, vy = c * fwd - s * left, s * fwd + c * left  # team frame
        if abs(x) >= self._lim_x and x * vx > 0.0:
            vx = 0.0
        if abs(y) >= self._lim_y and y * vy > 0.0:
            vy = 0.0
        return c * vx + s * vy, -s * vx + c * vy


def _bend(obstacles: list[tuple[float, float, float]], ax: float, ay: float) -> tuple[float, float]:
    """Bend the robot-frame target (ax, ay) sideways around (x, y, radius) obstacles on the way."""
    for ox, oy, radius in obstacles:
        d = math.hypot(ox, oy)
        if d < 1e-6 or d > radius + 0.3:
            continue
        na = math.hypot(ax, ay)
        if na < d or (ox * ax + oy * ay) <= 0.0:
            continue
        side = 1.0 if (ax * oy - ay * ox) < 0.0 else -1.0  # step to the side the obstacle is not on
        push = 2.0 * (radius + 0.5 - d)
        ax, ay = ax - oy / d * side * push, ay + ox / d * side * push
    return ax, ay


def _free_spot(obstacles: list[list[float]], tx: float, ty: float, space: float) -> tuple[float, float]:
    """Move the robot-frame target (tx, ty) out of the obstacles' personal space.

    An obstacle whose squared distance exceeds ``space`` squared by a relative 1e-9 is skipped
    without ``math.hypot``: the distance hypot would give is at least ``space`` then (the sum of
    squares and hypot differ by a few ulp at most), so the result is the same to the bit."""
    beyond = space * space * (1.0 + 1e-9)
    for ox, oy in obstacles:
        dx, dy = tx - ox, ty - oy
        if dx * dx + dy * dy > beyond:
            continue
        d = math.hypot(dx, dy)
        if d >= space:
            continue
        if d < 1e-6:
            dx, dy, d = -ox, -oy, max(1e-6, math.hypot(ox, oy))
        tx, ty = ox + dx / d * space, oy + dy / d * space
    return tx, ty
