"""The SPL wire protocols on UDP: a match refereed by a real GameController, or watched by the
tools teams use with one (``teamsim match --gc-broadcast`` / ``--gc-listen``).

The bridge runs a match paced to real time (one simulated second per wall-clock second; a match
slower than real time runs as fast as it can) and speaks the three channels of the SPL
GameController (GameController3's README, "Network Communication"):

==============================  ============  =====================================================
channel                         port          ``broadcast`` mode / ``listen`` mode
==============================  ============  =====================================================
control (RoboCupGameControl-    3838          sends the simulator's own game state at
Data v18, "RGme")                             ``state_hz`` (2 Hz) to ``host`` / receives the
                                              external GameController's packets on ``host``; the
                                              match follows them (:mod:`teamsim.gc_referee`)
status (RoboCupGameControl-     3939          every robot's status at ``status_hz`` (1 Hz): its
ReturnData v4, "RGrt")                        own pose estimate and ball from its beliefs
                                              (:func:`cognition.returndata.status_packet`), to
                                              ``host`` / to the GameController's address
team messages (<= 128 bytes)    10000 + team  every message a robot sends, as sent, to ``host`` /
                                              to the GameController's address
==============================  ============  =====================================================

``host`` is the loopback address unless set: in ``broadcast`` mode it is where packets go (a
subnet's broadcast address such as ``192.168.1.255`` reaches a whole network), in ``listen``
mode the address the control socket binds (``0.0.0.0``: every interface).

Robustness of ``listen``: every datagram is decoded on its own; one with a wrong length,
header or version, a field outside the v18 ranges, or teams other than the match's is rejected
and counted by reason (:class:`BridgeStats`, printed in the match summary) and changes
nothing. Between two physics steps the bridge reads datagrams for at most ``poll_seconds`` of
wall time (a valid packet costs about 80 us to decode, a repeat of the previous one or garbage
about 1 us), so a flood (thousands of packets a second) costs bounded time per step and cannot
stall the match; the socket's receive buffer holds the rest, and the kernel drops what does
not fit (those are neither followed nor counted). When no
valid packet has arrived for ``timeout`` seconds (wall clock), the bridge logs a
``gamecontroller_lost`` event and warns once; the match stays in the last state it was given
until packets come back (``gamecontroller_back``).

Parameters (:class:`BridgeParams`):

====================  ==========  ==============  ===============================================
parameter             default     range           meaning
====================  ==========  ==============  ===============================================
mode                  (required)                  ``broadcast`` or ``listen``
host                  127.0.0.1   an IPv4 address see above
gc_port               3838        [0, 65535]      control port (0 in ``listen``: any free port,
                                                  :attr:`GameControllerBridge.port` says which)
return_port           3939        [1, 65535]      status port
team_port_base        10000       [1, 65280]      team messages go to this + team number
state_hz              2           (0, 100]        game-state packets per second (``broadcast``)
status_hz             1           (0, 100]        status packets per robot and second
timeout               2           (0, 3600]       seconds without GameController packets before
                                                  the warning (``listen``)
poll_seconds          0.002       (0, 1]          longest time spent reading between two physics steps
====================  ==========  ==============  ===============================================
"""

from __future__ import annotations

import ipaddress
import select
import socket
import struct
import time
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, ClassVar, TypeVar

from cognition.gamestate import (
    GAMECONTROLLER_DATA_PORT,
    GAMECONTROLLER_HEADER,
    GAMECONTROLLER_RETURN_PORT,
    GAMECONTROLLER_VERSION,
    PACKET_SIZE,
    GameControlData,
)
from cognition.representations import BallModel, RobotPose
from cognition.returndata import RETURN_HEADER, RETURN_PACKET_SIZE, RETURN_VERSION, ReturnData, status_packet
from teamsim.gc_referee import GameControllerReferee
from teamsim.match import Match
from teamsim.params import Range, Ranges, check_choice, check_ranges, positive
from teamsim.summary import MatchSummary

T = TypeVar("T")
MODES = ("broadcast", "listen")
"""Valid values of :attr:`BridgeParams.mode`."""
TEAM_PORT_BASE = 10000
REJECT_REASONS = ("size", "header", "version", "field", "teams")
"""Why a received packet was rejected: wrong length, header or version, a field outside its
range, or a GameController packet for other teams than the match's."""
RECEIVE_BUFFER_BYTES = 1 << 20
"""Receive buffer asked of the kernel for the control socket (a burst of about 8,000 packets)."""


@dataclass(frozen=True)
class BridgeParams:
    """Where and how often the bridge talks (see the module table)."""

    mode: str
    host: str = "127.0.0.1"
    gc_port: int = GAMECONTROLLER_DATA_PORT
    return_port: int = GAMECONTROLLER_RETURN_PORT
    team_port_base: int = TEAM_PORT_BASE
    state_hz: float = 2.0
    status_hz: float = 1.0
    timeout: float = 2.0
    poll_seconds: float = 0.002

    RANGES: ClassVar[Ranges] = {
        "gc_port": Range(0, 65535),
        "return_port": Range(1, 65535),
        "team_port_base": Range(1, 65535 - 255),
        "state_hz": positive(100.0),
        "status_hz": positive(100.0),
        "timeout": positive(3600.0),
        "poll_seconds": positive(1.0),
    }

    def __post_init__(self) -> None:
        check_choice("BridgeParams", "mode", self.mode, MODES)
        check_ranges(self)
        try:
            address = ipaddress.ip_address(self.host)
        except ValueError:
            raise ValueError(f"BridgeParams.host must be an IPv4 address, got {self.host!r}") from None
        if address.version != 4:
            raise ValueError(f"BridgeParams.host must be an IPv4 address, got {self.host!r}")
        if self.mode == "broadcast" and address.is_unspecified:
            raise ValueError(
                "BridgeParams.host 0.0.0.0 is not a destination: broadcast to 127.0.0.1 (default), a host, "
                "or a subnet's broadcast address such as 192.168.1.255"
            )
        if self.mode == "broadcast" and self.gc_port == 0:
            raise ValueError("BridgeParams.gc_port 0 (any free port) only applies to listen mode")


@dataclass
class BridgeStats:
    """What went over the wire."""

    received: int = 0
    """Valid GameController packets for this match's teams (the newest of each poll is followed)."""
    rejected: Counter[str] = field(default_factory=Counter)
    """Rejected packets by reason (:data:`REJECT_REASONS`)."""
    sent_game_state: int = 0
    sent_status: int = 0
    sent_team_messages: int = 0
    send_errors: int = 0
    """Datagrams the operating system refused to send (no route, buffer full)."""
    gc_lost: int = 0
    """Times the GameController fell silent for longer than ``timeout``."""

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready dict."""
        return {
            "received": self.received,
            "rejected": sum(self.rejected.values()),
            "rejected_by_reason": dict(sorted(self.rejected.items())),
            "sent_game_state": self.sent_game_state,
            "sent_status": self.sent_status,
            "sent_team_messages": self.sent_team_messages,
            "send_errors": self.send_errors,
            "gc_lost": self.gc_lost,
        }


def decode_game_control(data: bytes, stats: BridgeStats) -> GameControlData | None:
    """A GameController packet, or ``None`` after counting why it is rejected; nothing raises."""
    return _decode(data, stats, PACKET_SIZE, GAMECONTROLLER_HEADER, GAMECONTROLLER_VERSION, GameControlData.unpack)


def decode_return(data: bytes, stats: BridgeStats) -> ReturnData | None:
    """A robot's status packet, or ``None`` after counting why it is rejected; nothing raises."""
    return _decode(data, stats, RETURN_PACKET_SIZE, RETURN_HEADER, RETURN_VERSION, ReturnData.unpack)


def _decode(
    data: bytes, stats: BridgeStats, size: int, header: bytes, version: int, unpack: Callable[[bytes], T]
) -> T | None:
    """``unpack(data)`` after the cheap checks, each failure counted under its reason."""
    if len(data) != size:
        stats.rejected["size"] += 1
    elif data[:4] != header:
        stats.rejected["header"] += 1
    elif data[4] != version:
        stats.rejected["version"] += 1
    else:
        try:
            return unpack(data)
        except (ValueError, TypeError, struct.error):
            stats.rejected["field"] += 1
    return None


def robot_status(match: Match, index: int) -> ReturnData:
    """The status robot ``index`` reports: its brain's pose estimate and ball, from its beliefs
    (``beliefs.pose`` and ``beliefs.ball``, else the brain's ``pose``), and its fallen signal."""
    robot = match.world.robots[index]
    brain = match.brains[index]
    beliefs = getattr(brain, "beliefs", None)
    pose = getattr(beliefs, "pose", None)
    if not isinstance(pose, RobotPose):
        pose = getattr(brain, "pose", None)
    ball = getattr(beliefs, "ball", None)
    frame = match.last_frames[index]
    fallen = frame.fallen if frame is not None else robot.is_fallen()
    return status_packet(
        robot.number,
        match.config.referee.team_numbers[robot.team],
        fallen,
        pose if isinstance(pose, RobotPose) else None,
        ball if isinstance(ball, BallModel) else None,
    )


class GameControllerBridge:
    """Runs a match paced to real time and connects it to the GameController protocols.

    Use as a context manager (the sockets are closed at the end). ``warn`` receives one line
    when the GameController falls silent; ``clock`` is the wall clock (s)."""

    def __init__(
        self,
        match: Match,
        params: BridgeParams,
        warn: Callable[[str], None] | None = None,
        clock: Callable[[], float] = time.monotonic,
    ):
        self.match = match
        self.params = params
        self.stats = BridgeStats()
        self.warn = warn or (lambda line: None)
        self.clock = clock
        self.listening = params.mode == "listen"
        if self.listening and not isinstance(match.referee, GameControllerReferee):
            raise ValueError("listen mode needs a match built with external_referee=True")
        if not self.listening and isinstance(match.referee, GameControllerReferee):
            raise ValueError("broadcast mode needs a match with its own referee (external_referee=False)")
        self.peer: str | None = None if self.listening else params.host
        """Where status packets and team messages go (listen: the GameController's address, once known)."""
        self._tx = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self._rx: socket.socket | None = None
        try:
            self._tx.setsockopt(socket.SOL_SOCKET, socket.SO_BROADCAST, 1)
            self._tx.setblocking(False)
            self.port = params.gc_port
            """The control port (the one bound in listen mode)."""
            if self.listening:
                self._rx = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
                self._rx.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
                self._rx.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, RECEIVE_BUFFER_BYTES)
                try:
                    self._rx.bind((params.host, params.gc_port))
                except OSError as exc:
                    raise OSError(
                        f"cannot listen for the GameController on {params.host}:{params.gc_port}: {exc}"
                    ) from exc
                self._rx.setblocking(False)
                self.port = self._rx.getsockname()[1]
        except BaseException:
            self.close()
            raise
        self._team_numbers = match.config.referee.team_numbers
        self._last_packet: float | None = None
        self._last_raw = b""
        self._last_game: GameControlData | None = None
        self._silent = False
        self._started_at = 0.0
        self._next_state = 0.0
        self._next_status = [0.0] * len(match.world.robots)
        self.interrupted = False
        """Whether :meth:`run` stopped at Ctrl-C."""
        match.channel.taps.append(self._mirror)

    def __enter__(self) -> GameControllerBridge:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        """Close the sockets and stop mirroring team messages."""
        if self._mirror in self.match.channel.taps:
            self.match.channel.taps.remove(self._mirror)
        for sock in (self._tx, self._rx):
            if sock is not None:
                sock.close()

    # -- running ---------------------------------------------------------------------------
    def run(self, until: float | None = None, on_step: Callable[[Match], None] | None = None) -> MatchSummary:
        """Play the match in real time until it is finished (or until simulated time ``until``,
        s); Ctrl-C stops it early (:attr:`interrupted`). The summary carries the traffic
        figures in ``network``."""
        m = self.match
        start, t0 = self.clock(), m.time
        self._started_at = start
        n = len(m.world.robots)
        period = 1.0 / self.params.status_hz
        self._next_state = m.time
        self._next_status = [m.time + period * (i + 1) / n for i in range(n)]  # spread over a period
        try:
            while not m.finished and (until is None or m.time < until - 1e-9):
                self._wait_until(start + (m.time - t0))
                m.step()
                if on_step is not None:
                    on_step(m)
                self._send_due()
        except KeyboardInterrupt:
            self.interrupted = True
        m.wall_seconds += self.clock() - start
        summary = m.summary()
        summary.network = {"mode": self.params.mode, "host": self.params.host, "port": self.port}
        summary.network.update(self.stats.to_dict())
        return summary

    def _wait_until(self, due: float) -> None:
        """Handle incoming packets until the wall clock reaches ``due`` (at least once)."""
        while True:
            if self._rx is not None:
                self._drain()
                self._check_silence()
            left = due - self.clock()
            if left <= 0.0:
                return
            if self._rx is not None:
                select.select([self._rx], [], [], left)
            else:
                time.sleep(left)

    def _drain(self) -> None:
        """Read datagrams for up to ``poll_seconds``; follow the newest valid packet."""
        assert self._rx is not None
        newest: tuple[GameControlData, str] | None = None
        deadline = self.clock() + self.params.poll_seconds
        while self.clock() < deadline:
            try:
                data, sender = self._rx.recvfrom(2048)
            except (BlockingIOError, InterruptedError):
                break
            except OSError:
                self.stats.send_errors += 1  # an ICMP error from an earlier send surfaces here
                continue
            if data == self._last_raw:  # a repeat of the previous valid packet: no need to decode it again
                game = self._last_game
            else:
                game = decode_game_control(data, self.stats)
            if game is None:
                continue
            self._last_raw, self._last_game = data, game
            if {t.team_number for t in game.teams} != set(self._team_numbers):
                self.stats.rejected["teams"] += 1
                continue
            self.stats.received += 1
            newest = (game, sender[0])
        if newest is None:
            return
        game, address = newest
        referee = self.match.referee
        assert isinstance(referee, GameControllerReferee)
        referee.follow(game, self.match.time)
        self.peer = address
        self._last_packet = self.clock()
        if self._silent:
            self._silent = False
            self.match.log.add(self.match.time, "gamecontroller_back", address=address)

    def _check_silence(self) -> None:
        since = self._last_packet if self._last_packet is not None else self._started_at
        silent_for = self.clock() - since
        if self._silent or silent_for < self.params.timeout:
            return
        self._silent = True
        self.stats.gc_lost += 1
        where = f"{self.params.host}:{self.port}"
        if self._last_packet is None:
            line = f"no GameController packets on {where} for {silent_for:.1f} s; the game waits in INITIAL"
        else:
            line = f"the GameController on {where} is silent for {silent_for:.1f} s; the game stays in its last state"
        self.match.log.add(self.match.time, "gamecontroller_lost", seconds=round(silent_for, 3))
        self.warn(line)

    # -- sending ---------------------------------------------------------------------------
    def _send(self, data: bytes, address: tuple[str, int]) -> bool:
        try:
            self._tx.sendto(data, address)
        except OSError:
            self.stats.send_errors += 1
            return False
        return True

    def _send_due(self) -> None:
        m = self.match
        p = self.params
        if not self.listening and m.time >= self._next_state - 1e-9:
            self._next_state += 1.0 / p.state_hz
            packet = m.game_state().with_changes(packet_number=self.stats.sent_game_state & 0xFF)
            if self._send(packet.pack(), (p.host, p.gc_port)):
                self.stats.sent_game_state += 1
        if self.peer is None:
            return
        for i in range(len(m.world.robots)):
            if m.time >= self._next_status[i] - 1e-9:
                self._next_status[i] += 1.0 / p.status_hz
                if m.last_frames[i] is None:
                    continue  # a robot that has not thought yet has nothing to report
                if self._send(robot_status(m, i).pack(), (self.peer, p.return_port)):
                    self.stats.sent_status += 1

    def _mirror(self, team: int, sender: int, payload: bytes, now: float) -> None:
        """A team message as a robot sends it: to UDP port ``team_port_base`` + team number."""
        if self.peer is None:
            return
        number = self.match.config.referee.team_numbers[team]
        if self._send(payload, (self.peer, self.params.team_port_base + number)):
            self.stats.sent_team_messages += 1
