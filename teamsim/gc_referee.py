"""The referee when an external GameController runs the game (``teamsim match --gc-listen``).

In a real SPL game the human referees decide and the GameController operator types their
decisions in; the robots only see the GameController's packets. With an external
GameController the simulator plays the part of the field and of the referees' hands, and the
GameController the part of the decisions:

=====================  ===========================================================================
what                   who decides, and what the simulator does
=====================  ===========================================================================
state, first half      the GameController. On SET without a set play (a kickoff) the ball is put on
                       the centre mark; a change of half switches sides: active robots are carried
                       to their initial positions and the ball to the centre.
kicking team,          the GameController (kick-offs and set plays); the packet's clocks are passed
secondary time, clock  to the robots unchanged.
score                  the GameController. A goal it awards is logged and counted.
penalties              the GameController, with its codes: a robot it penalises is removed from the
                       field, a robot it releases is put back by the return rule
                       (:mod:`teamsim.placement`); nothing returns on a timer.
set plays              the GameController. When its set play matches the one the automatic rules
                       found, the ball already lies where they placed it.
goals, ball out,       found by the automatic rules and logged as ``suggestion`` events only; the
fouls                  ball is put back (centre after a goal, the set-play spot after it left the
                       field), as the referees would pick it up. A foul is suggested again for
                       the same robot and code at most every :data:`SUGGEST_EVERY` seconds.
=====================  ===========================================================================

The packets the robots receive are the GameController's, with the two team blocks in the
simulator's team-index order; before the first one arrives the game waits in INITIAL. The
match ends when the GameController reports FINISHED in the second half. Penalty shoot-outs and
timeouts are passed to the robots as the GameController announces them; the simulator does
not arrange the robots for a shoot-out.
"""

from __future__ import annotations

from collections.abc import Sequence

from cognition.field import Field
from cognition.gamestate import GameControlData, GameStateId, Penalty, SetPlay
from teamsim.events import EventLog
from teamsim.placement import illegal_kickoff_robots, initial_position
from teamsim.referee import Referee, RefereeParams
from teamsim.world import CollisionEvent, World

SUGGEST_EVERY = 5.0
"""Seconds before the same foul of the same robot is suggested again."""


class GameControllerReferee(Referee):
    """A referee whose decisions come from GameController packets (:meth:`follow`)."""

    def __init__(self, world: World, field_map: Field, params: RefereeParams, log: EventLog):
        super().__init__(world, field_map, params, log)
        self.external: GameControlData | None = None
        """The latest packet followed (teams in team-index order); ``None`` before the first."""
        self._suggested: dict[tuple[str, int, int, int], float] = {}

    def game_state(self) -> GameControlData:
        """The GameController's latest packet (the own INITIAL packet before the first one)."""
        return self.external if self.external is not None else super().game_state()

    # -- following the GameController ------------------------------------------------------
    def follow(self, data: GameControlData, now: float) -> None:
        """Take over the decisions of a GameController packet at simulated time ``now`` (s).

        ``ValueError`` if the packet is for other teams than this match's ``team_numbers``."""
        numbers = self.params.team_numbers
        try:
            ours = (data.team(numbers[0]), data.team(numbers[1]))
        except KeyError:
            theirs = tuple(t.team_number for t in data.teams)
            raise ValueError(f"GameController packet is for teams {theirs}, this match has {numbers}") from None
        data = data.with_changes(teams=ours)
        first = bool(data.first_half)
        if first != self.first_half:
            self._switch_half(first, now)
        if data.kicking_team in numbers:
            self.kicking_team = numbers.index(data.kicking_team)
        for t in (0, 1):
            while self.score[t] < ours[t].score:
                self.score[t] += 1
                self.counters.goals.append((now, t, 1 if self.first_half else 2))
                self.log.add(now, "goal", team=t, score=tuple(self.score), source="gamecontroller")
            self.score[t] = ours[t].score  # an operator's correction may also lower it
        state = GameStateId(data.state)
        if state != self.state:
            self._follow_state(state, SetPlay(data.set_play), now)
        play = SetPlay(data.set_play)
        if play != self.set_play:
            self.set_play = play
            if play == SetPlay.NONE:
                self.log.add(now, "set_play_over", source="gamecontroller")
            else:
                self.set_play_until = now + max(0, data.secondary_time)
                self.counters.set_plays.append((now, int(play), self.kicking_team))
                self.log.add(now, "set_play", play=play.name, team=self.kicking_team, source="gamecontroller")
        for t in (0, 1):
            for number in range(1, self.n + 1):
                self._follow_penalty(t, number, ours[t].players[number - 1].penalty, now)
                st = self.status[(t, number)]
                if st.penalty != Penalty.NONE:
                    st.penalized_until = now + ours[t].players[number - 1].secs_till_unpenalised
        self.secs_remaining = float(data.secs_remaining)
        self.external = data

    def _follow_state(self, state: GameStateId, play: SetPlay, now: float) -> None:
        if state == GameStateId.PLAYING and self.state == GameStateId.SET:
            self._kickoff(now)
            return
        self._enter(state, now)
        if state == GameStateId.READY:
            self._ready_still_since = -1.0
        elif state == GameStateId.SET and play == SetPlay.NONE:
            self.world.place_ball(0.0, 0.0)
            for team in (0, 1):
                kicking = team == self.kicking_team
                for number in illegal_kickoff_robots(self.field, self._team_positions(team), kicking):
                    self.log.add(now, "suggestion", what="illegal_position_in_set", team=team, number=number)
        elif state == GameStateId.FINISHED:
            if self.first_half:
                self.log.add(now, "half_time", score=tuple(self.score))
            else:
                self.finished = True
                self.log.add(now, "full_time", score=tuple(self.score))

    def _follow_penalty(self, team: int, number: int, code: int, now: float) -> None:
        st = self.status[(team, number)]
        if code != Penalty.NONE and st.penalty == Penalty.NONE:
            self.penalize(team, number, code, now, reason="gamecontroller")
        elif code == Penalty.NONE and st.penalty != Penalty.NONE:
            self.unpenalize(team, number, now)
        elif code != st.penalty:
            st.penalty = int(code)
            self.log.add(now, "penalty_changed", team=team, number=number, code=Penalty(code).name)

    def _switch_half(self, first: bool, now: float) -> None:
        self.first_half = first
        self.log.add(now, "side_switch", first_half=first)
        for r in self.world.robots:
            if r.penalized:
                continue  # stays beside the field until the GameController releases it
            r.fallen_until = -1.0
            self._place(r, initial_position(self.field, r.number, self.n), now, carried=True)
        self.world.place_ball(0.0, 0.0)

    # -- the field between packets ---------------------------------------------------------
    def update(self, now: float, events: Sequence[CollisionEvent]) -> None:
        """One physics step: carrying, ball touches, and the automatic decisions as suggestions."""
        self._now_for_packet = now
        self._end_carrying(now)
        for ev in events:
            if ev.kind in ("robot_ball", "robot_kick"):
                self.last_touch_team = ev.a[0]
        if self.finished:
            return
        if self.state == GameStateId.PLAYING:
            self._check_goal_and_out(now)
        if self.state in (GameStateId.READY, GameStateId.PLAYING):
            self._auto_penalties(now, events)

    def _goal(self, now: float, scorer: int) -> None:
        self.world.place_ball(0.0, 0.0)
        self.log.add(now, "suggestion", what="goal", team=scorer)

    def _start_set_play(self, now: float, play: SetPlay, team: int, x: float, y: float) -> None:
        self.world.place_ball(x, y)
        self.fouls.reset_stuck(x, y, now)
        self.log.add(now, "suggestion", what=play.name.lower(), team=team, x=x, y=y)

    def _foul(self, team: int, number: int, code: int, now: float) -> None:
        key = ("penalty", team, number, int(code))
        if now - self._suggested.get(key, -SUGGEST_EVERY) >= SUGGEST_EVERY:
            self._suggested[key] = now
            self.log.add(now, "suggestion", what="penalty", team=team, number=number, code=Penalty(code).name)
