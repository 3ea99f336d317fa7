"""The declared cognition pipeline (:mod:`cognition.pipeline`, :mod:`cognition.modules`): every
configuration plans to modules whose declarations hold, or is refused naming what is missing;
providers are chosen by name from a config file; ground truth reaches declared oracles only."""

from __future__ import annotations

import itertools
import json
from pathlib import Path

import numpy as np
import pytest

from cognition.brain import BrainContext
from cognition.field import make_field
from cognition.pipeline import (
    DECLARATIONS,
    OBSERVATIONS,
    OPTIONAL_SLOTS,
    TRUTH,
    CognitionConfig,
    PipelineError,
    plan,
    providers,
)
from cognition.worldmodel.beliefs import MODULES, CognitionBeliefs
from teamsim.match import Match, MatchConfig
from teamsim.referee import RefereeParams

FIELD = make_field("spl2025")
SHORT = RefereeParams(half_seconds=4.0, initial_seconds=0.5, ready_seconds=2.0, set_seconds=0.5, halftime_seconds=1.0)


def _configs() -> list[CognitionConfig]:
    """Every provider of every slot at least once (the others at their defaults), and the truth."""
    out = [CognitionConfig(), TRUTH]
    for slot in CognitionConfig.SLOTS:
        out.extend(CognitionConfig(**{slot: name}) for name in providers(slot))
    out.append(CognitionConfig(**{slot: "none" for slot in OPTIONAL_SLOTS}))
    return out


@pytest.mark.parametrize(
    ("config", "observation", "ground_truth"),
    list(itertools.product(_configs(), OBSERVATIONS, (True, False))),
)
def test_every_plan_satisfies_its_declarations_or_is_refused(
    config: CognitionConfig, observation: str, ground_truth: bool
) -> None:
    inputs = set(OBSERVATIONS[observation]) | ({"ground truth"} if ground_truth else set())
    particle = config.localization not in ("odometry", "oracle")
    needs_truth = config.beliefs == "truth" or config.localization == "oracle"
    should_fail = config.beliefs == "cognition" and particle and observation == "none"
    should_fail |= needs_truth and not ground_truth
    if should_fail:
        with pytest.raises(PipelineError, match=r"requires '(percepts|ground truth)', which nothing provides"):
            plan(config, observation, ground_truth)
        return
    planned = plan(config, observation, ground_truth)
    have = set(inputs)
    for d in planned:  # each module runs after everything it requires, and after what it uses when planned
        assert set(d.requires) <= have, (d, have)
        assert not (set(d.uses) & {p.provides for p in planned}) - have, d
        have.add(d.provides)
    assert planned[-1].provides == "beliefs" and len({d.stage for d in planned}) == len(planned)
    stages = [d.stage for d in planned]
    assert ("vision" in stages) == (observation == "images" and config.beliefs == "cognition")
    for slot in OPTIONAL_SLOTS:  # a "none" provider leaves its module out
        if getattr(config, slot) == "none":
            assert DECLARATIONS[slot][providers(slot)[0]].stage not in stages
    if config.beliefs == "truth":
        assert stages == ["truth beliefs"]


def test_every_declared_provider_has_a_module_and_builds() -> None:
    assert set(MODULES) == {(slot, name) for slot, opts in DECLARATIONS.items() for name in opts}
    context = BrainContext(1, 2, 5, FIELD, 30.0, np.random.default_rng(0), observation="images")
    for config in _configs():
        cb = CognitionBeliefs(context, config)
        assert cb.stages == tuple(d.stage for d in plan(config, "images"))
        assert set(cb.modules) == set(cb.stages)


def test_unknown_providers_and_parameters_are_errors_naming_them() -> None:
    with pytest.raises(ValueError, match=r"CognitionConfig.localization must be one of .*'maturing'.*got 'mlc'"):
        CognitionConfig(localization="mlc")
    with pytest.raises(ValueError, match=r"CognitionConfig.obstacles must be one of .*'grid'.*got 'lidar'"):
        CognitionConfig.from_mapping({"obstacles": "lidar"})
    with pytest.raises(ValueError, match=r"CognitionConfig.ball must be one of \['kalman'\], got 'none'"):
        CognitionConfig(ball="none")  # the beliefs need a ball: only optional slots take 'none'
    with pytest.raises(ValueError, match=r"unknown .*cognition key\(s\) \['particles'\]"):
        MatchConfig.from_mapping({"cognition": {"particles": 100}})
    with pytest.raises(ValueError, match=r"cognition.localization_params key\(s\) \['partciles'\]"):
        MatchConfig.from_mapping({"cognition": {"localization_params": {"partciles": 100}}})
    with pytest.raises(ValueError, match=r"unknown MatchConfig key\(s\) \['localization'\]"):
        MatchConfig.from_mapping({"localization": "amcl"})  # brain settings live in the cognition section
    with pytest.raises(ValueError, match=r"vision='dnt' but vision_params.method='hough'"):
        CognitionConfig.from_mapping({"vision_params": {"method": "hough"}})
    assert CognitionConfig(vision="hough").vision_params.method == "hough"


def test_a_match_refuses_localizing_without_percepts_but_dead_reckons_without_them() -> None:
    with pytest.raises(ValueError, match=r"module 'localization' \(localization='maturing'\) requires 'percepts'"):
        MatchConfig(observation="none", cognition=CognitionConfig())
    # odometry needs no percepts: the same frames are enough for it, and the ball model predicts
    m = Match(MatchConfig(players_per_team=1, observation="none", cognition=CognitionConfig(localization="odometry")))
    m.run(until=6.0)
    s = m.summary().localization
    assert s is not None and s.variant == "odometry" and s.frames > 100
    assert s.position_error_mean < 1.0  # dead reckoning from the known start, a few seconds in
    assert MatchConfig(observation="none", cognition=CognitionConfig(), players="random").cognition is not None


def test_ground_truth_reaches_only_declared_oracle_providers() -> None:
    seen: dict[str, list[bool]] = {}

    class Spy(CognitionBeliefs):
        def begin(self, frame, ground_truth=None):  # type: ignore[no-untyped-def]
            seen.setdefault(self.config.summary(), []).append(ground_truth is not None)
            super().begin(frame, ground_truth)

    import cognition.behaviors.team_play as team_play

    original = team_play.CognitionBeliefs
    team_play.CognitionBeliefs = Spy  # type: ignore[misc]
    try:
        for config in (CognitionConfig(), CognitionConfig(localization="oracle"), TRUTH):
            Match(MatchConfig(players_per_team=1, cognition=config, referee=SHORT)).run(until=2.0)
    finally:
        team_play.CognitionBeliefs = original  # type: ignore[misc]
    assert not CognitionConfig().reads_ground_truth and TRUTH.reads_ground_truth
    assert not any(seen[CognitionConfig().summary()])  # the stack never gets the truth
    assert all(seen[CognitionConfig(localization="oracle").summary()]) and all(seen[TRUTH.summary()])


def test_optional_modules_can_be_left_out() -> None:
    lean = CognitionConfig(hypotheses="none", team_ball="none", obstacles="none", goal="none")
    m = Match(MatchConfig(players_per_team=2, cognition=lean, referee=SHORT))
    m.run(until=6.0)
    brain = m.brains[0]
    assert brain.provider.stages == ("input check", "localization", "team messages", "ball model", "beliefs")  # type: ignore[attr-defined]
    b = brain.beliefs  # type: ignore[attr-defined]
    assert b.goal is None and b.team_ball is None and b.look_at is None and b.obstacles.shape == (0, 2)
    assert m.summary().localization is not None and m.summary().localization.frames > 0


def test_providers_are_chosen_from_the_config_file(tmp_path: Path) -> None:
    from teamsim.cli import build_parser, config_from_args

    path = tmp_path / "c.json"
    path.write_text(json.dumps({"players_per_team": 1, "cognition": {"localization": "amcl", "obstacles": "grid"}}))
    config = config_from_args(build_parser().parse_args(["match", "--config", str(path)]))
    assert config.cognition is not None and (config.cognition.localization, config.cognition.obstacles) == (
        "amcl",
        "grid",
    )
    m = Match(config)
    provider = m.brains[0].provider  # type: ignore[attr-defined]
    assert type(provider.obstacles).__name__ == "ObstacleGrid" and provider.localizer.name == "amcl"
    # an option replaces only its own key of the file's section
    config = config_from_args(build_parser().parse_args(["match", "--config", str(path), "--localization", "reset"]))
    assert config.cognition is not None and (config.cognition.localization, config.cognition.obstacles) == (
        "reset",
        "grid",
    )
    none = config_from_args(build_parser().parse_args(["match", "--localization", "none"]))
    assert none.cognition is None  # scripted players on the truth
    assert config_from_args(build_parser().parse_args(["match"])).cognition == CognitionConfig()  # the default


def test_every_module_takes_its_parameters_from_the_config() -> None:
    from cognition.localization import LocalizationParams
    from cognition.worldmodel.goal import GoalModelParams
    from cognition.worldmodel.hypotheses import HypothesisParams
    from cognition.worldmodel.kalman_ball import KalmanBallParams
    from cognition.worldmodel.obstacles import ObstacleGridParams

    config = CognitionConfig.from_mapping(
        {
            "localization": "amcl",
            "obstacles": "grid",
            "localization_params": {"particles": 77},
            "ball_params": {"accel_sigma": 0.5},
            "hypotheses_params": {"decay_per_second": 0.2},
            "goal_params": {"decay_per_second": 0.3},
            "obstacle_grid_params": {"extent": 2.0},
        }
    )
    cb = CognitionBeliefs(BrainContext(1, 2, 5, FIELD, 30.0, np.random.default_rng(0)), config)
    assert cb.localizer is not None and cb.localizer.params == LocalizationParams(particles=77)
    assert cb.ball_model is not None and cb.ball_model.params == KalmanBallParams(accel_sigma=0.5)
    assert cb.hypotheses is not None and cb.hypotheses.params == HypothesisParams(decay_per_second=0.2)
    assert cb.goal_model is not None and cb.goal_model.params == GoalModelParams(decay_per_second=0.3)
    assert cb.obstacles is not None and cb.obstacles.params == ObstacleGridParams(extent=2.0)  # type: ignore[union-attr]


def test_a_registered_provider_is_chosen_by_name_and_runs_in_its_slot() -> None:
    from cognition.modules import BallModule, register_provider, unregister_provider

    runs: list[int] = []

    class CountingBall(BallModule):  # a team's own ball filter would go here
        def run(self, board):  # type: ignore[no-untyped-def]
            runs.append(1)
            super().run(board)

    with pytest.raises(ValueError, match=r"unknown CognitionConfig.ball|must be one of \['kalman'\], got 'counting'"):
        CognitionConfig(ball="counting")
    register_provider("ball", "counting", CountingBall, requires=("odometry", "robot pose"), uses=("percepts",))
    try:
        config = CognitionConfig(ball="counting")
        assert [d.stage for d in plan(config)] == [d.stage for d in plan(CognitionConfig())]  # same slot, same row
        m = Match(MatchConfig(players_per_team=1, cognition=config, referee=SHORT))
        m.run(until=2.0)
        assert len(runs) == m.frames * 2 and m.summary().localization is not None
        with pytest.raises(ValueError, match=r"ball already has a provider 'counting'"):
            register_provider("ball", "counting", CountingBall, requires=())
        with pytest.raises(ValueError, match=r"unknown representation 'sonar'"):
            register_provider("ball", "sonar", CountingBall, requires=("sonar",))
        with pytest.raises(ValueError, match=r"unknown slot 'input check'"):
            register_provider("input check", "mine", CountingBall, requires=())
        with pytest.raises(ValueError, match=r"ball='kalman' is built in"):
            unregister_provider("ball", "kalman")
    finally:
        unregister_provider("ball", "counting")
    assert "counting" not in providers("ball")
