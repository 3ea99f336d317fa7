"""Team messages: bit-exact round trips, the 128-byte limit, and rejection of bad packets."""

from __future__ import annotations

import binascii
import math
import struct

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cognition.gamestate import TEAM_MESSAGE_MAX_BYTES
from cognition.worldmodel.messages import (
    MAX_BALL_AGE,
    MAX_BALL_VARIANCE,
    MAX_POSE_STD,
    REJECT_REASONS,
    SIZE,
    MalformedMessageError,
    Role,
    TeamMessage,
    unpack,
)


def _random_message(rng: np.random.Generator) -> TeamMessage:
    c = rng.uniform(0.01, 0.5, 2)
    return TeamMessage(
        player=int(rng.integers(1, 8)), x=rng.uniform(-5, 5), y=rng.uniform(-3.5, 3.5),
        theta=rng.uniform(-math.pi, math.pi), pose_std=rng.uniform(0, 2), ball_x=rng.uniform(-5, 5),
        ball_y=rng.uniform(-3.5, 3.5), ball_vx=rng.uniform(-3, 3), ball_vy=rng.uniform(-3, 3),
        ball_age=rng.uniform(0, 60), ball_cov_xx=c[0], ball_cov_xy=0.5 * math.sqrt(c[0] * c[1]),
        ball_cov_yy=c[1], ball_confidence=rng.uniform(0, 1), ball_valid=bool(rng.integers(2)),
        role=Role(int(rng.integers(0, 5))), fallen=bool(rng.integers(2)), penalized=bool(rng.integers(2)),
        lost=bool(rng.integers(2)),
    )  # fmt: skip


def test_round_trip_is_bit_exact_and_within_the_limit():
    rng = np.random.default_rng(0)
    assert SIZE <= TEAM_MESSAGE_MAX_BYTES
    for _ in range(500):
        m = _random_message(rng)
        data = m.pack()
        assert len(data) == SIZE
        back = unpack(data)
        assert back.pack() == data  # bytes -> message -> bytes is exact
        assert unpack(back.pack()) == back  # and so is message -> bytes -> message
        assert back.player == m.player and back.role == m.role and back.lost == m.lost
        assert back.ball_valid == m.ball_valid and back.fallen == m.fallen and back.penalized == m.penalized
        assert abs(back.x - m.x) < 1e-6 and abs(back.ball_vy - m.ball_vy) < 1e-6
        assert abs(back.ball_confidence - m.ball_confidence) <= 1 / 65535


def test_truncated_corrupted_and_foreign_packets_are_rejected():
    data = _random_message(np.random.default_rng(1)).pack()
    with pytest.raises(MalformedMessageError, match="bytes"):
        unpack(data[:-1])
    with pytest.raises(MalformedMessageError, match="bytes"):
        unpack(data + b"\0")
    for i in range(SIZE):
        bad = bytearray(data)
        bad[i] ^= 0x10
        with pytest.raises(MalformedMessageError):
            unpack(bytes(bad))
    with pytest.raises(MalformedMessageError, match="must be bytes"):
        unpack("not bytes")  # type: ignore[arg-type]


def _with_crc(body: bytes) -> bytes:
    return body + struct.pack("<H", binascii.crc_hqx(body, 0xFFFF))


def test_well_formed_packets_with_bad_content_are_rejected():
    good = TeamMessage(player=2).pack()[:-2]
    nan_x = good[:6] + struct.pack("<f", float("nan")) + good[10:]
    with pytest.raises(MalformedMessageError, match="x"):
        unpack(_with_crc(nan_x))
    with pytest.raises(MalformedMessageError, match="magic"):
        unpack(_with_crc(b"XX" + good[2:]))
    with pytest.raises(MalformedMessageError, match="version"):
        unpack(_with_crc(good[:2] + b"\x09" + good[3:]))
    with pytest.raises(MalformedMessageError, match="player"):
        unpack(_with_crc(good[:3] + b"\x09" + good[4:]))
    with pytest.raises(MalformedMessageError, match="role"):
        unpack(_with_crc(good[:5] + b"\x63" + good[6:]))
    with pytest.raises(MalformedMessageError, match="flag"):
        unpack(_with_crc(good[:4] + b"\xf0" + good[5:]))


@settings(max_examples=300, deadline=None)
@given(st.binary(min_size=0, max_size=200))
def test_arbitrary_bytes_never_crash_the_receiver(data):
    try:
        m = unpack(data)
    except MalformedMessageError:
        return
    assert m.pack() == data


def test_building_a_bad_message_is_a_clear_error():
    with pytest.raises(ValueError, match="player"):
        TeamMessage(player=0)
    with pytest.raises(ValueError, match="ball_vx"):
        TeamMessage(player=1, ball_vx=float("inf"))
    with pytest.raises(ValueError, match=r"ball_cov_xx must be finite"):
        TeamMessage(player=1, ball_cov_xx=float("inf"))
    with pytest.raises(ValueError, match=r"pose_std must be a number, got '1'"):
        TeamMessage(player=1, pose_std="1")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="semi-definite"):
        TeamMessage(player=1, ball_cov_xx=0.1, ball_cov_yy=0.1, ball_cov_xy=0.5)


_FMT = struct.Struct("<2sBBBB3ff4ff3fH")
_FIELDS = ("x", "y", "theta", "pose_std", "ball_x", "ball_y", "ball_vx", "ball_vy", "ball_age", "ball_cov_xx",
           "ball_cov_xy", "ball_cov_yy")  # fmt: skip


def _content(**floats: float) -> bytes:
    """A packet with a valid CRC whose float fields are set directly (TeamMessage would refuse them)."""
    values = {"pose_std": 0.1, "ball_age": 0.0, "ball_cov_xx": 0.01, "ball_cov_yy": 0.01} | floats
    body = _FMT.pack(b"TS", 1, 2, 8, 0, *(values.get(name, 0.0) for name in _FIELDS), 65535)
    return _with_crc(body)


@pytest.mark.parametrize(
    ("floats", "reason", "message"),
    [
        ({"ball_cov_xx": math.inf}, "non_finite", r"TeamMessage\.ball_cov_xx must be finite, got inf"),
        ({"ball_cov_yy": math.inf, "ball_cov_xy": 1.0}, "non_finite", r"ball_cov_yy must be finite"),
        ({"ball_age": math.inf}, "non_finite", r"TeamMessage\.ball_age must be finite, got inf"),
        ({"pose_std": math.inf}, "non_finite", r"TeamMessage\.pose_std must be finite, got inf"),
        ({"theta": math.nan}, "non_finite", r"TeamMessage\.theta must be finite, got nan"),
        ({"pose_std": 1000.0}, "out_of_range", r"TeamMessage\.pose_std must be in \[0, 100\] m, got 1000\.0"),
        ({"ball_cov_yy": 101.0}, "out_of_range", r"TeamMessage\.ball_cov_yy must be in \[0, 100\] m\^2, got 101\.0"),
        ({"ball_age": 2e9}, "out_of_range", r"TeamMessage\.ball_age must be in \[0, 1e\+09\] s, got 2000000000\.0"),
        ({"ball_vy": -60.0}, "out_of_range", r"TeamMessage\.ball_vy must be in \[-50, 50\] m/s, got -60\.0"),
        ({"ball_x": 150.0}, "out_of_range", r"TeamMessage\.ball_x must be in \[-100, 100\] m, got 150\.0"),
        ({"ball_cov_xy": 0.02}, "covariance", r"positive semi-definite .*xx=0\.0099.*, xy=0\.0199.*, yy=0\.0099"),
    ],
)
def test_absurd_content_with_a_valid_checksum_is_rejected_naming_the_field(floats, reason, message):
    with pytest.raises(MalformedMessageError, match=message) as e:
        unpack(_content(**floats))
    assert e.value.reason == reason


def test_every_rejection_has_a_documented_reason():
    good = TeamMessage(player=2).pack()
    cases = {
        "format": [good[:-1], _with_crc(b"XX" + good[2:-2]), _with_crc(good[:2] + b"\x02" + good[3:-2]), "text"],
        "checksum": [good[:10] + bytes([good[10] ^ 1]) + good[11:]],
        "out_of_range": [_with_crc(good[:3] + b"\x09" + good[4:-2]), _with_crc(good[:5] + b"\x63" + good[6:-2])],
    }
    for reason, packets in cases.items():
        assert reason in REJECT_REASONS
        for p in packets:
            with pytest.raises(MalformedMessageError) as e:
                unpack(p)  # type: ignore[arg-type]
            assert e.value.reason == reason, (p, e.value)


def test_the_largest_accepted_values_round_trip():
    m = TeamMessage(player=7, x=-100.0, y=100.0, theta=-4.0, pose_std=MAX_POSE_STD, ball_x=100.0, ball_y=-100.0,
                    ball_vx=50.0, ball_vy=-50.0, ball_age=MAX_BALL_AGE, ball_cov_xx=MAX_BALL_VARIANCE,
                    ball_cov_xy=-MAX_BALL_VARIANCE, ball_cov_yy=MAX_BALL_VARIANCE, ball_confidence=1.0)  # fmt: skip
    assert unpack(m.pack()) == m
