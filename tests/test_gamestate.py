"""The GameController v18 representation: wire format and malformed packets."""

from __future__ import annotations

import pytest

from cognition.gamestate import PACKET_SIZE, GameControlData, GameStateId, Penalty, RobotInfo, TeamInfo


def test_packet_size_matches_v18_struct() -> None:
    # 18 header bytes + 2 teams x (10 bytes + 20 players x 2 bytes)
    assert PACKET_SIZE == 18 + 2 * (10 + 40)


def test_pack_unpack_round_trip() -> None:
    players = tuple(RobotInfo(Penalty.PLAYER_PUSHING, 31) if i == 2 else RobotInfo() for i in range(20))
    data = GameControlData(
        packet_number=7,
        state=GameStateId.PLAYING,
        secs_remaining=412,
        secondary_time=-3,
        kicking_team=5,
        teams=(TeamInfo(team_number=5, score=2, message_budget=1100, players=players), TeamInfo(team_number=9)),
    )
    raw = data.pack()
    assert raw[:4] == b"RGme" and raw[4] == 18 and len(raw) == PACKET_SIZE
    back = GameControlData.unpack(raw)
    assert back == data
    assert back.team(5).players[2].penalty == Penalty.PLAYER_PUSHING
    with pytest.raises(KeyError, match="team number 3"):
        back.team(3)


@pytest.mark.parametrize(
    ("raw", "message"),
    [
        (b"RGme", "must be 118 bytes"),
        (b"XXXX" + bytes(PACKET_SIZE - 4), "header"),
        (b"RGme\x11" + bytes(PACKET_SIZE - 5), "version"),
    ],
)
def test_malformed_packets_are_rejected(raw: bytes, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        GameControlData.unpack(raw)


# byte offsets in the v18 packet: 18 header bytes, then per team 10 bytes and 20 x (penalty, secs)
_AT = {"packet_number": 5, "players_per_team": 6, "competition_phase": 7, "competition_type": 8, "game_phase": 9,
       "state": 10, "set_play": 11, "first_half": 12, "kicking_team": 13}  # fmt: skip
_TEAM1 = 18 + 10 + 2 * 20


def _valid() -> bytes:
    return GameControlData(kicking_team=5, teams=(TeamInfo(team_number=5), TeamInfo(team_number=9))).pack()


def _with(raw: bytes, offset: int, value: int) -> bytes:
    out = bytearray(raw)
    out[offset] = value
    return bytes(out)


@pytest.mark.parametrize(
    ("offset", "value", "message"),
    [
        (_AT["state"], 77, r"GameControlData\.state must be one of \[0, 1, 2, 3, 4, 5\], got 77"),
        (_AT["set_play"], 6, r"GameControlData\.set_play must be one of \[0, 1, 2, 3, 4, 5\], got 6"),
        (_AT["game_phase"], 4, r"GameControlData\.game_phase must be one of \[0, 1, 2, 3\], got 4"),
        (_AT["competition_phase"], 2, r"GameControlData\.competition_phase must be one of \[0, 1\], got 2"),
        (_AT["competition_type"], 200, r"GameControlData\.competition_type must be one of \[0, 1\], got 200"),
        (_AT["first_half"], 2, r"GameControlData\.first_half must be one of \[0, 1\], got 2"),
        (_AT["players_per_team"], 0, r"GameControlData\.players_per_team must be in 1\.\.20, got 0"),
        (_AT["players_per_team"], 21, r"GameControlData\.players_per_team must be in 1\.\.20, got 21"),
        (_AT["kicking_team"], 7, r"GameControlData\.kicking_team must be one of \[5, 9, 255\], got 7"),
        (18 + 1, 10, r"GameControlData\.teams\[0\]\.field_player_colour must be one of \[0, .*9\], got 10"),
        (_TEAM1 + 2, 255, r"GameControlData\.teams\[1\]\.goalkeeper_colour must be one of \[0, .*9\], got 255"),
        (_TEAM1 + 3, 21, r"GameControlData\.teams\[1\]\.goalkeeper must be in 0\.\.20, got 21"),
        (
            _TEAM1 + 10 + 2 * 3,
            99,
            r"GameControlData\.teams\[1\]\.players\[3\]\.penalty must be one of \[0, 1, .*15\], got 99",
        ),
        (18 + 10 + 2 * 19, 12, r"GameControlData\.teams\[0\]\.players\[19\]\.penalty must be one of .*, got 12"),
        (_TEAM1, 5, r"teams\[0\] and teams\[1\] must have different team numbers, got \(5, 5\)"),
    ],
)
def test_undefined_values_are_rejected_naming_the_field(offset: int, value: int, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        GameControlData.unpack(_with(_valid(), offset, value))


def test_every_defined_value_is_accepted() -> None:
    raw = _valid()
    for offset, values in [
        (_AT["state"], range(6)), (_AT["set_play"], range(6)), (_AT["game_phase"], range(4)),
        (_AT["competition_phase"], range(2)), (_AT["competition_type"], range(2)), (_AT["first_half"], range(2)),
        (_AT["players_per_team"], range(1, 21)), (_AT["kicking_team"], (5, 9, 255)), (_AT["packet_number"], (0, 255)),
        (18 + 1, range(10)), (18 + 3, range(21)), (18 + 10, (0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 14, 15)),
        (18 + 11, (0, 255)),
    ]:  # fmt: skip
        for v in values:
            assert GameControlData.unpack(_with(raw, offset, v)).pack() == _with(raw, offset, v)


@pytest.mark.parametrize(
    ("changes", "error", "message"),
    [
        ({"state": 77}, ValueError, r"GameControlData\.state must be one of \[0, 1, 2, 3, 4, 5\], got 77"),
        (
            {"secs_remaining": 40_000},
            ValueError,
            r"GameControlData\.secs_remaining must be in -32768\.\.32767, got 40000",
        ),
        ({"packet_number": 256}, ValueError, r"GameControlData\.packet_number must be in 0\.\.255, got 256"),
        ({"kicking_team": 0}, ValueError, r"GameControlData\.kicking_team must be one of \[5, 9, 255\], got 0"),
        ({"state": 3.0}, TypeError, r"GameControlData\.state must be an integer, got 3\.0"),
        ({"teams": (TeamInfo(team_number=5),)}, ValueError, r"GameControlData\.teams must be two TeamInfo blocks"),
        (
            {"teams": (TeamInfo(team_number=5), TeamInfo(team_number=9, players=(RobotInfo(),) * 5))},
            ValueError,
            r"GameControlData\.teams\[1\]\.players must hold 20 RobotInfo entries, got 5",
        ),
        (
            {"teams": (TeamInfo(team_number=5, message_budget=-1), TeamInfo(team_number=9))},
            ValueError,
            r"GameControlData\.teams\[0\]\.message_budget must be in 0\.\.65535, got -1",
        ),
        (
            {
                "teams": (
                    TeamInfo(team_number=5),
                    TeamInfo(team_number=9, players=(RobotInfo(Penalty.MANUAL, -2),) * 20),
                )
            },
            ValueError,
            r"GameControlData\.teams\[1\]\.players\[0\]\.secs_till_unpenalised must be >= 0",
        ),
    ],
)
def test_pack_refuses_out_of_range_values(changes: dict[str, object], error: type[Exception], message: str) -> None:
    # struct raised struct.error (not a ValueError, no field name) for some and wrote state 77 unchanged
    data = GameControlData(kicking_team=5, teams=(TeamInfo(team_number=5), TeamInfo(team_number=9)))
    with pytest.raises(error, match=message):
        data.with_changes(**changes).pack()


def test_pack_saturates_the_penalty_clock_like_the_game_controller() -> None:
    players = (RobotInfo(Penalty.REQUEST_FOR_PICKUP, 300),) + (RobotInfo(),) * 19
    data = GameControlData(kicking_team=255, teams=(TeamInfo(team_number=5, players=players), TeamInfo(team_number=9)))
    assert GameControlData.unpack(data.pack()).teams[0].players[0].secs_till_unpenalised == 255
    assert GameControlData().pack() == GameControlData.unpack(GameControlData().pack()).pack()  # defaults are valid
