"""Localization: convergence, tracking, kidnapping recovery, game-controller events, robustness.

Frames come from real matches (the simulator's camera model and odometry); the filters see
only the sensor frames, and the truth is read from the simulator for scoring.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.stats import binomtest

from cognition.brain import BrainContext
from cognition.field import make_field
from cognition.gamestate import GameControlData, GameStateId, RobotInfo, TeamInfo
from cognition.localization import VARIANTS, LocalizationParams, make_localizer
from cognition.localization.particle_filter import ParticleFilter
from cognition.localization.places import return_poses
from cognition.percepts import Percepts
from cognition.representations import (
    BrainOutput,
    HeadRequest,
    HeadState,
    MotionRequest,
    OdometryReading,
    SensorFrame,
    WalkRequest,
)
from teamsim.events import Kidnap
from teamsim.match import Match, MatchConfig
from teamsim.referee import RefereeParams

SPL = make_field("spl2025")
ME = 0  # robot index of team 0, player 1 in a 1 v 1 match


class ScanBrain:
    """Sweeps the head yaw between -1.4 and 1.4 rad; stands, or (``walk``) walks a square
    loop in the own half while PLAYING. It steers by the true pose (a test driver; the
    localizers under test never see it)."""

    uses_oracle = True
    LOOP = ((-3.0, -1.8), (-1.0, -1.8), (-1.0, 1.2), (-3.0, 1.2))

    def __init__(self, walk: bool = False):
        self.walk = walk
        self.leg = 0

    def reset(self, context: BrainContext) -> None:
        self.context = context

    def think(self, frame: SensorFrame, oracle) -> BrainOutput:
        head = HeadRequest(yaw=1.4 * math.sin(0.8 * frame.time), pitch=0.35)
        if not self.walk or frame.game.state != GameStateId.PLAYING:
            return BrainOutput(MotionRequest(head=head))
        me = oracle.self_pose
        tx, ty = self.LOOP[self.leg]
        if math.hypot(tx - me.x, ty - me.y) < 0.25:
            self.leg = (self.leg + 1) % len(self.LOOP)
            tx, ty = self.LOOP[self.leg]
        err = (math.atan2(ty - me.y, tx - me.x) - me.theta + math.pi) % (2 * math.pi) - math.pi
        walk = WalkRequest(forward=0.2 if abs(err) < 0.5 else 0.0, turn=max(-0.8, min(0.8, 1.5 * err)))
        return BrainOutput(MotionRequest(walk=walk, head=head))


def record(seed: int, seconds: float, walk: bool = False, percepts: str = "default", events=(), playing=False):
    """Frames of robot ``ME`` and its true team-frame poses, from a 1 v 1 match."""
    ref = (
        RefereeParams(initial_seconds=1000.0) if not playing else RefereeParams(initial_seconds=0.5, ready_seconds=1.0)
    )
    cfg = MatchConfig(seed=seed, players_per_team=1, percepts=percepts, referee=ref, events=tuple(events))
    m = Match(cfg, brains=lambda team, number: ScanBrain(walk))
    frames, truth, last = [], [], None
    robot = m.world.robots[ME]
    while m.time < seconds:
        m.step()
        f = m.last_frames[ME]
        if f is not None and f is not last:
            last = f
            frames.append(f)
            truth.append(m.referee.team_pose(robot))
    return frames, np.array(truth)


def errors(poses, truth, symmetric: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Position (m) and heading (rad) errors; ``symmetric``: the smaller of truth and mirror."""
    est = np.array([p.pose for p in poses])

    def err(t):
        d = np.hypot(est[:, 0] - t[:, 0], est[:, 1] - t[:, 1])
        a = np.abs((est[:, 2] - t[:, 2] + math.pi) % (2 * math.pi) - math.pi)
        return d, a

    d, a = err(truth)
    if symmetric:
        mirror = np.column_stack([-truth[:, 0], -truth[:, 1], truth[:, 2] + math.pi])
        d2, a2 = err(mirror)
        use = d2 < d
        d, a = np.where(use, d2, d), np.where(use, a2, a)
    return d, a


def run(variant: str, frames, seed: int = 0, params: LocalizationParams | None = None, uniform: bool = False):
    loc = make_localizer(variant, SPL, params, np.random.default_rng(seed), player_number=1, players_per_team=1)
    if uniform:
        assert isinstance(loc, ParticleFilter)
        loc.set_uniform()
    return [loc.update(f) for f in frames], loc


# -- convergence and tracking ---------------------------------------------------------------
@pytest.mark.parametrize("variant", ["reset"])
def test_standing_robot_converges_from_uniform_prior(variant):
    ok = 0
    for seed in range(5):
        frames, truth = record(seed, 6.0)
        poses, _ = run(variant, frames, seed, uniform=True)
        d, a = errors(poses, truth, symmetric=True)
        tail = slice(int(4.0 * 30), None)  # after 4 s
        if np.mean(d[tail]) < 0.3 and np.degrees(np.mean(a[tail])) < 10.0:
            ok += 1
    assert ok >= 4, f"{variant}: converged in only {ok} of 5 seeds"


def test_walking_robot_is_tracked():
    means = []
    for seed in range(3):
        frames, truth = record(seed, 25.0, walk=True, playing=True)
        poses, _ = run("lowvar", frames, seed)
        d, _ = errors(poses, truth)
        playing = np.array([f.game.state == GameStateId.PLAYING and not f.penalty for f in frames])
        assert playing.sum() > 400
        means.append(np.mean(d[playing]))
    assert np.mean(means) < 0.25, means


def test_ideal_percepts_give_near_zero_error():
    frames, truth = record(3, 8.0, percepts="ideal")
    poses, _ = run("lowvar", frames, 3)
    d, a = errors(poses, truth)
    assert np.mean(d[-60:]) < 0.05 and np.degrees(np.mean(a[-60:])) < 2.0, (np.mean(d[-60:]), np.mean(a[-60:]))


@pytest.mark.parametrize("option", [{"line_model": "hough"}, {"adaptive": True}, {"reset_from_any_feature": True}])
def test_model_options_track_a_standing_robot(option):
    frames, truth = record(4, 6.0)
    poses, _ = run("reset", frames, 4, LocalizationParams(**option))
    d, _ = errors(poses, truth)
    assert np.mean(d[-60:]) < 0.3


# -- kidnapping -----------------------------------------------------------------------------
def _recovery_time(poses, truth, t0_index: int, hz: float = 30.0) -> float:
    """Seconds after ``t0_index`` until the error stays below 0.5 m and 30 degrees for 1 s,
    modulo the field's symmetry: with goals of one colour nothing tells a kidnapped robot
    which half it was put in, so the mirrored pose is as correct as the true one."""
    d, a = errors(poses, truth, symmetric=True)
    good = (d < 0.5) & (a < math.radians(30))
    hold = int(hz)
    for i in range(t0_index, len(good) - hold):
        if good[i : i + hold].all():
            return (i - t0_index) / hz
    return (len(good) - t0_index) / hz  # not recovered: the horizon (censored)


@pytest.mark.slow(seconds=22)
def test_reset_and_amcl_recover_from_kidnapping_faster_than_mcl():
    times: dict[str, list[float]] = {"mcl": [], "amcl": [], "reset": []}
    for seed in range(20):
        rng = np.random.default_rng(100 + seed)
        target = (float(rng.uniform(-3.5, 3.5)), float(rng.uniform(-2.5, 2.5)), float(rng.uniform(-math.pi, math.pi)))
        ev = Kidnap(time=8.0, team=0, number=1, pose=target)
        frames, truth = record(seed, 30.0, playing=True, events=[ev])
        k = next(i for i, f in enumerate(frames) if f.time >= 8.0)
        for v in times:  # the papers' variants: without the safety net
            poses, _ = run(v, frames, seed, LocalizationParams(relocalize_seconds=0.0))
            times[v].append(_recovery_time(poses, truth, k))
    for v in ("amcl", "reset"):
        faster = sum(t < m for t, m in zip(times[v], times["mcl"], strict=True))
        slower = sum(t > m for t, m in zip(times[v], times["mcl"], strict=True))
        # one-sided sign test over the seeds where the two differ (p < 0.05)
        p = binomtest(faster, faster + slower, 0.5, alternative="greater").pvalue if faster + slower else 1.0
        assert np.mean(times[v]) < np.mean(times["mcl"]) and p < 0.05, (v, times[v], times["mcl"], p)


@pytest.fixture(scope="module")
def kidnapped_walks() -> list[tuple[int, list[SensorFrame], np.ndarray, int]]:
    """Eight 70 s recordings of a robot walking its loop, carried to a random pose at 8 s
    (seed, frames, true poses, index of the first frame after the kidnapping)."""
    out = []
    for seed in range(8):
        rng = np.random.default_rng(100 + seed)
        target = (float(rng.uniform(-3.5, 3.5)), float(rng.uniform(-2.5, 2.5)), float(rng.uniform(-math.pi, math.pi)))
        frames, truth = record(seed, 70.0, walk=True, playing=True, events=[Kidnap(8.0, 0, 1, target)])
        out.append((seed, frames, truth, next(i for i, f in enumerate(frames) if f.time >= 8.0)))
    return out


@pytest.mark.slow(seconds=5)
@pytest.mark.parametrize("variant", ["mcl", "lowvar", "amcl", "reset", "maturing"])
def test_no_variant_stays_lost_after_a_kidnapping(variant, kidnapped_walks):
    """While good percepts keep arriving, every variant finds the robot again (modulo the
    field's mirror symmetry) within the 62 s after the kidnapping in at least 7 of the 8
    recordings (measured: all 8 for every variant, at worst after 42 s; before the pose-jump and
    maturing changes of 2026-11-27 maturing stayed lost in about 1 of 32 runs over 4 filter
    seeds). Without the safety net (``relocalize_seconds = 0``, the papers' algorithms) mcl
    stayed lost in 4 of these 8 recordings, lowvar in 1 and maturing in 3."""
    lost = []
    for seed, frames, truth, k in kidnapped_walks:
        poses, loc = run(variant, frames, seed)
        horizon = (len(frames) - k) / 30.0
        t = _recovery_time(poses, truth, k)
        if t >= horizon - 1.0:
            lost.append((seed, loc.relocalizations))
    assert len(lost) <= 1, (variant, lost)
    if variant == "mcl":  # the contrast: the plain algorithm does stay lost
        lost = sum(
            _recovery_time(run(variant, frames, seed, LocalizationParams(relocalize_seconds=0.0))[0], truth, k)
            >= (len(frames) - k) / 30.0 - 1.0
            for seed, frames, truth, k in kidnapped_walks
        )
        assert lost >= 3, lost


@pytest.mark.slow(seconds=5)
def test_the_safety_net_seldom_fires_and_seldom_hurts_while_the_robot_is_localized():
    """False positives and noise (``harsh`` percepts) leave some observations unexplained while
    the estimate is right. Over 4 walking recordings and the 5 particle variants (20 runs of
    25 s), the net fires at most twice a run, and the mean error exceeds the papers' plain
    variant's by more than 0.1 m in at most 2 runs (measured: 1, reset; before 2026-11-27 it
    was maturing, pulled 4 m away after an injection)."""
    worse, fires = 0, []
    for seed in range(4):
        frames, truth = record(seed, 25.0, walk=True, playing=True, percepts="harsh")
        for v in ("mcl", "lowvar", "amcl", "reset", "maturing"):
            poses, loc = run(v, frames, seed)
            plain, _ = run(v, frames, seed, LocalizationParams(relocalize_seconds=0.0))
            d, _ = errors(poses, truth, symmetric=True)
            d0, _ = errors(plain, truth, symmetric=True)
            worse += int(np.mean(d[150:]) > np.mean(d0[150:]) + 0.1)
            fires.append(loc.relocalizations)
    assert max(fires) <= 2 and worse <= 2, (fires, worse)


@pytest.mark.parametrize("variant", ["reset", "maturing"])
def test_vision_poses_never_seed_the_estimates_mirror_image(variant):
    """With white goals a pose and its mirror image explain every percept alike, so vision
    proposes both. While the estimate is right, poses near its mirror image must not enter
    the cloud: there they would live on as a second mode, and a robot that sees little for a
    while (a goalkeeper facing its net) was measured flipping 180 degrees through them. A
    ``lost_spread`` near 0 keeps the robot "lost", so vision poses are injected at every
    resampling; none may land near the mirror image."""
    frames, truth = record(2, 6.0)
    # matured candidates must also beat the estimate, which a right estimate never lets them
    # (test_matured_candidates_must_beat_the_estimate): here that rule is off
    params = LocalizationParams(lost_spread=1e-6, maturing_beat_estimate=False)
    loc = make_localizer(variant, SPL, params, np.random.default_rng(4), player_number=1, players_per_team=1)
    assert isinstance(loc, ParticleFilter)
    injected, near_mirror, err = 0, 0, []
    for f, (tx, ty, _) in zip(frames, truth, strict=True):
        pose = loc.update(f)
        injected += loc.injected
        xy = loc.parts[: loc.n, :2]
        near_mirror += int(np.sum(np.hypot(xy[:, 0] + tx, xy[:, 1] + ty) < 1.0))
        err.append(math.hypot(pose.x - tx, pose.y - ty))
    assert injected > 100, injected  # vision poses did come in
    assert near_mirror == 0, near_mirror
    assert np.mean(err) < 0.3, np.mean(err)


def test_matured_candidates_must_beat_the_estimate():
    """A matured candidate replaces particles only when it explained the frames clearly better
    than the estimate (``maturing_margin``). A robot whose estimate is right, kept "lost" so
    that every resampling asks for poses, receives none: no candidate beats a right estimate,
    and the estimate stays right. With the rule off the same frames bring in hundreds."""
    frames, truth = record(2, 6.0)
    for beat in (True, False):
        params = LocalizationParams(lost_spread=1e-6, maturing_beat_estimate=beat)
        loc = make_localizer("maturing", SPL, params, np.random.default_rng(4), player_number=1, players_per_team=1)
        assert isinstance(loc, ParticleFilter)
        injected, err = 0, []
        for f, (tx, ty, _) in zip(frames, truth, strict=True):
            pose = loc.update(f)
            injected += loc.injected
            err.append(math.hypot(pose.x - tx, pose.y - ty))
        if beat:
            assert injected == 0, injected
            assert np.mean(err) < 0.3, np.mean(err)
        else:
            assert injected > 100, injected


def test_matured_injection_needs_the_margin():
    """:func:`maturing.inject_matured_nb` takes only candidates old enough whose mean advantage
    over the estimate exceeds the margin; with a NaN margin (rule off) age alone decides."""
    from cognition.localization.maturing import inject_matured_nb

    cand = np.array([[1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [3.0, 0.0, 0.0], [4.0, 0.0, 0.0]])
    ages = np.array([9, 9, 3, 9], dtype=np.int64)
    adv = np.array([[6.0, 10.0], [4.0, 10.0], [50.0, 10.0], [-1.0, 10.0]])  # means 0.6, 0.4, 5, -0.1
    state = np.array([7], dtype=np.uint64)
    parts = np.zeros((40, 3))
    got = inject_matured_nb(parts, np.arange(40), cand, ages, adv, 4, 7, 0.5, state)
    assert got == 40 and np.all(np.abs(parts[:, 0] - 1.0) < 0.3)  # only the first: old enough and 0.6 > 0.5
    assert inject_matured_nb(parts, np.arange(40), cand, ages, adv, 4, 7, 0.7, state) == 0
    got = inject_matured_nb(parts, np.arange(40), cand, ages, adv, 4, 7, math.nan, state)
    assert got == 40 and set(np.round(parts[:, 0]).astype(int)) == {1, 2, 4}  # every old candidate


def test_mirror_guard_keeps_poses_beside_an_estimate_near_the_centre():
    """Near the centre spot the estimate and its mirror image are close in position, so the
    guard compares whole poses (heading at ``MIRROR_HEADING_SCALE`` m/rad). A pose beside the
    estimate facing its way stays, and so does one at the mirror image's position facing the
    estimate's way (a guard by position alone turned it into a pose beside the estimate facing
    the other way: a robot at kickoff flipped by 180 degrees). A pose beside the estimate but
    turned by 180 degrees, and a pose at the mirror image itself, are mirrored onto the
    estimate's side."""
    from cognition.localization.frame_step import away_from_mirror_nb

    x, y, th = 0.5, -0.2, 0.3  # the mirror image (-0.5, 0.2, 0.3 + pi) is 1.08 m away in position
    poses = np.array([
        [0.6, -0.1, 0.4],  # beside the estimate, facing its way
        [-0.55, 0.25, 0.4],  # at the mirror image's position, facing the estimate's way
        [0.45, -0.25, th + math.pi - 0.1],  # beside the estimate, turned by 180 degrees
        [-0.55, 0.25, th + math.pi + 0.2 - 2.0 * math.pi],  # at the mirror image
        [3.0, 1.0, 0.0],  # far from both
    ])  # fmt: skip
    away_from_mirror_nb(poses, np.arange(5), x, y, th)
    np.testing.assert_allclose(poses[0], [0.6, -0.1, 0.4])
    np.testing.assert_allclose(poses[1], [-0.55, 0.25, 0.4])
    np.testing.assert_allclose(poses[2], [-0.45, 0.25, th - 0.1], atol=1e-12)
    np.testing.assert_allclose(poses[3], [0.55, -0.25, th + 0.2], atol=1e-12)
    np.testing.assert_allclose(poses[4], [3.0, 1.0, 0.0])


def test_mirror_guard_keeps_the_twin_nearer_the_estimate():
    """Over random estimates and poses: each pose comes out as itself or its mirror image
    (-x, -y, theta + pi), which explains the percepts alike; it is mirrored exactly when the
    mirror image lies within ``MIRROR_RADIUS`` of the estimate and nearer to it (distance over
    position and heading), so no pose is left nearer the estimate's mirror image within it."""
    from cognition.localization.frame_step import MIRROR_HEADING_SCALE, MIRROR_RADIUS, away_from_mirror_nb

    rng = np.random.default_rng(3)

    def dist(p: np.ndarray, q: tuple[float, float, float]) -> np.ndarray:
        dth = (p[:, 2] - q[2] + math.pi) % (2.0 * math.pi) - math.pi
        return np.sqrt((p[:, 0] - q[0]) ** 2 + (p[:, 1] - q[1]) ** 2 + (MIRROR_HEADING_SCALE * dth) ** 2)

    mirrored_count = 0
    for _ in range(50):
        est = (rng.uniform(-2.0, 2.0), rng.uniform(-1.5, 1.5), rng.uniform(-math.pi, math.pi))
        mirror = (-est[0], -est[1], est[2] + math.pi)
        poses = np.column_stack([rng.uniform(-3, 3, 200), rng.uniform(-2, 2, 200), rng.uniform(-math.pi, math.pi, 200)])
        before = poses.copy()
        away_from_mirror_nb(poses, np.arange(200), *est)
        turned = (before[:, 2] + 2.0 * math.pi) % (2.0 * math.pi) - math.pi
        flipped = np.column_stack([-before[:, 0], -before[:, 1], turned])
        expect = (dist(before, mirror) < MIRROR_RADIUS) & (dist(before, mirror) < dist(before, est))
        np.testing.assert_allclose(poses[expect], flipped[expect], atol=1e-12)
        np.testing.assert_array_equal(poses[~expect], before[~expect])
        assert np.all(dist(poses[expect], est) < MIRROR_RADIUS)
        assert not np.any((dist(poses, mirror) < MIRROR_RADIUS) & (dist(poses, mirror) < dist(poses, est) - 1e-9))
        mirrored_count += int(expect.sum())
    assert 300 < mirrored_count < 5000  # the rule acts, but not on most poses


def _pose_of(parts: np.ndarray, w: np.ndarray, prev: tuple[float, float, float]) -> np.ndarray:
    """:func:`kernels.pose_nb` with the default parameters (0.4 m cluster, jump weight 0.2)."""
    from cognition.localization import kernels

    p = LocalizationParams()
    out = np.zeros(14)
    prev_arr = np.array([*prev, 1.0])
    kernels.pose_nb(parts, len(w), w / w.sum(), prev_arr, p.cluster_radius, 0.5, 0.5, p.jump_weight, out)
    return out


def test_the_pose_jumps_only_to_a_heavier_cluster():
    """CMU III.E lets the pose jump to the heaviest particle when the cluster at the previous
    estimate is light. A lone heavy particle (one injected pose that explained a frame) whose
    own cluster weighs less than the cloud at the estimate must not take the estimate away;
    a heavier cluster elsewhere must."""
    rng = np.random.default_rng(0)
    cloud = np.column_stack([rng.normal(1.0, 0.7, 190), rng.normal(2.0, 0.7, 190), np.zeros(190)])
    far = np.array([[-3.0, -1.0, 2.0]] * 10) + rng.normal(0.0, 0.02, (10, 3))
    parts = np.ascontiguousarray(np.vstack([cloud, far]))
    w = np.r_[np.full(190, 1.0), np.full(9, 0.2), [3.0]]  # the heaviest particle is far away, its cluster light
    out = _pose_of(parts, w, (1.0, 2.0, 0.0))
    assert out[4] < 0.2, out[4]  # the cluster at the estimate is light: the jump rule is in play
    assert math.hypot(out[0] - 1.0, out[1] - 2.0) < 0.5, out[:3]
    assert out[4] * w.sum() > w[190:].sum()  # and it still outweighs the far cluster
    w[190:] = 20.0  # now the far cluster outweighs the cloud's
    out = _pose_of(parts, w, (1.0, 2.0, 0.0))
    assert math.hypot(out[0] + 3.0, out[1] + 1.0) < 0.1, out[:3]


def test_candidates_mature_only_on_frames_with_a_landmark():
    """Darmstadt VI: a candidate matures on consistent observations of different features.
    A line fits many poses, so a frame that shows only lines keeps the candidates that fit it
    but adds no age; in image matches, candidates aged on line-only frames took accurate
    robots away. Over a walking recording, the oldest candidate never ages on a line-only
    frame, and candidates do mature on the others."""
    from cognition.localization.sensor import T, pack_observations

    frames, _ = record(3, 12.0, walk=True, playing=True)
    loc = make_localizer("maturing", SPL, rng=np.random.default_rng(1), player_number=1, players_per_team=1)
    assert isinstance(loc, ParticleFilter)
    line_only, aged, peak = 0, 0, 0
    for f in frames:
        before = loc.candidate_counts.max(initial=0)
        loc.update(f)
        after = loc.candidate_counts.max(initial=0)
        peak = max(peak, after)
        if f.percepts is None or len(f.percepts) == 0:
            continue
        types = pack_observations(f.percepts, loc._table)[:, 0]
        if np.all(types == T.LINE):
            line_only += before > 0
            assert after <= before, (f.time, before, after)
        aged += after > before
    assert line_only >= 10 and aged >= 20, (line_only, aged)
    assert peak >= LocalizationParams().maturing_threshold, peak


# -- game-controller events -----------------------------------------------------------------
def _frame(
    t: float, state=GameStateId.PLAYING, first_half=1, penalty=0, picked=False, odo=(0.0, 0.0, 0.0), percepts=None
):
    players = tuple(RobotInfo(penalty=penalty if i == 0 else 0) for i in range(7))
    game = GameControlData(
        state=state, first_half=first_half, teams=(TeamInfo(team_number=1, players=players), TeamInfo(team_number=2))
    )
    return SensorFrame(
        time=t, frame_index=int(t * 30), team_number=1, player_number=1, odometry=OdometryReading(*odo),
        head=HeadState(),
        game=game, picked_up=picked, percepts=percepts,
    )  # fmt: skip


@pytest.mark.parametrize("variant", ["mcl", "amcl", "reset", "maturing"])
def test_side_switch_mirrors_the_particles(variant):
    loc = make_localizer(variant, SPL, rng=np.random.default_rng(0), player_number=1, players_per_team=1)
    loc.update(_frame(0.0))
    before = loc.parts[: loc.n].copy()
    loc.update(_frame(0.1, first_half=0))
    after = loc.parts[: loc.n]
    assert np.allclose(after[:, :2], -before[:, :2], atol=0.05)
    dth = (after[:, 2] - before[:, 2]) % (2 * math.pi)
    assert np.allclose(dth, math.pi, atol=0.05)


def test_pickup_in_ready_moves_particles_to_placements_and_penalty_to_return_spots():
    loc = make_localizer("lowvar", SPL, rng=np.random.default_rng(1), player_number=1, players_per_team=1)
    loc.set_uniform()
    loc.update(_frame(0.0, state=GameStateId.READY))
    loc.update(_frame(0.1, state=GameStateId.READY, picked=True))
    xy = loc.parts[: loc.n, :2]
    near_keeper = np.hypot(xy[:, 0] + SPL.half_length - 0.25, xy[:, 1]) < 0.6
    assert near_keeper.mean() > 0.4  # the keeper's kickoff spot is one of two candidates
    assert np.all(xy[:, 0] < 0.0)
    for rule in ("spl2025", "spl2010"):
        loc = make_localizer("reset", SPL, LocalizationParams(return_rule=rule), np.random.default_rng(2))
        loc.update(_frame(0.0))
        loc.update(_frame(0.1, penalty=2))
        spots = return_poses(SPL, rule)
        d = np.min(
            np.hypot(loc.parts[: loc.n, None, 0] - spots[None, :, 0], loc.parts[: loc.n, None, 1] - spots[None, :, 1]),
            axis=1,
        )
        assert np.all(d < 0.8)
        sides = np.sign(loc.parts[: loc.n, 1])
        assert 0.3 < np.mean(sides > 0) < 0.7  # both return spots are populated


@pytest.mark.parametrize("variant", ["lowvar", "reset", "maturing"])
def test_a_penalty_cleared_at_half_time_puts_the_robot_on_its_touchline_spot(variant):
    """The referee clears every penalty when the second half starts and lines all robots up on
    their touchline spots in INITIAL. A robot penalised at half time must then believe it
    stands on its own spot, not at a penalty return spot (one of which lies on the other
    touchline, facing the other way); a return during play still uses the return spots."""
    from cognition.localization.places import placement_poses

    loc = make_localizer(variant, SPL, rng=np.random.default_rng(4), player_number=1, players_per_team=5)
    loc.update(_frame(0.0))
    loc.update(_frame(0.1, penalty=2, picked=True))  # penalised in the first half
    loc.update(_frame(0.2, state=GameStateId.FINISHED, penalty=2, picked=True))
    loc.update(_frame(0.3, state=GameStateId.INITIAL, first_half=0, penalty=0, picked=True))
    spot = placement_poses(SPL, 1, 5, GameStateId.INITIAL, False)[0]
    parts = loc.parts[: loc.n]
    assert np.all(np.hypot(parts[:, 0] - spot[0], parts[:, 1] - spot[1]) < 0.8)
    assert np.all(np.abs((parts[:, 2] - spot[2] + math.pi) % (2 * math.pi) - math.pi) < 0.6)
    pose = loc.update(_frame(0.4, state=GameStateId.INITIAL, first_half=0, picked=False))
    assert math.hypot(pose.x - spot[0], pose.y - spot[1]) < 0.3
    loc.update(_frame(0.5, first_half=0, penalty=2, picked=True))  # penalised in play, then back
    loc.update(_frame(0.6, first_half=0, penalty=0, picked=True))
    spots = return_poses(SPL, loc.params.return_rule)
    xy = loc.parts[: loc.n, None, :2]
    assert np.all(np.min(np.hypot(xy[..., 0] - spots[None, :, 0], xy[..., 1] - spots[None, :, 1]), axis=1) < 0.8)


# -- robustness -----------------------------------------------------------------------------
@pytest.mark.parametrize("variant", VARIANTS)
def test_a_minute_without_percepts_stays_finite(variant):
    loc = make_localizer(variant, SPL, rng=np.random.default_rng(0), player_number=1, players_per_team=1)
    truth = (0.0, 0.0, 0.0) if variant == "oracle" else None
    for i in range(1800):
        pose = loc.update(_frame(i / 30.0, odo=(0.005, 0.001, 0.01), percepts=Percepts.empty(i / 30.0)), truth)
    assert math.isfinite(pose.x) and math.isfinite(pose.y) and math.isfinite(pose.theta)
    assert np.all(np.isfinite(pose.covariance))
    if isinstance(loc, ParticleFilter):
        assert loc.n >= 1 and np.all(np.isfinite(loc.parts[: loc.n])) and abs(loc.w[: loc.n].sum() - 1) < 1e-9


def test_observations_no_particle_explains_leave_finite_weights():
    frames, _ = record(5, 2.0)
    loc = make_localizer("amcl", SPL, rng=np.random.default_rng(0), player_number=1, players_per_team=1)
    for f in frames:
        loc.update(f)
    seen = [f for f in frames if f.percepts is not None and len(f.percepts) > 0][-1]
    rows = np.array(seen.percepts.rows)
    rows[:, 0] += 500.0  # everything 500 m away
    offsets = np.r_[0, np.cumsum(np.bincount(seen.percepts.kinds, minlength=8))]
    far = Percepts(frames[-1].time, rows, offsets, None, None)
    pose = loc.update(replace(frames[-1], percepts=far))
    assert np.all(np.isfinite(loc.w[: loc.n])) and math.isfinite(pose.x) and math.isfinite(pose.theta)


def test_same_seed_same_estimates():
    frames, _ = record(6, 4.0)
    a, _ = run("reset", frames, 9)
    b, _ = run("reset", frames, 9)
    assert [p.pose for p in a] == [p.pose for p in b]


def test_bad_input_is_a_clear_error():
    with pytest.raises(ValueError, match="unknown localization variant"):
        make_localizer("kalman", SPL)
    with pytest.raises(ValueError, match="unknown LocalizationParams key"):
        LocalizationParams.from_mapping({"particle_count": 10})
    with pytest.raises(ValueError, match="particles"):
        LocalizationParams(particles=0)
    with pytest.raises(ValueError, match="line_model"):
        LocalizationParams(line_model="ransac")
    with pytest.raises(ValueError, match="oracle"):
        make_localizer("oracle", SPL).update(_frame(0.0))


def test_pose_is_one_mode_of_a_bimodal_cloud_and_lost_tracks_the_spread():
    loc = make_localizer("lowvar", SPL, rng=np.random.default_rng(3), player_number=1, players_per_team=1)
    assert isinstance(loc, ParticleFilter)
    loc.set_particles_around(np.array([[2.0, 1.0, 0.5], [-2.0, -1.0, 0.5 - math.pi]]), sigma_xy=0.05)
    pose = loc.update(_frame(0.0))
    modes = np.array([[2.0, 1.0], [-2.0, -1.0]])
    assert np.min(np.hypot(modes[:, 0] - pose.x, modes[:, 1] - pose.y)) < 0.1  # not the mean (0, 0)
    assert pose.lost  # two modes 4.5 m apart
    loc.set_particles_around(np.array([[2.0, 1.0, 0.5]]), sigma_xy=0.05)
    pose = loc.update(_frame(0.1))
    assert not pose.lost and math.hypot(pose.x - 2.0, pose.y - 1.0) < 0.05
    assert pose.particles.shape == (loc.n, 3) and abs(pose.weights.sum() - 1.0) < 1e-9
    assert pose.covariance.shape == (3, 3) and pose.covariance[0, 0] < 0.01
