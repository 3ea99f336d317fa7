"""The two GameController structs on the wire: golden bytes, round trips, rejections, fuzzing.

The golden packets are written byte by byte in the field order of the official
``RoboCupGameControlData.h`` (control data v18, return data v4), not with the module's own
``struct`` formats, so a layout error in the module cannot hide in the test. The fuzz tests
throw at least :data:`fuzzing.PER_DECODER` random and mutated packets at each of the bridge's
decoders (:func:`teamsim.gc_bridge.decode_game_control`, :func:`decode_return`): nothing
escapes, a packet is accepted exactly when an oracle written here from the C header finds it
valid (accepted ones re-encode to the same bytes), and every other one adds one to the
rejection counters, under the reason the oracle names first.
"""

from __future__ import annotations

import math
import struct
from collections import Counter

import numpy as np
import pytest
from fuzzing import BATCH, GC_BASES, PER_DECODER, gc_problems, mutate, run_seeded

from cognition.gamestate import GameControlData, GameStateId, Penalty, SetPlay, TeamColour
from cognition.representations import BallModel, RobotPose
from cognition.returndata import RETURN_PACKET_SIZE, ReturnData, status_packet
from teamsim.gc_bridge import REJECT_REASONS, BridgeStats, decode_game_control, decode_return


def _u16(v: int) -> bytes:
    return v.to_bytes(2, "little")


def _i16(v: int) -> bytes:
    return v.to_bytes(2, "little", signed=True)


def _f32(v: float) -> bytes:
    return struct.pack("<f", v)


# -- control data v18 -----------------------------------------------------------------------


def _golden_control() -> bytes:
    """A v18 packet in the C header's field order: PLAYING, a kick-in for team 12, first half."""
    head = b"RGme" + bytes([18, 42, 5, 1, 0, 0, 3, 4, 1, 12]) + _i16(412) + _i16(-3)
    # header, version, packetNumber, playersPerTeam, competitionPhase, competitionType, gamePhase,
    # state, setPlay, firstHalf, kickingTeam, secsRemaining, secondaryTime
    players12 = b"".join(bytes([2, 31]) if i == 2 else bytes([0, 0]) for i in range(20))
    team12 = bytes([12, 1, 3, 1, 2, 0]) + _u16(0) + _u16(1100) + players12
    # teamNumber, fieldPlayerColour (RED), goalkeeperColour (BLACK), goalkeeper, score, penaltyShot,
    # singleShots, messageBudget, players[20] = (penalty, secsTillUnpenalised)
    players7 = b"".join(bytes([15, 0]) if i == 4 else bytes([0, 0]) for i in range(20))
    team7 = bytes([7, 0, 4, 1, 0, 0]) + _u16(0) + _u16(1200) + players7
    return head + team12 + team7


def test_golden_control_packet_decodes_field_by_field_and_reencodes_to_the_same_bytes() -> None:
    raw = _golden_control()
    assert len(raw) == 118
    game = GameControlData.unpack(raw)
    assert (game.packet_number, game.players_per_team, game.game_phase) == (42, 5, 0)
    assert game.state == GameStateId.PLAYING and game.set_play == SetPlay.KICK_IN
    assert (game.first_half, game.kicking_team, game.secs_remaining, game.secondary_time) == (1, 12, 412, -3)
    a, b = game.team(12), game.team(7)
    assert (a.field_player_colour, a.goalkeeper_colour, a.goalkeeper, a.score) == (
        TeamColour.RED,
        TeamColour.BLACK,
        1,
        2,
    )
    assert a.message_budget == 1100 and b.message_budget == 1200
    assert a.players[2].penalty == Penalty.PLAYER_PUSHING and a.players[2].secs_till_unpenalised == 31
    assert b.players[4].penalty == Penalty.MANUAL
    assert sum(p.penalty != 0 for t in game.teams for p in t.players) == 2
    assert game.pack() == raw


# -- return data v4 -------------------------------------------------------------------------


def _golden_return() -> bytes:
    """A v4 status packet in the C header's field order (values exact in float32)."""
    return (
        b"RGrt"
        + bytes([4, 3, 12, 1])  # version, playerNum, teamNum, fallen
        + _f32(1250.0)
        + _f32(-2000.5)
        + _f32(0.5)  # pose x, y (mm), theta (rad)
        + _f32(2.25)  # ballAge (s)
        + _f32(300.0)
        + _f32(-40.0)  # ball x, y relative to the robot (mm)
    )


def test_golden_return_packet_decodes_field_by_field_and_reencodes_to_the_same_bytes() -> None:
    raw = _golden_return()
    assert len(raw) == RETURN_PACKET_SIZE == 32
    r = ReturnData.unpack(raw)
    assert r == ReturnData(3, 12, True, 1250.0, -2000.5, 0.5, 2.25, 300.0, -40.0)
    assert r.pack() == raw
    never = ReturnData(20, 255).pack()
    assert never[4:8] == bytes([4, 20, 255, 0]) and never[20:24] == _f32(-1.0)  # ball never seen


def test_return_round_trip_keeps_values_to_float32_precision() -> None:
    rng = np.random.default_rng(3)
    for _ in range(200):
        values = rng.uniform(-9000, 9000, 6)
        values[3] = abs(values[3])  # a ball age
        r = ReturnData(int(rng.integers(1, 21)), int(rng.integers(0, 256)), bool(rng.integers(2)), *map(float, values))
        back = ReturnData.unpack(r.pack())
        assert (back.player_number, back.team_number, back.fallen) == (r.player_number, r.team_number, r.fallen)
        got = np.array([back.x, back.y, back.theta, back.ball_age, back.ball_x, back.ball_y])
        assert np.allclose(got, values, rtol=2**-23, atol=0) and np.all(got == values.astype(np.float32))
        assert back.pack() == r.pack()


@pytest.mark.parametrize(
    ("changes", "error", "message"),
    [
        ({"player_number": 0}, ValueError, r"player_number must be in 1\.\.20, got 0"),
        ({"player_number": 21}, ValueError, r"player_number must be in 1\.\.20, got 21"),
        ({"team_number": 256}, ValueError, r"team_number must be in 0\.\.255, got 256"),
        ({"player_number": 2.0}, TypeError, r"player_number must be an integer"),
        ({"fallen": 1}, TypeError, r"fallen must be a bool"),
        ({"x": math.nan}, ValueError, r"ReturnData\.x must be a finite float32, got nan"),
        ({"ball_y": math.inf}, ValueError, r"ReturnData\.ball_y must be a finite float32"),
        ({"theta": 1e39}, ValueError, r"ReturnData\.theta must be a finite float32"),
        ({"ball_age": -1.5}, ValueError, r"ball_age must be -1 \(never seen\) or more, got -1\.5"),
    ],
)
def test_pack_refuses_fields_outside_the_struct(changes: dict[str, object], error: type, message: str) -> None:
    values: dict[str, object] = {"player_number": 1, "team_number": 1, **changes}
    with pytest.raises(error, match=message):
        ReturnData(**values).pack()  # type: ignore[arg-type]


def _patched(offset: int, data: bytes) -> bytes:
    raw = bytearray(_golden_return())
    raw[offset : offset + len(data)] = data
    return bytes(raw)


@pytest.mark.parametrize(
    ("raw", "message"),
    [
        (_golden_return()[:31], "must be 32 bytes, got 31"),
        (_golden_return() + b"\0", "must be 32 bytes, got 33"),
        (_patched(0, b"RGme"), "header must be b'RGrt', got b'RGme'"),
        (_patched(4, bytes([3])), "version must be 4, got 3"),
        (_patched(5, bytes([0])), r"player_number must be in 1\.\.20, got 0"),
        (_patched(7, bytes([255])), "fallen must be 0 or 1, got 255"),
        (_patched(8, _f32(math.nan)), r"ReturnData\.x must be a finite float32"),
        (_patched(16, _f32(-math.inf)), r"ReturnData\.theta must be a finite float32"),
        (_patched(20, _f32(-2.0)), r"ball_age must be -1 \(never seen\) or more"),
    ],
)
def test_unpack_names_what_is_wrong(raw: bytes, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        ReturnData.unpack(raw)


def test_status_packet_reports_beliefs_in_millimetres_and_unknowns_as_such() -> None:
    pose = RobotPose(1.25, -2.0, 3 * math.pi / 2, np.eye(3), False, 0, np.zeros((0, 3)), np.zeros(0))
    ball = BallModel(0.3, -0.04, 0.0, 0.0, np.eye(4), 1.5, -2.0, 2.25, "valid", "vision")
    r = status_packet(3, 12, True, pose, ball)
    assert (r.player_number, r.team_number, r.fallen) == (3, 12, True)
    assert (r.x, r.y, r.ball_age) == (1250.0, -2000.0, 2.25)
    assert r.theta == pytest.approx(-math.pi / 2)  # wrapped into [-pi, pi]
    assert (r.ball_x, r.ball_y) == pytest.approx((300.0, -40.0))
    unseen = BallModel(0.0, 0.0, 0.0, 0.0, np.eye(4), math.nan, math.nan, math.inf, "invalid", "none")
    lost = RobotPose(math.nan, 0.0, 0.0, np.eye(3), True, 0, np.zeros((0, 3)), np.zeros(0))
    for r in (status_packet(1, 1, False, None, None), status_packet(1, 1, False, lost, unseen)):
        assert (r.x, r.y, r.theta, r.ball_age, r.ball_x, r.ball_y) == (0.0, 0.0, 0.0, -1.0, 0.0, 0.0)
        assert ReturnData.unpack(r.pack()) == r


# -- fuzzing the bridge's decoders ----------------------------------------------------------

_RETURN_BASES = [
    _golden_return(),
    ReturnData(1, 0).pack(),
    ReturnData(20, 255, False, -4500.0, 3000.0, -3.14, 0.0, 0.0, 0.0).pack(),
]
_RETURN_FLOATS = (8, 12, 16, 20, 24, 28)
_RETURN_LAYOUT = struct.Struct("<4sBBBB6f")


def _return_problems(raw: bytes) -> list[str]:
    """What the C header (and the documented checks) find wrong with a status packet."""
    if len(raw) != 32:
        return ["size"]
    header, version, player, _team, fallen, *floats = _RETURN_LAYOUT.unpack(raw)
    if header != b"RGrt":
        return ["header"]
    if version != 4:
        return ["version"]
    problems = []
    if not 1 <= player <= 20:
        problems.append("player")
    if fallen > 1:
        problems.append("fallen")
    if not all(math.isfinite(f) for f in floats):
        problems.append("float")
    elif floats[3] < -1.0:
        problems.append("ball_age")
    return problems


def _reason(problems: list[str]) -> str:
    """The counter a packet with these oracle problems must land in."""
    first = problems[0]
    return first if first in ("size", "header", "version") else "field"


def _fuzz_decoder(make, problems_of, decode) -> Counter[str]:  # type: ignore[no-untyped-def]
    seen: Counter[str] = Counter()

    def fuzz(rng: np.random.Generator) -> None:
        for _ in range(BATCH):
            raw = make(rng)
            problems = problems_of(raw)
            stats = BridgeStats()
            out = decode(raw, stats)  # nothing may escape
            seen["decoded"] += 1
            if problems:
                assert out is None, f"accepted an invalid packet ({problems}): {raw.hex()}"
                assert stats.rejected == Counter({_reason(problems): 1}), (problems, stats.rejected)
                seen[_reason(problems)] += 1
            else:
                assert out is not None and not stats.rejected, f"valid packet rejected: {raw.hex()}"
                assert out.pack() == raw
                seen["accepted"] += 1

    run_seeded(fuzz)
    assert seen["decoded"] >= PER_DECODER, seen
    assert 0.1 * seen["decoded"] <= seen["accepted"] <= 0.9 * seen["decoded"], seen
    return seen


def test_fuzzed_control_packets_are_accepted_exactly_when_valid_and_otherwise_counted() -> None:
    def make(rng: np.random.Generator) -> bytes:
        r = rng.random()
        if r < 0.08:
            return rng.bytes(int(rng.integers(0, 240)))
        if r < 0.18:
            return b"RGme\x12" + rng.bytes(113)
        return mutate(rng, GC_BASES[int(rng.integers(len(GC_BASES)))])

    def problems(raw: bytes) -> list[str]:  # the shared oracle says "header" for a wrong version too
        found = gc_problems(raw)
        return ["version"] if found == ["header"] and raw[:4] == b"RGme" else found

    seen = _fuzz_decoder(make, problems, decode_game_control)
    assert all(seen[r] > 0 for r in REJECT_REASONS if r != "teams"), seen


def test_fuzzed_status_packets_are_accepted_exactly_when_valid_and_otherwise_counted() -> None:
    def make(rng: np.random.Generator) -> bytes:
        r = rng.random()
        if r < 0.08:
            return rng.bytes(int(rng.integers(0, 65)))
        if r < 0.18:
            return b"RGrt\x04" + rng.bytes(27)
        return mutate(rng, _RETURN_BASES[int(rng.integers(len(_RETURN_BASES)))], _RETURN_FLOATS)

    seen = _fuzz_decoder(make, _return_problems, decode_return)
    assert all(seen[r] > 0 for r in REJECT_REASONS if r != "teams"), seen
