"""The Kalman ball module on frames of a real match: tracking, fading, teammates, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cognition.representations import RobotPose
from cognition.worldmodel.ball import KalmanBallModel
from cognition.worldmodel.kalman_ball import KalmanBallParams
from cognition.worldmodel.messages import TeamMessage
from teamsim.match import Match, MatchConfig

ROBOT = 2  # team 0, player 3: a scripted player on truth beliefs, whose head always tracks the ball


def _record(seconds: float, seed: int = 0):
    m = Match(MatchConfig(seed=seed))
    frames, truth, last = [], [], None
    robot = m.world.robots[ROBOT]
    while m.time < seconds:
        m.step()
        f = m.last_frames[ROBOT]
        if f is None or f is last:
            continue
        last = f
        x, y, th = robot.pose() if callable(robot.pose) else robot.pose
        bx, by = m.world.ball.position
        c, s = math.cos(th), math.sin(th)
        truth.append((c * (bx - x) + s * (by - y), -s * (bx - x) + c * (by - y)))
        frames.append(f)
    return frames, np.array(truth)


@pytest.fixture(scope="module")
def match_frames():
    return _record(40.0)


@pytest.mark.parametrize("mode", ["adaptive", "fixed"])
def test_a_seen_ball_is_tracked_in_robot_coordinates(match_frames, mode):
    frames, truth = match_frames
    model = KalmanBallModel(0.05, KalmanBallParams(sigma_mode=mode))
    err, raw = [], []
    for f, t in zip(frames, truth, strict=True):
        b = model.update(f)
        if b.source == "vision" and f.game.state == 3 and np.hypot(*t) < 3.0:
            err.append(math.hypot(b.x - t[0], b.y - t[1]))
            row = f.percepts.ball.rows[0]
            raw.append(math.hypot(row[0] - t[0], row[1] - t[1]))
    assert len(err) > 150
    assert np.mean(err) < 0.25 and np.mean(err) < 0.5 * np.mean(raw), (np.mean(err), np.mean(raw))


def test_an_unseen_ball_fades_to_invalid_and_a_teammate_revives_it(match_frames):
    frames, _ = match_frames
    model = KalmanBallModel(0.05)
    for f in frames[:300]:
        model.update(f)
    blind = [f.__class__(**{**f.__dict__, "percepts": None}) for f in frames[300:]]
    levels = [model.update(f).level for f in blind[:-1]]
    assert levels[0] == "valid" and "suspicious" in levels and levels[-1] == "invalid"
    first_invalid = levels.index("invalid") / 30.0
    assert 2.0 < first_invalid < 10.0, first_invalid  # seconds without a sighting
    pose = RobotPose(0.0, 0.0, 0.0, np.eye(3) * 0.01, False, 0, np.zeros((0, 3)), np.zeros(0))
    mate = TeamMessage(player=4, ball_x=1.0, ball_y=0.5, ball_cov_xx=0.01, ball_cov_yy=0.01, ball_valid=True)
    b = model.update(blind[-1], pose, [mate])
    assert b.source == "team" and b.level == "valid"
    assert abs(b.x - 1.0) < 0.2 and abs(b.y - 0.5) < 0.2 and abs(b.field_x - b.x) < 1e-9


def test_no_percepts_no_ball():
    frames, _ = _record(0.5)
    b = KalmanBallModel(0.05).update(frames[0].__class__(**{**frames[0].__dict__, "percepts": None}))
    assert b.level == "invalid" and b.source == "none" and math.isinf(b.age)
