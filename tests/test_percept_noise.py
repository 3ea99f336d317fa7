"""Statistics of the percept model over many seeded images: angular sigmas, detection rates."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from cognition.field import make_field
from cognition.percepts import measurement_covariance
from teamsim.match import MatchConfig
from teamsim.params import from_mapping
from teamsim.percept_params import Detection, PerceptParams
from teamsim.percepts import PerceptSynthesizer, Scene, SceneRobot

FIELD = make_field("spl2025")
BALL_R = FIELD.dims.ball_diameter / 2
# every visible feature detected, no false positives: isolates the angular noise
ALWAYS = replace(
    PerceptParams(),
    **{k: Detection(1.0, 30.0, 30.0) for k in ("post", "cross", "line", "circle", "mark", "ball", "robot", "pole")},
    head_speed_detection=0.0,
    walking_detection=1.0,
    ball_speed_detection=0.0,
    phantom_crossing_rate=0.0,
    phantom_mark_rate=0.0,
    background_post_rate=0.0,
    feet_ball_rate=0.0,
    false_ball_rate=0.0,
    crossing_confusion=0.0,
)

CASES = {
    "standing": {},
    "head moving": {"yaw_rate": 2.0, "pitch_rate": -1.5},
    "walking": {"walking": True},
    "walking and head moving": {"walking": True, "yaw_rate": -1.0, "pitch_rate": 0.8},
}


def _angle_errors(params: PerceptParams, robot: SceneRobot, ball: tuple[float, float], n: int, seed: int = 1):
    """Angular errors (alpha, beta) of the ball and of the opponent penalty mark over ``n`` images."""
    syn = PerceptSynthesizer(FIELD, params, np.random.default_rng(seed))
    scene = Scene.build([robot], ball, 5)
    errs = np.full((n, 4), np.nan)
    sig = None
    for k in range(n):
        p = syn.synthesize(scene)[robot.number - 1]
        cam = p.camera
        cx, cy, h = cam.position
        c, s = math.cos(robot.theta), math.sin(robot.theta)
        truth = {"ball": (ball, BALL_R), "mark": ((3.2, 0.0), 0.0)}
        for j, (name, table) in enumerate((("ball", p.ball), ("mark", p.penalty_marks))):
            rows = [i for i, t in enumerate(table.truth) if t == (0 if name == "ball" else 1)]
            if not rows:
                continue
            (wx, wy), z = truth[name]
            tx, ty = c * (wx - robot.x) + s * (wy - robot.y), -s * (wx - robot.x) + c * (wy - robot.y)
            mx, my = table.xy[rows[0]]
            a_true = math.atan2(h - z, math.hypot(tx - cx, ty - cy))
            a_meas = math.atan2(h - z, math.hypot(mx - cx, my - cy))
            b_true = math.atan2(ty - cy, tx - cx)
            b_meas = math.atan2(my - cy, mx - cx)
            errs[k, 2 * j] = a_meas - a_true
            errs[k, 2 * j + 1] = math.remainder(b_meas - b_true, 2 * math.pi)
            sig = (table.sigma_alpha[rows[0]], table.sigma_beta[rows[0]])
    return errs, sig


@pytest.mark.parametrize("case", sorted(CASES))
def test_empirical_angular_sigmas_match_the_model(case: str) -> None:
    kw = CASES[case]
    robot = SceneRobot(0, 2, 2.0, 0.0, 0.0, head_pitch=0.25, **kw)  # type: ignore[arg-type]
    errs, reported = _angle_errors(ALWAYS, robot, (3.5, 0.4), 4000)
    sa, sb = ALWAYS.sigmas(kw.get("pitch_rate", 0.0), kw.get("yaw_rate", 0.0), kw.get("walking", False))
    assert reported == pytest.approx((sa, sb), rel=1e-12)  # adaptive: the percept reports the true model
    for col, expected in ((0, sa), (1, sb), (2, sa), (3, sb)):
        e = errs[:, col]
        assert np.isfinite(e).mean() > 0.998  # a point measured above the horizon cannot be projected
        e = e[np.isfinite(e)]
        assert abs(np.mean(e)) < 4 * expected / math.sqrt(len(e))
        assert np.std(e) == pytest.approx(expected, rel=0.05), (case, col)
    # the image-wide share of the error correlates the ball's and the post's errors (fraction 0.5)
    both = np.isfinite(errs).all(axis=1)
    corr = np.corrcoef(errs[both, 0], errs[both, 2])[0, 1]
    assert corr == pytest.approx(ALWAYS.shared_noise_fraction, abs=0.06)


def test_head_motion_and_walking_increase_the_sigmas() -> None:
    p = PerceptParams()
    still = p.sigmas(0.0, 0.0, False)
    assert still == (p.sigma_alpha_base, p.sigma_beta_base)
    moving = p.sigmas(2.0, 1.0, False)
    assert moving[0] == pytest.approx(p.sigma_alpha_base + p.c_tilt * 2.0)
    assert moving[1] == pytest.approx(p.sigma_beta_base + p.c_pan * 1.0)
    walking = p.sigmas(0.0, 0.0, True)
    assert walking == (p.sigma_alpha_base + p.sigma_alpha_moving, p.sigma_beta_base + p.sigma_beta_moving)


def test_distance_error_grows_with_distance() -> None:
    robot = SceneRobot(0, 2, 0.0, 0.0, 0.0, head_pitch=0.1, walking=True)
    spreads = []
    for d in (1.5, 3.0, 4.5):
        syn = PerceptSynthesizer(FIELD, ALWAYS, np.random.default_rng(2))
        scene = Scene.build([robot], (d, 0.0), 5)
        xs = [p.ball.x[0] for p in (syn.synthesize(scene)[1] for _ in range(1500)) if len(p.ball)]
        spreads.append(np.std(xs))
    assert spreads[0] < spreads[1] < spreads[2]
    assert spreads[2] > 3 * spreads[0]


def test_fixed_reported_sigma_does_not_change_the_noise() -> None:
    robot = SceneRobot(0, 2, 2.0, 0.0, 0.0, head_pitch=0.25, walking=True)
    fixed = replace(ALWAYS, reported_sigma="fixed", fixed_sigma=math.radians(15.0))
    e_adaptive, _ = _angle_errors(ALWAYS, robot, (3.5, 0.4), 1000, seed=5)
    e_fixed, reported = _angle_errors(fixed, robot, (3.5, 0.4), 1000, seed=5)
    assert reported == pytest.approx((math.radians(15.0), math.radians(15.0)))
    assert np.array_equal(e_adaptive, e_fixed, equal_nan=True)


def test_ideal_preset_has_zero_error_and_zero_sigma() -> None:
    robot = SceneRobot(0, 2, 2.0, 0.0, 0.0, head_pitch=0.25, walking=True, yaw_rate=3.0, pitch_rate=2.0)
    errs, reported = _angle_errors(PerceptParams.preset("ideal"), robot, (3.5, 0.4), 50)
    assert np.all(np.abs(errs) < 1e-12)
    assert reported == (0.0, 0.0)


def test_covariance_follows_darmstadt_eq_8_and_12() -> None:
    h, sa, sb = 0.5, math.radians(3.0), math.radians(2.0)
    d = 2.0
    xx, xy, yy = measurement_covariance(d, 0.0, 0.0, 0.0, h, sa, sb)
    alpha = math.atan2(h, d)
    assert math.sqrt(xx) == pytest.approx(h / math.tan(alpha) - h / math.tan(alpha + sa))
    assert math.sqrt(yy) == pytest.approx(math.tan(sb) * d)
    assert xy == pytest.approx(0.0, abs=1e-15)
    # rotated by the bearing (eqs. 14-15): at 90 degrees the roles swap
    xx2, xy2, yy2 = measurement_covariance(0.0, d, 0.0, 0.0, h, sa, sb)
    assert (xx2, yy2) == pytest.approx((yy, xx))
    assert xy2 == pytest.approx(0.0, abs=1e-12)


def _rate(params: PerceptParams, robot: SceneRobot, ball, n: int = 4000, seed: int = 4) -> float:
    syn = PerceptSynthesizer(FIELD, params, np.random.default_rng(seed))
    scene = Scene.build([robot], ball, 5)
    hits = 0
    for _ in range(n):
        p = syn.synthesize(scene)[robot.number - 1]
        hits += int(np.any(p.ball.truth == 0))
    return hits / n


@pytest.mark.parametrize(
    ("distance", "kw", "ball_speed"),
    [
        (2.0, {}, 0.0),
        (5.0, {}, 0.0),  # between full_range 4.5 and max_range 5.5: linear fall-off
        (2.0, {"walking": True, "yaw_rate": 2.0}, 0.0),
        (2.0, {}, 2.0),
    ],
)
def test_ball_detection_rate_matches_the_model(distance: float, kw: dict, ball_speed: float) -> None:
    p = PerceptParams()
    robot = SceneRobot(0, 2, 0.0, 0.0, 0.0, head_pitch=0.1 if distance < 3 else -0.05, **kw)
    got = _rate(p, robot, (distance, 0.0, ball_speed, 0.0))
    ground = math.hypot(distance - 0.0587 * math.cos(robot.head_pitch), 0.0)  # optical centre is ahead of the neck
    expected = p.ball.probability(ground)
    expected *= p.motion_factor(robot.pitch_rate, robot.yaw_rate, robot.walking)
    expected /= 1.0 + p.ball_speed_detection * ball_speed
    assert got == pytest.approx(expected, abs=0.03)


def test_post_and_crossing_detection_rates_match_the_model() -> None:
    p = PerceptParams()
    syn = PerceptSynthesizer(FIELD, p, np.random.default_rng(9))
    robot = SceneRobot(0, 2, 1.0, 0.0, 0.0, head_pitch=0.0)
    scene = Scene.build([robot], None, 5)
    corner = next(i for i, c in enumerate(FIELD.crossings) if (c.x, c.y) == (3.9, 1.1))
    post_hits = cross_hits = 0
    n = 4000
    for _ in range(n):
        per = syn.synthesize(scene)[1]
        post_hits += int(np.any(per.posts.truth == 2))
        cross_hits += int(np.any(per.crossings.truth == corner))
    cam_x = 1.0 + 0.05871
    assert post_hits / n == pytest.approx(p.post.probability(math.hypot(4.5 - cam_x, 0.8)), abs=0.03)
    # the goal-area corner (3.9, 1.1) is seen as an L or, confused, as a T: detection is what counts
    assert cross_hits / n == pytest.approx(p.cross.probability(math.hypot(3.9 - cam_x, 1.1)), abs=0.03)


def test_crossing_confusion_rate() -> None:
    p = replace(ALWAYS, crossing_confusion=0.2)
    syn = PerceptSynthesizer(FIELD, p, np.random.default_rng(11))
    scene = Scene.build([SceneRobot(0, 2, 1.0, 0.0, 0.0)], None, 5)
    wrong = total = 0
    for _ in range(3000):
        per = syn.synthesize(scene)[1]
        for t, k in zip(per.crossings.truth, per.crossings.subtype, strict=True):
            total += 1
            wrong += int(FIELD.crossing_kinds[t] != k)
    assert wrong / total == pytest.approx(0.2, abs=0.02)


def test_bad_parameters_are_clear_errors() -> None:
    with pytest.raises(ValueError, match="unknown PerceptParams preset 'noisy'"):
        PerceptParams.preset("noisy")
    with pytest.raises(ValueError, match="sigma_alpha_base"):
        PerceptParams(sigma_alpha_base=-0.01)
    with pytest.raises(ValueError, match="rate"):
        Detection(rate=1.5)
    with pytest.raises(ValueError, match="max_range"):
        Detection(1.0, 5.0, 4.0)
    with pytest.raises(ValueError, match="reported_sigma"):
        PerceptParams(reported_sigma="sometimes")
    with pytest.raises(ValueError, match="unknown PerceptParams key"):
        from_mapping(PerceptParams, {"sigma_gamma": 1.0})
    with pytest.raises(ValueError, match=r"unknown MatchConfig\.percepts preset"):
        MatchConfig.from_mapping({"percepts": "noisy"})
    with pytest.raises(ValueError, match="width"):
        MatchConfig.from_mapping({"camera": {"upper": {"width": 0}}})
    with pytest.raises(ValueError, match="observation"):
        MatchConfig(observation="telepathy")


def test_presets_from_mappings_keep_the_preset_values() -> None:
    cfg = MatchConfig.from_mapping({"percepts": {"preset": "harsh", "ball": {"rate": 0.5}, "latency": 0.0}})
    harsh = PerceptParams.preset("harsh")
    assert cfg.percepts.ball == Detection(0.5, harsh.ball.full_range, harsh.ball.max_range)
    assert cfg.percepts.latency == 0.0 and cfg.percepts.c_tilt == harsh.c_tilt
    assert MatchConfig(percepts="ideal").percepts == PerceptParams.preset("ideal")
