"""The policy observation (:mod:`cognition.behaviors.observation`) equals, to the bit, the plain
implementation it replaced: on recorded beliefs of ``soccer_v0`` and on beliefs with the values
that take other paths (NaN and infinite entries, NaN or tied obstacle distances, float32
obstacles, teammates outside the slots)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from numpy.typing import NDArray

from cognition.behaviors import observation
from cognition.behaviors.observation import ObservationBuilder
from cognition.field import make_field
from cognition.worldmodel.beliefs import Beliefs
from cognition.worldmodel.representations import Teammate
from cognition.worldmodel.team import TeamBallEstimate
from envs import soccer_v0

FIELD = make_field("spl2025")


def _reference_build(self: ObservationBuilder, b: Beliefs) -> NDArray[np.float32]:
    """The observation as :meth:`ObservationBuilder.build` computed it before its rewrite for speed."""
    o = [0.0] * self.size
    p = b.pose
    inv_l = self._inv_l
    c, s = math.cos(p.theta), math.sin(p.theta)
    o[0], o[1], o[2], o[3] = p.x / self._hl, p.y / self._hw, c, s
    cov = p.covariance
    o[4] = p.position_std / 2.0
    o[5] = math.sqrt(max(0.0, float(cov[2, 2]))) / math.pi
    o[6] = float(p.lost)
    ball = b.ball
    if ball.level != "invalid":
        o[7], o[8], o[9], o[10] = ball.x * inv_l, ball.y * inv_l, ball.vx / 3.0, ball.vy / 3.0
    o[observation._LEVELS[ball.level]] = 1.0
    o[14] = min(ball.age, 10.0) / 10.0
    if ball.level != "invalid" and math.isfinite(ball.field_x):
        o[15], o[16] = ball.field_x / self._hl, ball.field_y / self._hw
    if b.team_ball is not None:
        tx, ty = b.to_robot(b.team_ball.x, b.team_ball.y)
        o[17], o[18], o[19] = 1.0, tx * inv_l, ty * inv_l
    gx, gy = b.to_robot(self._hl, 0.0)
    ox, oy = b.to_robot(-self._hl, 0.0)
    o[20], o[21], o[22], o[23] = gx * inv_l, gy * inv_l, ox * inv_l, oy * inv_l
    if b.goal is not None:
        o[24], o[25], o[26] = b.goal.confidence, b.goal.centre_x * inv_l, b.goal.centre_y * inv_l
    g = b.game
    o[observation._STATES.get(g.state, 27)] = 1.0  # IntEnum keys: a plain int state finds them
    o[32] = float(g.kicking_team == self.team_number)
    o[33] = float(g.set_play != 0)
    o[34] = g.secondary_time / 30.0
    o[35] = g.secs_remaining / 600.0
    own = g.team(self.team_number)
    other = g.teams[1] if g.teams[0].team_number == self.team_number else g.teams[0]
    o[36] = (own.score - other.score) / 5.0
    o[37] = float(b.penalty != 0)
    o[38] = own.players[b.player_number - 1].secs_till_unpenalised / 45.0
    o[39] = float(b.fallen)
    o[40] = float(b.player_number == 1)
    for m in b.teammates:
        slot = m.number - 1 if m.number < b.player_number else m.number - 2
        if not 0 <= slot < self.players_per_team - 1:
            continue
        i = observation._BASE + observation._MATE * slot
        mx, my = b.to_robot(m.x, m.y)
        o[i], o[i + 1], o[i + 2], o[i + 3], o[i + 4] = 1.0, mx * inv_l, my * inv_l, float(m.active), m.age / 3.0
    obs = b.obstacles
    if len(obs):
        d = obs[:, 0] ** 2 + obs[:, 1] ** 2
        i = observation._BASE + observation._MATE * (self.players_per_team - 1)
        for k in np.argsort(d, kind="stable")[: observation.OBSTACLE_SLOTS]:
            o[i], o[i + 1], o[i + 2] = 1.0, float(obs[k, 0]) / 3.0, float(obs[k, 1]) / 3.0
            i += observation._OBSTACLE
    out = np.array(o, dtype=np.float32)
    if not np.isfinite(out).all():  # rare: a belief without a value reads as 0
        np.nan_to_num(out, copy=False, nan=0.0, posinf=1.0, neginf=-1.0)
    np.minimum(out, 1.0, out=out)  # clip to [-1, 1] (np.clip costs several times more on a short vector)
    np.maximum(out, -1.0, out=out)
    return out


def _recorded(mode: str) -> list[tuple[ObservationBuilder, Beliefs]]:
    hz = 10.0 if mode == "truth" else 30.0
    env = soccer_v0.parallel_env(
        players_per_team=5, control="both", observation=mode, cognition_hz=hz, start="playing", max_cycles=10**9
    )
    space = env.action_space("home_1")
    space.seed(0)
    env.reset(seed=1)
    out = []
    for _ in range(25):
        env.step({a: space.sample() for a in env.agents})
        for brain in env.core.match.brains:
            out.append((brain.observer, brain.latest_beliefs()))
    return out


@pytest.mark.parametrize("mode", ["truth", "percepts"])
def test_equal_to_the_plain_implementation_on_recorded_beliefs(mode: str) -> None:
    recorded = _recorded(mode)
    assert any(len(b.obstacles) > observation.OBSTACLE_SLOTS for _, b in recorded)  # the nearest are chosen
    for builder, beliefs in recorded:
        np.testing.assert_array_equal(builder.build(beliefs), _reference_build(builder, beliefs))


def test_equal_to_the_plain_implementation_on_unusual_values() -> None:
    builder, beliefs = _recorded("truth")[3]
    nan, inf = math.nan, math.inf
    pose = beliefs.pose
    cases = [
        dict(obstacles=np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.5, 0.5], [0.0, -1.0], [0.6, 0.6]])),  # ties
        dict(obstacles=np.array([[nan, 0.0], [0.3, 0.1], [2.0, nan], [0.2, 0.2]])),
        dict(obstacles=np.array([[0.1, 0.2], [0.1000001, 0.2], [3.0, 1.0]], dtype=np.float32)),
        dict(obstacles=np.array([[inf, 0.0], [1e39, 0.0], [-1e300, 5.0]])),
        dict(obstacles=np.zeros((0, 2))),
        dict(pose=dataclasses.replace(pose, x=nan)),
        dict(pose=dataclasses.replace(pose, y=inf, theta=-0.0)),
        dict(ball=dataclasses.replace(beliefs.ball, x=inf, vx=-inf, field_x=nan)),
        dict(team_ball=TeamBallEstimate(nan, 1.0, 0.0, 0.0, 0.0, (2,))),
        dict(team_ball=TeamBallEstimate(1e40, -1e40, 0.0, 0.0, 0.0, (2,))),
        dict(
            teammates=(
                Teammate(9, 1.0, 1.0, 0.0, 0.5),
                Teammate(2, nan, 0.0, 0.0, inf),
                Teammate(1, 0.1, 0.2, 0.0, 1.0),
            )
        ),
    ]
    for changes in cases:
        b = dataclasses.replace(beliefs, **changes)
        with np.errstate(over="ignore"):  # values beyond float32 become +-1 (both warn when casting)
            ours, reference = builder.build(b), _reference_build(builder, b)
        np.testing.assert_array_equal(ours, reference, err_msg=str(changes))
        assert ours.dtype == np.float32 and np.all(np.abs(ours) <= 1.0)
