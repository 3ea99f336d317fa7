"""The referee and game controller: SPL game states, goals, set plays, penalties, placement.

State machine (per half): INITIAL -> [STANDBY, if ``standby_seconds`` > 0] -> READY -> SET ->
PLAYING -> (goal) READY -> ... and at
the end of the half FINISHED; after the half-time break the teams switch sides and the
second half starts in INITIAL. The kicking team alternates between halves; after a goal the
conceding team kicks off. The game clock (``secs_remaining``) runs in PLAYING only.

Automatic penalties (SPL codes from :class:`cognition.gamestate.Penalty`):

======================  =================================================================
penalty                 detected when
======================  =================================================================
LEAVING_THE_FIELD       an active robot that had entered the field is fully outside the
                        field lines (and not inside its goal), in READY or PLAYING
ILLEGAL_POSITION_IN_SET a robot is in an illegal kickoff position when SET begins and the
                        rule set penalises (``spl2025``); ``spl2010`` places it instead
PLAYER_PUSHING          a robot drives into an opponent (pushing evidence from contacts)
                        for ``fouls.pushing_seconds``, or its charge topples the opponent
INACTIVE_PLAYER         a robot has been fallen for ``fouls.inactive_seconds``
LOCAL_GAME_STUCK        the ball has stayed within ``fouls.stuck_radius`` for ``fouls.stuck_seconds``
                        with a robot next to it; the nearest robot is removed
======================  =================================================================

The evidence is gathered by :class:`teamsim.fouls.FoulDetector`. A penalised robot is
removed from the field, waits ``penalty_seconds`` and is placed back by the return rule
(:mod:`teamsim.placement`). Scripts can request any penalty.

Manual placement: robots placed by the referee are carried, so their ``picked_up`` signal
is on for ``carry_seconds``.

Parameters (:class:`RefereeParams`, seconds). Every number is checked against its range when
the parameters are built (:func:`cognition.params.check_ranges`):

====================  ==========  ============  ==========================================================
parameter             default     range         meaning
====================  ==========  ============  ==========================================================
half_seconds          600         (0, 86400]    length of a half on the game clock (runs in PLAYING)
halftime_seconds      10          [0, 3600]     break between the halves (in FINISHED)
initial_seconds       2           [0, 3600]     time in INITIAL
standby_seconds       0           [0, 3600]     time in STANDBY (0: no STANDBY)
ready_seconds         45          (0, 3600]     longest READY (earlier when every robot stands still)
set_seconds           5           (0, 3600]     time in SET
kickoff_free_seconds  10          [0, 3600]     after a kickoff only the kicking team may play the ball
set_play_seconds      30          [0, 3600]     length of a set play
penalty_seconds       45          (0, 3600]     time a penalised robot stays removed
carry_seconds         1.5         [0, 3600]     ``picked_up`` time of a robot the referee places
rules                 spl2025                   ``spl2025`` or ``spl2010`` (return rule, illegal SET positions)
set_position_rule     auto                      ``auto`` (by ``rules``), ``place`` or ``penalize``
fouls                 FoulParams                thresholds of the automatic fouls (:mod:`teamsim.fouls`)
team_numbers          (1, 2)      [1, 255]      GameController team numbers of team 0 and 1 (different)
====================  ==========  ============  ==========================================================
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import ClassVar, Literal

from cognition.field import Field
from cognition.gamestate import (
    GameControlData,
    GameStateId,
    Penalty,
    RobotInfo,
    SetPlay,
    TeamInfo,
)
from cognition.positions import kickoff_position
from teamsim.events import EventLog
from teamsim.fouls import FoulDetector, FoulParams
from teamsim.params import Range, Ranges, check_choice, check_ranges, non_negative, positive
from teamsim.placement import (
    RETURN_RULES,
    attack_sign,
    illegal_kickoff_robots,
    initial_position,
    is_inside_field,
    return_position,
    team_to_world,
    world_to_team,
)
from teamsim.robot import Robot, get_position
from teamsim.world import CollisionEvent, RobotId, World

_PLAYING = RobotInfo()
"""The packet's entry of a player that is not penalised (a frozen record: one serves them all)."""
_S_INITIAL, _S_STANDBY, _S_READY, _S_SET, _S_PLAYING, _S_FINISHED = (
    GameStateId.INITIAL, GameStateId.STANDBY, GameStateId.READY, GameStateId.SET, GameStateId.PLAYING,
    GameStateId.FINISHED,
)  # fmt: skip
_NO_SET_PLAY = SetPlay.NONE
_PENALISING_STATES = (GameStateId.READY, GameStateId.PLAYING)
"""The enum members the per-step code compares with, as module names: in CPython 3.11 reading a
member off its class (``GameStateId.PLAYING``) costs about 0.1 us, a module name a tenth of that,
and the referee compares the state several times in every physics step (the same objects)."""


def _ceil(seconds: float) -> int:
    """Whole seconds shown on a clock, robust to float accumulation (59.9999999 -> 60)."""
    return math.ceil(seconds - 1e-6)


@dataclass(frozen=True)
class RefereeParams:
    """Timing and rule parameters of the referee (seconds, metres)."""

    half_seconds: float = 600.0
    halftime_seconds: float = 10.0
    initial_seconds: float = 2.0
    standby_seconds: float = 0.0
    ready_seconds: float = 45.0
    set_seconds: float = 5.0
    kickoff_free_seconds: float = 10.0
    set_play_seconds: float = 30.0
    penalty_seconds: float = 45.0
    carry_seconds: float = 1.5
    rules: Literal["spl2025", "spl2010"] = "spl2025"
    set_position_rule: Literal["auto", "place", "penalize"] = "auto"
    fouls: FoulParams = field(default_factory=FoulParams)
    team_numbers: tuple[int, int] = (1, 2)

    RANGES: ClassVar[Ranges] = {
        "half_seconds": positive(86_400.0),
        "halftime_seconds": non_negative(3600.0),
        "initial_seconds": non_negative(3600.0),
        "standby_seconds": non_negative(3600.0),
        "ready_seconds": positive(3600.0),
        "set_seconds": positive(3600.0),
        "kickoff_free_seconds": non_negative(3600.0),
        "set_play_seconds": non_negative(3600.0),
        "penalty_seconds": positive(3600.0),
        "carry_seconds": non_negative(3600.0),
        "team_numbers": Range(1, 255),
    }

    def __post_init__(self) -> None:
        check_ranges(self)
        check_choice("RefereeParams", "rules", self.rules, RETURN_RULES)
        check_choice(
            "RefereeParams",
            "set_position_rule",
            self.set_position_rule,
            ("auto", "place", "penalize"),
        )
        if self.team_numbers[0] == self.team_numbers[1]:
            raise ValueError(f"RefereeParams.team_numbers must be two different numbers, got {self.team_numbers}")

    @property
    def penalize_illegal_set(self) -> bool:
        """Whether robots illegally positioned at SET are penalised (else placed)."""
        if self.set_position_rule == "auto":
            return self.rules == "spl2025"
        return self.set_position_rule == "penalize"


class _Clocks:
    """When the referee's per-step loops over the robots next have work (s of match time): the
    earliest ``carried_until`` of a carried robot (``put_down``) and the earliest
    ``penalized_until`` of a penalised one (``returns``); ``inf`` when there is none.

    Every write of those fields goes through :meth:`_RobotStatus.__setattr__`, which keeps
    ``put_down`` at or before every carry's end and sets ``returns`` to ``-inf`` (look at every
    robot at the next step, which works the earliest out again). The loops, run only once their
    clock is due, then do what they did when run in every physics step.
    """

    __slots__ = ("put_down", "returns")

    def __init__(self) -> None:
        self.put_down = math.inf
        self.returns = math.inf


@dataclass
class _RobotStatus:
    penalty: int = Penalty.NONE
    penalized_until: float = 0.0
    removed_at: tuple[float, float] = (0.0, 0.0)
    carried_until: float = -1.0
    penalty_count: int = 0
    clocks: _Clocks | None = field(default=None, repr=False, compare=False)
    """The referee's clocks, told about every change of a time below (``None``: no referee)."""

    def __setattr__(self, name: str, value: object) -> None:
        object.__setattr__(self, name, value)
        if name == "carried_until" or name == "penalty" or name == "penalized_until":
            clocks = self.__dict__.get("clocks")  # absent while __init__ sets the fields
            if clocks is None:
                return
            if name == "carried_until":
                if 0.0 <= value < clocks.put_down:  # type: ignore[operator]
                    clocks.put_down = value
            else:
                clocks.returns = -math.inf


@dataclass
class RefereeCounters:
    """What happened in the match so far."""

    goals: list[tuple[float, int, int]] = field(default_factory=list)
    """(time s, scoring team index, half 1/2) per goal."""
    kickoffs: list[tuple[float, int]] = field(default_factory=list)
    """(time s, kicking team index) per kickoff (PLAYING after SET)."""
    penalties: list[tuple[float, int, int, int]] = field(default_factory=list)
    """(time s, team index, player number, penalty code) per penalty."""
    returns: list[tuple[float, int, int]] = field(default_factory=list)
    """(time s, team index, player number) per return from a penalty."""
    placements: int = 0
    set_plays: list[tuple[float, int, int]] = field(default_factory=list)
    """(time s, set play code, kicking team index)."""


class Referee:
    """Runs the game: states, clock, goals, ball out, penalties and placement."""

    def __init__(self, world: World, field_map: Field, params: RefereeParams, log: EventLog):
        self.world = world
        self.field = field_map
        d = field_map.dims
        self._goal_line_x = field_map.half_length + d.line_width / 2
        self._touch_line_y = field_map.half_width + d.line_width / 2
        self._goal_half_width = d.goal_inner_width / 2
        """Where the ball is out (m, world frame, the ball's edge past the lines' outer edges), worked out once."""
        self.params = params
        self.log = log
        self.n = world.players_per_team
        self.state = GameStateId.INITIAL
        self.first_half = True
        self.finished = False
        self.kicking_team = 0
        self.first_kickoff_team = 0
        self.set_play = SetPlay.NONE
        self.set_play_until = 0.0
        self.state_since = 0.0
        self.secs_remaining = params.half_seconds
        self.score = [0, 0]
        self._clocks = _Clocks()
        self.status: dict[RobotId, _RobotStatus] = {
            (r.team, r.number): _RobotStatus(clocks=self._clocks) for r in world.robots
        }
        self._robot_status = [(r, self.status[(r.team, r.number)]) for r in world.robots]
        """Every robot with its status record, in robot order."""
        self.counters = RefereeCounters()
        self.last_touch_team: int | None = None
        self.fouls = FoulDetector(world, field_map, params.fouls)
        self._ready_still_since = -1.0
        self._kickoff_until = 0.0
        self._budget_left = [0, 0]
        self._packet = 0
        self._cached: GameControlData | None = None
        self._cache_key: tuple[object, ...] | None = None
        self._now_for_packet = 0.0

    # -- frames ----------------------------------------------------------------------------
    def sign(self, team: int) -> float:
        """+1 if ``team`` attacks world +x now."""
        return attack_sign(team, self.first_half)

    def team_pose(self, robot: Robot) -> tuple[float, float, float]:
        """The robot's pose in its own team frame."""
        return world_to_team(self.sign(robot.team), *robot.pose)

    # -- setup -----------------------------------------------------------------------------
    def start(self) -> None:
        """Put all robots at their initial positions and the ball at the centre."""
        for r in self.world.robots:
            r.add_to(self.world.space)
            self._place(r, initial_position(self.field, r.number, self.n), now=0.0, carried=False)
        self.world.place_ball(0.0, 0.0)
        self._enter(GameStateId.INITIAL, 0.0)

    def play_now(self, now: float) -> None:
        """Skip INITIAL, READY and SET: enter PLAYING at once without a kickoff (drills start here,
        after the caller has placed robots and ball)."""
        self.set_play = SetPlay.NONE
        self._kickoff_until = now
        self._enter(GameStateId.PLAYING, now)
        self.fouls.reset_stuck(self.world.ball.position.x, self.world.ball.position.y, now)

    def _place(self, robot: Robot, team_pose: tuple[float, float, float], now: float, carried: bool) -> None:
        robot.teleport(*team_to_world(self.sign(robot.team), *team_pose))
        st = self.status[(robot.team, robot.number)]
        self.fouls.placed((robot.team, robot.number), is_inside_field(self.field, team_pose[0], team_pose[1]))
        if carried:
            st.carried_until = now + self.params.carry_seconds
            robot.picked_up = True

    def _enter(self, state: GameStateId, now: float) -> None:
        self.state = state
        self.state_since = now
        self.log.add(now, "state", state=state.name, first_half=self.first_half)

    # -- the game controller packet --------------------------------------------------------
    def set_message_budget(self, left: Sequence[int]) -> None:
        """Tell the referee each team's remaining message budget (published in the packet)."""
        self._budget_left = [int(left[0]), int(left[1])]

    def game_state(self) -> GameControlData:
        """The current RoboCupGameControlData v18 content (teams in team-index order)."""
        now, ceil = self._now_for_packet, math.ceil
        key = (
            self.state,
            self.set_play,
            self.first_half,
            self.kicking_team,
            _ceil(self.secs_remaining),
            tuple(self.score),
            tuple(self._budget_left),
            # (penalty, _ceil(seconds left)) of every robot, _ceil written out: asked every cognition frame
            tuple([(s.penalty, ceil(s.penalized_until - now - 1e-6)) for s in self.status.values()]),
            self._secondary(),
        )
        if self._cached is not None and key == self._cache_key:
            return self._cached
        self._packet += 1
        teams = []
        for t in (0, 1):
            players = []
            for num in range(1, 21):
                st = self.status.get((t, num))
                if st is None or st.penalty == Penalty.NONE:
                    players.append(_PLAYING)
                else:
                    left = max(0, _ceil(st.penalized_until - self._now_for_packet))
                    players.append(RobotInfo(int(st.penalty), left))
            teams.append(
                TeamInfo(
                    team_number=self.params.team_numbers[t],
                    field_player_colour=t,
                    goalkeeper_colour=t,
                    goalkeeper=1,
                    score=self.score[t],
                    message_budget=self._budget_left[t],
                    players=tuple(players),
                )
            )
        self._cached = GameControlData(
            packet_number=self._packet & 0xFF,
            players_per_team=self.n,
            state=int(self.state),
            set_play=int(self.set_play),
            first_half=int(self.first_half),
            kicking_team=self.params.team_numbers[self.kicking_team],
            secs_remaining=_ceil(self.secs_remaining),
            secondary_time=self._secondary(),
            teams=(teams[0], teams[1]),
        )
        self._cache_key = key
        return self._cached

    def _secondary(self) -> int:
        now = self._now_for_packet
        if self.state == _S_READY:
            return max(0, _ceil(self.state_since + self.params.ready_seconds - now))
        if self.state == _S_SET:
            return max(0, _ceil(self.state_since + self.params.set_seconds - now))
        if self.state == _S_PLAYING and self.set_play != _NO_SET_PLAY:
            return max(0, _ceil(self.set_play_until - now))
        if self.state == _S_PLAYING and now < self._kickoff_until:
            return max(0, _ceil(self._kickoff_until - now))
        return 0

    # -- penalties -------------------------------------------------------------------------
    def is_active(self, team: int, number: int) -> bool:
        """Whether the robot is on the field (not penalised)."""
        return self.status[(team, number)].penalty == Penalty.NONE

    def penalize(self, team: int, number: int, code: int, now: float, reason: str = "auto") -> bool:
        """Remove a robot with SPL penalty ``code``; False if it already is penalised."""
        if code == Penalty.NONE or code not in Penalty._value2member_map_:
            raise ValueError(f"unknown penalty code {code!r}; valid: {[int(p) for p in Penalty if p]}")
        st = self.status[(team, number)]
        if st.penalty != Penalty.NONE:
            return False
        robot = self.world.robot(team, number)
        tx, ty, _ = self.team_pose(robot)
        st.penalty = int(code)
        st.penalized_until = now + self.params.penalty_seconds
        st.removed_at = (tx, ty)
        st.penalty_count += 1
        robot.penalized = True
        robot.picked_up = True
        robot.kick_request = None
        robot.remove_from(self.world.space)
        # shown beside the field, next to the touchline it was removed at
        bench_y = math.copysign(self.field.half_width + self.field.dims.border_strip * 0.8, ty or 1.0)
        robot.teleport(*team_to_world(self.sign(team), tx, bench_y, 0.0))
        self.counters.penalties.append((now, team, number, int(code)))
        self.log.add(now, "penalty", team=team, number=number, code=Penalty(code).name, reason=reason)
        return True

    def unpenalize(self, team: int, number: int, now: float) -> None:
        """Return a penalised robot to the field by the active return rule."""
        st = self.status[(team, number)]
        if st.penalty == Penalty.NONE:
            return
        robot = self.world.robot(team, number)
        sign = self.sign(team)
        ball_team = world_to_team(sign, self.world.ball.position.x, self.world.ball.position.y, 0.0)
        taken = [self.team_pose(r)[:2] for r in self.world.robots if r.team == team and r.in_space]
        pose = return_position(self.field, self.params.rules, st.removed_at[1], ball_team[1], taken)
        st.penalty = Penalty.NONE
        st.penalized_until = 0.0
        robot.penalized = False
        robot.add_to(self.world.space)
        robot.fallen_until = -1.0
        self._place(robot, pose, now, carried=True)
        self.counters.returns.append((now, team, number))
        self.log.add(now, "unpenalized", team=team, number=number, x=pose[0], y=pose[1])

    def _clear_penalties(self, now: float) -> None:
        for (team, number), st in self.status.items():
            if st.penalty != Penalty.NONE:
                st.penalty = Penalty.NONE
                robot = self.world.robot(team, number)
                robot.penalized = False
                robot.add_to(self.world.space)
                self.log.add(now, "penalty_cleared", team=team, number=number)

    # -- the main update -------------------------------------------------------------------
    def update(self, now: float, events: Sequence[CollisionEvent]) -> None:
        """Advance the game by one physics step that ended at ``now``."""
        self._now_for_packet = now
        dt = self.world.dt
        if now >= self._clocks.put_down:
            self._end_carrying(now)
        for ev in events:
            if ev.kind in ("robot_ball", "robot_kick"):
                self.last_touch_team = ev.a[0]
                if self.set_play != _NO_SET_PLAY and ev.a[0] == self.kicking_team:
                    self._end_set_play(now)
        if self.finished:
            return
        p = self.params
        s = self.state
        if s == _S_INITIAL and now - self.state_since >= p.initial_seconds:
            if p.standby_seconds > 0:
                self._enter(GameStateId.STANDBY, now)
            else:
                self._start_ready(now)
        elif s == _S_STANDBY and now - self.state_since >= p.standby_seconds:
            self._start_ready(now)
        elif s == _S_READY:
            self._update_ready(now)
        elif s == _S_SET and now - self.state_since >= p.set_seconds:
            self._kickoff(now)
        elif s == _S_PLAYING:
            self.secs_remaining = max(0.0, self.secs_remaining - dt)
            if self.set_play != _NO_SET_PLAY and now >= self.set_play_until:
                self._end_set_play(now)
            if not self._check_goal_and_out(now) and self.secs_remaining <= 0.0:
                self._end_half(now)
        elif s == _S_FINISHED and now - self.state_since >= p.halftime_seconds:
            self._start_second_half(now)
        if self.state in _PENALISING_STATES:
            self._auto_penalties(now, events)
        if now >= self._clocks.returns:
            self._update_penalty_timers(now)

    def _kickoff(self, now: float) -> None:
        """SET ends: PLAYING starts with a kickoff (only the kicking team may play the ball for a while)."""
        self._enter(GameStateId.PLAYING, now)
        self._kickoff_until = now + self.params.kickoff_free_seconds
        self.fouls.reset_stuck(self.world.ball.position.x, self.world.ball.position.y, now)
        self.counters.kickoffs.append((now, self.kicking_team))
        self.log.add(now, "kickoff", team=self.kicking_team)

    def _end_carrying(self, now: float) -> None:
        """Put down the robots whose carry time is over (their ``picked_up`` signal goes off)."""
        due = math.inf
        for r, st in self._robot_status:
            until = st.carried_until
            if until >= 0:
                if now >= until:
                    st.carried_until = -1.0
                    r.picked_up = False
                elif until < due:
                    due = until
        self._clocks.put_down = due

    def _start_ready(self, now: float) -> None:
        self._enter(GameStateId.READY, now)
        self._ready_still_since = -1.0
        self.set_play = SetPlay.NONE

    def _update_ready(self, now: float) -> None:
        p = self.params
        elapsed = now - self.state_since
        all_ready = elapsed >= 3.0 and self._all_legal_and_still()
        if all_ready and self._ready_still_since < 0:
            self._ready_still_since = now
        elif not all_ready:
            self._ready_still_since = -1.0
        if elapsed >= p.ready_seconds or (all_ready and now - self._ready_still_since >= 1.0):
            self._start_set(now)

    def _team_positions(self, team: int) -> dict[int, tuple[float, float]]:
        return {
            r.number: self.team_pose(r)[:2]
            for r in self.world.robots
            if r.team == team and self.is_active(r.team, r.number)
        }

    def _all_legal_and_still(self) -> bool:
        # the cheaper test first: while robots walk to their spots the first one moving decides
        for r in self.world.robots:
            if r.in_space and (r.is_fallen() or abs(r.body.velocity) > 0.03 or abs(r.body.angular_velocity) > 0.1):
                return False
        for team in (0, 1):
            if illegal_kickoff_robots(self.field, self._team_positions(team), team == self.kicking_team):
                return False
        return True

    def _start_set(self, now: float) -> None:
        self._enter(GameStateId.SET, now)
        self.world.place_ball(0.0, 0.0)
        for team in (0, 1):
            kicking = team == self.kicking_team
            for number in illegal_kickoff_robots(self.field, self._team_positions(team), kicking):
                if self.params.penalize_illegal_set:
                    self.penalize(team, number, Penalty.ILLEGAL_POSITION_IN_SET, now)
                else:
                    robot = self.world.robot(team, number)
                    self._place(robot, kickoff_position(self.field, number, kicking), now, carried=True)
                    self.counters.placements += 1
                    self.log.add(now, "placed", team=team, number=number)

    def _check_goal_and_out(self, now: float) -> bool:
        b = get_position(self.world.ball._body)  # ball.position, read in C
        bx, by = b.x, b.y
        r = self.world.ball_radius
        f = self.field
        beyond_goal_line = abs(bx) - r > self._goal_line_x
        if beyond_goal_line and abs(by) < self._goal_half_width:
            world_sign = 1.0 if bx > 0 else -1.0
            scorer = 0 if self.sign(0) == world_sign else 1
            self._goal(now, scorer)
            return True
        if abs(by) - r > self._touch_line_y:
            taker = 1 - self.last_touch_team if self.last_touch_team is not None else 0
            x = min(max(bx, -f.half_length), f.half_length)
            self._start_set_play(now, SetPlay.KICK_IN, taker, x, math.copysign(f.half_width, by))
            return True
        if beyond_goal_line:
            world_sign = 1.0 if bx > 0 else -1.0
            defender = 0 if self.sign(0) == -world_sign else 1
            y_side = math.copysign(1.0, by)
            if self.last_touch_team == defender:
                self._start_set_play(
                    now,
                    SetPlay.CORNER_KICK,
                    1 - defender,
                    world_sign * f.half_length,
                    y_side * f.half_width,
                )
            else:
                ga = f.dims.goal_area_length
                self._start_set_play(
                    now,
                    SetPlay.GOAL_KICK,
                    defender,
                    world_sign * (f.half_length - ga),
                    y_side * f.dims.goal_area_width / 2,
                )
            return True
        return False

    def _goal(self, now: float, scorer: int) -> None:
        self.score[scorer] += 1
        half = 1 if self.first_half else 2
        self.counters.goals.append((now, scorer, half))
        self.log.add(now, "goal", team=scorer, score=tuple(self.score))
        self.kicking_team = 1 - scorer
        self.set_play = SetPlay.NONE
        self.world.place_ball(0.0, 0.0)
        self._start_ready(now)

    def _start_set_play(self, now: float, play: SetPlay, team: int, x: float, y: float) -> None:
        self.world.place_ball(x, y)
        self.set_play = play
        self.kicking_team = team
        self.set_play_until = now + self.params.set_play_seconds
        self.fouls.reset_stuck(x, y, now)
        self.counters.set_plays.append((now, int(play), team))
        self.log.add(now, "set_play", play=play.name, team=team, x=x, y=y)

    def _end_set_play(self, now: float) -> None:
        self.set_play = SetPlay.NONE
        self.log.add(now, "set_play_over")

    def _end_half(self, now: float) -> None:
        self.set_play = SetPlay.NONE
        self._enter(GameStateId.FINISHED, now)
        if self.first_half:
            self.log.add(now, "half_time", score=tuple(self.score))
        else:
            self.finished = True
            self.log.add(now, "full_time", score=tuple(self.score))

    def _start_second_half(self, now: float) -> None:
        self.first_half = False
        self.secs_remaining = self.params.half_seconds
        self._clear_penalties(now)
        self.kicking_team = 1 - self.first_kickoff_team
        self.log.add(now, "side_switch")
        for r in self.world.robots:
            r.fallen_until = -1.0
            self._place(r, initial_position(self.field, r.number, self.n), now, carried=True)
        self.world.place_ball(0.0, 0.0)
        self._enter(GameStateId.INITIAL, now)

    # -- automatic penalties ---------------------------------------------------------------
    def _auto_penalties(self, now: float, events: Sequence[CollisionEvent]) -> None:
        check_stuck = self.state == _S_PLAYING
        for (team, number), code in self.fouls.detect(now, events, check_stuck):
            self._foul(team, number, code, now)

    def _foul(self, team: int, number: int, code: int, now: float) -> None:
        """An automatic foul was detected: penalise the robot."""
        self.penalize(team, number, code, now)

    def _update_penalty_timers(self, now: float) -> None:
        for (team, number), st in self.status.items():
            if st.penalty and now >= st.penalized_until:  # penalised (Penalty.NONE is 0) and time is up
                self.unpenalize(team, number, now)
        self._clocks.returns = min([st.penalized_until for st in self.status.values() if st.penalty], default=math.inf)
