"""CMU multi-hypothesis ball: decay, negative information, teammates, override."""

from __future__ import annotations

import itertools
import math
from dataclasses import replace

import numpy as np
import pytest

from cognition.percepts import N_KINDS, Kind, Percepts
from cognition.representations import OdometryReading, RobotPose
from cognition.worldmodel.hypotheses import BallHypotheses, HypothesisParams
from cognition.worldmodel.messages import TeamMessage
from teamsim.match import Match, MatchConfig

ROBOT = 2


@pytest.fixture(scope="module")
def seen_frame():
    """A frame of a scripted player on truth beliefs that sees the ball (its head tracks it)."""
    m = Match(MatchConfig(seed=0))
    while True:
        m.step()
        f = m.last_frames[ROBOT]
        seen = f is not None and f.percepts is not None and f.percepts.count(Kind.BALL) == 1
        if seen and m.time > 3 and f.percepts.ball.distance[0] < 3.0:
            return f


def _without_ball(f):
    p = f.percepts
    rows, offsets = p.table_and_offsets
    keep = [r for k in range(N_KINDS) if k != Kind.BALL for r in range(offsets[k], offsets[k + 1])]
    counts = [offsets[k + 1] - offsets[k] if k != Kind.BALL else 0 for k in range(N_KINDS)]
    new = Percepts(p.time, rows[keep], np.r_[0, np.cumsum(counts)], p._camera_row, p._spec)
    assert new.count(Kind.BALL) == 0 and new.camera is not None
    return new


def _at(f, t, percepts="same", odo=(0.0, 0.0, 0.0)):
    return replace(f, time=t, percepts=f.percepts if percepts == "same" else percepts, odometry=OdometryReading(*odo))


def test_a_hidden_ball_fades_through_suspicious_to_invalid(seen_frame):
    model = BallHypotheses()
    b = model.update(seen_frame)
    assert b.level == "valid" and b.source == "vision" and b.confidence == 1.0
    levels, confs = [], []
    for k in range(1, 400):  # no image at all: no negative information, only time
        b = model.update(_at(seen_frame, seen_frame.time + k / 30, percepts=None))
        levels.append(b.level)
        confs.append(b.confidence)
        if b.level == "suspicious":
            assert b.look_at is not None  # active-gaze request
    assert all(a >= c for a, c in itertools.pairwise(confs))
    assert "suspicious" in levels and levels[-1] == "invalid"
    assert 3.0 < levels.index("suspicious") / 30 < 8.0


def test_looking_at_the_place_without_seeing_the_ball_drops_it_fast(seen_frame):
    blind = _without_ball(seen_frame)
    slow, fast = BallHypotheses(), BallHypotheses()
    slow.update(seen_frame)
    fast.update(seen_frame)
    for k in range(1, 16):  # half a second
        a = slow.update(_at(seen_frame, seen_frame.time + k / 30, percepts=None))
        b = fast.update(_at(seen_frame, seen_frame.time + k / 30, percepts=blind))
    assert a.level == "valid" and b.level == "invalid"


def test_walking_decays_own_hypotheses_but_not_teammates(seen_frame):
    pose = RobotPose(0.0, 0.0, 0.0, np.eye(3) * 0.01, False, 0, np.zeros((0, 3)), np.zeros(0))
    own = BallHypotheses()
    own.update(seen_frame)
    team = BallHypotheses()
    msg = TeamMessage(player=4, ball_x=-2.0, ball_y=1.0, ball_age=0.1, ball_confidence=1.0, ball_valid=True)
    team.update(_at(seen_frame, seen_frame.time, percepts=None), pose, [msg])
    for k in range(1, 61):  # two seconds of walking forward at 0.25 m/s
        a = own.update(_at(seen_frame, seen_frame.time + k / 30, percepts=None, odo=(0.25 / 30, 0.0, 0.0)))
        b = team.update(_at(seen_frame, seen_frame.time + k / 30, percepts=None, odo=(0.25 / 30, 0.0, 0.0)), pose)
    standing = 1.0 - 2.0 * HypothesisParams().decay_per_second
    assert a.confidence < standing - 0.1  # walking made the own memory worse
    assert b.source == "team" and abs(b.confidence - (standing - 0.1 * 0.08)) < 0.02
    assert b.level == "valid" and abs(b.x + 2.0) < 1e-9 and abs(b.y - 1.0) < 1e-9


def test_a_teammate_revives_an_invalid_ball_and_a_seen_ball_overrides(seen_frame):
    pose = RobotPose(1.0, 0.0, math.pi / 2, np.eye(3) * 0.01, False, 0, np.zeros((0, 3)), np.zeros(0))
    model = BallHypotheses()
    model.update(seen_frame)
    for k in range(1, 600):
        b = model.update(_at(seen_frame, seen_frame.time + k / 30, percepts=None))
    assert b.level == "invalid"
    msg = TeamMessage(player=5, ball_x=1.0, ball_y=2.0, ball_age=0.0, ball_confidence=1.0, ball_valid=True)
    b = model.update(_at(seen_frame, seen_frame.time + 20.0, percepts=None), pose, [msg])
    assert b.level == "valid" and b.source == "team"
    assert abs(b.x - 2.0) < 1e-9 and abs(b.y) < 1e-9  # 2 m straight ahead of a robot facing +y
    b = model.update(_at(seen_frame, seen_frame.time + 20.1), pose)
    assert b.source == "vision" and abs(b.x - seen_frame.percepts.ball.x[0]) < 1e-12


def test_bad_parameters_are_clear_errors():
    with pytest.raises(ValueError, match="suspicious_level"):
        HypothesisParams(valid_level=0.2, suspicious_level=0.5)
    with pytest.raises(ValueError, match="view_distance"):
        HypothesisParams(view_distance=0.0)
