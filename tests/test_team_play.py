"""Scripted team play: roles, skills, head control, and matches against random walkers and itself."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cognition.behaviors.head_control import HeadControl
from cognition.behaviors.skills import Skills
from cognition.behaviors.team_play import assign_role
from cognition.brain import BrainContext
from cognition.field import make_field
from cognition.gamestate import GameControlData, GameStateId
from cognition.pipeline import CognitionConfig
from cognition.representations import BallModel, RobotPose
from cognition.worldmodel.beliefs import Beliefs, Teammate
from cognition.worldmodel.messages import Role
from teamsim.brains import random_brains, scripted_brains
from teamsim.match import Match, MatchConfig
from teamsim.referee import RefereeParams

FIELD = make_field("spl2025")


def beliefs(
    number: int,
    pose: tuple[float, float, float],
    ball: tuple[float, float] | None,
    mates: tuple[Teammate, ...] = (),
    lost: bool = False,
    source: str = "truth",
    look_at: tuple[float, float] | None = None,
    time: float = 10.0,
) -> Beliefs:
    x, y, th = pose
    rp = RobotPose(x, y, th, np.eye(3) * (1.0 if lost else 1e-4), lost, 0, np.zeros((0, 3)), np.zeros(0), "t")
    if ball is None:
        bm = BallModel(0, 0, 0, 0, np.eye(4), math.nan, math.nan, 99.0, "invalid", "none")
    else:
        c, s = math.cos(th), math.sin(th)
        dx, dy = ball[0] - x, ball[1] - y
        bm = BallModel(
            c * dx + s * dy, -s * dx + c * dy, 0, 0, np.eye(4) * 0.01, ball[0], ball[1], 0.0, "valid", "vision"
        )
    game = GameControlData(state=GameStateId.PLAYING)
    return Beliefs(time, number, game, 0, False, False, rp, bm, None, None, mates, np.zeros((0, 2)), look_at, source)  # type: ignore[arg-type]


def mate(number: int, x: float, y: float, role: Role = Role.NONE, penalized: bool = False) -> Teammate:
    return Teammate(number, x, y, 0.0, 0.5, role, penalized=penalized)


def context(number: int) -> BrainContext:
    return BrainContext(1, number, 5, FIELD, 30.0, np.random.default_rng(0))


def test_nearest_field_player_strikes_and_the_keeper_keeps() -> None:
    b = beliefs(3, (1.0, 0.0, 0.0), (1.5, 0.0), (mate(2, 3.0, 0.0), mate(4, -3.5, 0.0), mate(1, 1.4, 0.0)))
    assert assign_role(b) == Role.STRIKER  # the keeper (1) is nearer but never strikes
    far = beliefs(3, (-2.0, 0.0, 0.0), (1.5, 0.0), (mate(2, 1.0, 0.0), mate(4, -3.5, 0.0)))
    assert assign_role(far) == Role.SUPPORTER  # 4 is nearer the own goal and defends
    back = beliefs(4, (-3.5, 0.0, 0.0), (1.5, 0.0), (mate(2, 1.0, 0.0), mate(3, -2.0, 0.0)))
    assert assign_role(back) == Role.DEFENDER
    assert assign_role(beliefs(1, (-4.0, 0.0, 0.0), (-3.8, 0.0))) == Role.KEEPER


def test_striker_role_has_hysteresis_and_ignores_penalised_mates() -> None:
    mates = (mate(2, 1.2, 0.0, Role.NONE),)
    b = beliefs(3, (1.0, 0.0, 0.0), (1.4, 0.1), mates)  # 2 is 0.2 m nearer
    assert assign_role(b, Role.NONE) == Role.DEFENDER  # 2 strikes even before it says so; 3 is the only back
    assert assign_role(b, Role.STRIKER) == Role.STRIKER  # keeps the role within the bonus
    gone = beliefs(3, (1.0, 0.0, 0.0), (1.4, 0.1), (mate(2, 1.2, 0.0, penalized=True),))
    assert assign_role(gone, Role.NONE) == Role.STRIKER


def test_striker_kicks_toward_the_goal_when_lined_up() -> None:
    sk = Skills(context(3))
    for by in (-1.0, 0.0, 1.2):
        bx = 2.0
        aim = math.atan2(-by, FIELD.half_length - bx)
        me = (bx - 0.2 * math.cos(aim), by - 0.2 * math.sin(aim), aim)
        m = sk.kick_to_goal(beliefs(3, me, (bx, by)))
        assert m.kick is not None
        world_dir = me[2] + m.kick.direction
        # the kick line passes between the posts
        y_at_goal = by + math.tan(world_dir) * (FIELD.half_length - bx)
        assert abs(y_at_goal) < FIELD.dims.goal_inner_width / 2


def test_ball_at_a_corner_is_played_with_a_side_kick_from_inside_the_limits() -> None:
    # no line-up spot straight behind a corner ball lies within the field limits; the striker
    # stands where it may and kicks sideways instead of waiting for LOCAL_GAME_STUCK
    sk = Skills(context(3))
    lim_x = FIELD.half_length + sk.params.outside_allowance
    lim_y = FIELD.half_width + sk.params.outside_allowance
    for bx, by in ((FIELD.half_length, -FIELD.half_width), (FIELD.half_length, FIELD.half_width)):
        aim = sk.feasible_aim(bx, by)
        heading = sk.lineup_heading(bx, by, aim)
        assert heading is not None and abs(math.remainder(aim - heading, math.tau)) <= sk.params.side_kick + 1e-9
        d = sk.params.approach_distance
        sx, sy = bx - d * math.cos(heading), by - d * math.sin(heading)
        assert abs(sx) <= lim_x + 1e-9 and abs(sy) <= lim_y + 1e-9
        m = sk.kick_to_goal(beliefs(3, (sx, sy, heading), (bx, by)))
        assert m.kick is not None and abs(m.kick.direction) > sk.params.kick_alignment  # a side kick
        assert math.sin(heading + m.kick.direction) * -by > 0.0  # along the goal line, toward the goal


def test_walks_never_lead_further_out_at_the_field_limits() -> None:
    sk = Skills(context(3))
    lim_x = FIELD.half_length + sk.params.outside_allowance
    for th in (0.0, 0.7, -2.0, math.pi):
        b = beliefs(3, (lim_x + 0.01, 0.5, th), (4.4, 0.4))
        for fwd, left in ((0.3, 0.0), (0.0, 0.3), (-0.2, 0.2), (0.2, -0.3)):
            f2, l2 = sk._stay_inside(b, fwd, left)
            vx = math.cos(th) * f2 - math.sin(th) * l2  # team frame, along the field
            vy = math.sin(th) * f2 + math.cos(th) * l2
            assert vx <= 1e-12  # never further out past the goal line
            assert vy == pytest.approx(math.sin(th) * fwd + math.cos(th) * left)  # sideways untouched


def test_far_striker_walks_to_the_ball_and_keeper_stays_between_ball_and_goal() -> None:
    sk = Skills(context(3))
    m = sk.kick_to_goal(beliefs(3, (-1.0, 0.0, 0.0), (1.0, 0.0)))
    assert m.kick is None and m.walk.forward > 0.0
    keeper = Skills(context(1))
    for by in (-1.5, 1.5):
        b = beliefs(1, (-4.2, 0.0, 0.0), (-1.0, by))
        walk = keeper.keeper(b).walk
        assert walk.left * by > 0.0  # steps toward the ball's side of the goal


def test_head_scans_when_lost_and_looks_at_a_suspicious_hypothesis() -> None:
    head = HeadControl(context(3))
    yaws = []
    for k in range(20):
        r = head.request(beliefs(3, (0.0, 0.0, 0.0), (1.0, 0.0), lost=True, source="cognition", time=12.0 + k / 30))
        yaws.append(r.yaw)
        assert head.state == "scan"
    assert max(yaws) - min(yaws) > 1.0  # a sweep, not a stare
    head = HeadControl(context(3))
    b = beliefs(3, (0.0, 0.0, 0.0), (1.0, 0.0), source="cognition", look_at=(1.0, 1.0), time=13.9)
    r = head.request(b)
    assert head.state == "look_at" and r.yaw == pytest.approx(math.pi / 4, abs=0.05)
    truth = HeadControl(context(3))
    truth.request(beliefs(3, (0.0, 0.0, 0.0), (1.0, 0.0), lost=True, time=12.0))
    assert truth.state != "scan"  # truth beliefs never need landmarks


def _match(seed: int, minutes: float, home: str, away: str) -> tuple[int, int]:
    cfg = MatchConfig(seed=seed, observation="none", referee=RefereeParams(half_seconds=30.0 * minutes))
    kinds = {"scripted": scripted_brains(None), "random": random_brains}
    h, a = kinds[home], kinds[away]
    s = Match(cfg, brains=lambda t, n: h(t, n) if t == 0 else a(t, n)).run()
    return s.score


@pytest.mark.slow(seconds=50)
def test_scripted_team_beats_random_walkers() -> None:
    # once at home and once away: the away team plays in the mirrored frame and kicks off second
    home = _match(0, 3.0, "scripted", "random")
    away = _match(1, 3.0, "random", "scripted")
    assert home[0] >= home[1] + 3 and away[1] >= away[0] + 3, (home, away)


@pytest.mark.slow(seconds=55)
def test_scripted_vs_scripted_is_a_live_game() -> None:
    # equal teams: neither defence is impenetrable (that both sides can score is checked above)
    score = _match(0, 10.0, "scripted", "scripted")
    assert sum(score) >= 1, score


def test_random_walkers_are_deterministic_per_seed() -> None:
    def final(seed: int) -> list[tuple[float, float, float]]:
        m = Match(MatchConfig(seed=seed, observation="none", players="random", players_per_team=2))
        m.run(until=70.0)
        return [r.pose for r in m.world.robots]

    assert final(3) == final(3) and final(3) != final(4)


def test_scripted_players_on_percepts_reach_the_ball() -> None:
    cfg = MatchConfig(
        seed=2, players_per_team=3, cognition=CognitionConfig(), referee=RefereeParams(half_seconds=120.0)
    )
    m = Match(cfg)
    m.run(until=90.0)
    assert m.referee.counters.kickoffs  # the game reached PLAYING
    errors = m.localization_errors.summary()
    assert errors is not None and errors.position_error_mean < 0.5
    kicks = sum(1 for e in m.log.events if e.kind in ("kick", "goal"))
    moved = math.hypot(*m.world.ball.position) > 0.3 or kicks > 0
    assert moved


def _free_spot_reference(obstacles: list[list[float]], tx: float, ty: float, space: float) -> tuple[float, float]:
    """The personal-space rule as first written: math.hypot for every obstacle."""
    for ox, oy in obstacles:
        dx, dy = tx - ox, ty - oy
        d = math.hypot(dx, dy)
        if d >= space:
            continue
        if d < 1e-6:
            dx, dy, d = -ox, -oy, max(1e-6, math.hypot(ox, oy))
        tx, ty = ox + dx / d * space, oy + dy / d * space
    return tx, ty


def test_free_spot_skips_far_obstacles_without_changing_a_bit() -> None:
    """The squared-distance shortcut of ``_free_spot`` gives the reference's target to the bit,
    for random obstacles and targets, obstacles on the target, and distances at the boundary
    (exactly ``space`` away, and one ulp either side)."""
    from cognition.behaviors.skills import _free_spot

    g = np.random.default_rng(11)
    moved = 0
    for _ in range(3000):
        space = float(g.choice([0.3, 0.45, 0.6]))
        obstacles = g.uniform(-1.5, 1.5, (int(g.integers(0, 12)), 2)).tolist()
        tx, ty = g.uniform(-1.5, 1.5, 2).tolist()
        if obstacles and g.random() < 0.3:  # a target on the boundary of an obstacle's space
            ox, oy = obstacles[0]
            a = g.uniform(-math.pi, math.pi)
            r = float(np.nextafter(space, [0.0, space, 9.0][int(g.integers(0, 3))]))
            tx, ty = ox + r * math.cos(a), oy + r * math.sin(a)
        if obstacles and g.random() < 0.05:
            tx, ty = obstacles[-1]
        got, want = _free_spot(obstacles, tx, ty, space), _free_spot_reference(obstacles, tx, ty, space)
        assert got == want, (obstacles, tx, ty, space)
        moved += want != (tx, ty)
    assert moved > 300  # the rule acted often
