"""The game-controller representation every robot receives: RoboCupGameControlData v18.

This mirrors the SPL GameController's C struct (header ``"RGme"``, struct version 18,
little-endian, UDP port 3838) field for field, so that the simulator's referee can publish
exactly what a real GameController would and later work can put it on the wire unchanged
(:meth:`GameControlData.pack` / :meth:`GameControlData.unpack`).

Every field has the range the official ``RoboCupGameControlData.h`` (v18) defines for it:

=======================  ===============  ==========================================================
field                    accepted         meaning
=======================  ===============  ==========================================================
packet_number            0..255           counter of sent packets (wraps around)
players_per_team         1..20            players per team (at most :data:`MAX_NUM_PLAYERS`)
competition_phase        0, 1             ROUNDROBIN 0, PLAYOFF 1 (:class:`CompetitionPhase`)
competition_type         0, 1             NORMAL 0, MOST_PASSES 1 (:class:`CompetitionType`)
game_phase               0..3             NORMAL 0, PENALTY_SHOOT 1, OVERTIME 2, TIMEOUT 3
state                    0..5             INITIAL 0, READY 1, SET 2, PLAYING 3, FINISHED 4, STANDBY 5
set_play                 0..5             NONE 0, GOAL_KICK 1, PUSHING_FREE_KICK 2, CORNER_KICK 3,
                                          KICK_IN 4, PENALTY_KICK 5
first_half               0, 1             1 during the first half, 0 otherwise
kicking_team             a team number    team number of the team that kicks off / takes the set
                         or 255           play; :data:`KICKING_TEAM_NONE` (255) when nobody does
secs_remaining           -32768..32767    seconds left in the half (s)
secondary_time           -32768..32767    seconds of the secondary clock (remaining READY, ...) (s)
teams                    2 blocks         the two teams, with different team numbers
teams[i].team_number     0..255           the team's GameController number
teams[i].*_colour        0..9             BLUE 0, RED 1, YELLOW 2, BLACK 3, WHITE 4, GREEN 5,
                                          ORANGE 6, PURPLE 7, BROWN 8, GRAY 9 (:class:`TeamColour`)
teams[i].goalkeeper      0..20            player number of the goalkeeper, 0 when there is none
teams[i].score           0..255           goals
teams[i].penalty_shot    0..255           penalty shot counter (or the fallback-mode flag)
teams[i].single_shots    0..65535         bit mask of successful penalty shots
teams[i].message_budget  0..65535         team messages the team may still send in this game
teams[i].players         20 entries       per player (index = number - 1):
  .penalty               :class:`Penalty` 0..11, 14, 15: the penalty code, 0 when playing
  .secs_till_unpenalised 0..255           seconds until the robot may return (s)
=======================  ===============  ==========================================================

:meth:`GameControlData.unpack` checks every one of these ranges and raises ``ValueError``
naming the field, the accepted values and the value found (e.g. ``GameControlData.teams[1]
.players[3].penalty must be one of [...], got 99``), so a packet with undefined values never
reaches a robot's behaviour. :meth:`GameControlData.pack` checks the same ranges (``TypeError``
for a value that is not an integer) instead of letting :mod:`struct` write or refuse garbage;
like the GameController, it saturates ``secs_till_unpenalised`` at 255. Building a
:class:`GameControlData` does not check anything: the referee builds one whenever the game
changes and it must stay cheap.
"""

from __future__ import annotations

import operator
import struct
from dataclasses import dataclass, field, replace
from enum import IntEnum

from cognition.records import fast_init

GAMECONTROLLER_HEADER = b"RGme"
GAMECONTROLLER_VERSION = 18
GAMECONTROLLER_DATA_PORT = 3838
GAMECONTROLLER_RETURN_PORT = 3939
MAX_NUM_PLAYERS = 20
TEAM_MESSAGE_MAX_BYTES = 128
TEAM_MESSAGE_BUDGET = 1200
KICKING_TEAM_NONE = 255
"""``kicking_team`` when no team kicks off or takes a set play."""


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


class CompetitionPhase(IntEnum):
    """Phase of the competition."""

    ROUNDROBIN = 0
    PLAYOFF = 1


class CompetitionType(IntEnum):
    """Type of the competition."""

    NORMAL = 0
    MOST_PASSES = 1


class TeamColour(IntEnum):
    """Jersey colours of the SPL GameController."""

    BLUE = 0
    RED = 1
    YELLOW = 2
    BLACK = 3
    WHITE = 4
    GREEN = 5
    ORANGE = 6
    PURPLE = 7
    BROWN = 8
    GRAY = 9


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


@fast_init
@dataclass(frozen=True)
class RobotInfo:
    """Penalty state of one player."""

    penalty: int = Penalty.NONE
    """Penalty code (:class:`Penalty`), 0 when the robot plays."""
    secs_till_unpenalised: int = 0
    """Seconds until the robot may return (s), 0 when not penalised."""


def _empty_players() -> tuple[RobotInfo, ...]:
    return tuple(RobotInfo() for _ in range(MAX_NUM_PLAYERS))


@fast_init
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


@fast_init
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
    kicking_team: int = KICKING_TEAM_NONE
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
        """The little-endian wire format of the v18 struct.

        ``ValueError`` (``TypeError`` for a non-integer) names the first field outside the
        ranges of the module docstring; ``secs_till_unpenalised`` saturates at 255."""
        check(self, saturate_secs=True)
        out = [
            _HEAD.pack(
                GAMECONTROLLER_HEADER,
                GAMECONTROLLER_VERSION,
                self.packet_number,
                self.players_per_team,
                self.competition_phase,
                self.competition_type,
                self.game_phase,
                self.state,
                self.set_play,
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
                out.append(_PLAYER.pack(p.penalty, min(255, operator.index(p.secs_till_unpenalised))))
        return b"".join(out)

    @classmethod
    def unpack(cls, data: bytes) -> GameControlData:
        """Parse a v18 packet; ``ValueError`` names what is wrong with a malformed one (size,
        header, version, or the first field outside the ranges of the module docstring)."""
        if not isinstance(data, bytes | bytearray | memoryview):
            raise TypeError(f"GameControlData packet must be bytes, got {type(data).__name__}")
        if len(data) != PACKET_SIZE:
            raise ValueError(f"GameControlData packet must be {PACKET_SIZE} bytes, got {len(data)}")
        values = _WHOLE.unpack(data)
        head = values[:_HEAD_VALUES]
        if head[0] != GAMECONTROLLER_HEADER:
            raise ValueError(f"GameControlData header must be {GAMECONTROLLER_HEADER!r}, got {head[0]!r}")
        if head[1] != GAMECONTROLLER_VERSION:
            raise ValueError(f"GameControlData version must be {GAMECONTROLLER_VERSION}, got {head[1]}")
        teams = []
        offset = len(head)
        plausible = True  # every range the ints of the struct do not imply already (then check() passes)
        for _ in range(2):
            t = values[offset : offset + _TEAM_VALUES]
            pairs = values[offset + _TEAM_VALUES : offset + _TEAM_VALUES + 2 * MAX_NUM_PLAYERS]
            offset += _TEAM_VALUES + 2 * MAX_NUM_PLAYERS
            players = tuple(_robot_info(pairs[k], pairs[k + 1]) for k in range(0, 2 * MAX_NUM_PLAYERS, 2))
            teams.append(TeamInfo(*t, players=players))
            plausible = plausible and t[1] <= _MAX_COLOUR and t[2] <= _MAX_COLOUR and t[3] <= MAX_NUM_PLAYERS
            plausible = plausible and set(pairs[::2]) <= _PENALTY_SET
        out = cls(
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
        numbers = (teams[0].team_number, teams[1].team_number)
        plausible = (
            plausible
            and 1 <= head[3] <= MAX_NUM_PLAYERS
            and head[4] in _COMPETITION_PHASES
            and head[5] in _COMPETITION_TYPES
            and head[6] in _GAME_PHASES
            and head[7] in _STATES
            and head[8] in _SET_PLAYS
            and head[9] in (0, 1)
            and numbers[0] != numbers[1]
            and head[10] in (*numbers, KICKING_TEAM_NONE)
        )
        if not plausible:
            check(out)  # raises, naming the first field out of range
        return out


_HEAD_VALUES = len(_HEAD.unpack(bytes(_HEAD.size)))
_TEAM_VALUES = len(_TEAM.unpack(bytes(_TEAM.size)))
_WHOLE = struct.Struct(_HEAD.format + 2 * (_TEAM.format[1:] + MAX_NUM_PLAYERS * _PLAYER.format[1:]))
"""The whole v18 packet in one format (one unpack call instead of 43)."""
_ROBOT_INFOS: dict[tuple[int, int], RobotInfo] = {}
"""Shared immutable :class:`RobotInfo` per (penalty, secs) pair seen in packets."""
_MAX_COLOUR = max(TeamColour)
_PENALTY_SET = frozenset(int(p) for p in Penalty)
_COMPETITION_PHASES = frozenset(int(v) for v in CompetitionPhase)
_COMPETITION_TYPES = frozenset(int(v) for v in CompetitionType)
_GAME_PHASES = frozenset(int(v) for v in GamePhase)
_STATES = frozenset(int(v) for v in GameStateId)
_SET_PLAYS = frozenset(int(v) for v in SetPlay)


def _robot_info(penalty: int, secs: int) -> RobotInfo:
    """The shared :class:`RobotInfo` of a (penalty, secs) pair (frozen, so sharing is safe)."""
    info = _ROBOT_INFOS.get((penalty, secs))
    if info is None:
        info = _ROBOT_INFOS[(penalty, secs)] = RobotInfo(penalty, secs)
    return info


_U8 = (0, 0xFF)
_U16 = (0, 0xFFFF)
_I16 = (-0x8000, 0x7FFF)
_PENALTIES = sorted(int(p) for p in Penalty)
_HEAD_FIELDS: tuple[tuple[str, tuple[int, int] | list[int]], ...] = (
    ("packet_number", _U8),
    ("players_per_team", (1, MAX_NUM_PLAYERS)),
    ("competition_phase", sorted(int(v) for v in CompetitionPhase)),
    ("competition_type", sorted(int(v) for v in CompetitionType)),
    ("game_phase", sorted(int(v) for v in GamePhase)),
    ("state", sorted(int(v) for v in GameStateId)),
    ("set_play", sorted(int(v) for v in SetPlay)),
    ("first_half", [0, 1]),
    ("secs_remaining", _I16),
    ("secondary_time", _I16),
)
_TEAM_FIELDS: tuple[tuple[str, tuple[int, int] | list[int]], ...] = (
    ("team_number", _U8),
    ("field_player_colour", sorted(int(v) for v in TeamColour)),
    ("goalkeeper_colour", sorted(int(v) for v in TeamColour)),
    ("goalkeeper", (0, MAX_NUM_PLAYERS)),
    ("score", _U8),
    ("penalty_shot", _U8),
    ("single_shots", _U16),
    ("message_budget", _U16),
)


def _int(name: str, value: object) -> int:
    try:
        return operator.index(value)  # type: ignore[arg-type]
    except TypeError:
        raise TypeError(f"{name} must be an integer, got {value!r}") from None


def _in(name: str, value: object, allowed: tuple[int, int] | list[int]) -> None:
    """``ValueError`` unless ``value`` is in ``allowed``: a (low, high) range or a list of values."""
    v = _int(name, value)
    if isinstance(allowed, tuple):
        if not allowed[0] <= v <= allowed[1]:
            raise ValueError(f"{name} must be in {allowed[0]}..{allowed[1]}, got {value!r}")
    elif v not in allowed:
        raise ValueError(f"{name} must be one of {allowed}, got {value!r}")


def check(data: GameControlData, saturate_secs: bool = False) -> None:
    """Raise ``ValueError`` (``TypeError`` for a non-integer) naming the first field of ``data``
    outside the ranges of the module docstring; ``saturate_secs`` lets ``secs_till_unpenalised``
    exceed 255 (:meth:`GameControlData.pack` writes 255 then)."""
    for name, allowed in _HEAD_FIELDS:
        _in(f"GameControlData.{name}", getattr(data, name), allowed)
    teams = data.teams
    if not isinstance(teams, tuple | list) or len(teams) != 2 or not all(isinstance(t, TeamInfo) for t in teams):
        raise ValueError(f"GameControlData.teams must be two TeamInfo blocks, got {teams!r}")
    for i, t in enumerate(teams):
        o = f"GameControlData.teams[{i}]"
        for name, allowed in _TEAM_FIELDS:
            _in(f"{o}.{name}", getattr(t, name), allowed)
        players = t.players
        if not isinstance(players, tuple | list) or len(players) != MAX_NUM_PLAYERS:
            n = len(players) if isinstance(players, tuple | list) else players
            raise ValueError(f"{o}.players must hold {MAX_NUM_PLAYERS} RobotInfo entries, got {n!r}")
        for j, p in enumerate(players):
            if not isinstance(p, RobotInfo):
                raise ValueError(f"{o}.players[{j}] must be a RobotInfo, got {p!r}")
            _in(f"{o}.players[{j}].penalty", p.penalty, _PENALTIES)
            secs = f"{o}.players[{j}].secs_till_unpenalised"
            if not saturate_secs:
                _in(secs, p.secs_till_unpenalised, _U8)
            elif _int(secs, p.secs_till_unpenalised) < 0:
                raise ValueError(f"{secs} must be >= 0 (above 255 is sent as 255), got {p.secs_till_unpenalised!r}")
    numbers = (_int("team_number", teams[0].team_number), _int("team_number", teams[1].team_number))
    if numbers[0] == numbers[1]:
        raise ValueError(f"GameControlData.teams[0] and teams[1] must have different team numbers, got {numbers}")
    _in("GameControlData.kicking_team", data.kicking_team, [*numbers, KICKING_TEAM_NONE])
