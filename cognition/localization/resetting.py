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

Every pose is one a robot can stand at: on the carpet (the field and its border strip) and not
inside a goal (``FieldModel.geo[8:12]``); a sample elsewhere is dropped, so fewer than asked may
come back (not in the papers). A circle of the measured distance around a far landmark reaches
well beyond the goal lines: poses behind the goals explained a robot's few lines and one
crossing as well as its true pose and became ``maturing`` candidates that took accurate
estimates away (5 v 5 image matches, whose vision finds penalty marks up to 3 m away).

The injection strategy :class:`SensorResetting` (variant ``reset``) puts these poses into the
particle filter: the AMCL share (:mod:`.amcl`), at least ``reset_probability`` while lost, and a
particle count that adapts to the evidence.

Noise from the observation's own distance and bearing sigmas is added to every sample.
Ambiguous features (white goals, crossings, marks) draw their map landmark at random for
every sample, so samples appear at every symmetric place at once.
All poses are (x m, y m, theta rad) in the team frame; observations in the robot frame.

The samplers are compiled (numba) and draw from the filter's own xorshift64* state
(:func:`kernels.rand_u`, :func:`kernels.rand_n`, a uint64 array of length 1) like the other
particle-filter kernels: they run at most frames of the ``maturing`` and ``reset`` filters,
where the Python loop over samples cost hundreds of microseconds per frame, and passing a
``numpy.random.Generator`` into compiled code costs over 20 us per call.
``tests/test_resetting.py`` checks them draw for draw against a plain Python reference.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.localization.amcl import AMCLInjection
from cognition.localization.fieldmodel import FieldModel
from cognition.localization.kernels import rand_index, rand_n, rand_u
from cognition.localization.sensor import O, T
from cognition.localization.strategy import FilterView
from cognition.representations import RobotPose

_POST, _CROSS, _LINE, _CIRCLE, _MARK, _POLE = (
    int(T.POST),
    int(T.CROSS),
    int(T.LINE),
    int(T.CIRCLE),
    int(T.MARK),
    int(T.POLE),
)
_TYPE, _X, _Y, _A, _B = int(O.TYPE), int(O.X), int(O.Y), int(O.A), int(O.B)
_SR, _SB, _DIST, _BEAR = int(O.SR), int(O.SB), int(O.DIST), int(O.BEAR)


@nb.njit(cache=True, error_model="python", fastmath=False)
def _post_candidates(posts, ob):  # pragma: no cover - compiled
    """Indices of the map posts (``FieldModel.posts`` rows) observation ``ob`` may be."""
    side, goal = ob[_A], ob[_B]
    out = np.empty(posts.shape[0], dtype=np.int64)
    k = 0
    for i in range(posts.shape[0]):
        if side > 0.5 and posts[i, 2] != side:
            continue
        if goal > -0.5 and posts[i, 3] != goal:
            continue
        out[k] = i
        k += 1
    return out[:k]


@nb.njit(cache=True, error_model="python", fastmath=False)
def _landmarks(posts, crossings, marks, poles, ob):  # pragma: no cover - compiled
    """Map positions (K x 2, team frame, m) a single observation may be."""
    t = int(ob[_TYPE])
    if t == _POST:
        idx = _post_candidates(posts, ob)
        out = np.empty((idx.shape[0], 2))
        for k in range(idx.shape[0]):
            out[k, 0], out[k, 1] = posts[idx[k], 0], posts[idx[k], 1]
        return out
    if t == _CROSS:
        n = 0
        for i in range(crossings.shape[0]):
            if crossings[i, 3] == ob[_A]:
                n += 1
        out = np.empty((n, 2))
        n = 0
        for i in range(crossings.shape[0]):
            if crossings[i, 3] == ob[_A]:
                out[n, 0], out[n, 1] = crossings[i, 0], crossings[i, 1]
                n += 1
        return out
    if t == _CIRCLE:
        return np.zeros((1, 2))
    if t == _MARK:
        return marks.copy()
    if t == _POLE:
        return poles.copy()
    return np.zeros((0, 2))


@nb.njit(cache=True, error_model="python", fastmath=False)
def _standable(x, y, geo):  # pragma: no cover - compiled
    """Whether a robot can stand at (x, y) (m, team frame): on the carpet (``geo[8]``, ``geo[9]``:
    its half extents) and not inside a goal (``geo[10]``: half width to the posts' outer sides,
    ``geo[11]``: depth behind the goal line at ``geo[6]``)."""
    ax = abs(x)
    in_goal = geo[6] < ax < geo[6] + geo[11] and abs(y) < geo[10]
    return ax <= geo[8] and abs(y) <= geo[9] and not in_goal


@nb.njit(cache=True, error_model="python", fastmath=False)
def _around_feature_nb(posts, crossings, marks, poles, ob, m, geo, state):  # pragma: no cover - compiled
    """See :func:`around_feature`."""
    lm = _landmarks(posts, crossings, marks, poles, ob)
    if lm.shape[0] == 0 or m <= 0:
        return np.zeros((0, 3))
    out = np.empty((m, 3))
    n_lm = lm.shape[0]
    k = 0
    for _ in range(m):
        pick = rand_index(state, n_lm)
        d = max(ob[_DIST] + ob[_SR] * rand_n(state), 0.05)
        bear = ob[_BEAR] + ob[_SB] * rand_n(state)
        phi = -math.pi + 2.0 * math.pi * rand_u(state)
        c, s = math.cos(phi), math.sin(phi)
        px, py = lm[pick, 0] + d * c, lm[pick, 1] + d * s
        if not _standable(px, py, geo):
            continue
        out[k, 0], out[k, 1] = px, py
        out[k, 2] = (math.atan2(-s, -c) - bear + math.pi) % (2 * math.pi) - math.pi
        k += 1
    return out[:k]


@nb.njit(cache=True, error_model="python", fastmath=False)
def _two_posts_nb(posts, a, b, m, geo, state):  # pragma: no cover - compiled
    """See :func:`from_two_posts`."""
    ca, cb = _post_candidates(posts, a), _post_candidates(posts, b)
    pairs = np.empty((ca.shape[0] * cb.shape[0], 2), dtype=np.int64)
    n_pairs = 0
    for i in ca:
        for j in cb:
            if i != j and posts[i, 3] == posts[j, 3]:
                pairs[n_pairs, 0], pairs[n_pairs, 1] = i, j
                n_pairs += 1
    if n_pairs == 0 or m <= 0:
        return np.zeros((0, 3))
    order = math.copysign(1.0, a[_X] * b[_Y] - a[_Y] * b[_X])  # + if b is left of a
    out = np.empty((m, 3))
    k = 0
    for _ in range(4 * m):
        if k == m:
            break
        q = rand_index(state, n_pairs)
        i, j = pairs[q, 0], pairs[q, 1]
        p1x, p1y, p2x, p2y = posts[i, 0], posts[i, 1], posts[j, 0], posts[j, 1]
        r1 = max(a[_DIST] + a[_SR] * rand_n(state), 0.05)
        r2 = max(b[_DIST] + b[_SR] * rand_n(state), 0.05)
        dx, dy = p2x - p1x, p2y - p1y
        dd = math.hypot(dx, dy)
        if dd < 1e-9 or dd > r1 + r2 or dd < abs(r1 - r2):
            continue
        along = (r1 * r1 - r2 * r2 + dd * dd) / (2 * dd)
        h = math.sqrt(max(r1 * r1 - along * along, 0.0))
        bx, by = p1x + along * dx / dd, p1y + along * dy / dd
        ex, ey = -dy / dd, dx / dd
        for sgn in (1.0, -1.0):
            px, py = bx + sgn * h * ex, by + sgn * h * ey
            e1x, e1y, e2x, e2y = p1x - px, p1y - py, p2x - px, p2y - py
            if math.copysign(1.0, e1x * e2y - e1y * e2x) != order or not _standable(px, py, geo):
                continue
            bear = a[_BEAR] + a[_SB] * rand_n(state)
            th = math.atan2(e1y, e1x) - bear
            out[k, 0], out[k, 1] = px, py
            out[k, 2] = (th + math.pi) % (2 * math.pi) - math.pi
            k += 1
            break
    return out[:k]


@nb.njit(cache=True, error_model="python", fastmath=False)
def _from_vision_nb(posts, crossings, marks, poles, obs, m, any_feature, geo, state):  # pragma: no cover - compiled
    """See :func:`from_vision`."""
    if m <= 0 or obs.shape[0] == 0:
        return np.zeros((0, 3))
    first, second, n_posts, n_usable = -1, -1, 0, 0
    for r in range(obs.shape[0]):
        t = obs[r, _TYPE]
        if t == _POST:
            if n_posts == 0:
                first = r
            elif n_posts == 1:
                second = r
            n_posts += 1
        if t != _LINE:
            n_usable += 1
    if n_posts >= 2:
        got = _two_posts_nb(posts, obs[first], obs[second], m, geo, state)
        if got.shape[0]:
            return got
    if n_posts >= 1:
        return _around_feature_nb(posts, crossings, marks, poles, obs[first], m, geo, state)
    if any_feature and n_usable:
        pick = rand_index(state, n_usable)
        for r in range(obs.shape[0]):
            if obs[r, _TYPE] != _LINE:
                if pick == 0:
                    return _around_feature_nb(posts, crossings, marks, poles, obs[r], m, geo, state)
                pick -= 1
    return np.zeros((0, 3))


def around_feature(
    model: FieldModel, ob: NDArray[np.float64], m: int, state: NDArray[np.uint64]
) -> NDArray[np.float64]:
    """Up to ``m`` poses (k x 3) on circles of the measured distance around the landmarks ``ob`` may
    be, those where no robot can stand (off the carpet, inside a goal) dropped (``state``: the
    filter's xorshift64* state, advanced)."""
    return _around_feature_nb(
        model.posts, model.crossings, model.marks, model.poles, _row(ob), int(m), model.geo, state
    )


def from_two_posts(
    model: FieldModel, a: NDArray[np.float64], b: NDArray[np.float64], m: int, state: NDArray[np.uint64]
) -> NDArray[np.float64]:
    """Up to ``m`` poses (k x 3) from two post observations ``a``, ``b`` (circle intersections),
    none where no robot can stand; none at all when the circles meet only there (then
    :func:`from_vision` falls back to the first post alone, as when they do not meet)."""
    return _two_posts_nb(model.posts, _row(a), _row(b), int(m), model.geo, state)


def from_vision(
    model: FieldModel, obs: NDArray[np.float64], m: int, any_feature: bool, state: NDArray[np.uint64]
) -> NDArray[np.float64]:
    """Up to ``m`` reset poses (k x 3) from the observations (two posts, one post, or a random
    feature when ``any_feature``); ``obs``: observation rows (:func:`sensor.pack_observations`)."""
    rows = np.ascontiguousarray(obs, dtype=np.float64)
    return _from_vision_nb(
        model.posts, model.crossings, model.marks, model.poles, rows, int(m), bool(any_feature), model.geo, state
    )


def _row(ob: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.ascontiguousarray(ob, dtype=np.float64)


def resetting_share(share: float, lost: bool, reset_probability: float) -> float:
    """CMU III.D: while the pose is lost at least ``reset_probability`` of the resampled
    particles come from vision; otherwise ``share`` (the AMCL rule, :func:`.amcl.augmented_share`)."""
    return max(share, reset_probability) if lost else share


class SensorResetting(AMCLInjection):
    """CMU III.D sensor resetting: the AMCL share (at least ``reset_probability`` while lost) is
    filled with poses from vision (:func:`from_vision`), and the particle count adapts: it is
    ``ceil(floor / evidence)`` between ``min_particles`` and ``particles`` (the CMU rule: fewer
    particles are drawn as the weights grow)."""

    name = "reset"

    def initial_count(self) -> int:
        return self.params.floor_particles

    def count(self, n: int, w_avg: float) -> int:
        p = self.params
        lo = p.floor_particles
        return int(min(p.particles, max(lo, math.ceil(lo / max(w_avg, 1e-3)))))

    def share(self, w_raw: float, lost: bool) -> float:
        return resetting_share(super().share(w_raw, lost), lost, self.params.reset_probability)

    def inject(self, pf: FilterView, slots: NDArray[np.int64], obs: NDArray[np.float64], pose: RobotPose) -> int:
        p = self.params
        fresh = from_vision(pf.model, obs, slots.shape[0], p.reset_from_any_feature, pf.kernel_state)
        got = int(fresh.shape[0])
        pf.parts[slots[:got]] = pf.away_from_mirror(fresh, pose)
        return got
