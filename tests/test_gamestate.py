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
