"""Odometry error statistics and the team-message channel (delay, loss, budget)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cognition.pipeline import CognitionConfig
from cognition.representations import HeadRequest, OdometryReading, WalkRequest
from teamsim.channel import ChannelParams, TeamChannel
from teamsim.match import Match, MatchConfig
from teamsim.odometry import OdometryModel, OdometryParams, TrueOdometry

N = 20000


def _reports(params: OdometryParams, planned: tuple[float, float, float], seed: int = 1) -> np.ndarray:
    model = OdometryModel(params, np.random.default_rng(seed))
    return np.array([[r.dx, r.dy, r.dtheta] for r in (model.report(planned) for _ in range(N))])


def test_translation_noise_is_proportional_to_distance() -> None:
    params = OdometryParams(drift_sigma=0.0, scale_sigma=0.0)
    for dx in (0.005, 0.02):
        r = _reports(params, (dx, 0.0, 0.0))
        assert r[:, 0].mean() == pytest.approx(dx, rel=0.01)
        assert r[:, 0].std() == pytest.approx(params.trans_noise * dx, rel=0.05)
        assert np.all(r[:, 1] == 0.0) and np.all(r[:, 2] == 0.0)


def test_rotation_noise_from_turning_and_sidesteps() -> None:
    params = OdometryParams(drift_sigma=0.0, scale_sigma=0.0)
    turn = _reports(params, (0.0, 0.0, 0.03))
    assert turn[:, 2].std() == pytest.approx(params.rot_noise * 0.03, rel=0.05)
    side = _reports(params, (0.0, 0.01, 0.0))
    assert side[:, 2].std() == pytest.approx(params.sideways_rot_noise * 0.01, rel=0.05)
    assert side[:, 1].std() == pytest.approx(params.trans_noise * 0.01, rel=0.05)


def test_standing_still_reports_no_motion() -> None:
    r = _reports(OdometryParams(), (0.0, 0.0, 0.0))
    assert np.all(r == 0.0)


def test_systematic_drift_and_scale_are_per_robot() -> None:
    params = OdometryParams(trans_noise=0.0, rot_noise=0.0, sideways_rot_noise=0.0)
    drifts = []
    for seed in range(200):
        model = OdometryModel(params, np.random.default_rng(seed))
        a = model.report((0.01, 0.0, 0.0))
        b = model.report((0.01, 0.0, 0.0))
        assert a == b  # systematic: the same error every time
        assert a.dtheta == pytest.approx(model.drift * 0.01)
        assert a.dx == pytest.approx(0.01 * model.scale)
        drifts.append(model.drift)
    assert np.std(drifts) == pytest.approx(params.drift_sigma, rel=0.15)


def test_walking_robot_odometry_against_truth() -> None:
    """Over 6 s of straight walking the report drifts from the truth, the truth matches the body."""
    match = Match(MatchConfig(seed=3))
    robot = match.world.robot(0, 2)
    robot.teleport(-2.0, 0.0, 0.0)
    for _ in range(200):  # let the referee's INITIAL state pass; walk in PLAYING-independent way
        robot.command(WalkRequest(forward=0.2), None, HeadRequest())
        match.world.step(match.time)
        match.steps += 1
        match.time = match.steps * match.world.dt
    planned, true = robot.take_motion()
    true_odo = TrueOdometry(*true)
    x, y, _ = robot.pose
    # the true motion is what the body did
    assert true_odo.dx == pytest.approx(x + 2.0, abs=1e-6)
    assert true_odo.dy == pytest.approx(y, abs=1e-6)
    # the walking engine's plan agrees with the body when nothing is in the way
    assert planned[0] == pytest.approx(true_odo.dx, abs=0.02)
    reported = match.odometry[1].report(planned)
    assert isinstance(reported, OdometryReading) and not isinstance(reported, TrueOdometry)
    assert reported.dx != true_odo.dx


def test_teleport_is_not_in_odometry() -> None:
    match = Match(MatchConfig(seed=1))
    robot = match.world.robot(1, 3)
    robot.take_motion()
    robot.teleport(1.0, 1.0, 1.0)
    match.world.step(0.0)
    planned, true = robot.take_motion()
    assert math.hypot(true[0], true[1]) < 1e-6 and abs(true[2]) < 1e-6
    assert planned == (0.0, 0.0, 0.0)


# -- team channel ---------------------------------------------------------------------------


def test_channel_delay_and_sender_exclusion() -> None:
    ch = TeamChannel(ChannelParams(delay=0.2, jitter=0.0, loss=0.0), 3, np.random.default_rng(0))
    assert ch.send(0, 1, b"hello", now=1.0)
    assert ch.receive(0, 1.19) == {}
    got = ch.receive(0, 1.2)
    assert sorted(got) == [2, 3]  # the sender does not hear itself
    assert got[2][0].payload == b"hello" and got[2][0].sent_at == 1.0 and got[2][0].sender == 1
    assert ch.receive(1, 5.0) == {}  # the other team hears nothing


def test_channel_loss_rate() -> None:
    ch = TeamChannel(ChannelParams(loss=0.3, budget=10_000), 5, np.random.default_rng(4))
    for i in range(2000):
        ch.send(0, 1 + i % 5, b"x", now=i * 0.01)
    received = sum(len(v) for v in ch.receive(0, 100.0).values())
    copies = 2000 * 4
    assert received / copies == pytest.approx(0.7, abs=0.02)
    assert ch.stats[0].lost + ch.stats[0].delivered == copies


def test_channel_budget_is_enforced() -> None:
    ch = TeamChannel(ChannelParams(budget=10, loss=0.0), 2, np.random.default_rng(0))
    results = [ch.send(1, 1, b"m", now=0.0) for _ in range(15)]
    assert results == [True] * 10 + [False] * 5
    assert ch.budget_left == [10, 0]
    assert ch.stats[1].sent == 10 and ch.stats[1].refused == 5
    assert sum(len(v) for v in ch.receive(1, 1.0).values()) == 10


def test_channel_rejects_bad_messages() -> None:
    ch = TeamChannel(ChannelParams(), 2, np.random.default_rng(0))
    with pytest.raises(ValueError, match="129 bytes"):
        ch.send(0, 1, bytes(129), 0.0)
    with pytest.raises(TypeError, match="bytes"):
        ch.send(0, 1, "text", 0.0)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"ChannelParams\.loss must be a real number in \[0, 1\], got 1\.5"):
        ChannelParams(loss=1.5)


def test_match_budget_spread_over_the_game() -> None:
    """Scripted players on the cognition stack pace their team messages: a budget of 60 for a
    2 x 600 s game lets each of the 5 players send once per 1200 * 5 / 60 = 100 s, so in the
    first 120 s (PLAYING from about 28 s) each sends once, at kickoff, and nothing is refused."""
    cfg = MatchConfig(seed=2, cognition=CognitionConfig(localization="odometry"), channel=ChannelParams(budget=60))
    match = Match(cfg)
    match.run(until=120.0)
    for team in (0, 1):
        assert match.channel.stats[team].sent == cfg.players_per_team
        assert match.channel.stats[team].refused == 0
