"""The referee: state machine, goals, ball out, side switch, automatic and scripted penalties,
both return rules, manual placement and kidnapping."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest
from helpers import ScriptBrain, short_config

from cognition.gamestate import GameStateId, Penalty, SetPlay
from cognition.oracle import OracleInput
from cognition.representations import SensorFrame, WalkRequest
from teamsim.events import ForceFall, ForcePenalty, Kidnap, PlaceBall
from teamsim.fouls import FoulParams
from teamsim.match import Match, MatchConfig
from teamsim.referee import RefereeParams


def stand_match(
    config: MatchConfig | None = None, **policies: object
) -> tuple[Match, dict[tuple[int, int], ScriptBrain]]:
    """A match whose robots stand still unless a policy is given as ``p<team>_<number>``."""
    brains: dict[tuple[int, int], ScriptBrain] = {}

    def factory(team: int, number: int) -> ScriptBrain:
        brain = ScriptBrain(policies.get(f"p{team}_{number}"))  # type: ignore[arg-type]
        brains[(team, number)] = brain
        return brain

    return Match(config or short_config(), brains=factory), brains


def run_until_state(match: Match, state: GameStateId, limit: float = 120.0) -> None:
    while match.referee.state != state:
        assert match.time < limit, f"state {state.name} not reached by {limit} s"
        match.step()


def penalties(match: Match) -> list[tuple[int, int, str]]:
    return [(t, n, Penalty(c).name) for _, t, n, c in match.referee.counters.penalties]


def walk_toward(tx: float, ty: float, speed: float = 0.25, state: GameStateId | None = None):
    """A policy that walks to a team-frame target (only in ``state``, if given)."""

    def policy(frame: SensorFrame, oracle: OracleInput) -> WalkRequest:
        if state is not None and frame.game.state != state:
            return WalkRequest()
        me = oracle.self_pose
        ang = math.atan2(ty - me.y, tx - me.x) - me.theta
        return WalkRequest(forward=speed * math.cos(ang), left=speed * math.sin(ang))

    return policy


def test_state_sequence_and_game_packet() -> None:
    match, brains = stand_match()
    seen = [match.referee.state]
    while match.referee.state != GameStateId.PLAYING:
        match.step()
        if match.referee.state != seen[-1]:
            seen.append(match.referee.state)
    assert seen == [GameStateId.INITIAL, GameStateId.READY, GameStateId.SET, GameStateId.PLAYING]
    # the brains saw the same states through the GameController packet
    states = [f.game.state for f in brains[(0, 2)].frames]
    assert states[0] == GameStateId.INITIAL and GameStateId.READY in states and GameStateId.SET in states
    assert match.referee.counters.kickoffs == [(match.time, 0)]
    game = match.game_state()
    assert game.state == GameStateId.PLAYING and game.kicking_team == 1 and game.first_half == 1
    assert game.secondary_time == 10  # kickoff: defenders keep out of the circle for 10 s
    start = game.secs_remaining
    match.run(until=match.time + 5.0)
    assert match.game_state().secs_remaining == start - 5


def test_optional_standby_state() -> None:
    match, _ = stand_match(short_config(standby_seconds=3.0))
    seen = [match.referee.state]
    while match.referee.state != GameStateId.READY:
        match.step()
        if match.referee.state != seen[-1]:
            seen.append(match.referee.state)
    assert seen == [GameStateId.INITIAL, GameStateId.STANDBY, GameStateId.READY]
    assert match.time == pytest.approx(2.0 + 3.0, abs=0.02)


def test_goal_scores_and_conceding_team_kicks_off() -> None:
    match, _ = stand_match()
    run_until_state(match, GameStateId.PLAYING)
    match.apply_event(PlaceBall(0.0, 3.5, 0.0, 3.0, 0.0))  # rolling into the +x goal
    run_until_state(match, GameStateId.READY, limit=match.time + 5)
    assert match.referee.score == [1, 0]  # team 0 attacks +x in the first half
    assert match.game_state().teams[0].score == 1
    assert match.referee.kicking_team == 1
    assert (match.world.ball.position.x, match.world.ball.position.y) == (0.0, 0.0)
    run_until_state(match, GameStateId.PLAYING, limit=match.time + 40)
    assert match.referee.counters.kickoffs[-1][1] == 1


def test_ball_out_gives_kick_in_and_goal_kick() -> None:
    match, _ = stand_match()
    run_until_state(match, GameStateId.PLAYING)
    match.referee.last_touch_team = 0
    match.apply_event(PlaceBall(0.0, 1.0, 2.9, 0.0, 1.5))
    while match.referee.set_play == SetPlay.NONE:
        match.step()
    assert match.referee.set_play == SetPlay.KICK_IN and match.referee.kicking_team == 1
    bx, by = match.world.ball.position
    assert by == pytest.approx(3.0) and bx == pytest.approx(1.0, abs=0.1)
    match.referee.set_play = SetPlay.NONE
    match.referee.last_touch_team = 0  # attacker kicks it over the goal line: goal kick
    match.apply_event(PlaceBall(0.0, 4.3, 2.0, 1.5, 0.0))
    while match.referee.set_play == SetPlay.NONE:
        match.step()
    assert match.referee.set_play == SetPlay.GOAL_KICK and match.referee.kicking_team == 1
    assert tuple(match.world.ball.position) == pytest.approx((3.9, 1.1))
    assert match.game_state().set_play == SetPlay.GOAL_KICK


def test_half_time_switches_sides_and_team_frames() -> None:
    match, brains = stand_match(short_config(half_seconds=20.0))
    run_until_state(match, GameStateId.FINISHED)
    assert match.log.of_kind("half_time")
    match.world.place_ball(1.0, 0.5)
    first = brains[(0, 2)]
    run_until_state(match, GameStateId.INITIAL, limit=200)
    assert match.referee.first_half is False and match.log.of_kind("side_switch")
    match.step()
    # the same world ball is now seen mirrored in team 0's frame
    match.world.place_ball(1.0, 0.5)
    match.run(until=match.time + 0.1)
    oracle = first.oracles[-1]
    assert (oracle.ball_x, oracle.ball_y) == pytest.approx((-1.0, -0.5))
    assert brains[(1, 2)].oracles[-1].ball_x == pytest.approx(1.0)
    # robots were carried to their new own half: team 0 now stands at world x > 0
    for r in match.world.robots:
        x = r.pose[0]
        assert (x > 0) == (r.team == 0)
    assert all(f.picked_up for f in [first.frames[-1]])
    assert first.frames[-1].game.first_half == 0
    match.run()
    assert match.finished and match.log.of_kind("full_time")
    assert match.referee.counters.kickoffs[0][1] == 0 and match.referee.counters.kickoffs[-1][1] == 1


def test_leaving_the_field_removal_and_spl2025_return() -> None:
    cfg = short_config(penalty_seconds=10.0)
    match, brains = stand_match(cfg, p0_4=walk_toward(-1.0, 5.0, state=GameStateId.PLAYING))
    run_until_state(match, GameStateId.PLAYING)
    while not match.referee.counters.penalties:
        match.step()
        assert match.time < 150
    assert penalties(match) == [(0, 4, "LEAVING_THE_FIELD")]
    robot = match.world.robot(0, 4)
    assert not robot.in_space and robot.penalized
    removed_at = match.time
    assert match.game_state().teams[0].players[3].penalty == Penalty.LEAVING_THE_FIELD
    assert match.game_state().teams[0].players[3].secs_till_unpenalised == 10
    brains[(0, 4)].policy = None
    while robot.penalized:
        match.step()
    assert match.time - removed_at == pytest.approx(10.0, abs=0.02)
    tx, ty, tth = match.referee.team_pose(robot)
    f = match.field
    assert tx == pytest.approx(-f.half_length + f.dims.penalty_mark_distance)
    assert ty == pytest.approx(f.half_width + 0.5)  # nearest touchline: it left at y > 0
    assert tth == pytest.approx(-math.pi / 2)  # facing the field
    assert robot.in_space and robot.picked_up
    match.run(until=match.time + 0.1)
    assert brains[(0, 4)].frames[-1].picked_up and brains[(0, 4)].frames[-1].penalty == 0


def test_spl2010_return_at_midfield_opposite_the_ball() -> None:
    cfg = short_config(rules="spl2010", penalty_seconds=3.0)
    match, _ = stand_match(cfg)
    run_until_state(match, GameStateId.PLAYING)
    match.world.place_ball(1.0, 2.0)  # ball at y > 0 in team 0's frame
    match.apply_event(ForcePenalty(match.time, 0, 2, Penalty.REQUEST_FOR_PICKUP))
    robot = match.world.robot(0, 2)
    assert robot.penalized
    while robot.penalized:
        match.step()
    tx, ty, tth = match.referee.team_pose(robot)
    # at the midfield line (stepped back only to keep clear of a robot standing there)
    assert -1.0 < tx <= 0.0 and ty == pytest.approx(-3.0) and tth == pytest.approx(math.pi / 2)
    others = [match.referee.team_pose(r) for r in match.world.robots if r.team == 0 and r is not robot]
    assert all(math.hypot(tx - x, ty - y) >= 0.35 for x, y, _ in others)
    assert penalties(match) == [(0, 2, "REQUEST_FOR_PICKUP")]
    assert match.referee.counters.returns[-1][1:] == (0, 2)


def test_illegal_position_in_set_is_penalised_under_spl2025() -> None:
    match, _ = stand_match(short_config(), p1_5=walk_toward(-1.0, 2.5))  # team 1 walks into its opponent half
    run_until_state(match, GameStateId.SET)
    assert penalties(match) == [(1, 5, "ILLEGAL_POSITION_IN_SET")]
    assert not match.world.robot(1, 5).in_space


def test_illegal_position_in_set_is_placed_under_spl2010() -> None:
    match, brains = stand_match(short_config(rules="spl2010"), p1_5=walk_toward(-1.0, 2.5))
    run_until_state(match, GameStateId.SET)
    assert penalties(match) == []
    robot = match.world.robot(1, 5)
    assert robot.picked_up and match.referee.counters.placements == 1
    tx, ty, _ = match.referee.team_pose(robot)
    assert tx < 0 and math.hypot(tx, ty) > match.field.centre_circle.radius  # a legal spot
    match.run(until=match.time + 0.1)
    assert brains[(1, 5)].frames[-1].picked_up


def test_pushing_penalises_the_pusher() -> None:
    match, _ = stand_match()
    run_until_state(match, GameStateId.PLAYING)
    pusher, victim = match.world.robot(0, 2), match.world.robot(1, 2)
    pusher.teleport(1.0, 0.0, 0.0)
    victim.teleport(1.35, 0.0, math.pi)
    brain = match.brains[1]
    brain.policy = lambda frame, oracle: WalkRequest(forward=0.25)  # type: ignore[attr-defined]
    t0 = match.time
    while not match.referee.counters.penalties and match.time < t0 + 10:
        match.step()
    assert penalties(match) == [(0, 2, "PLAYER_PUSHING")]
    assert match.time - t0 < 5.0


def test_fallen_too_long_is_inactive() -> None:
    match, _ = stand_match()
    run_until_state(match, GameStateId.PLAYING)
    match.apply_event(ForceFall(match.time, 1, 3, duration=30.0))
    t0 = match.time
    while not match.referee.counters.penalties:
        match.step()
    assert penalties(match) == [(1, 3, "INACTIVE_PLAYER")]
    assert match.time - t0 == pytest.approx(20.0, abs=0.02)


def test_short_fall_is_not_penalised_and_robot_gets_up() -> None:
    match, brains = stand_match()
    run_until_state(match, GameStateId.PLAYING)
    match.apply_event(ForceFall(match.time, 1, 3, duration=3.0))
    match.run(until=match.time + 1.0)
    assert brains[(1, 3)].frames[-1].fallen
    match.run(until=match.time + 2.5)
    assert not brains[(1, 3)].frames[-1].fallen and penalties(match) == []


def test_local_game_stuck_removes_the_nearest_robot() -> None:
    match, _ = stand_match(short_config(fouls=FoulParams(stuck_seconds=8.0)))
    run_until_state(match, GameStateId.PLAYING)
    x, y, _ = match.world.robot(1, 4).pose
    match.world.place_ball(x + 0.3, y)
    t0 = match.time
    while not match.referee.counters.penalties:
        match.step()
        assert match.time < t0 + 12
    assert penalties(match) == [(1, 4, "LOCAL_GAME_STUCK")]


def test_kidnapping_moves_robot_without_odometry() -> None:
    cfg = replace(
        short_config(),
        events=(Kidnap(3.0, 0, 3, (2.0, -1.0, 1.0), sense_pickup=False), Kidnap(4.0, 1, 2, None, sense_pickup=True)),
    )
    match, brains = stand_match(cfg)
    match.run(until=3.5)
    assert match.world.robot(0, 3).pose == pytest.approx((2.0, -1.0, 1.0), abs=1e-3)
    frame = brains[(0, 3)].frames[-1]
    assert not frame.picked_up
    assert math.hypot(frame.odometry.dx, frame.odometry.dy) < 0.01
    match.run(until=4.2)
    assert brains[(1, 2)].frames[-1].picked_up
    kid = match.log.of_kind("kidnap")
    assert [(e.get("team"), e.get("number")) for e in kid] == [(0, 3), (1, 2)]
    x, y = kid[1].get("x"), kid[1].get("y")
    assert match.field.is_inside(x, y)


def test_bad_referee_and_event_input() -> None:
    with pytest.raises(ValueError, match="half_seconds"):
        RefereeParams(half_seconds=-1.0)
    with pytest.raises(ValueError, match="rules"):
        RefereeParams(rules="spl1999")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="code"):
        ForcePenalty(1.0, 0, 1, code=12)
    with pytest.raises(ValueError, match="time"):
        Kidnap(-1.0, 0, 1)
    with pytest.raises(ValueError, match="names player 6"):
        MatchConfig(events=(ForceFall(1.0, 0, 6),))


def test_the_referees_clocks_skip_only_steps_in_which_nobody_is_due() -> None:
    """The referee runs its put-down and return loops only when a carried robot's or a penalised
    robot's time is due (its clocks). A match whose clocks are forced due in every step (the loops
    run in every physics step, as before the clocks) goes the same way, step for step: the same
    picked-up and penalised flags, poses and event log, through carries by the referee, kidnaps
    sensed as pick-ups, scripted and automatic penalties, returns and the side switch."""
    kidnaps = [Kidnap(t, i % 2, 1 + i % 5, None, sense_pickup=True) for i, t in enumerate((3.0, 9.5, 14.25, 31.0))]
    pushing = int(Penalty.PLAYER_PUSHING)
    penalties = [ForcePenalty(t, 1 - i % 2, 1 + (2 * i) % 5, pushing) for i, t in enumerate((5.0, 12.0, 13.0, 29.5))]
    events = (*kidnaps, *penalties)
    cfg = replace(short_config(half_seconds=20.0, penalty_seconds=4.0, carry_seconds=0.7), events=events)
    clocked, forced = Match(cfg), Match(cfg)
    always = forced.referee.update

    def update(now: float, evs: list) -> None:  # type: ignore[type-arg]
        forced.referee._clocks.put_down = forced.referee._clocks.returns = -math.inf
        always(now, evs)

    forced.referee.update = update  # type: ignore[method-assign]
    runs = {"put down": 0, "returns": 0}  # how often the clocked referee ran each loop
    end_carrying, timers = clocked.referee._end_carrying, clocked.referee._update_penalty_timers

    def counted_end_carrying(now: float) -> None:
        runs["put down"] += 1
        end_carrying(now)

    def counted_timers(now: float) -> None:
        runs["returns"] += 1
        timers(now)

    clocked.referee._end_carrying = counted_end_carrying  # type: ignore[method-assign]
    clocked.referee._update_penalty_timers = counted_timers  # type: ignore[method-assign]
    picked = 0
    while not clocked.finished:
        clocked.step()
        forced.step()
        for a, b in zip(clocked.world.robots, forced.world.robots, strict=True):
            assert (a.picked_up, a.penalized, a.pose) == (b.picked_up, b.penalized, b.pose), f"t={clocked.time}"
            picked += a.picked_up
    assert forced.finished and clocked.log.events == forced.log.events
    returned = len(clocked.referee.counters.returns)
    assert returned >= 4 and picked > 100  # carries and returns were exercised
    assert 0 < runs["put down"] < 0.05 * clocked.steps and 0 < runs["returns"] < 0.05 * clocked.steps  # work saved
