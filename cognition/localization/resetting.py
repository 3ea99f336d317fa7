"""Poses generated from what the robot sees (sensor resetting).

* **Two goal posts** (CMU III.D): the robot stands where the circles of the two measured
  distances around the two map posts intersect; of the two intersections the one that
  reproduces the observed left-to-right order of the posts is kept; the heading follows
  from the bearing of the first post.
* **One goal post** (CMU III.D): a random point on the circle of the measured distance
  around a candidate post; the heading follows from the bearing.
* **One random feature of any kind** (DNT 4.5): as for one post, around a random map
  landmark of the feature's type (crossing of the same kind, penalty mark, centre circle,
  corner pole).

Noise from the observation's own distance and bearing sigmas is added to every sample.
Ambiguous features (white goals, crossings, marks) draw their map landmark at random for
every sample, so samples appear at every symmetric place at once.
All poses are (x m, y m, theta rad) in the team frame; observations in the robot frame.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from cognition.localization.fieldmodel import FieldModel
from cognition.localization.sensor import O, T


def _post_candidates(model: FieldModel, ob: NDArray[np.float64]) -> NDArray[np.int64]:
    side, goal = ob[O.A], ob[O.B]
    p = model.posts
    ok = np.ones(p.shape[0], dtype=bool)
    if side > 0.5:
        ok &= p[:, 2] == side
    if goal > -0.5:
        ok &= p[:, 3] == goal
    return np.flatnonzero(ok)


def _landmarks(model: FieldModel, ob: NDArray[np.float64]) -> NDArray[np.float64]:
    """Map positions (K x 2) a single observation may be."""
    t = int(ob[O.TYPE])
    if t == T.POST:
        return model.posts[_post_candidates(model, ob), :2]
    if t == T.CROSS:
        return model.crossings[model.crossings[:, 3] == ob[O.A], :2]
    if t == T.CIRCLE:
        return np.zeros((1, 2))
    if t == T.MARK:
        return model.marks
    if t == T.POLE:
        return model.poles
    return np.zeros((0, 2))


def around_feature(model: FieldModel, ob: NDArray[np.float64], m: int, rng: np.random.Generator) -> NDArray[np.float64]:
    """``m`` poses on circles of the measured distance around the landmarks ``ob`` may be."""
    marks = _landmarks(model, ob)
    if marks.shape[0] == 0 or m <= 0:
        return np.zeros((0, 3))
    pick = marks[rng.integers(0, marks.shape[0], m)]
    d = np.maximum(ob[O.DIST] + ob[O.SR] * rng.standard_normal(m), 0.05)
    bear = ob[O.BEAR] + ob[O.SB] * rng.standard_normal(m)
    phi = rng.uniform(-math.pi, math.pi, m)
    x = pick[:, 0] + d * np.cos(phi)
    y = pick[:, 1] + d * np.sin(phi)
    th = np.arctan2(-np.sin(phi), -np.cos(phi)) - bear
    return np.column_stack([x, y, np.mod(th + math.pi, 2 * math.pi) - math.pi])


def from_two_posts(
    model: FieldModel, a: NDArray[np.float64], b: NDArray[np.float64], m: int, rng: np.random.Generator
) -> NDArray[np.float64]:
    """``m`` poses from two post observations ``a``, ``b`` (circle intersections)."""
    pairs = [
        (i, j)
        for i in _post_candidates(model, a)
        for j in _post_candidates(model, b)
        if i != j and model.posts[i, 3] == model.posts[j, 3]
    ]
    if not pairs or m <= 0:
        return np.zeros((0, 3))
    order = math.copysign(1.0, a[O.X] * b[O.Y] - a[O.Y] * b[O.X])  # + if b is left of a
    out = np.empty((m, 3))
    k = 0
    for _ in range(4 * m):
        if k == m:
            break
        i, j = pairs[int(rng.integers(0, len(pairs)))]
        p1, p2 = model.posts[i, :2], model.posts[j, :2]
        r1 = max(a[O.DIST] + a[O.SR] * rng.standard_normal(), 0.05)
        r2 = max(b[O.DIST] + b[O.SR] * rng.standard_normal(), 0.05)
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
            if math.copysign(1.0, e1[0] * e2[1] - e1[1] * e2[0]) != order:
                continue
            bear = a[O.BEAR] + a[O.SB] * rng.standard_normal()
            th = math.atan2(e1[1], e1[0]) - bear
            out[k] = (p[0], p[1], (th + math.pi) % (2 * math.pi) - math.pi)
            k += 1
            break
    return out[:k]


def from_vision(
    model: FieldModel, obs: NDArray[np.float64], m: int, any_feature: bool, rng: np.random.Generator
) -> NDArray[np.float64]:
    """Up to ``m`` reset poses from the observations (two posts, one post, or a random feature)."""
    if m <= 0 or obs.shape[0] == 0:
        return np.zeros((0, 3))
    posts = obs[obs[:, O.TYPE] == T.POST]
    if posts.shape[0] >= 2:
        got = from_two_posts(model, posts[0], posts[1], m, rng)
        if got.shape[0]:
            return got
    if posts.shape[0] >= 1:
        return around_feature(model, posts[0], m, rng)
    if any_feature:
        usable = obs[obs[:, O.TYPE] != T.LINE]
        if usable.shape[0]:
            return around_feature(model, usable[int(rng.integers(0, usable.shape[0]))], m, rng)
    return np.zeros((0, 3))
