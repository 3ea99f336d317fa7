"""Localization in matches: scripted players on the cognition stack, their errors, the CLI flag, the particle view."""

from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from cognition.behaviors.head_control import HeadParams
from cognition.behaviors.team_play import ScriptedBrain
from cognition.field import make_colour_scheme
from cognition.localization import VARIANTS, LocalizationParams
from cognition.oracle import OracleInput, OraclePose
from cognition.pipeline import CognitionConfig
from cognition.representations import RobotPose, SensorFrame
from cognition.worldmodel.beliefs import Beliefs
from teamsim.brains import LocalizationErrors, default_brains, scripted_brains
from teamsim.camera_views import belief_overlay
from teamsim.cli import main
from teamsim.match import Match, MatchConfig
from teamsim.placement import world_to_team
from teamsim.referee import RefereeParams
from teamsim.render import Belief, TopDownRenderer


def _particles_available() -> bool:
    try:
        from cognition.localization.particle_filter import ParticleFilter  # noqa: F401
    except ImportError:
        return False
    return True


PARTICLE_VARIANTS = [v for v in VARIANTS if v not in ("odometry", "oracle")]
needs_particles = pytest.mark.skipif(not _particles_available(), reason="particle filter not written yet")


def _config(localization: str | None, **kwargs: object) -> MatchConfig:
    """5 v 5 scripted team play with a short READY phase: robots walk from about 2 s and play from 17 s."""
    referee = RefereeParams(half_seconds=60.0, ready_seconds=10.0)
    cognition = None if localization is None else CognitionConfig(localization=localization)
    return replace(MatchConfig(referee=referee, cognition=cognition), **kwargs)  # type: ignore[arg-type]


def _true_team_pose(match: Match, index: int) -> tuple[float, float, float]:
    robot = match.world.robots[index]
    return world_to_team(match.referee.sign(robot.team), *robot.pose)


@pytest.fixture(scope="module")
def runs() -> dict[str, Match]:
    out = {}
    for variant in ("odometry", "oracle"):
        m = Match(_config(variant))
        m.run(until=20.0)
        out[variant] = m
    return out


# -- (a) matches with players on the cognition stack -----------------------------------------
@pytest.mark.parametrize("variant", ["odometry", "oracle"])
def test_players_on_the_cognition_stack_report_poses_and_errors(runs: dict[str, Match], variant: str) -> None:
    m = runs[variant]
    assert m.referee.counters.kickoffs  # the game reached PLAYING, robots walked on their estimates
    for i, brain in enumerate(m.brains):
        assert isinstance(brain, ScriptedBrain) and brain.cognition.beliefs == "cognition"
        assert brain.cognition.localization == variant
        assert isinstance(brain.pose, RobotPose) and brain.pose.variant == variant
        assert brain.pose is brain.provider.localizer.pose  # type: ignore[union-attr]
        assert brain.beliefs is not None and brain.beliefs.pose is brain.pose  # the behaviour's pose
        truth = _true_team_pose(m, i)  # now, up to 1/30 s after the estimate's frame
        err = math.hypot(brain.pose.x - truth[0], brain.pose.y - truth[1])
        assert err < (0.02 if variant == "oracle" else 1.5)
    loc = m.summary().localization
    assert loc is not None and loc.variant == variant
    assert loc.frames == m.frames * len(m.world.robots)  # nobody was penalised
    if variant == "oracle":
        assert loc.position_error_mean < 1e-6 and loc.position_error_p90 < 1e-6
        assert loc.heading_error_mean < 1e-6 and loc.lost_share == 0.0
    else:
        assert 0.0 < loc.position_error_mean <= loc.position_error_p90 < 1.5
        assert math.isfinite(loc.heading_error_mean) and 0.0 < loc.heading_error_mean < 30.0
        assert loc.lost_share == 0.0  # dead reckoning never claims to be lost
    assert m.summary().deterministic_dict()["localization"] == loc.to_dict()
    assert "localization   " + variant in m.summary().format()


def test_default_match_has_no_localization_report() -> None:
    m = Match(_config(None))
    s = m.run(until=3.0)
    assert s.localization is None and "localization" not in s.format()
    for brain in m.brains:  # scripted players on truth beliefs: no estimate to report
        assert isinstance(brain, ScriptedBrain) and brain.cognition.beliefs == "truth" and brain.pose is None
        assert brain.beliefs is not None and brain.beliefs.source == "truth"


class _SpyBrain(ScriptedBrain):
    """Records the oracle input of every frame, the truth handed to the localizer, the
    localizer's estimates and the own pose the decisions use."""

    def reset(self, context):  # type: ignore[no-untyped-def]
        super().reset(context)
        self.oracles: list[OracleInput | None] = []
        self.truths: list[tuple[float, float, float] | None] = []
        self.estimates: list[tuple[float, float, float]] = []
        self.used: list[tuple[float, float, float]] = []
        localizer = self.provider.localizer  # type: ignore[union-attr]
        update = localizer.update

        def spy(frame: SensorFrame, truth: tuple[float, float, float] | None = None, **kw: bool) -> RobotPose:
            self.truths.append(truth)
            pose = update(frame, truth, **kw)
            self.estimates.append(pose.pose)
            return pose

        localizer.update = spy  # type: ignore[method-assign]

    def begin(self, frame, oracle):  # type: ignore[no-untyped-def]
        self.oracles.append(oracle)
        super().begin(frame, oracle)

    def _transition(self, b: Beliefs) -> str:
        self.used.append(b.pose.pose)
        return super()._transition(b)


@pytest.mark.parametrize("variant", ["odometry", "oracle"])
def test_brain_acts_on_its_estimate_and_only_oracle_gets_truth(variant: str) -> None:
    m = Match(
        _config(variant, players_per_team=2),
        brains=lambda team, number: _SpyBrain(CognitionConfig(localization=variant)),
    )
    m.run(until=12.0)
    for brain in m.brains:
        assert isinstance(brain, _SpyBrain) and brain.uses_oracle == (variant == "oracle")
        assert len(brain.oracles) == len(brain.truths) == len(brain.used) == m.frames  # every frame
        assert brain.used == brain.estimates  # decisions read the estimate ...
        if variant == "oracle":
            assert all(o is not None for o in brain.oracles)
            truth = [(o.self_pose.x, o.self_pose.y, o.self_pose.theta) for o in brain.oracles]  # type: ignore[union-attr]
            assert brain.truths == truth and brain.estimates == truth  # the oracle variant's pose is the truth
        else:
            assert all(o is None for o in brain.oracles)  # ... no ground truth reaches the brain ...
            assert all(t is None for t in brain.truths)  # ... nor its localizer
    loc = m.localization_errors.summary()
    assert loc is not None
    if variant == "oracle":
        assert loc.position_error_p90 < 1e-9 and loc.heading_error_mean < 1e-6
    else:
        assert loc.position_error_p90 > 1e-3  # dead reckoning drifts away from the truth


def test_head_scans_every_few_seconds_and_while_lost() -> None:
    m = Match(_config("odometry", players_per_team=1))
    robot = m.world.robots[0]
    brain = m.brains[0]
    assert isinstance(brain, ScriptedBrain)
    yaws, states = [], []
    while m.time < 16.0:
        m.step()
        yaws.append(robot.head.yaw)
        states.append(brain.head.state)
    scan_share = states.count("scan") / len(states)
    assert 0.1 < scan_share < 0.35  # about 1 s in every 5 s
    assert min(yaws) < -1.2 and max(yaws) > 1.2 and max(abs(y) for y in yaws) <= 1.5 + 1e-9

    # a lost estimate makes the head scan outside the routine window too
    brain = ScriptedBrain(
        CognitionConfig(localization="oracle"), head_params=HeadParams(scan_period=100.0, scan_duration=0.5)
    )
    brain.reset(m.brains[0].context)  # type: ignore[arg-type]
    frame = m.last_frames[0]
    assert frame is not None
    oracle = OracleInput(OraclePose(1, -1.0, 0.0, 0.0), (), (), 0.0, 2.0, 0.0, 0.0)  # the variant reads the pose
    frame = replace(frame, time=50.0)  # routine scans of player 1 run from 0.7 s to 1.2 s of every 100 s
    brain.think(frame, oracle)
    assert not brain.pose.lost and brain.head.state != "scan"  # type: ignore[union-attr]
    localizer = brain.provider.localizer  # type: ignore[union-attr]
    lost = replace(localizer.pose, lost=True)
    localizer._update = lambda frame, truth: lost  # type: ignore[method-assign]
    yaws = []
    for k in range(30):  # one second: two legs of the 0.5 s sweep
        out = brain.think(replace(frame, time=50.1 + k / 30.0), oracle)
        assert brain.head.state == "scan"
        yaws.append(out.motion.head.yaw)
    assert min(yaws) == pytest.approx(-1.4, abs=0.1) and max(yaws) == pytest.approx(1.4, abs=0.1)


# -- (b) determinism and random streams ----------------------------------------------------
@pytest.mark.parametrize("variant", ["odometry", pytest.param("mcl", marks=needs_particles)])
def test_same_seed_same_estimates(variant: str) -> None:
    finals = []
    for _ in range(2):
        m = Match(_config(variant, players_per_team=3, seed=4))
        m.run(until=20.0)
        finals.append([(b.pose.pose, b.pose.lost, b.pose.particles.tobytes()) for b in m.brains])  # type: ignore[attr-defined]
    assert finals[0] == finals[1]


def test_brain_streams_are_new_children_after_the_old_ones() -> None:
    cfg = _config("odometry", players_per_team=3, seed=9)
    n = cfg.players_per_team
    m = Match(cfg)
    old = np.random.SeedSequence(cfg.seed).spawn(5 + 4 * n)  # the order before brains had streams
    for k, odo in enumerate(m.odometry):
        g = np.random.Generator(np.random.PCG64(old[4 + 2 * n + k]))
        assert odo.drift == float(g.normal(0.0, cfg.odometry.drift_sigma))
    new = np.random.SeedSequence(cfg.seed).spawn(5 + 6 * n)
    states = set()
    for k, brain in enumerate(m.brains):
        rng = brain.provider.localizer.rng  # type: ignore[attr-defined]
        assert rng.bit_generator.state == np.random.Generator(np.random.PCG64(new[5 + 4 * n + k])).bit_generator.state
        states.add(str(rng.bit_generator.state))
    assert len(states) == 2 * n


def test_default_brains_unchanged_by_localization_support() -> None:
    cfg = MatchConfig(referee=RefereeParams(half_seconds=20.0, ready_seconds=8.0), players_per_team=3)
    a, b = Match(cfg), Match(cfg, brains=scripted_brains(None))  # default: scripted play on truth beliefs
    a.run(until=40.0)
    b.run(until=40.0)
    assert a.snapshot() == b.snapshot() and a.log.events == b.log.events


def test_default_brains_are_scripted_or_random() -> None:
    brain = default_brains("scripted", CognitionConfig(localization="odometry"), "spl2010")(0, 2)
    assert isinstance(brain, ScriptedBrain) and brain.cognition.localization == "odometry"
    assert brain.cognition.localization_params.return_rule == "spl2010"  # the referee's rule
    with pytest.raises(ValueError, match=r"unknown players 'oracle'; valid: \['scripted', 'random'\]"):
        default_brains("oracle", None, "spl2025")


# -- (c) configuration --------------------------------------------------------------------
def test_unknown_variant_names_the_valid_ones() -> None:
    with pytest.raises(ValueError, match=r"MatchConfig\.cognition\.localization must be one of .*'mcl'.*'oracle'"):
        MatchConfig.from_mapping({"cognition": {"localization": "kalman"}})
    with pytest.raises(ValueError, match=r"CognitionConfig\.localization must be one of .*'amcl'.*got 'kalman'"):
        ScriptedBrain(CognitionConfig(localization="kalman"))


def test_localization_params_from_mapping_and_return_rule_from_referee() -> None:
    cfg = MatchConfig.from_mapping(
        {
            "cognition": {"localization": "odometry", "localization_params": {"particles": 120}},
            "referee": {"rules": "spl2010"},
        }
    )
    assert cfg.cognition is not None and cfg.cognition.localization_params == LocalizationParams(particles=120)
    with pytest.raises(
        ValueError, match=r"unknown MatchConfig\.cognition\.localization_params key\(s\) \['partcles'\]"
    ):
        MatchConfig.from_mapping({"cognition": {"localization_params": {"partcles": 3}}})
    with pytest.raises(TypeError, match="localization_params"):
        CognitionConfig(localization_params=3)  # type: ignore[arg-type]
    m = Match(replace(cfg, players_per_team=1))
    for brain in m.brains:
        params = brain.provider.localizer.params  # type: ignore[attr-defined]
        assert params.return_rule == "spl2010" and params.particles == 120


def test_localization_errors_accumulate() -> None:
    errs = LocalizationErrors()
    assert errs.summary() is None
    empty = np.zeros((0, 3))
    for k in range(10):
        pose = RobotPose(float(k), 0.0, 0.1, np.eye(3), k == 0, 0, empty, np.zeros(0), "x")
        errs.add(pose, (0.0, 0.0, -0.1))
    s = errs.summary()
    assert s is not None and s.frames == 10 and s.variant == "x"
    assert s.position_error_mean == pytest.approx(4.5) and s.position_error_p90 == pytest.approx(8.1)
    assert s.heading_error_mean == pytest.approx(math.degrees(0.2)) and s.lost_share == pytest.approx(0.1)


# -- (d) the command line -------------------------------------------------------------------
def test_cli_match_with_localization(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    argv = ["match", "--localization", "odometry", "--half-seconds", "10", "--players-per-team", "2"]
    assert main([*argv, "--out", str(tmp_path)]) == 0
    text = capsys.readouterr().out
    assert "localization   odometry: position error mean" in text and "lost 0.0%" in text
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["localization"]["variant"] == "odometry" and summary["localization"]["frames"] > 0
    assert json.loads((tmp_path / "config.json").read_text())["cognition"]["localization"] == "odometry"


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--video-particles"], "needs --video"),
        (["--video-particles", "--video", "x.gif", "--video-robot", "none"], "needs --video"),
        (["--video-particles", "--video", "x.gif", "--localization", "none"], "needs a cognition stack"),
    ],
)
def test_cli_video_particles_needs_video_and_localization(
    argv: list[str], message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["match", "--half-seconds", "5", *argv]) == 2
    assert message in capsys.readouterr().err


def test_cli_unknown_variant(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["match", "--localization", "kalman"]) == 2
    assert "invalid choice: 'kalman'" in capsys.readouterr().err


# -- the particle view ----------------------------------------------------------------------
def test_belief_overlay_converts_team_to_world_frame() -> None:
    m = Match(_config("odometry", players_per_team=2))
    brain = m.brains[2]  # team 1 player 1, attacking world -x in the first half
    assert m.referee.sign(1) == -1.0
    particles = np.array([[1.0, 2.0, 0.5], [-3.0, 0.5, -3.0]])
    brain.pose = RobotPose(1.0, 2.0, 0.5, np.eye(3), True, 2, particles, np.full(2, 0.5), "x")  # type: ignore[attr-defined]
    b = belief_overlay(m, 1, 1)
    assert b is not None and b.team == 1 and b.lost
    assert (b.x, b.y) == (-1.0, -2.0) and b.theta == pytest.approx(0.5 - math.pi)
    assert b.particles[:, :2].tolist() == [[-1.0, -2.0], [3.0, -0.5]]
    assert b.particles[1, 2] == pytest.approx(math.pi - 3.0)
    assert belief_overlay(Match(_config(None, players_per_team=1)), 0, 1) is None


def test_renderer_draws_particles_and_estimate_in_team_colour() -> None:
    m = Match(_config(None, players_per_team=1))
    scheme = make_colour_scheme("classic")
    view = TopDownRenderer(m.field, scheme)
    plain = view.render(m.snapshot())
    belief = Belief(1, 2.0, 1.0, 0.0, np.array([[-2.0, -1.5, 0.0], [0.5, -2.0, 1.0], [50.0, 0.0, 0.0]]))
    img = view.render(m.snapshot(), beliefs=[belief])
    colour = np.array(scheme.team_colours[1], dtype=np.uint8)
    for x, y in ((-2.0, -1.5), (0.5, -2.0), (2.0 + 0.15, 1.0)):  # two particles and the estimate's outline
        c, r = (round(v) for v in view.to_pixel(x, y))
        assert (img[r, c] == colour).all() and not (plain[r, c] == colour).all()
    with pytest.raises(ValueError, match="team"):
        Belief(2, 0.0, 0.0, 0.0)


# -- every variant in a 5 v 5 match ---------------------------------------------------------
@needs_particles
@pytest.mark.parametrize("variant", VARIANTS)
def test_every_variant_plays_20_seconds(variant: str) -> None:
    m = Match(_config(variant))
    s = m.run(until=20.0)
    for brain in m.brains:
        pose = brain.pose  # type: ignore[attr-defined]
        assert isinstance(pose, RobotPose) and pose.variant == variant
        assert all(math.isfinite(v) for v in pose.pose) and np.isfinite(pose.covariance).all()
        assert pose.particles.shape == (pose.n_particles, 3) and np.isfinite(pose.particles).all()
        if pose.n_particles:
            assert pose.weights.sum() == pytest.approx(1.0)
    assert s.localization is not None and 0 < s.localization.frames <= m.frames * 10
    assert math.isfinite(s.localization.position_error_mean)
