"""Fuzzing the two decoders a robot feeds with bytes from the network.

``GameControlData.unpack`` (GameController packets) and the team-message path
(``messages.unpack`` and ``TeamState.update``) get 10,000 generated inputs each (``TeamState``:
2,500 examples of 4 to 12 messages in 2 or 3 frames): random bytes,
and valid packets mutated by bit flips, byte overwrites with extreme values, float fields set
to extreme float32 values (NaN, infinities, the largest float32, values just beyond each
documented bound), truncation and extension. Team messages mostly get their CRC recomputed
after the mutation, so that the content checks behind the checksum are what is exercised.

Each decoder is compared with an oracle written here from the documented ranges (the
RoboCupGameControlData.h v18 values; the tables of :mod:`cognition.worldmodel.messages` and
:mod:`cognition.worldmodel.team`): a packet is accepted exactly when the oracle finds nothing
wrong with it, nothing but the documented error type escapes, every rejected team message is
counted under one of its actual problems, and what is accepted is finite and within bounds,
and an accepted GameController packet can be turned into a policy observation.

The runs are derandomized (fixed examples, no example database), so the suite stays deterministic.
"""

from __future__ import annotations

import binascii
import math
import struct

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cognition.behaviors.observation import ObservationBuilder
from cognition.field import make_field
from cognition.gamestate import PACKET_SIZE, GameControlData, GameStateId, Penalty, RobotInfo, TeamInfo
from cognition.representations import BallModel, HeadState, OdometryReading, RobotPose, SensorFrame, TeamMessageIn
from cognition.worldmodel.beliefs import Beliefs
from cognition.worldmodel.messages import SIZE, MalformedMessageError, Role, TeamMessage, unpack
from cognition.worldmodel.team import TEAM_REJECT_REASONS, TeamState

FUZZ = settings(
    max_examples=10_000,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
FIELD = make_field("spl2025")
CARPET = (4.5 + 0.7 + 1.0, 3.0 + 0.7 + 1.0)  # field + border strip + the 1 m margin (m)

# -- mutations ------------------------------------------------------------------------------

_EXTREME_BYTES = [0, 1, 2, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 19, 20, 21, 99, 127, 128, 254, 255]
_EXTREME_FLOATS = [
    math.nan, math.inf, -math.inf, 0.0, -0.0, 1e-45, -1e-45, 3.4e38, -3.4e38, -1.0, -1e-30,
    100.0, 100.001, -100.001, 50.0, 50.01, 4.0, 4.001, math.pi, 1e9, 1.1e9, 99.0, 99.99, 100.01,
    CARPET[0], CARPET[0] + 0.01, -CARPET[0] - 0.01, CARPET[1], CARPET[1] + 0.01, -CARPET[1] - 0.01,
]  # fmt: skip

_op = st.one_of(
    st.tuples(st.just("flip"), st.integers(0, 200), st.integers(0, 7)),
    st.tuples(st.just("byte"), st.integers(0, 200), st.sampled_from(_EXTREME_BYTES) | st.integers(0, 255)),
    st.tuples(st.just("float"), st.integers(0, 11), st.sampled_from(_EXTREME_FLOATS) | st.floats(width=32)),
    st.tuples(
        st.just("int16"), st.integers(0, 200), st.sampled_from([-32768, -1, 0, 1, 32767]) | st.integers(-32768, 32767)
    ),
    st.tuples(st.just("cut"), st.integers(0, 200), st.just(0)),
    st.tuples(st.just("extend"), st.integers(1, 16), st.integers(0, 255)),
)


def _mutate(raw: bytes, ops: list[tuple[str, int, float]], float_offsets: tuple[int, ...]) -> bytes:
    """Apply mutation ``ops`` to ``raw`` (indices wrap around the current length)."""
    out = bytearray(raw)
    for kind, at, value in ops:
        if not out and kind != "extend":
            continue
        i = at % len(out) if out else 0
        if kind == "flip":
            out[i] ^= 1 << int(value)
        elif kind == "byte":
            out[i] = int(value)
        elif kind == "float" and float_offsets:
            o = float_offsets[at % len(float_offsets)]
            if o + 4 <= len(out):
                out[o : o + 4] = struct.pack("<f", value)
        elif kind == "int16" and i + 2 <= len(out):
            out[i : i + 2] = struct.pack("<h", int(value))
        elif kind == "cut":
            del out[i:]
        elif kind == "extend":
            out += bytes([int(value)]) * at
    return bytes(out)


# -- GameController packets -----------------------------------------------------------------

_PLAYERS = tuple(RobotInfo(p, 45 if p else 0) for p in (0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 14, 15, 0, 0, 0, 0, 0, 0))
GC_BASES = [
    GameControlData(kicking_team=255).pack(),
    GameControlData(
        packet_number=200, players_per_team=7, competition_phase=1, competition_type=1, game_phase=1, state=3,
        set_play=5, first_half=0, kicking_team=12, secs_remaining=-5, secondary_time=32767,
        teams=(TeamInfo(team_number=12, field_player_colour=9, goalkeeper_colour=3, goalkeeper=0, score=255,
                        penalty_shot=7, single_shots=0xFFFF, message_budget=0, players=_PLAYERS),
               TeamInfo(team_number=255, field_player_colour=0, goalkeeper=20)),
    ).pack(),
    GameControlData(state=GameStateId.PLAYING, kicking_team=2, secs_remaining=412, teams=(
        TeamInfo(team_number=1), TeamInfo(team_number=2, players=tuple(reversed(_PLAYERS))))).pack(),
]  # fmt: skip
_GC_HEAD = struct.Struct("<4sBBBBBBBBBBhh")
_GC_TEAM = struct.Struct("<BBBBBBHH")


def _gc_problems(raw: bytes) -> list[str]:
    """What RoboCupGameControlData.h v18 says is wrong with ``raw`` (empty: a valid packet)."""
    if len(raw) != PACKET_SIZE:
        return ["size"]
    (header, version, _packet, per_team, comp_phase, comp_type, game_phase, state, set_play, first_half, kicking,
     _secs, _secondary) = _GC_HEAD.unpack_from(raw, 0)  # fmt: skip
    problems = []
    if header != b"RGme" or version != 18:
        return ["header"]
    for name, value, ok in [
        ("players_per_team", per_team, range(1, 21)), ("competition_phase", comp_phase, (0, 1)),
        ("competition_type", comp_type, (0, 1)), ("game_phase", game_phase, (0, 1, 2, 3)),
        ("state", state, range(6)), ("set_play", set_play, range(6)), ("first_half", first_half, (0, 1)),
    ]:  # fmt: skip
        if value not in ok:
            problems.append(name)
    numbers = []
    for t in range(2):
        base = 18 + t * 50
        number, colour, keeper_colour, keeper, *_ = _GC_TEAM.unpack_from(raw, base)
        numbers.append(number)
        if colour > 9 or keeper_colour > 9:
            problems.append("colour")
        if keeper > 20:
            problems.append("goalkeeper")
        for p in range(20):
            if raw[base + 10 + 2 * p] not in (0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 14, 15):
                problems.append("penalty")
    if numbers[0] == numbers[1]:
        problems.append("team numbers")
    if kicking not in (*numbers, 255):
        problems.append("kicking_team")
    return problems


_OBS_POSE = RobotPose(-1.0, 0.5, 0.3, np.eye(3) * 0.01, False, 0, np.zeros((0, 3)), np.zeros(0))
_OBS_BALL = BallModel(1.0, 0.2, 0.1, 0.0, np.eye(4) * 0.01, 0.0, 0.8, 0.5, "valid", "vision")


def _observe(game: GameControlData, team_number: int, player: int) -> np.ndarray:
    beliefs = Beliefs(
        time=1.0, player_number=player, game=game, penalty=game.team(team_number).players[player - 1].penalty,
        fallen=False, picked_up=False, pose=_OBS_POSE, ball=_OBS_BALL, team_ball=None, goal=None, teammates=(),
    )  # fmt: skip
    return ObservationBuilder(FIELD, 5, team_number).build(beliefs)


_gc_input = st.one_of(
    st.binary(min_size=0, max_size=2 * PACKET_SIZE),
    st.binary(min_size=PACKET_SIZE, max_size=PACKET_SIZE).map(lambda b: b"RGme\x12" + b[5:]),
    st.builds(
        lambda base, ops: _mutate(base, ops, ()), st.sampled_from(GC_BASES), st.lists(_op, min_size=1, max_size=4)
    ),
)


@FUZZ
@given(raw=_gc_input, player=st.integers(1, 5))
def test_gamecontroller_unpack_accepts_exactly_the_defined_values(raw: bytes, player: int) -> None:
    problems = _gc_problems(raw)
    try:
        game = GameControlData.unpack(raw)
    except ValueError as e:
        assert problems, f"valid packet rejected: {e}"
        return
    assert not problems, f"accepted a packet with {problems}"
    assert game.pack() == raw  # pack checks the same ranges: what was accepted is representable
    assert GameStateId(game.state) in GameStateId and all(
        Penalty(p.penalty) in Penalty for t in game.teams for p in t.players
    )
    for t in game.teams:  # the consumer: a robot of either team builds its policy observation
        obs = _observe(game, t.team_number, player)
        assert obs.dtype == np.float32 and np.isfinite(obs).all() and np.abs(obs).max() <= 1.0


# -- team messages --------------------------------------------------------------------------

_MSG = struct.Struct("<2sBBBB3ff4ff3fH")
_FLOAT_OFFSETS = tuple(6 + 4 * k for k in range(12))  # x, y, theta, pose_std, ball x y vx vy, age, cov xx xy yy
MSG_BASES = [
    TeamMessage(player=2).pack(),
    TeamMessage(player=3, x=-4.0, y=2.5, theta=3.1, pose_std=0.3, ball_x=1.0, ball_y=-0.5, ball_vx=2.0, ball_vy=-1.0,
                ball_age=0.5, ball_cov_xx=0.04, ball_cov_xy=0.01, ball_cov_yy=0.02, ball_confidence=0.8,
                ball_valid=True, role=Role.STRIKER).pack(),
    TeamMessage(player=4, x=CARPET[0], y=-CARPET[1], theta=-4.0, pose_std=100.0, ball_x=-CARPET[0], ball_y=CARPET[1],
                ball_vx=50.0, ball_vy=-50.0, ball_age=1e9, ball_cov_xx=100.0, ball_cov_xy=-100.0, ball_cov_yy=100.0,
                ball_confidence=1.0, ball_valid=True, role=Role.DEFENDER, fallen=True, penalized=True,
                lost=True).pack(),
    TeamMessage(player=7, x=0.0, y=0.0, pose_std=0.0, ball_age=0.0, ball_cov_xx=0.0, ball_cov_xy=0.0, ball_cov_yy=0.0,
                ball_valid=True, role=Role.KEEPER).pack(),
]  # fmt: skip


def _with_crc(raw: bytes) -> bytes:
    if len(raw) != SIZE:
        return raw
    return raw[:-2] + struct.pack("<H", binascii.crc_hqx(raw[:-2], 0xFFFF))


def _message_problems(raw: bytes, sender: int | None = None, own: int = 1) -> set[str]:
    """Every reason the documented rules give to reject ``raw`` (empty: accept). ``sender`` None
    checks the packet alone (``messages.unpack``), else also what ``TeamState`` checks."""
    if not isinstance(raw, bytes) or len(raw) != SIZE:
        return {"format"}
    if binascii.crc_hqx(raw[:-2], 0xFFFF) != struct.unpack("<H", raw[-2:])[0]:
        return {"checksum"}
    magic, version, player, flags, role, *floats, _conf = _MSG.unpack(raw[:-2])
    if magic != b"TS" or version != 1:
        return {"format"}
    problems = set()
    if flags & ~15 or role not in (0, 1, 2, 3, 4) or not 1 <= player <= 7:
        problems.add("out_of_range")
    x, y, theta, pose_std, bx, by, vx, vy, age, cxx, cxy, cyy = floats
    if not all(math.isfinite(v) for v in floats):
        problems.add("non_finite")
        finite = False
    else:
        finite = True
        if max(abs(x), abs(y), abs(bx), abs(by)) > 100 or abs(theta) > 4 or max(abs(vx), abs(vy)) > 50:
            problems.add("out_of_range")
        if not (0 <= pose_std <= 100 and 0 <= age <= 1e9 and 0 <= cxx <= 100 and 0 <= cyy <= 100):
            problems.add("out_of_range")
        if cxy * cxy > cxx * cyy * (1 + 1e-6):
            problems.add("covariance")
    if sender is not None:
        if player != sender or player == own:
            problems.add("sender")
        if finite and (max(abs(x), abs(bx)) > CARPET[0] or max(abs(y), abs(by)) > CARPET[1]):
            problems.add("off_field")
    return problems


def _check_accepted(m: TeamMessage) -> None:
    values = [m.x, m.y, m.theta, m.pose_std, m.ball_x, m.ball_y, m.ball_vx, m.ball_vy, m.ball_age, m.ball_cov_xx,
              m.ball_cov_xy, m.ball_cov_yy, m.ball_confidence]  # fmt: skip
    assert all(math.isfinite(v) for v in values)
    assert 1 <= m.player <= 7 and abs(m.theta) <= 4.0 and 0.0 <= m.ball_confidence <= 1.0
    assert 0.0 <= m.pose_std <= 100.0 and 0.0 <= m.ball_age <= 1e9 and max(abs(m.ball_vx), abs(m.ball_vy)) <= 50.0
    assert 0.0 <= m.ball_cov_xx <= 100.0 and 0.0 <= m.ball_cov_yy <= 100.0
    assert m.ball_cov_xy**2 <= m.ball_cov_xx * m.ball_cov_yy * (1 + 1e-6)


_mutated_message = st.builds(
    lambda base, ops, crc: _with_crc(_mutate(base, ops, _FLOAT_OFFSETS)) if crc else _mutate(base, ops, _FLOAT_OFFSETS),
    st.sampled_from(MSG_BASES),
    st.lists(_op, min_size=1, max_size=4),
    st.sampled_from([True, True, True, True, False]),  # mostly a valid CRC: the content checks get exercised
)
_message_input = st.one_of(
    st.binary(min_size=0, max_size=2 * SIZE),
    st.binary(min_size=SIZE, max_size=SIZE).map(_with_crc),
    st.binary(min_size=SIZE - 2, max_size=SIZE - 2).map(lambda b: _with_crc(b"TS\x01" + b[3:] + b"\0\0")),
    _mutated_message,
)


@FUZZ
@given(raw=_message_input)
def test_message_unpack_accepts_exactly_the_documented_content(raw: bytes) -> None:
    problems = _message_problems(raw)
    try:
        m = unpack(raw)
    except MalformedMessageError as e:
        assert problems, f"valid message rejected: {e}"
        assert e.reason in problems, (e.reason, problems, str(e))
        return
    assert not problems, f"accepted a message with {problems}"
    _check_accepted(m)
    assert m.pack() == raw


@settings(FUZZ, max_examples=2_500)  # at least 2 x 2 messages an example: at least 10,000 messages
@given(
    batches=st.lists(
        st.lists(st.tuples(_message_input, st.integers(1, 7)), min_size=2, max_size=4), min_size=2, max_size=3
    )
)
def test_team_state_keeps_only_valid_on_carpet_messages_and_counts_every_other(
    batches: list[list[tuple[bytes, int]]],
) -> None:
    state = TeamState(own_number=1, field=FIELD)
    invalid = 0
    for k, batch in enumerate(batches):
        t = 0.1 * k
        before = dict(state.rejected_by_reason)
        expected_latest = {n: msg for n, (_, msg) in state.latest.items()}
        for raw, sender in batch:
            problems = _message_problems(raw, sender)
            if problems:
                invalid += 1
            else:
                expected_latest[sender] = unpack(raw)
        frame = SensorFrame(t, k, 1, 1, OdometryReading(), HeadState(), GameControlData(), messages=tuple(
            TeamMessageIn(sender, raw, t) for raw, sender in batch))  # fmt: skip
        mates = state.update(frame)
        assert state.rejected == invalid == sum(state.rejected_by_reason.values())
        assert set(state.rejected_by_reason) <= set(TEAM_REJECT_REASONS)
        counted = {r: n - before.get(r, 0) for r, n in state.rejected_by_reason.items() if n != before.get(r, 0)}
        possible = set().union(*(_message_problems(raw, s) for raw, s in batch))
        assert set(counted) <= possible, (counted, possible)
        assert {m.player: m for m in mates} == expected_latest
        for m in mates:
            _check_accepted(m)
            assert max(abs(m.x), abs(m.ball_x)) <= CARPET[0] and max(abs(m.y), abs(m.ball_y)) <= CARPET[1]
