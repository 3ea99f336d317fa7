"""Obstacle grid and 72-sector model: occupancy where robots are, free space, odometry, memory."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cognition.percepts import Kind
from cognition.pipeline import CognitionConfig
from cognition.representations import OdometryReading
from cognition.worldmodel.obstacles import SECTORS, ObstacleGrid, ObstacleGridParams, ObstacleSectors
from teamsim.match import Match, MatchConfig

ROBOT = 2


@pytest.fixture(scope="module")
def frames_with_truth():
    """Frames of one robot and, per frame, the other robots' positions in its robot frame."""
    m = Match(MatchConfig(seed=5))  # scripted team play on truth beliefs
    out, last = [], None
    while m.time < 20.0:
        m.step()
        f = m.last_frames[ROBOT]
        if f is None or f is last:
            continue
        last = f
        x, y, th = m.world.robots[ROBOT].pose
        c, s = math.cos(th), math.sin(th)
        others = [
            (c * (r.pose[0] - x) + s * (r.pose[1] - y), -s * (r.pose[0] - x) + c * (r.pose[1] - y))
            for i, r in enumerate(m.world.robots)
            if i != ROBOT
        ]
        out.append((f, np.array(others)))
    return out


def test_grid_is_occupied_at_robots_and_free_elsewhere(frames_with_truth):
    """With the noisy robot percepts of the default camera model, the map's occupancy at the
    true positions of nearby robots is far above its occupancy away from all robots."""
    grid = ObstacleGrid()
    at_robots, elsewhere = [], []
    for k, (f, others) in enumerate(frames_with_truth):
        model = grid.update(f.time, f.odometry, f.percepts)
        if k % 10 or k < 90:
            continue
        occ = model.occupancy
        assert occ is not None
        known = np.abs(occ - 0.5) > 0.05  # cells the camera has mapped
        for ox, oy in others:
            near = (np.hypot(grid.cx - ox, grid.cy - oy) < 0.3) & known
            if math.hypot(ox, oy) < 2.5 and near.any():
                at_robots.append(occ[near].max())
        d = np.min(np.hypot(grid.cx[..., None] - others[:, 0], grid.cy[..., None] - others[:, 1]), -1)
        mask = (d > 1.0) & known
        if mask.any():
            elsewhere.append(occ[mask].mean())
    assert len(at_robots) >= 10 and len(elsewhere) >= 10
    assert np.mean(at_robots) > 0.6 and np.mean(at_robots) > 1.7 * np.mean(elsewhere), (
        np.mean(at_robots),
        np.mean(elsewhere),
    )


def test_grid_moves_with_odometry_and_forgets():
    grid = ObstacleGrid(ObstacleGridParams(decay_per_second=0.5))
    i, j = grid.n // 2, grid.n // 2 + 10  # cell at x = +1.05 m, y = +0.05 m
    grid.logodds[i, j] = 4.0
    grid.update(0.0, OdometryReading(), None)
    grid.update(0.1, OdometryReading(dx=0.5), None)  # the robot walks 0.5 m forward
    k = np.unravel_index(np.argmax(grid.logodds), grid.logodds.shape)
    assert abs(grid.cx[k] - (grid.cx[i, j] - 0.5)) < 0.11 and abs(grid.cy[k] - grid.cy[i, j]) < 0.11
    grid.update(0.2, OdometryReading(dtheta=math.pi / 2), None)  # and turns left
    k = np.unravel_index(np.argmax(grid.logodds), grid.logodds.shape)
    assert abs(grid.cx[k]) < 0.15 and grid.cy[k] < -0.4  # now to its right
    for t in np.arange(0.3, 10.0, 0.1):
        model = grid.update(float(t), OdometryReading(), None)
    assert len(model.obstacles) == 0 and np.allclose(grid.logodds, 0.0)


def test_sectors_keep_the_nearest_obstacle_and_forget(frames_with_truth):
    sec = ObstacleSectors(memory=2.0)
    seen = None
    for f, _others in frames_with_truth:
        model = sec.update(f.time, f.odometry, f.percepts)
        if f.percepts is not None and f.percepts.count(Kind.ROBOT) and seen is None:
            seen = (f, model)
    assert seen is not None and len(seen[1].obstacles) >= 1
    assert np.isfinite(sec.distance).sum() <= SECTORS
    t = frames_with_truth[-1][0].time
    model = sec.update(t + 5.0, OdometryReading(), None)
    assert len(model.obstacles) == 0  # older than the memory


def _reference_sectors_update(distance, stamp, memory, time, o, percepts):
    """The plain numpy sector update the compiled kernel replaced (the reference)."""
    known = np.isfinite(distance) & (time - stamp <= memory)
    ang = (np.arange(SECTORS) + 0.5) * (2 * math.pi / SECTORS) - math.pi
    pts = np.column_stack([distance[known] * np.cos(ang[known]), distance[known] * np.sin(ang[known])])
    stamps = stamp[known]
    c, s = math.cos(o.dtheta), math.sin(o.dtheta)
    px, py = pts[:, 0] - o.dx, pts[:, 1] - o.dy
    pts = np.column_stack([c * px + s * py, -s * px + c * py])
    distance[:] = np.inf
    stamp[:] = -np.inf

    def put(x, y, t):
        k = int((math.atan2(y, x) + math.pi) / (2 * math.pi) * SECTORS) % SECTORS
        d = math.hypot(x, y)
        if d < distance[k] or t > stamp[k]:
            distance[k], stamp[k] = d, t

    for (x, y), t in zip(pts, stamps, strict=True):
        put(x, y, t)
    if percepts is not None:
        for r in percepts.table(Kind.ROBOT).rows:
            put(float(r[0]), float(r[1]), time)


def test_sectors_match_the_plain_reference_frame_by_frame(frames_with_truth):
    """The compiled sector update against the plain numpy one on a match's recorded frames."""
    sec = ObstacleSectors(memory=2.0)
    dist, stamp = np.full(SECTORS, np.inf), np.full(SECTORS, -np.inf)
    held = 0
    for f, _others in frames_with_truth:
        model = sec.update(f.time, f.odometry, f.percepts)
        _reference_sectors_update(dist, stamp, 2.0, f.time, f.odometry, f.percepts)
        np.testing.assert_allclose(sec.distance, dist, rtol=1e-12)
        np.testing.assert_array_equal(sec.stamp, stamp)
        assert len(model.obstacles) == np.isfinite(dist).sum()
        held += int(np.isfinite(dist).sum())
    assert held > 0  # the frames did hold obstacles


def test_bad_parameters_are_clear_errors():
    with pytest.raises(ValueError, match="log_free"):
        ObstacleGridParams(log_free=0.2)
    with pytest.raises(ValueError, match="memory"):
        ObstacleSectors(memory=0.0)


def test_models_are_chosen_by_name():
    from cognition.behaviors.team_play import ScriptedBrain
    from cognition.worldmodel import make_ball_model, make_obstacle_model
    from cognition.worldmodel.ball import KalmanBallModel
    from cognition.worldmodel.hypotheses import BallHypotheses

    assert isinstance(make_obstacle_model("grid"), ObstacleGrid)
    assert isinstance(make_obstacle_model("sectors"), ObstacleSectors)
    assert isinstance(make_ball_model("kalman", 0.05), KalmanBallModel)
    assert isinstance(make_ball_model("hypotheses", 0.05), BallHypotheses)
    with pytest.raises(ValueError, match="unknown obstacle model"):
        make_obstacle_model("lidar")
    with pytest.raises(ValueError, match="unknown ball model"):
        make_ball_model("magic", 0.05)
    with pytest.raises(ValueError, match=r"CognitionConfig\.obstacles must be one of .*got 'lidar'"):
        ScriptedBrain(CognitionConfig(localization="lowvar", obstacles="lidar"))
    grid = CognitionConfig(localization="lowvar", obstacles="grid")
    m = Match(MatchConfig(seed=6), brains=lambda t, n: ScriptedBrain(grid))
    m.run(until=3.0)
    provider = m.brains[0].provider  # type: ignore[attr-defined]
    assert isinstance(provider.obstacles, ObstacleGrid) and provider.obstacle_model is not None
