"""Team state and team ball: malformed or absurd packets are dropped (and counted by reason),
fusion follows the uncertainties, and no accepted report can make a ball NaN or put it off the
carpet."""

from __future__ import annotations

import binascii
import math
import struct

import numpy as np
import pytest

from cognition.brain import BrainContext
from cognition.field import make_field
from cognition.gamestate import GameControlData
from cognition.oracle import OracleInput, OraclePose
from cognition.pipeline import CognitionConfig
from cognition.representations import (
    BallModel,
    HeadState,
    OdometryReading,
    RobotPose,
    SensorFrame,
    TeamMessageIn,
)
from cognition.worldmodel.ball import KalmanBallModel
from cognition.worldmodel.beliefs import Beliefs, CognitionBeliefs
from cognition.worldmodel.messages import TeamMessage
from cognition.worldmodel.team import TEAM_REJECT_REASONS, TeamState, carpet_limits, team_ball

FIELD = make_field("spl2025")
LIMITS = carpet_limits(FIELD)  # 4.5 + 0.7 + 1 = 6.2 m, 3 + 0.7 + 1 = 4.7 m


def _frame(t, messages=()):
    return SensorFrame(t, 0, 1, 1, OdometryReading(), HeadState(), GameControlData(), messages=tuple(messages))


def _pose(x=0.0, y=0.0, th=0.0, var=0.01):
    return RobotPose(x, y, th, np.eye(3) * var, False, 0, np.zeros((0, 3)), np.zeros(0))


def test_team_state_keeps_latest_valid_reports_and_counts_bad_ones():
    state = TeamState(own_number=1, field=FIELD, max_age=2.0)
    good = TeamMessage(player=3, ball_x=1.0, ball_valid=True).pack()
    newer = TeamMessage(player=3, ball_x=2.0, ball_valid=True).pack()
    bad = bytearray(good)
    bad[10] ^= 1
    msgs = [
        TeamMessageIn(3, good, 0.0),
        TeamMessageIn(4, bytes(bad), 0.0),  # corrupted
        TeamMessageIn(5, good[:20], 0.0),  # truncated
        TeamMessageIn(2, good, 0.0),  # player 3's message under number 2
    ]
    mates = state.update(_frame(0.0, msgs))
    assert [m.player for m in mates] == [3] and state.rejected == 3
    assert state.rejected_by_reason == {"checksum": 1, "format": 1, "sender": 1}
    mates = state.update(_frame(0.5, [TeamMessageIn(3, newer, 0.5)]))
    assert mates[0].ball_x == 2.0
    assert state.update(_frame(3.0)) == []  # too old


def test_fusion_weights_by_covariance_pose_quality_and_age():
    sharp = TeamMessage(player=2, ball_x=1.0, ball_y=0.0, ball_cov_xx=0.01, ball_cov_yy=0.01, ball_valid=True,
                        pose_std=0.05, ball_age=0.0)  # fmt: skip
    vague = TeamMessage(player=3, ball_x=2.0, ball_y=0.0, ball_cov_xx=0.01, ball_cov_yy=0.01, ball_valid=True,
                        pose_std=1.0, ball_age=0.0)  # fmt: skip
    tb = team_ball(None, None, 1, [sharp, vague])
    assert tb is not None and set(tb.contributors) == {2, 3}
    assert 1.0 < tb.x < 1.05  # the well-localized robot dominates
    old = TeamMessage(player=4, ball_x=3.0, ball_cov_xx=0.01, ball_cov_yy=0.01, ball_valid=True, pose_std=0.05,
                      ball_age=10.0)  # fmt: skip
    tb2 = team_ball(None, None, 1, [sharp, old])
    assert tb2 is not None and tb2.x < 1.1  # an old sighting counts little
    equal = TeamMessage(
        player=5, ball_x=3.0, ball_cov_xx=0.01, ball_cov_yy=0.01, ball_valid=True, pose_std=0.05, ball_age=0.0
    )
    tb3 = team_ball(None, None, 1, [sharp, equal])
    assert tb3 is not None and abs(tb3.x - 2.0) < 1e-9 and tb3.cov_xx < 0.5 * (0.01 + 0.05**2) + 1e-12


def test_own_ball_is_rotated_into_the_team_frame():
    p = np.diag([0.04, 0.0001, 1.0, 1.0])  # uncertain along the robot's x only
    own = BallModel(1.0, 0.0, 0.0, 0.0, p, 0.0, 1.0, 0.0, "valid", "vision")
    tb = team_ball(own, _pose(0.0, 0.0, math.pi / 2, var=1e-6), 1, [])
    assert tb is not None and tb.contributors == (1,)
    assert abs(tb.x) < 1e-12 and abs(tb.y - 1.0) < 1e-12
    assert tb.cov_yy > 10 * tb.cov_xx  # robot x is team y when facing +y
    assert team_ball(None, None, 1, []) is None
    invalid = BallModel(1.0, 0.0, 0.0, 0.0, p, 0.0, 1.0, 0.0, "invalid", "prediction")
    assert team_ball(invalid, _pose(), 1, []) is None


_BODY = struct.Struct("<2sBBBB3ff4ff3fH")


def _raw(
    player: int = 2,
    x: float = 0.0,
    y: float = 0.0,
    pose_std: float = 0.1,
    ball: tuple[float, float] = (1.0, 0.0),
    vel: tuple[float, float] = (0.0, 0.0),
    age: float = 0.0,
    cov: tuple[float, float, float] = (0.01, 0.0, 0.01),
) -> bytes:
    """A team message with a valid checksum and whatever content, ball valid (bypasses TeamMessage)."""
    body = _BODY.pack(b"TS", 1, player, 8, 0, x, y, 0.0, pose_std, *ball, *vel, age, *cov, 65535)
    return body + struct.pack("<H", binascii.crc_hqx(body, 0xFFFF))


INF, NAN = math.inf, math.nan
ABSURD = [  # (payload, reason TeamState must count it under)
    (_raw(cov=(INF, 0.0, 0.01)), "non_finite"),  # turned the Kalman ball into NaN, reported valid
    (_raw(ball=(99.0, 0.0)), "off_field"),  # pulled the team ball off the field
    (_raw(ball=(0.0, LIMITS[1] + 0.1)), "off_field"),  # just beyond the carpet plus 1 m
    (_raw(x=-(LIMITS[0] + 0.1)), "off_field"),  # the sender's own pose beyond it
    (_raw(x=NAN), "non_finite"),
    (_raw(pose_std=INF), "non_finite"),
    (_raw(age=INF), "non_finite"),
    (_raw(vel=(-INF, 0.0)), "non_finite"),
    (_raw(pose_std=1e5), "out_of_range"),
    (_raw(cov=(1e4, 0.0, 1.0)), "out_of_range"),
    (_raw(cov=(0.01, 0.0, -0.01)), "out_of_range"),
    (_raw(vel=(0.0, 1e3)), "out_of_range"),
    (_raw(cov=(0.01, 0.5, 0.01)), "covariance"),
    (_raw(player=3), "sender"),  # sent by 2 under number 3
]


def test_absurd_messages_with_valid_checksums_are_rejected_and_counted_by_reason():
    state = TeamState(own_number=1, field=FIELD)
    for k, (payload, reason) in enumerate(ABSURD):
        before = dict(state.rejected_by_reason)
        assert state.update(_frame(0.1 * k, [TeamMessageIn(2, payload, 0.1 * k)])) == [], reason
        assert state.rejected_by_reason.get(reason, 0) == before.get(reason, 0) + 1, reason
    assert state.rejected == len(ABSURD) == sum(state.rejected_by_reason.values())
    assert set(state.rejected_by_reason) <= set(TEAM_REJECT_REASONS)
    # the edges of the carpet plus margin are accepted
    edge = _raw(x=-LIMITS[0], y=LIMITS[1], ball=(LIMITS[0], -LIMITS[1]))
    assert [m.player for m in state.update(_frame(5.0, [TeamMessageIn(2, edge, 5.0)]))] == [2]


def test_team_state_parameters_are_checked():
    with pytest.raises(ValueError, match=r"max_age .*got 0"):
        TeamState(1, FIELD, max_age=0)
    with pytest.raises(ValueError, match=r"margin .*got -1"):
        TeamState(1, FIELD, margin=-1.0)
    assert TeamState(1, FIELD, margin=0.0).limits == (4.5 + 0.7, 3.0 + 0.7)


def _on_carpet(x: float, y: float) -> bool:
    return math.isfinite(x) and math.isfinite(y) and abs(x) <= LIMITS[0] + 1e-9 and abs(y) <= LIMITS[1] + 1e-9


def _cognition() -> CognitionBeliefs:
    context = BrainContext(team_number=1, player_number=1, players_per_team=5, field=FIELD, cognition_hz=30.0)
    return CognitionBeliefs(context, CognitionConfig(localization="oracle"))


def _truth(x: float, y: float, theta: float) -> OracleInput:
    """The ground truth of the ``oracle`` localization: the robot at (x, y, theta), team frame."""
    return OracleInput(OraclePose(1, x, y, theta), (), (), 0.0, 0.0, 0.0, 0.0)


def _check_beliefs(b: Beliefs) -> None:
    ball = b.ball
    assert np.isfinite(ball.covariance).all() and math.isfinite(ball.x) and math.isfinite(ball.vx)
    if ball.level != "invalid":
        assert _on_carpet(ball.field_x, ball.field_y), (ball.field_x, ball.field_y)
    tb = b.team_ball
    if tb is not None:
        assert _on_carpet(tb.x, tb.y) and all(math.isfinite(v) for v in (tb.cov_xx, tb.cov_xy, tb.cov_yy))


def test_a_stream_of_absurd_messages_leaves_the_ball_model_and_team_ball_finite_and_on_the_carpet():
    beliefs = _cognition()
    for i in range(150):  # 5 s; the robot sees nothing, faces +x (theta 0: inf * 0 made the NaN)
        t = i / 30
        msgs = [TeamMessageIn(2, ABSURD[i % len(ABSURD)][0], t)]
        if i >= 60:  # then a sane teammate reports the ball at (2, 1)
            msgs.append(TeamMessageIn(3, _raw(player=3, ball=(2.0, 1.0), cov=(0.02, 0.0, 0.02)), t))
        b = beliefs.update(_frame(t, msgs), _truth(0.0, 0.0, 0.0))
        _check_beliefs(b)
        if i < 60:
            assert b.ball.level == "invalid" and b.team_ball is None and b.teammates == ()
    assert b.team_ball is not None and b.team_ball.contributors == (3,)
    assert abs(b.team_ball.x - 2.0) < 1e-6 and abs(b.team_ball.y - 1.0) < 1e-6
    assert b.ball.level == "valid" and math.hypot(b.ball.field_x - 2.0, b.ball.field_y - 1.0) < 0.05
    assert beliefs.team.rejected == 150 and beliefs.team.rejected_by_reason["off_field"] >= 30
    # what a brain reports for the match summary: every rejected message, by reason
    counts = beliefs.rejected_inputs()
    assert sum(counts.values()) == 150 and counts["team_message_off_field"] >= 30
    assert all(k.startswith("team_message_") for k in counts)


def test_accepted_extreme_reports_keep_the_ball_model_and_team_ball_finite_and_on_the_carpet():
    lx, ly = LIMITS
    thin = (100.0, 99.99, 100.0)  # largest variances, correlation 0.9999: a thin diagonal ellipse
    extreme = [
        _raw(player=2, ball=(lx, 0.0), vel=(50.0, 50.0), cov=(1e-3, 0.0, 1e-3), pose_std=0.0),  # fast, at the edge
        _raw(player=3, ball=(-lx, -ly), vel=(-50.0, 0.0), cov=thin, pose_std=100.0, age=1e9),
        _raw(player=4, ball=(1.0, -1.0), cov=(100.0, -99.99, 100.0), pose_std=0.0),
        _raw(player=5, ball=(1.2, -1.0), cov=thin, pose_std=0.0),
    ]
    beliefs = _cognition()
    for i in range(300):
        t = i / 30
        msgs = [TeamMessageIn(2 + k, extreme[k], t) for k in range(4) if (i + k) % 3]
        _check_beliefs(beliefs.update(_frame(t, msgs), _truth(-4.0, 2.0, 0.0)))
    assert beliefs.team.rejected == 0


def test_fused_mean_is_clipped_to_the_limits_and_bad_own_balls_are_left_out():
    # two thin ellipses, 1 m apart, along nearly parallel diagonals: the information-weighted
    # mean lies where their axes cross, 15 m beyond either report
    a = TeamMessage(player=2, ball_x=0.0, ball_y=0.0, ball_cov_xx=25.0, ball_cov_xy=24.999, ball_cov_yy=25.0,
                    ball_valid=True, pose_std=0.0, ball_age=0.0)  # fmt: skip
    b = TeamMessage(player=3, ball_x=1.0, ball_y=0.0, ball_cov_xx=24.5, ball_cov_xy=24.99, ball_cov_yy=25.5,
                    ball_valid=True, pose_std=0.0, ball_age=0.0)  # fmt: skip
    free = team_ball(None, None, 1, [a, b])
    assert free is not None and free.x > 10.0 and free.y > 10.0  # why the limits are needed
    tb = team_ball(None, None, 1, [a, b], limits=LIMITS)
    assert tb is not None and (tb.x, tb.y) == LIMITS and (tb.cov_xx, tb.cov_xy) == (free.cov_xx, free.cov_xy)
    nan_cov = BallModel(1.0, 0.0, 0.0, 0.0, np.full((4, 4), np.nan), 0.0, 1.0, 0.0, "valid", "vision")
    assert team_ball(nan_cov, _pose(), 1, []) is None
    only_mate = team_ball(nan_cov, _pose(), 1, [b], limits=LIMITS)
    assert only_mate is not None and only_mate.contributors == (3,)


def test_ball_model_drops_a_non_finite_state_instead_of_reporting_a_certain_ball():
    model = KalmanBallModel(0.05)
    model.x, model.p = np.array([1.0, 0.0, 0.0, 0.0]), np.full((4, 4), np.nan)
    b = model.update(_frame(0.0), _pose())
    assert b.level == "invalid" and b.source == "none" and model.x is None  # max(0, nan) read as sd 0: "valid"
    model.x, model.p = np.array([np.nan, 0.0, 0.0, 0.0]), np.eye(4) * 0.01
    assert model.update(_frame(0.1), _pose()).level == "invalid"


def test_the_message_memo_gives_the_fusion_of_no_memo_to_the_bit():
    """Frames of changing teammates (kept, replaced, degenerate, non-finite, invalid) and own
    balls: with one memo kept over all frames, the team ball equals the one computed without
    it, every field to the bit; a memo entry of another ``age_variance_per_second`` is not reused."""
    g = np.random.default_rng(7)

    def message(player: int) -> TeamMessage:
        kind = g.integers(0, 10)
        cov = (0.0, 0.0, 0.0) if kind == 0 else (g.uniform(1e-4, 1.0), g.uniform(-1e-4, 1e-4), g.uniform(1e-4, 1.0))
        return TeamMessage(
            player=player, ball_x=float(g.uniform(-4, 4)), ball_y=float(g.uniform(-3, 3)), ball_cov_xx=cov[0],
            ball_cov_xy=cov[1], ball_cov_yy=cov[2], ball_valid=bool(kind != 1), penalized=bool(kind == 2),
            pose_std=float(g.uniform(0.0, 0.5)), ball_age=float(g.uniform(0.0, 2.0)),
        )  # fmt: skip

    mates = {p: message(p) for p in (2, 3, 4, 5)}
    memo: dict = {}
    fused = 0
    for frame in range(300):
        for p in mates:
            if g.random() < 0.1:
                mates[p] = message(p)
        current = [mates[p] for p in sorted(mates) if g.random() < 0.8]
        cov = np.diag([g.uniform(1e-3, 0.2), g.uniform(1e-3, 0.2), 0.1, 0.1])
        own = BallModel(
            float(g.uniform(-1, 1)), float(g.uniform(-1, 1)), 0.0, 0.0, cov, float(g.uniform(-4, 4)),
            float(g.uniform(-3, 3)), float(g.uniform(0, 1)), "valid" if frame % 7 else "invalid", "vision",
        )  # fmt: skip
        pose = _pose(float(g.uniform(-4, 4)), float(g.uniform(-3, 3)), float(g.uniform(-3, 3)), var=0.02)
        avps = 0.25 if frame % 50 else 0.5
        plain = team_ball(own, pose, 1, current, age_variance_per_second=avps, limits=LIMITS)
        kept = team_ball(own, pose, 1, current, age_variance_per_second=avps, limits=LIMITS, terms=memo)
        assert repr(kept) == repr(plain)
        fused += plain is not None and len(plain.contributors) > 2
    assert fused > 100 and len(memo) > 4  # teammates were fused, from the memo
