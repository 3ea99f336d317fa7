"""Team state and team ball: malformed packets are dropped, fusion follows the uncertainties."""

from __future__ import annotations

import math

import numpy as np

from cognition.gamestate import GameControlData
from cognition.representations import (
    BallModel,
    HeadState,
    OdometryReading,
    RobotPose,
    SensorFrame,
    TeamMessageIn,
)
from cognition.worldmodel.messages import TeamMessage
from cognition.worldmodel.team import TeamState, team_ball


def _frame(t, messages=()):
    return SensorFrame(t, 0, 1, 1, OdometryReading(), HeadState(), GameControlData(), messages=tuple(messages))


def _pose(x=0.0, y=0.0, th=0.0, var=0.01):
    return RobotPose(x, y, th, np.eye(3) * var, False, 0, np.zeros((0, 3)), np.zeros(0))


def test_team_state_keeps_latest_valid_reports_and_counts_bad_ones():
    state = TeamState(own_number=1, max_age=2.0)
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
