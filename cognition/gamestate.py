"""The game-controller representation every robot receives: RoboCupGameControlData v18.

This mirrors the SPL GameController's C struct (header ``"RGme"``, struct version 18,
little-endian, UDP port 3838) field for field, so that the simulator's referee can publish
exactly what a real GameController would and later work can put it on the wire unchanged
(:meth:`GameControlData.pack` / :meth:`GameControlData.unpack`).

=================  ======================================================================
field              meaning
=================  ======================================================================
state              INITIAL 0, READY 1, SET 2, PLAYING 3, FINISHED 4, STANDBY 5
set_play           NONE 0, GOAL_KICK 1, PUSHING_FREE_KICK 2, CORNER_KICK 3, KICK_IN 4,
                   PENALTY_KICK 5
first_half         1 during the first half, 0 otherwise
kicking_team       team number of the team that kicks off / takes the set play
secs_remaining     seconds left in the half (s)
secondary_time     seconds of the secondary clock (remaining READY, set play, ...) (s)
teams[i]           per team: number, colours, goalkeeper, score, message budget and, per
                   player, the penalty code and the seconds until unpenalised
=================  ======================================================================
"""

from __future__ import annotations

import struct
from dataclasses import dataclass, field, replace
from enum import IntEnum

GAMECONTROLLER_HEADER = b"RGme"
GAMECONTROLLER_VERSION = 18
GAMECONTROLLER_DATA_PORT = 3838
GAMECONTROLLER_RETURN_PORT = 3939
MAX_NUM_PLAYERS = 20
TEAM_MESSAGE_MAX_BYTES = 128
TEAM_MESSAGE_BUDGET = 1200


class GameStateId(IntEnum):
    """The primary game states of the SPL GameController."""

    INITIAL = 0
    READY = 1
    SET = 2
    PLAYING = 3
    FINISHED = 4
    STANDBY = 5


class SetPlay(IntEnum):
    """Set plays (free kicks) announced by the GameController."""

    NONE = 0
    GOAL_KICK = 1
    PUSHING_FREE_KICK = 2
    CORNER_KICK = 3
    KICK_IN = 4
    PENALTY_KICK = 5


class GamePhase(IntEnum):
    """Phase of the game."""

    NORMAL = 0
    PENALTY_SHOOT = 1
    OVERTIME = 2
    TIMEOUT = 3


class Penalty(IntEnum):
    """SPL penalty codes (GameController v18)."""

    NONE = 0
    ILLEGAL_BALL_CONTACT = 1
    PLAYER_PUSHING = 2
    ILLEGAL_MOTION_IN_SET = 3
    INACTIVE_PLAYER = 4
    ILLEGAL_POSITION = 5
    LEAVING_THE_FIELD = 6
    REQUEST_FOR_PICKUP = 7
    LOCAL_GAME_STUCK = 8
    ILLEGAL_POSITION_IN_SET = 9
    PLAYER_STANCE = 10
    ILLEGAL_MOTION_IN_STANDBY = 11
    SUBSTITUTE = 14
    MANUAL = 15


@dataclass(frozen=True)
class RobotInfo:
    """Penalty state of one player."""

    penalty: int = Penalty.NONE
    """Penalty code (:class:`Penalty`), 0 when the robot plays."""
    secs_till_unpenalised: int = 0
    """Seconds until the robot may return (s), 0 when not penalised."""


def _empty_players() -> tuple[RobotInfo, ...]:
    return tuple(RobotInfo() for _ in range(MAX_NUM_PLAYERS))


@dataclass(frozen=True)
class TeamInfo:
    """One team's block of the GameController packet."""

    team_number: int = 0
    field_player_colour: int = 0
    goalkeeper_colour: int = 0
    goalkeeper: int = 1
    """Player number (1-based) of the goalkeeper."""
    score: int = 0
    penalty_shot: int = 0
    single_shots: int = 0
    message_budget: int = TEAM_MESSAGE_BUDGET
    """Team messages this team may still send in this game."""
    players: tuple[RobotInfo, ...] = field(default_factory=_empty_players)
    """Per player (index = number - 1), :data:`MAX_NUM_PLAYERS` entries."""


_HEAD = struct.Struct("<4sBBBBBBBBBBhh")
_TEAM = struct.Struct("<BBBBBBHH")
_PLAYER = struct.Struct("<BB")
PACKET_SIZE = _HEAD.size + 2 * (_TEAM.size + MAX_NUM_PLAYERS * _PLAYER.size)


@dataclass(frozen=True)
class GameControlData:
    """What the GameController broadcasts (RoboCupGameControlData, struct version 18).

    ``teams[0]`` and ``teams[1]`` are in the simulator's team-index order (index 0 is the
    home team); a robot finds its own block with :meth:`team`.
    """

    packet_number: int = 0
    players_per_team: int = 5
    competition_phase: int = 0
    competition_type: int = 0
    game_phase: int = GamePhase.NORMAL
    state: int = GameStateId.INITIAL
    set_play: int = SetPlay.NONE
    first_half: int = 1
    kicking_team: int = 0
    secs_remaining: int = 600
    secondary_time: int = 0
    teams: tuple[TeamInfo, TeamInfo] = (TeamInfo(team_number=1), TeamInfo(team_number=2))

    def team(self, team_number: int) -> TeamInfo:
        """The block of the team with this team number; ``KeyError`` if absent."""
        for t in self.teams:
            if t.team_number == team_number:
                return t
        raise KeyError(f"team number {team_number} is not in this game")

    def with_changes(self, **changes: object) -> GameControlData:
        """A copy with some fields replaced."""
        return replace(self, **changes)  # type: ignore[arg-type]

    def pack(self) -> bytes:
        """The little-endian wire format of the v18 struct."""
        out = [
            _HEAD.pack(
                GAMECONTROLLER_HEADER,
                GAMECONTROLLER_VERSION,
                self.packet_number & 0xFF,
                self.players_per_team,
                self.competition_phase,
                self.competition_type,
                int(self.game_phase),
                int(self.state),
                int(self.set_play),
                self.first_half,
                self.kicking_team,
                self.secs_remaining,
                self.secondary_time,
            )
        ]
        for t in self.teams:
            out.append(
                _TEAM.pack(
                    t.team_number,
                    t.field_player_colour,
                    t.goalkeeper_colour,
                    t.goalkeeper,
                    t.score,
                    t.penalty_shot,
                    t.single_shots,
                    t.message_budget,
                )
            )
            for p in t.players:
                out.append(_PLAYER.pack(int(p.penalty), min(255, p.secs_till_unpenalised)))
        return b"".join(out)

    @classmethod
    def unpack(cls, data: bytes) -> GameControlData:
        """Parse a v18 packet; ``ValueError`` names what is wrong with a malformed one."""
        if len(data) != PACKET_SIZE:
            raise ValueError(f"GameControlData packet must be {PACKET_SIZE} bytes, got {len(data)}")
        head = _HEAD.unpack_from(data, 0)
        if head[0] != GAMECONTROLLER_HEADER:
            raise ValueError(f"GameControlData header must be {GAMECONTROLLER_HEADER!r}, got {head[0]!r}")
        if head[1] != GAMECONTROLLER_VERSION:
            raise ValueError(f"GameControlData version must be {GAMECONTROLLER_VERSION}, got {head[1]}")
        offset = _HEAD.size
        teams = []
        for _ in range(2):
            t = _TEAM.unpack_from(data, offset)
            offset += _TEAM.size
            players = []
            for _ in range(MAX_NUM_PLAYERS):
                pen, secs = _PLAYER.unpack_from(data, offset)
                offset += _PLAYER.size
                players.append(RobotInfo(pen, secs))
            teams.append(TeamInfo(*t, players=tuple(players)))
        return cls(
            packet_number=head[2],
            players_per_team=head[3],
            competition_phase=head[4],
            competition_type=head[5],
            game_phase=head[6],
            state=head[7],
            set_play=head[8],
            first_half=head[9],
            kicking_team=head[10],
            secs_remaining=head[11],
            secondary_time=head[12],
            teams=(teams[0], teams[1]),
        )
