"""The compiled sensor-resetting samplers against a plain numpy reference.

The reference below is the plain Python implementation of the same sampling, drawing its
random numbers with the same calls (:func:`kernels.rand_u`, :func:`kernels.rand_n`) from the
same xorshift64* state, so one state must give the same poses and leave the same state. The
observations are random mixes of posts (with and without side and goal), crossings, lines,
the circle and penalty marks around random robot poses on the SPL field.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.typing import NDArray

from cognition.field import make_field
from cognition.localization import kernels as K  # noqa: N812
from cognition.localization.fieldmodel import FieldModel
from cognition.localization.kernels import rand_n, rand_u
from cognition.localization.maturing import mature_nb
from cognition.localization.resetting import around_feature, from_two_posts, from_vision
from cognition.localization.sensor import N_O, O, T


# -- the plain reference --------------------------------------------------------------------
def _ref_candidates(model: FieldModel, ob: NDArray[np.float64]) -> NDArray[np.int64]:
    side, goal = ob[O.A], ob[O.B]
    p = model.posts
    ok = np.ones(p.shape[0], dtype=bool)
    if side > 0.5:
        ok &= p[:, 2] == side
    if goal > -0.5:
        ok &= p[:, 3] == goal
    return np.flatnonzero(ok)


def _ref_landmarks(model: FieldModel, ob: NDArray[np.float64]) -> NDArray[np.float64]:
    t = int(ob[O.TYPE])
    if t == T.POST:
        return model.posts[_ref_candidates(model, ob), :2]
    if t == T.CROSS:
        return model.crossings[model.crossings[:, 3] == ob[O.A], :2]
    if t == T.CIRCLE:
        return np.zeros((1, 2))
    if t == T.MARK:
        return model.marks
    if t == T.POLE:
        return model.poles
    return np.zeros((0, 2))


def ref_around(model: FieldModel, ob: NDArray[np.float64], m: int, state: NDArray[np.uint64]) -> NDArray[np.float64]:
    marks = _ref_landmarks(model, ob)
    if marks.shape[0] == 0 or m <= 0:
        return np.zeros((0, 3))
    out = []
    for _ in range(m):
        pick = marks[min(int(rand_u(state) * marks.shape[0]), marks.shape[0] - 1)]
        d = max(ob[O.DIST] + ob[O.SR] * rand_n(state), 0.05)
        bear = ob[O.BEAR] + ob[O.SB] * rand_n(state)
        phi = -math.pi + 2.0 * math.pi * rand_u(state)
        th = math.atan2(-math.sin(phi), -math.cos(phi)) - bear
        x, y = pick[0] + d * math.cos(phi), pick[1] + d * math.sin(phi)
        if _standable(model, x, y):
            out.append((x, y, (th + math.pi) % (2 * math.pi) - math.pi))
    return np.array(out).reshape(-1, 3)


SPL = make_field("spl2025").dims


def _standable(model: FieldModel, x: float, y: float) -> bool:
    hl, hw = model.geo[6], model.geo[7]
    on_carpet = abs(x) <= hl + SPL.border_strip and abs(y) <= hw + SPL.border_strip
    in_goal = hl < abs(x) < hl + SPL.goal_depth and abs(y) < SPL.goal_inner_width / 2 + SPL.goal_post_diameter
    return on_carpet and not in_goal


def ref_two_posts(
    model: FieldModel, a: NDArray[np.float64], b: NDArray[np.float64], m: int, state: NDArray[np.uint64]
) -> NDArray[np.float64]:
    pairs = [
        (i, j)
        for i in _ref_candidates(model, a)
        for j in _ref_candidates(model, b)
        if i != j and model.posts[i, 3] == model.posts[j, 3]
    ]
    if not pairs or m <= 0:
        return np.zeros((0, 3))
    order = math.copysign(1.0, a[O.X] * b[O.Y] - a[O.Y] * b[O.X])
    out = np.empty((m, 3))
    k = 0
    for _ in range(4 * m):
        if k == m:
            break
        i, j = pairs[min(int(rand_u(state) * len(pairs)), len(pairs) - 1)]
        p1, p2 = model.posts[i, :2], model.posts[j, :2]
        r1 = max(a[O.DIST] + a[O.SR] * rand_n(state), 0.05)
        r2 = max(b[O.DIST] + b[O.SR] * rand_n(state), 0.05)
        dv = p2 - p1
        dd = float(np.hypot(*dv))
        if dd < 1e-9 or dd > r1 + r2 or dd < abs(r1 - r2):
            continue
        along = (r1 * r1 - r2 * r2 + dd * dd) / (2 * dd)
        h = math.sqrt(max(r1 * r1 - along * along, 0.0))
        base = p1 + along * dv / dd
        perp = np.array([-dv[1], dv[0]]) / dd
        for sgn in (1.0, -1.0):
            p = base + sgn * h * perp
            e1, e2 = p1 - p, p2 - p
            if math.copysign(1.0, e1[0] * e2[1] - e1[1] * e2[0]) != order or not _standable(model, p[0], p[1]):
                continue
            bear = a[O.BEAR] + a[O.SB] * rand_n(state)
            th = math.atan2(e1[1], e1[0]) - bear
            out[k] = (p[0], p[1], (th + math.pi) % (2 * math.pi) - math.pi)
            k += 1
            break
    return out[:k]


def ref_from_vision(
    model: FieldModel, obs: NDArray[np.float64], m: int, any_feature: bool, state: NDArray[np.uint64]
) -> NDArray[np.float64]:
    if m <= 0 or obs.shape[0] == 0:
        return np.zeros((0, 3))
    posts = obs[obs[:, O.TYPE] == T.POST]
    if posts.shape[0] >= 2:
        got = ref_two_posts(model, posts[0], posts[1], m, state)
        if got.shape[0]:
            return got
    if posts.shape[0] >= 1:
        return ref_around(model, posts[0], m, state)
    if any_feature:
        usable = obs[obs[:, O.TYPE] != T.LINE]
        if usable.shape[0]:
            return ref_around(model, usable[min(int(rand_u(state) * usable.shape[0]), usable.shape[0] - 1)], m, state)
    return np.zeros((0, 3))


# -- observations of random poses -----------------------------------------------------------
def _observe(
    model: FieldModel, rng: np.random.Generator, pose: tuple[float, float, float] | None = None, lines: bool = True
) -> NDArray[np.float64]:
    """Observation rows of ``pose`` (random if None): posts (side, goal sometimes known),
    crossings of their kind and lines (random points and kinds; unless ``lines`` is off), the circle and
    marks, in a random order with distance noise."""
    if pose is None:
        pose = rng.uniform(-4.5, 4.5), rng.uniform(-3.0, 3.0), rng.uniform(-math.pi, math.pi)
    x, y, th = pose
    c, s = math.cos(th), math.sin(th)
    rows = []

    def add(kind: int, wx: float, wy: float, a: float = 0.0, b: float = -1.0) -> None:
        dx, dy = wx - x, wy - y
        rx, ry = c * dx + s * dy, -s * dx + c * dy
        row = np.zeros(N_O)
        row[O.TYPE], row[O.X], row[O.Y], row[O.A], row[O.B] = kind, rx, ry, a, b
        d = math.hypot(rx, ry) * (1.0 + 0.05 * rng.standard_normal())
        row[O.SR], row[O.SB] = 0.1 + 0.05 * d, 0.05
        row[O.DIST], row[O.BEAR] = d, math.atan2(ry, rx)
        rows.append(row)

    for p in rng.permutation(model.posts.shape[0])[: rng.integers(0, 4)]:
        side = model.posts[p, 2] if rng.random() < 0.6 else 0.0
        goal = model.posts[p, 3] if rng.random() < 0.5 else -1.0
        add(T.POST, model.posts[p, 0], model.posts[p, 1], side, goal)
    for q in rng.permutation(model.crossings.shape[0])[: rng.integers(0, 3) if lines else 0]:
        add(T.CROSS, model.crossings[q, 0], model.crossings[q, 1], model.crossings[q, 3])
    for _ in range(rng.integers(0, 3) if lines else 0):
        add(T.LINE, rng.uniform(-4, 4), rng.uniform(-3, 3))
    if rng.random() < (0.3 if lines else 1.0):
        add(T.CIRCLE, 0.0, 0.0)
    if rng.random() < 0.3:
        k = rng.integers(0, model.marks.shape[0])
        add(T.MARK, model.marks[k, 0], model.marks[k, 1])
    if not rows:
        return np.zeros((0, N_O))
    out = np.array(rows)
    return out[rng.permutation(out.shape[0])]


@pytest.fixture(scope="module")
def model() -> FieldModel:
    return FieldModel(make_field("spl2025"))


def test_from_vision_matches_the_plain_reference_draw_for_draw(model: FieldModel) -> None:
    g = np.random.default_rng(2024)
    kinds = set()
    for trial in range(400):
        obs = _observe(model, g)
        m = int(g.integers(0, 40))
        any_feature = bool(trial % 3)
        seed = int(g.integers(1, 2**63 - 1))
        s1, s2 = np.array([seed], dtype=np.uint64), np.array([seed], dtype=np.uint64)
        got = from_vision(model, obs, m, any_feature, s1)
        want = ref_from_vision(model, obs, m, any_feature, s2)
        assert got.shape == want.shape, (trial, got.shape, want.shape)
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-9)
        assert s1[0] == s2[0], f"trial {trial}: the random states drifted apart"
        kinds.add((int((obs[:, O.TYPE] == T.POST).sum()) if obs.shape[0] else 0, got.shape[0] > 0))
    assert {(0, True), (1, True), (2, True)} <= kinds, kinds  # every branch was taken


def _where_no_robot_stands(poses: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Off the spl2025 carpet (5.2 x 3.7 m half extents) or inside a goal (0.5 m deep, posts' outer
    sides 0.85 m from the axis)."""
    ax, ay = np.abs(poses[:, 0]), np.abs(poses[:, 1])
    return (ax > 5.2) | (ay > 3.7) | ((ax > 4.5) & (ax < 5.0) & (ay < 0.85))


def test_poses_from_vision_are_where_a_robot_can_stand(model: FieldModel) -> None:
    """A penalty mark seen 3 m away puts the robot on a circle that reaches 1.7 m behind the goal
    line (spl2025: mark 1.3 m in front of it, a 0.7 m border strip) and through the goal: those
    samples are dropped, the others kept at the measured distance, and no sampler returns one."""
    row = np.zeros(N_O)
    row[O.TYPE], row[O.X], row[O.DIST] = T.MARK, 3.0, 3.0
    poses = around_feature(model, row, 2000, np.array([5], dtype=np.uint64))
    assert 1000 < poses.shape[0] < 2000  # the arcs behind the goal lines and beyond the touchlines are gone
    assert not _where_no_robot_stands(poses).any()
    marks = model.marks
    d = np.min(np.hypot(poses[:, None, 0] - marks[None, :, 0], poses[:, None, 1] - marks[None, :, 1]), axis=1)
    np.testing.assert_allclose(d, 3.0, atol=1e-9)
    # 1.7 m: the circle stays on the carpet but runs through the goal, where |phi| < 30 degrees: 1/6 is dropped
    row[O.DIST] = 1.7
    poses = around_feature(model, row, 2000, np.array([6], dtype=np.uint64))
    assert 1600 < poses.shape[0] < 1740 and not _where_no_robot_stands(poses).any()
    g = np.random.default_rng(7)
    for _ in range(300):
        obs = _observe(model, g)
        got = from_vision(model, obs, 40, True, np.array([int(g.integers(1, 2**63 - 1))], dtype=np.uint64))
        assert not _where_no_robot_stands(got).any()


def test_two_posts_put_the_robot_where_both_distances_hold(model: FieldModel) -> None:
    """Without noise, the poses from two posts of one goal see both posts at their measured
    distances and the first at its bearing, on the side that keeps their left-right order."""
    x, y, th = 2.0, -1.0, 0.4
    rows = []
    for p in (0, 1):
        dx, dy = model.posts[p, 0] - x, model.posts[p, 1] - y
        rx, ry = math.cos(th) * dx + math.sin(th) * dy, -math.sin(th) * dx + math.cos(th) * dy
        row = np.zeros(N_O)
        row[O.TYPE], row[O.X], row[O.Y], row[O.A], row[O.B] = T.POST, rx, ry, model.posts[p, 2], model.posts[p, 3]
        row[O.DIST], row[O.BEAR] = math.hypot(rx, ry), math.atan2(ry, rx)
        rows.append(row)
    poses = from_two_posts(model, rows[0], rows[1], 20, np.array([7], dtype=np.uint64))
    assert poses.shape == (20, 3)
    np.testing.assert_allclose(poses, np.tile([x, y, th], (20, 1)), atol=1e-9)


def test_around_feature_puts_every_pose_at_the_measured_distance(model: FieldModel) -> None:
    row = np.zeros(N_O)
    row[O.TYPE], row[O.X], row[O.Y], row[O.DIST], row[O.BEAR] = T.CIRCLE, 1.5, 0.0, 1.5, 0.0
    poses = around_feature(model, row, 500, np.array([11], dtype=np.uint64))
    np.testing.assert_allclose(np.hypot(poses[:, 0], poses[:, 1]), 1.5, atol=1e-12)
    # the circle's centre lies straight ahead of every pose
    ahead = np.arctan2(-poses[:, 1], -poses[:, 0]) - poses[:, 2]
    np.testing.assert_allclose(np.mod(ahead + math.pi, 2 * math.pi) - math.pi, 0.0, atol=1e-9)
    assert np.ptp(np.arctan2(poses[:, 1], poses[:, 0])) > 6.0  # all the way around


# -- maturing candidates ----------------------------------------------------------------------
def ref_mature(model, cand, count, adv, obs, estimate, dx, dy, dth, consistency, hough, state):
    """The plain numpy candidate step (the code :func:`maturing.mature_nb` replaced)."""
    if cand.shape[0]:
        c, s = np.cos(cand[:, 2]), np.sin(cand[:, 2])
        cand[:, 0] += c * dx - s * dy
        cand[:, 1] += s * dx + c * dy
        cand[:, 2] = np.mod(cand[:, 2] + dth + math.pi, 2 * math.pi) - math.pi
    nc = cand.shape[0]
    if nc:
        ll = np.empty(nc)
        strict = obs.copy()
        strict[:, O.CONF] = 1.0
        strict[:, O.FLOOR] = 0.0
        m = model
        maps = (m.posts, m.crossings, m.lines, m.marks, m.poles, m.cross_grid, m.line_grid, m.geo)
        K.log_likelihood_nb(
            np.ascontiguousarray(cand), nc, strict, hough, *maps, ll, np.zeros((10, nc)), np.full(nc, 1.0 / nc),
            np.empty(obs.shape[0]),
        )  # fmt: skip
        own = np.empty(nc + 1)
        K.log_likelihood_nb(
            np.vstack([cand, estimate]), nc + 1, obs, hough, *maps, own, np.zeros((6, nc + 1)),
            np.full(nc + 1, 1.0 / (nc + 1)), np.empty(obs.shape[0]),
        )  # fmt: skip
        good = np.exp(ll / obs.shape[0]) >= consistency
        count = np.where(good, count + 1, 0)
        adv = adv + np.column_stack([(own[:nc] - own[nc]) / obs.shape[0], np.ones(nc)])
        keep = good
        cand, count, adv = cand[keep], count[keep], adv[keep]
    return cand, count, adv


def test_maturing_matches_the_plain_reference_over_a_walk(model: FieldModel) -> None:
    """Candidates of a robot walking a straight line, refilled from its observations and
    scored by the compiled step and by the plain one, stay the same frame after frame; some
    survive to maturity, and the wrong ones are dropped."""
    cap, consistency = 40, 0.3
    hough = np.zeros(5)
    g = np.random.default_rng(5)
    cand, count, adv, nc = np.zeros((cap, 3)), np.zeros(cap, dtype=np.int64), np.zeros((cap, 2)), 0
    rc, rn, ra = np.zeros((0, 3)), np.zeros(0, dtype=np.int64), np.zeros((0, 2))
    s1, s2 = np.array([99], dtype=np.uint64), np.array([99], dtype=np.uint64)
    oldest = 0
    x, y, th = -2.0, 1.0, 0.3
    for frame in range(90):
        dx, dy, dth = 0.01, 0.0, 0.002 * (frame % 3)
        x, y, th = x + dx * math.cos(th), y + dx * math.sin(th), th + dth
        obs = _observe(model, g, (x, y, th), lines=False)
        if obs.shape[0] == 0:
            continue
        estimate = np.array([x + 0.05, y - 0.03, th + 0.02])  # a good estimate, a little off
        nc = mature_nb(
            cand, count, adv, nc, obs, estimate, dx, dy, dth, consistency, hough, model.posts, model.crossings,
            model.lines, model.marks, model.poles, model.cross_grid, model.line_grid, model.geo, s1,
        )  # fmt: skip
        rc, rn, ra = ref_mature(model, rc, rn, ra, obs, estimate, dx, dy, dth, consistency, hough, s2)
        room = cap - rc.shape[0]
        if room >= max(1, cap // 4):
            fresh = ref_from_vision(model, obs, room, True, s2)
            rc, rn = np.concatenate([rc, fresh]), np.concatenate([rn, np.zeros(fresh.shape[0], dtype=np.int64)])
            ra = np.concatenate([ra, np.zeros((fresh.shape[0], 2))])
        assert nc == rc.shape[0], frame
        np.testing.assert_allclose(cand[:nc], rc, atol=1e-9)
        np.testing.assert_array_equal(count[:nc], rn)
        np.testing.assert_allclose(adv[:nc], ra, atol=1e-9)
        assert s1[0] == s2[0]
        oldest = max(oldest, int(rn.max(initial=0)))
    assert oldest >= 7  # candidates did mature (the default maturing_threshold)


def test_choose_draws_distinct_indices_uniformly() -> None:
    """Injection slots: ``m`` distinct indices of ``n``, each index equally likely (chi-square
    over 20,000 draws), and the whole range at m = n."""
    from scipy.stats import chisquare

    state = np.array([12345], dtype=np.uint64)
    hits = np.zeros(30, dtype=np.int64)
    for _ in range(20_000):
        got = K.choose_nb(30, 4, state)
        assert len(set(got.tolist())) == 4 and got.min() >= 0 and got.max() < 30
        hits[got] += 1
    assert chisquare(hits).pvalue > 1e-3, hits
    assert sorted(K.choose_nb(7, 7, state).tolist()) == list(range(7))
    assert K.choose_nb(7, 0, state).shape == (0,)
