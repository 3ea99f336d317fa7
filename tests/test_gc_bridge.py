"""A match on the SPL wire protocols: an external GameController referees it, tools listen to it.

The referee tests feed :meth:`GameControllerReferee.follow` packets directly and check what
the field does (robots removed and returned, no automatic decisions, side switch, end). The
loopback tests put real UDP datagrams on 127.0.0.1 between the match and a GameController
played by a separate process (or by the test itself): a state change and a penalty take
effect within 0.5 s of wall time, the match keeps real time under a flood of packets, a silent
GameController leaves the game in its last state with one warning, and the test receives the
match's game-state, status and team-message broadcasts. Every loopback test binds port 0 (any
free port), so tests can run in parallel.
"""

from __future__ import annotations

import itertools
import json
import math
import re
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest
from helpers import short_config

from cognition.brain import BrainContext
from cognition.gamestate import GameControlData, GameStateId, Penalty, RobotInfo, SetPlay, TeamInfo
from cognition.oracle import OracleInput
from cognition.representations import BrainOutput, SensorFrame
from teamsim.brains import default_brains
from teamsim.cli import main
from teamsim.gc_bridge import BridgeParams, BridgeStats, GameControllerBridge, decode_game_control, decode_return
from teamsim.match import Match, MatchConfig
from teamsim.placement import initial_position, world_to_team

LATENCY = 0.5
"""Wall seconds within which a GameController decision must show in the match."""


@pytest.fixture(autouse=True, scope="module")
def _compiled() -> None:
    """Run a short match first, so that no numba compilation (a cold cache on a fresh clone)
    stalls a match while the wall clock of a test is running."""
    Match(MatchConfig(players_per_team=2)).run(until=0.5)


def _packet(
    state: int = GameStateId.INITIAL,
    *,
    set_play: int = SetPlay.NONE,
    first_half: int = 1,
    kicking: int = 1,
    penalties: dict[tuple[int, int], int] | None = None,
    score: tuple[int, int] = (0, 0),
    numbers: tuple[int, int] = (1, 2),
    packet_number: int = 0,
) -> GameControlData:
    """A GameController packet; ``penalties`` maps (team number, player) to a penalty code."""
    pen = penalties or {}
    teams = tuple(
        TeamInfo(
            team_number=n,
            score=score[i],
            players=tuple(RobotInfo(pen.get((n, k), 0), 30 if pen.get((n, k)) else 0) for k in range(1, 21)),
        )
        for i, n in enumerate(numbers)
    )
    return GameControlData(
        packet_number=packet_number,
        players_per_team=2,
        state=state,
        set_play=set_play,
        first_half=first_half,
        kicking_team=kicking,
        teams=(teams[0], teams[1]),
    )


def _listening_match(players: int = 2, **params: object) -> tuple[Match, GameControllerBridge]:
    match = Match(MatchConfig(players_per_team=players), external_referee=True)
    return match, GameControllerBridge(match, BridgeParams("listen", gc_port=0, **params))  # type: ignore[arg-type]


def _receiver() -> socket.socket:
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.bind(("127.0.0.1", 0))
    sock.setblocking(False)
    return sock


def _drain(sock: socket.socket) -> list[bytes]:
    out = []
    while True:
        try:
            out.append(sock.recv(4096))
        except BlockingIOError:
            return out


@contextmanager
def _in_thread(target: Callable[[], None]) -> Iterator[None]:
    thread = threading.Thread(target=target, daemon=True)
    thread.start()
    try:
        yield
    finally:
        thread.join(timeout=10.0)


# -- the referee follows the packets -----------------------------------------------------------


def test_referee_takes_state_and_penalties_from_the_gamecontroller_and_nothing_returns_on_a_timer() -> None:
    m = Match(MatchConfig(players_per_team=2), external_referee=True)
    ref = m.referee
    m.run(until=3.0)
    assert ref.state == GameStateId.INITIAL  # the automatic referee would be in READY after 2 s
    ref.follow(_packet(GameStateId.READY, numbers=(2, 1)), m.time)  # team blocks in the GameController's order
    assert ref.state == GameStateId.READY
    assert [t.team_number for t in m.game_state().teams] == [1, 2]  # published in team-index order
    ref.follow(_packet(GameStateId.READY, penalties={(1, 2): Penalty.PLAYER_PUSHING}), m.time)
    robot = m.world.robot(0, 2)
    assert robot.penalized and not robot.in_space
    assert m.summary().penalties[-1][1:] == (0, 2, int(Penalty.PLAYER_PUSHING))
    assert m.game_state().team(1).players[1].penalty == Penalty.PLAYER_PUSHING
    m.run(until=m.time + 50.0)  # longer than penalty_seconds (45 s)
    assert robot.penalized and ref.state == GameStateId.READY  # no timer return, no automatic SET
    ref.follow(_packet(GameStateId.READY), m.time)
    assert not robot.penalized and robot.in_space
    assert m.summary().returns[-1][1:] == (0, 2)


def test_goals_ball_out_and_fouls_are_only_suggested_the_gamecontroller_scores() -> None:
    m = Match(MatchConfig(players_per_team=1), external_referee=True)
    ref = m.referee
    ref.follow(_packet(GameStateId.PLAYING), m.time)
    attacked_goal_x = ref.sign(0) * (ref.field.half_length + 0.25)
    m.world.place_ball(attacked_goal_x, 0.1)
    m.step()
    assert ref.score == [0, 0] and ref.state == GameStateId.PLAYING
    goal = m.log.of_kind("suggestion")[-1]
    assert (goal.get("what"), goal.get("team")) == ("goal", 0)
    assert math.hypot(*m.world.ball.position) < 0.05  # the ball is put back on the centre mark
    m.world.place_ball(1.0, ref.field.half_width + 0.3)
    m.step()
    out = m.log.of_kind("suggestion")[-1]
    assert out.get("what") == "kick_in" and ref.set_play == SetPlay.NONE
    assert m.world.ball.position.y == pytest.approx(ref.field.half_width, abs=0.05)
    ref.follow(_packet(GameStateId.PLAYING, score=(1, 0)), m.time)
    assert ref.score == [1, 0] and m.summary().goals[-1][1] == 0
    ref.follow(_packet(GameStateId.PLAYING, set_play=SetPlay.KICK_IN, kicking=2, score=(1, 0)), m.time)
    assert ref.set_play == SetPlay.KICK_IN and ref.kicking_team == 1
    robot = m.world.robot(0, 1)
    robot.fall(m.time, 60.0)
    m.run(until=m.time + 25.0)  # fallen longer than the inactive-player time
    assert not robot.penalized
    fouls = [e for e in m.log.of_kind("suggestion") if e.get("what") == "penalty" and e.get("team") == 0]
    inactive = [e for e in fouls if e.get("code") == "INACTIVE_PLAYER"]
    assert inactive and inactive[0].time >= 20.0  # fallen for the inactive-player time (20 s)
    assert all(b.time - a.time >= 5.0 for a, b in itertools.pairwise(inactive))  # not every step


def test_second_half_switches_sides_and_finished_ends_the_match() -> None:
    m = Match(MatchConfig(players_per_team=2), external_referee=True)
    ref = m.referee
    ref.follow(_packet(GameStateId.PLAYING), m.time)
    m.run(until=2.0)
    sign = ref.sign(0)
    ref.follow(_packet(GameStateId.FINISHED), m.time)
    assert m.log.of_kind("half_time") and not m.finished
    ref.follow(_packet(GameStateId.INITIAL, first_half=0), m.time)
    assert not ref.first_half and ref.sign(0) == -sign
    for r in m.world.robots:
        pose = world_to_team(ref.sign(r.team), *r.pose)
        assert pose[:2] == pytest.approx(initial_position(ref.field, r.number, 2)[:2], abs=1e-6)
    ref.follow(_packet(GameStateId.FINISHED, first_half=0), m.time)
    assert m.finished
    before = m.time
    m.run()
    assert m.time == before


def test_a_packet_for_other_teams_is_refused_and_changes_nothing() -> None:
    m = Match(MatchConfig(players_per_team=2), external_referee=True)
    with pytest.raises(ValueError, match=r"packet is for teams \(3, 4\), this match has \(1, 2\)"):
        m.referee.follow(_packet(GameStateId.PLAYING, numbers=(3, 4), kicking=3), 0.0)
    assert m.referee.state == GameStateId.INITIAL and m.referee.external is None


# -- on the wire ---------------------------------------------------------------------------------

_GAMECONTROLLER = r"""
import socket, sys, time
from cognition.gamestate import GameControlData, RobotInfo, TeamInfo

port = int(sys.argv[1])
sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
count = 0

def send(state, penalty=0, first_half=1, seconds=1.0):
    global count
    players = tuple(RobotInfo(penalty if k == 1 else 0, 45 if penalty and k == 1 else 0) for k in range(20))
    end = time.time() + seconds
    while time.time() < end:
        teams = (TeamInfo(team_number=2, players=players), TeamInfo(team_number=1))
        game = GameControlData(packet_number=count % 256, players_per_team=2, state=state, first_half=first_half,
                               kicking_team=1, teams=teams)
        sock.sendto(game.pack(), ("127.0.0.1", port))
        count += 1
        time.sleep(0.5)  # 2 Hz, as the GameController sends

send(0)
print("READY", time.time(), flush=True)
send(1, seconds=1.5)
print("PENALTY", time.time(), flush=True)
send(1, penalty=2, seconds=1.5)
send(4, penalty=2, first_half=0, seconds=0.6)
"""


def test_a_gamecontroller_in_another_process_referees_the_match_and_receives_status() -> None:
    status = _receiver()
    m, bridge = _listening_match(return_port=status.getsockname()[1])
    effect: dict[str, float] = {}

    def on_step(match: Match) -> None:
        if "READY" not in effect and match.referee.state == GameStateId.READY:
            effect["READY"] = time.time()
        if "PENALTY" not in effect and match.world.robot(1, 2).penalized:
            effect["PENALTY"] = time.time()

    with bridge:
        gc = subprocess.Popen(
            [sys.executable, "-c", _GAMECONTROLLER, str(bridge.port)], stdout=subprocess.PIPE, text=True
        )
        try:
            summary = bridge.run(until=60.0, on_step=on_step)
            out, _ = gc.communicate(timeout=30)
        finally:
            gc.kill()
    sent = {line.split()[0]: float(line.split()[1]) for line in out.splitlines()}
    assert set(sent) == {"READY", "PENALTY"} and set(effect) == {"READY", "PENALTY"}, (out, effect)
    for what in ("READY", "PENALTY"):
        assert 0.0 <= effect[what] - sent[what] <= LATENCY, (what, effect[what] - sent[what])
    assert m.finished  # FINISHED in the second half ended the match
    assert m.summary().penalties[-1][1:] == (1, 2, int(Penalty.PLAYER_PUSHING))
    assert summary.network is not None and summary.network["received"] >= 8 and summary.network["rejected"] == 0
    stats = BridgeStats()
    packets = [decode_return(raw, stats) for raw in _drain(status)]
    status.close()
    assert not stats.rejected and len(packets) >= 8 and summary.network["sent_status"] == len(packets)
    assert {(p.team_number, p.player_number) for p in packets if p is not None} == {(1, 1), (1, 2), (2, 1), (2, 2)}
    for p in packets:
        assert p is not None and abs(p.x) <= 5200 and abs(p.y) <= 3700 and p.ball_age >= 0.0


class _Chatty:
    """A brain that stands and sends a numbered team message every 5th frame."""

    uses_oracle = False

    def __init__(self) -> None:
        self.sent: list[bytes] = []
        self.number = 0

    def reset(self, context: BrainContext) -> None:
        self.number = context.player_number

    def think(self, frame: SensorFrame, oracle: OracleInput | None) -> BrainOutput:
        if frame.frame_index % 5:
            return BrainOutput()
        message = bytes([self.number, frame.frame_index % 256]) + b"chat"
        self.sent.append(message)
        return BrainOutput(message=message)


def _team_ports() -> tuple[int, socket.socket, socket.socket]:
    """A base port whose base + 1 and base + 2 are free, with both bound."""
    for _ in range(50):
        probe = _receiver()
        base = probe.getsockname()[1] - 1
        probe.close()
        try:
            one, two = (
                socket.socket(socket.AF_INET, socket.SOCK_DGRAM),
                socket.socket(socket.AF_INET, socket.SOCK_DGRAM),
            )
            one.bind(("127.0.0.1", base + 1))
            two.bind(("127.0.0.1", base + 2))
        except OSError:
            continue
        one.setblocking(False)
        two.setblocking(False)
        return base, one, two
    raise RuntimeError("no two adjacent free UDP ports")


def test_broadcast_sends_game_state_status_and_team_messages_in_real_time() -> None:
    control, status = _receiver(), _receiver()
    base, team1, team2 = _team_ports()
    chatty = [_Chatty(), _Chatty()]
    scripted = default_brains("scripted", None, "spl2025")
    brains = lambda team, number: scripted(team, number) if team == 0 else chatty[number - 1]  # noqa: E731
    config = short_config(initial_seconds=0.5, ready_seconds=1.0, set_seconds=0.5)
    m = Match(MatchConfig(players_per_team=2, referee=config.referee), brains=brains)
    params = BridgeParams(
        "broadcast", gc_port=control.getsockname()[1], return_port=status.getsockname()[1], team_port_base=base
    )
    with GameControllerBridge(m, params) as bridge:
        start = time.monotonic()
        summary = bridge.run(until=3.0)
        wall = time.monotonic() - start
    assert 2.9 <= wall <= 4.0  # paced to real time
    stats = BridgeStats()
    games = [decode_game_control(raw, stats) for raw in _drain(control)]
    assert not stats.rejected and 6 <= len(games) <= 7  # 2 Hz
    assert [g.packet_number for g in games if g is not None] == list(range(len(games)))
    states = [g.state for g in games if g is not None]
    assert states == sorted(states) and states[0] == GameStateId.INITIAL and GameStateId.READY in states
    packets = [decode_return(raw, stats) for raw in _drain(status)]
    assert not stats.rejected and 8 <= len(packets) <= 14  # 4 robots at 1 Hz
    by_robot = {(p.team_number, p.player_number): p for p in packets if p is not None}
    assert set(by_robot) == {(1, 1), (1, 2), (2, 1), (2, 2)}
    for number in (1, 2):  # team 1 plays on truth beliefs: the pose it reports is a pose on its half
        p = by_robot[(1, number)]
        assert -4500 <= p.x <= 0 and abs(p.y) <= 3700 and p.ball_age >= 0
        q = by_robot[(2, number)]  # the chatty brains have no beliefs: unknown pose and ball
        assert (q.x, q.y, q.ball_age) == (0.0, 0.0, -1.0)
    mirrored = _drain(team2)
    sent = [msg for brain in chatty for msg in brain.sent]
    assert sorted(mirrored) == sorted(sent) and len(sent) >= 10  # team number 2 on base + 2, as sent
    scripted_messages = len(_drain(team1))
    assert scripted_messages == m.channel.stats[0].sent
    assert summary.network is not None and summary.network["sent_team_messages"] == len(sent) + scripted_messages
    for sock in (control, status, team1, team2):
        sock.close()


def test_a_flood_of_packets_does_not_stall_the_match_and_bad_ones_are_counted() -> None:
    m, bridge = _listening_match()
    port = bridge.port
    sent_bad = 0
    valid = _packet(GameStateId.READY).pack()
    bad = [b"x" * 20, b"RGmf" + valid[4:], valid[:4] + bytes([17]) + valid[5:], valid[:10] + bytes([9]) + valid[11:]]

    def flood() -> None:
        nonlocal sent_bad
        sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        end = time.monotonic() + 2.0
        while time.monotonic() < end:
            for k in range(24):  # about 2,400 packets a second
                sock.sendto(bad[k % 4] if k % 8 else valid, ("127.0.0.1", port))
                sent_bad += k % 8 != 0
            time.sleep(0.01)
        sock.close()

    with bridge, _in_thread(flood):
        start = time.monotonic()
        summary = bridge.run(until=3.0)
        wall = time.monotonic() - start
    assert wall <= 3.3  # kept real time
    assert m.referee.state == GameStateId.READY
    net = summary.network
    assert net is not None and sent_bad >= 1500
    assert 0.95 * sent_bad <= net["rejected"] <= sent_bad
    assert set(net["rejected_by_reason"]) == {"size", "header", "version", "field"}
    assert net["received"] >= 0.95 * sent_bad / 7


def test_a_silent_gamecontroller_leaves_the_game_in_its_last_state_with_one_warning() -> None:
    warnings: list[str] = []
    m = Match(MatchConfig(players_per_team=2), external_referee=True)
    bridge = GameControllerBridge(m, BridgeParams("listen", gc_port=0, timeout=0.4), warn=warnings.append)

    done = threading.Event()

    def gamecontroller() -> None:
        sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        for pause in (0.2, 1.0):  # READY twice, then silence for 1 s
            sock.sendto(_packet(GameStateId.READY).pack(), ("127.0.0.1", bridge.port))
            time.sleep(pause)
        while not done.is_set():  # back, with SET
            sock.sendto(_packet(GameStateId.SET).pack(), ("127.0.0.1", bridge.port))
            time.sleep(0.1)
        sock.close()

    with bridge, _in_thread(gamecontroller):
        bridge.run(until=2.5)
        done.set()
    assert m.referee.state == GameStateId.SET
    assert len(warnings) == 1 and "silent" in warnings[0] and "last state" in warnings[0]
    lost, back = m.log.of_kind("gamecontroller_lost"), m.log.of_kind("gamecontroller_back")
    assert len(lost) == 1 and len(back) == 1 and lost[0].time < back[0].time
    assert [e.get("state") for e in m.log.of_kind("state")] == ["INITIAL", "READY", "SET"]


# -- the command line ----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--gc-port", "5000"], "--gc-port: only with --gc-broadcast or --gc-listen"),
        (["--gc-broadcast", "--gc-host", "0.0.0.0"], "0.0.0.0 is not a destination"),
        (["--gc-listen", "--gc-host", "gc.local"], "must be an IPv4 address, got 'gc.local'"),
        (["--gc-listen", "--gc-port", "70000"], "--gc-port"),
        (["--gc-broadcast", "--gc-listen"], "not allowed with argument"),
        (["--gc-listen", "--gc-timeout", "0"], "--gc-timeout"),
    ],
)
def test_bad_gamecontroller_options_are_one_line_errors(
    argv: list[str], message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["match", *argv]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


def test_a_port_in_use_is_a_clear_error(capsys: pytest.CaptureFixture[str]) -> None:
    busy = _receiver()
    port = str(busy.getsockname()[1])
    assert main(["match", "--gc-listen", "--gc-port", port, "--players-per-team", "1"]) == 2
    assert f"cannot listen for the GameController on 127.0.0.1:{port}" in capsys.readouterr().err
    busy.close()


def test_teamsim_match_gc_listen_plays_until_the_gamecontroller_ends_the_game(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    probe = _receiver()
    port = probe.getsockname()[1]
    probe.close()
    done = threading.Event()

    def gamecontroller() -> None:
        sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        for state, first, seconds in (
            (GameStateId.READY, 1, 2.0),
            (GameStateId.INITIAL, 0, 0.6),
            (GameStateId.FINISHED, 0, 20.0),
        ):
            end = time.monotonic() + seconds
            while time.monotonic() < end and not done.is_set():
                sock.sendto(_packet(state, first_half=first).pack(), ("127.0.0.1", port))
                time.sleep(0.2)
        sock.close()

    argv = ["match", "--gc-listen", "--gc-port", str(port), "--players-per-team", "2", "--localization", "none"]
    with _in_thread(gamecontroller):
        code = main([*argv, "--out", str(tmp_path)])
        done.set()
    out = capsys.readouterr().out
    assert code == 0
    assert f"GameController listen on 127.0.0.1:{port}" in out
    assert re.search(r"gamecontroller listen 127\.0\.0\.1:\d+: \d+ packets received, 0 rejected", out), out
    events = [json.loads(line) for line in (tmp_path / "events.jsonl").read_text().splitlines()]
    states = [e["state"] for e in events if e["kind"] == "state"]
    assert states == ["INITIAL", "READY", "INITIAL", "FINISHED"]  # the GameController's, not the automatic ones
    assert [e["kind"] for e in events if e["kind"] in ("side_switch", "full_time")] == ["side_switch", "full_time"]
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["network"]["mode"] == "listen" and summary["network"]["rejected"] == 0
