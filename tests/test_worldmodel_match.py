"""The world model inside matches: team messages within the budget, loss and delay, team balls."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from cognition.pipeline import CognitionConfig
from cognition.worldmodel.messages import unpack
from teamsim.channel import ChannelParams
from teamsim.match import Match, MatchConfig
from teamsim.referee import RefereeParams


def _run(channel: ChannelParams, seconds: float = 60.0):
    m = Match(
        MatchConfig(
            seed=3,
            cognition=CognitionConfig(localization="lowvar"),
            channel=channel,
            referee=RefereeParams(half_seconds=seconds, ready_seconds=10.0, halftime_seconds=2.0),
        )
    )
    contributors, errors = [], []
    while not m.referee.finished:
        m.step()
        if m.steps % 50:
            continue
        for i, brain in enumerate(m.brains):
            b = brain.beliefs
            if b is None:
                continue
            if b.team_ball is not None:
                contributors.append(len(b.team_ball.contributors))
            if b.ball.source == "vision" and not b.pose.lost:
                bx, by = m.world.ball.position
                # compare the Kalman ball's field position with the truth in the team frame
                sign = 1.0 if (m.world.robots[i].team == 0) == m.referee.first_half else -1.0
                errors.append(math.hypot(b.ball.field_x - sign * bx, b.ball.field_y - sign * by))
    return m, contributors, errors


@pytest.mark.slow(seconds=32)
def test_messages_respect_a_tight_budget_and_are_all_valid():
    m, contributors, errors = _run(ChannelParams(budget=100, loss=0.0))
    for team in (0, 1):
        st = m.channel.stats[team]
        assert st.refused == 0 and 60 <= st.sent <= 100, st
    assert all(b.provider.team.rejected == 0 for b in m.brains)
    assert max(contributors) >= 3  # teammates' balls do get fused
    assert np.median(errors) < 0.3


@pytest.mark.slow(seconds=32)
def test_loss_and_delay_degrade_gracefully():
    clean = _run(ChannelParams(loss=0.0, delay=0.02, jitter=0.0), seconds=20.0)
    lossy = _run(ChannelParams(loss=0.7, delay=0.5, jitter=0.3), seconds=20.0)
    assert clean[0].channel.stats[0].lost == 0 and lossy[0].channel.stats[0].lost > 0
    assert all(b.provider.team.rejected == 0 for b in lossy[0].brains)
    assert np.mean(lossy[1]) < np.mean(clean[1])  # fewer teammates heard
    assert np.mean(lossy[1]) >= 1.0 and np.median(lossy[2]) < 0.3  # the own ball is unaffected


def test_sent_payloads_are_team_messages():
    ref = RefereeParams(half_seconds=20, initial_seconds=0.5, ready_seconds=2.0, set_seconds=1.0)
    m = Match(MatchConfig(seed=4, cognition=CognitionConfig(localization="odometry"), referee=ref))
    sent = []
    orig = m.channel.send

    def spy(team, number, payload, now):
        sent.append((number, payload))
        return orig(team, number, payload, now)

    m.channel.send = spy  # type: ignore[method-assign]
    m.run(until=25.0)
    assert sent
    for number, payload in sent:
        msg = unpack(payload)
        assert msg.player == number


def test_world_model_is_drawn_on_the_top_down_view():
    from cognition.field import make_colour_scheme
    from teamsim.camera_views import belief_overlay
    from teamsim.render import Belief, TopDownRenderer

    ref = RefereeParams(half_seconds=20, initial_seconds=0.5, ready_seconds=2.0, set_seconds=1.0)
    m = Match(MatchConfig(seed=4, cognition=CognitionConfig(localization="lowvar"), referee=ref))
    m.run(until=8.0)
    view = TopDownRenderer(m.field, make_colour_scheme("classic"))
    belief = belief_overlay(m, 0, 3)
    assert belief is not None and belief.ball is not None  # player 3 (a supporter at 8 s) sees the ball
    plain = view.render(m.snapshot(), m.game_state())
    drawn = Belief(
        0, 0.0, 0.0, 0.0, ball=(2.0, 1.0), team_ball=(-2.0, -1.0), obstacles=np.array([[1.0, -2.0]]),
        goal=((3.5, 0.8), (3.5, -0.8)),
    )  # fmt: skip
    img = view.render(m.snapshot(), m.game_state(), beliefs=[drawn])
    for x, y in ((2.0 + 0.09, 1.0), (-2.0, -1.0), (1.05, -2.0), (3.5, 0.0)):
        c, r = (int(v) for v in view.to_pixel(x, y))
        assert np.any(img[r - 2 : r + 3, c - 2 : c + 3] != plain[r - 2 : r + 3, c - 2 : c + 3]), (x, y)
    with pytest.raises(ValueError, match="obstacles"):
        Belief(0, 0.0, 0.0, 0.0, obstacles=np.zeros(3))


def test_obstacle_model_is_chosen_in_the_match_config_and_cli(tmp_path):
    from cognition.worldmodel.obstacles import ObstacleGrid
    from teamsim.cli import main

    with pytest.raises(ValueError, match=r"MatchConfig\.cognition\.obstacles must be one of .*got 'lidar'"):
        MatchConfig.from_mapping({"cognition": {"obstacles": "lidar"}})
    ref = RefereeParams(half_seconds=20, initial_seconds=0.5, ready_seconds=2.0, set_seconds=1.0)
    grid = CognitionConfig(localization="odometry", obstacles="grid")
    m = Match(MatchConfig(seed=2, cognition=grid, referee=ref))
    m.run(until=2.0)
    assert all(isinstance(b.provider.obstacles, ObstacleGrid) for b in m.brains)
    code = main(["match", "--localization", "odometry", "--obstacles", "grid", "--half-seconds", "5",
                 "--players-per-team", "1", "--out", str(tmp_path)])  # fmt: skip
    assert code == 0 and json.loads((tmp_path / "config.json").read_text())["cognition"]["obstacles"] == "grid"
