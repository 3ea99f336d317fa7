"""Fuzzing the decoders a robot feeds with bytes from the network.

``GameControlData.unpack`` (GameController packets), ``messages.unpack`` (one team message)
and ``TeamState.update`` (a stream of team messages in frames) each decode at least
:data:`PER_DECODER` inputs, counted inside the test. Hypothesis draws a seed per example
(:data:`EXAMPLES` examples, derandomized, no example database: the suite stays deterministic
and a failure names the seed); a ``numpy`` generator seeded with it builds :data:`BATCH` inputs,
which keeps the hypothesis overhead (about 2 ms an example) off the ten thousand inputs:

- random bytes of any length up to twice the packet size;
- random bytes of the right size behind a valid header (GameController: ``RGme``, version 18;
  team message: ``TS``, version 1 and a valid CRC), so that every field check is reached;
- valid packets mutated 1 to 4 times: bit flips, bytes set to extreme or random values, int16
  overwrites, float32 fields set to extreme values (NaN, infinities, the largest float32, values
  at and just beyond each documented bound and the carpet) or random bits, truncation and
  extension. Team messages mostly get their CRC recomputed after the mutation, so that the
  content checks behind the checksum are what is exercised.

Each decoder is compared with an oracle written here from the documented ranges (the
RoboCupGameControlData.h v18 values; the tables of :mod:`cognition.worldmodel.messages` and
:mod:`cognition.worldmodel.team`): an input is accepted exactly when the oracle finds nothing
wrong with it, nothing but the documented error type escapes, every rejected team message is
counted under one of its actual problems, what is accepted is finite and within bounds, and an
accepted GameController packet can be turned into a policy observation. Each test also asserts
that between a tenth and nine tenths of its inputs were accepted and that every kind of
rejection occurred, so the validation paths are exercised and not only survived.
"""

from __future__ import annotations

import binascii
import math
import struct
from collections import Counter

import numpy as np
from fuzzing import BATCH, CARPET, GC_BASES, PER_DECODER, gc_problems, mutate, run_seeded

from cognition.behaviors.observation import ObservationBuilder
from cognition.field import make_field
from cognition.gamestate import PACKET_SIZE, GameControlData, GameStateId, Penalty
from cognition.representations import BallModel, HeadState, OdometryReading, RobotPose, SensorFrame, TeamMessageIn
from cognition.worldmodel.beliefs import Beliefs
from cognition.worldmodel.messages import REJECT_REASONS, SIZE, MalformedMessageError, Role, TeamMessage, unpack
from cognition.worldmodel.team import TEAM_REJECT_REASONS, TeamState

FIELD = make_field("spl2025")


_OBS_POSE = RobotPose(-1.0, 0.5, 0.3, np.eye(3) * 0.01, False, 0, np.zeros((0, 3)), np.zeros(0))
_OBS_BALL = BallModel(1.0, 0.2, 0.1, 0.0, np.eye(4) * 0.01, 0.0, 0.8, 0.5, "valid", "vision")


def _observe(game: GameControlData, team_number: int, player: int) -> np.ndarray:
    beliefs = Beliefs(
        time=1.0, player_number=player, game=game, penalty=game.team(team_number).players[player - 1].penalty,
        fallen=False, picked_up=False, pose=_OBS_POSE, ball=_OBS_BALL, team_ball=None, goal=None, teammates=(),
    )  # fmt: skip
    return ObservationBuilder(FIELD, 5, team_number).build(beliefs)


def _gc_input(rng: np.random.Generator) -> bytes:
    """One GameController input: random bytes, a random packet behind a valid header, or a
    mutated valid packet."""
    r = rng.random()
    if r < 0.08:
        return rng.bytes(int(rng.integers(0, 2 * PACKET_SIZE + 1)))
    if r < 0.18:
        return b"RGme\x12" + rng.bytes(PACKET_SIZE - 5)
    return mutate(rng, GC_BASES[int(rng.integers(len(GC_BASES)))])


def test_gamecontroller_unpack_accepts_exactly_the_defined_values() -> None:
    seen: Counter[str] = Counter()

    def fuzz(rng: np.random.Generator) -> None:
        for _ in range(BATCH):
            raw = _gc_input(rng)
            problems = gc_problems(raw)
            seen["decoded"] += 1
            try:
                game = GameControlData.unpack(raw)
            except ValueError as e:
                assert problems, f"valid packet rejected: {e}; {raw.hex()}"
                seen.update(set(problems))
                continue
            assert not problems, f"accepted a packet with {problems}: {raw.hex()}"
            seen["accepted"] += 1
            assert game.pack() == raw  # pack checks the same ranges: what was accepted is representable
            assert GameStateId(game.state) in GameStateId and all(
                Penalty(p.penalty) in Penalty for t in game.teams for p in t.players
            )
            player = int(rng.integers(1, 6))
            for t in game.teams:  # the consumer: a robot of either team builds its policy observation
                obs = _observe(game, t.team_number, player)
                assert obs.dtype == np.float32 and np.isfinite(obs).all() and np.abs(obs).max() <= 1.0

    run_seeded(fuzz)
    assert seen["decoded"] >= PER_DECODER, seen
    assert 0.1 * seen["decoded"] <= seen["accepted"] <= 0.9 * seen["decoded"], seen
    every = ("size", "header", "players_per_team", "competition_phase", "competition_type", "game_phase", "state",
             "set_play", "first_half", "colour", "goalkeeper", "penalty", "team numbers", "kicking_team")  # fmt: skip
    assert all(seen[p] >= 3 for p in every), seen


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


def _message_input(rng: np.random.Generator) -> bytes:
    """One team-message input: random bytes, a random packet with a valid CRC (with or without a
    valid magic and version), or a mutated valid message (its CRC mostly recomputed)."""
    r = rng.random()
    if r < 0.06:
        return rng.bytes(int(rng.integers(0, 2 * SIZE + 1)))
    if r < 0.12:
        return _with_crc(rng.bytes(SIZE))
    if r < 0.25:
        return _with_crc(b"TS\x01" + rng.bytes(SIZE - 3))
    raw = mutate(rng, MSG_BASES[int(rng.integers(len(MSG_BASES)))], _FLOAT_OFFSETS)
    return _with_crc(raw) if rng.random() < 0.8 else raw


def test_message_unpack_accepts_exactly_the_documented_content() -> None:
    seen: Counter[str] = Counter()

    def fuzz(rng: np.random.Generator) -> None:
        for _ in range(BATCH):
            raw = _message_input(rng)
            problems = _message_problems(raw)
            seen["decoded"] += 1
            try:
                m = unpack(raw)
            except MalformedMessageError as e:
                assert problems, f"valid message rejected: {e}; {raw.hex()}"
                assert e.reason in problems, (e.reason, problems, str(e), raw.hex())
                seen[e.reason] += 1
                continue
            assert not problems, f"accepted a message with {problems}: {raw.hex()}"
            seen["accepted"] += 1
            _check_accepted(m)
            assert m.pack() == raw

    run_seeded(fuzz)
    assert seen["decoded"] >= PER_DECODER, seen
    assert 0.1 * seen["decoded"] <= seen["accepted"] <= 0.9 * seen["decoded"], seen
    assert all(seen[reason] >= 50 for reason in REJECT_REASONS), seen


_STEPS = (0.0, 0.1, 0.1, 0.1, 0.5, 1.0, 3.5)
"""Seconds between two frames: the same frame time, the usual rates, and gaps beyond ``max_age``."""


def test_team_state_keeps_only_valid_on_carpet_messages_and_counts_every_other() -> None:
    seen: Counter[str] = Counter()

    def fuzz(rng: np.random.Generator) -> None:
        state = TeamState(own_number=1, field=FIELD)
        expected: dict[int, tuple[float, TeamMessage]] = {}  # what TeamState should hold
        t, k, invalid, decoded = 0.0, 0, 0, 0
        while decoded < BATCH:
            batch = []
            for _ in range(int(rng.integers(1, 7))):
                raw = _message_input(rng)
                # mostly the number in the packet: the checks beyond the sender's are reached
                claimed = raw[3] if len(raw) > 3 and 1 <= raw[3] <= 7 and rng.random() < 0.85 else None
                batch.append((raw, claimed or int(rng.integers(1, 8))))
            problems = [_message_problems(raw, sender) for raw, sender in batch]
            for (raw, sender), p in zip(batch, problems, strict=True):
                if p:
                    invalid += 1
                else:
                    expected[sender] = (t, unpack(raw))
            expected = {n: v for n, v in expected.items() if t - v[0] <= state.max_age}
            before = Counter(state.rejected_by_reason)
            frame = SensorFrame(t, k, 1, 1, OdometryReading(), HeadState(), GameControlData(), messages=tuple(
                TeamMessageIn(sender, raw, t) for raw, sender in batch))  # fmt: skip
            mates = state.update(frame)
            decoded += len(batch)
            assert state.rejected == invalid == sum(state.rejected_by_reason.values())
            assert set(state.rejected_by_reason) <= set(TEAM_REJECT_REASONS)
            counted = Counter(state.rejected_by_reason) - before
            for reason, n in counted.items():  # each rejection under one of that message's problems
                assert n <= sum(reason in p for p in problems), (counted, problems)
            assert {m.player: m for m in mates} == {n: msg for n, (_, msg) in expected.items()}
            for m in mates:
                _check_accepted(m)
                assert max(abs(m.x), abs(m.ball_x)) <= CARPET[0] and max(abs(m.y), abs(m.ball_y)) <= CARPET[1]
            t += _STEPS[int(rng.integers(len(_STEPS)))]
            k += 1
        seen.update(state.rejected_by_reason)
        seen["decoded"] += decoded
        seen["accepted"] += decoded - invalid

    run_seeded(fuzz)
    assert seen["decoded"] >= PER_DECODER, seen
    assert 0.1 * seen["decoded"] <= seen["accepted"] <= 0.9 * seen["decoded"], seen
    assert all(seen[reason] >= 50 for reason in TEAM_REJECT_REASONS), seen
