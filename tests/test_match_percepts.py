"""Percepts inside a match: every brain gets them each frame, with latency, deterministically."""

from __future__ import annotations

import math

import numpy as np
import pytest
from helpers import ScriptBrain

from cognition.gamestate import Penalty
from cognition.percepts import Percepts
from teamsim.events import ForceFall, ForcePenalty
from teamsim.match import Match, MatchConfig
from teamsim.percept_params import PerceptParams


def _run(config: MatchConfig, seconds: float) -> tuple[Match, list[ScriptBrain]]:
    brains: list[ScriptBrain] = []

    def factory(team: int, number: int) -> ScriptBrain:
        b = ScriptBrain()
        brains.append(b)
        return b

    m = Match(config, brains=factory)
    m.run(until=seconds)
    return m, brains


def test_every_brain_gets_percepts_every_frame_with_latency() -> None:
    cfg = MatchConfig(players_per_team=3)
    m, brains = _run(cfg, 3.0)
    latency = cfg.percepts.latency
    dt = 1.0 / cfg.physics.physics_hz
    seen_something = 0
    for b in brains:
        assert len(b.frames) == m.frames == math.ceil(3.0 * cfg.cognition_hz)
        for k, f in enumerate(b.frames):
            assert isinstance(f.percepts, Percepts)
            assert f.percepts.time <= f.time + 1e-9
            if k >= 3:  # the first images are taken at t = 0, before the latency has passed
                assert abs((f.time - f.percepts.time) - latency) <= dt + 1e-9
            seen_something += len(f.percepts)
    assert seen_something > 0


def test_percepts_match_the_truth_of_the_capture_time() -> None:
    cfg = MatchConfig(players_per_team=2, percepts="ideal")
    m, brains = _run(cfg, 0.5)
    # ideal: each reported ball lies where the ball truly is, in the robot frame of the capture
    robot = m.world.robots[0]
    frame = brains[0].frames[-1]
    assert frame.percepts is not None and frame.percepts.time == frame.time  # no latency in ideal
    x, y, th = robot.pose
    b = m.world.ball.position
    for bx, by in frame.percepts.ball.xy:
        c, s = math.cos(th), math.sin(th)
        # robots stand still in INITIAL/READY-free 0.5 s, so the pose at capture is the pose now
        assert (bx, by) == pytest.approx((c * (b.x - x) + s * (b.y - y), -s * (b.x - x) + c * (b.y - y)), abs=1e-6)


def test_same_seed_same_percepts() -> None:
    rows = []
    for _ in range(2):
        _, brains = _run(MatchConfig(players_per_team=2, seed=4), 2.0)
        rows.append([np.concatenate([f.percepts.rows for f in b.frames]) for b in brains])
    for a, b in zip(*rows, strict=True):
        assert np.array_equal(a, b, equal_nan=True)
    _, other = _run(MatchConfig(players_per_team=2, seed=5), 2.0)
    assert any(
        not np.array_equal(np.concatenate([f.percepts.rows for f in b.frames]), r, equal_nan=True)
        for b, r in zip(other, rows[0], strict=True)
    )


def test_penalized_and_fallen_robots_see_nothing() -> None:
    events = (
        ForcePenalty(time=0.2, team=0, number=2, code=int(Penalty.MANUAL)),
        ForceFall(time=0.2, team=1, number=1, duration=3.0),
    )
    cfg = MatchConfig(players_per_team=2, percepts="ideal", events=events)
    _, brains = _run(cfg, 1.0)
    n = cfg.players_per_team
    penalized, fallen = brains[1], brains[n]
    late = [f for f in penalized.frames if f.time > 0.3]
    assert late and all(len(f.percepts) == 0 and f.percepts.camera is None for f in late)
    late = [f for f in fallen.frames if 0.3 < f.time < 3.0]
    assert late and all(len(f.percepts) == 0 for f in late)
    assert any(len(f.percepts) > 0 for f in brains[0].frames)


def test_observation_none_gives_no_percepts() -> None:
    m, brains = _run(MatchConfig(players_per_team=1, observation="none"), 0.5)
    assert all(f.percepts is None for b in brains for f in b.frames)
    assert m.summary().percepts_per_frame == 0.0
    with pytest.raises(RuntimeError, match="observation='none'"):
        m.capture()


def test_harsh_preset_sees_less_than_default() -> None:
    counts = {}
    for preset in ("default", "harsh"):
        m, _ = _run(MatchConfig(players_per_team=3, percepts=PerceptParams.preset(preset), seed=2), 20.0)
        counts[preset] = m.summary().percepts_per_frame
    assert 0 < counts["harsh"] < counts["default"]
