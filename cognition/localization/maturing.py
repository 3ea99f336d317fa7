"""Particle maturing (Darmstadt paper, Sec. VI): candidate poses earn their place first.

A pose generated from a single observation (sensor resetting, :mod:`resetting`) is often
wrong: a crossing or a white post fits several places. Instead of replacing particles at
once, such poses become *candidates*. Every frame each candidate is moved by the odometry
and scored against that frame's observations with the strict sensor model (pure Gaussians:
confidence 1, no floors, so an inconsistent candidate cannot hide behind them); a candidate
whose per-observation likelihood exp(ll / K) reaches ``maturing_consistency`` is kept, any
other is dropped. The paper asks for consistent observations of *different features*: a kept
candidate counts one more consistent frame only when the frame shows a landmark (post,
crossing, centre circle, penalty mark, pole). Lines alone fit too many poses: when frames of
lines counted, candidates far from the robot matured while it saw only lines and took an
accurate estimate away (5 v 5 image matches). The free places are refilled from vision in
batches (when at least a quarter of them is free). Candidates with at least
``maturing_threshold`` consistent frames may replace particles at the next resampling
(:func:`kernels.inject_matured_nb`).

Everything per frame is one compiled call (:func:`mature_nb`, or :func:`move_candidates_nb`
on a frame without observations): the candidates live in a fixed buffer (C x 3 poses,
team frame, m and rad; C ages in frames), the first ``nc`` rows in use.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from cognition.localization import kernels as K  # noqa: N812 - short kernel namespace
from cognition.localization.resetting import _from_vision_nb
from cognition.localization.sensor import O, T

_CONF, _FLOOR, _TYPE = int(O.CONF), int(O.FLOOR), int(O.TYPE)
_LINE = int(T.LINE)


@nb.njit(cache=True, error_model="python", fastmath=False)
def move_candidates_nb(cand, nc, dx, dy, dth):  # pragma: no cover - compiled
    """Move the first ``nc`` candidate poses by the odometry (dx, dy m in the robot's frame
    of the previous frame, dth rad)."""
    for i in range(nc):
        c, s = math.cos(cand[i, 2]), math.sin(cand[i, 2])
        cand[i, 0] += c * dx - s * dy
        cand[i, 1] += s * dx + c * dy
        cand[i, 2] = (cand[i, 2] + dth + math.pi) % (2 * math.pi) - math.pi


@nb.njit(cache=True, error_model="python", fastmath=False)
def mature_nb(
    cand,
    count,
    nc,
    obs,
    dx,
    dy,
    dth,
    consistency,
    hough,
    posts,
    crossings,
    lines,
    marks,
    poles,
    cross_grid,
    line_grid,
    geo,
    ll,
    scratch,
    state,
):  # pragma: no cover - compiled
    """One frame of the candidates (module docstring) in place; returns the new ``nc``.

    ``cand`` (C x 3) and ``count`` (C) are the buffers, ``obs`` the frame's observation rows
    (K >= 1, :class:`~cognition.localization.sensor.O`), the map arrays those of
    :class:`~cognition.localization.fieldmodel.FieldModel`; ``ll`` (>= C) and ``scratch``
    (10 x >= C) are work space, ``state`` the filter's xorshift64* state.
    """
    move_candidates_nb(cand, nc, dx, dy, dth)
    k = obs.shape[0]
    if nc:
        strict = obs.copy()
        for r in range(k):
            strict[r, _CONF] = 1.0
            strict[r, _FLOOR] = 0.0
        w = np.full(nc, 1.0 / nc)
        K.log_likelihood_nb(
            cand, nc, strict, hough, posts, crossings, lines, marks, poles, cross_grid, line_grid, geo, ll, scratch,
            w, np.empty(k),
        )  # fmt: skip
        landmark = 0
        for r in range(k):
            if obs[r, _TYPE] != _LINE:
                landmark = 1
        kept = 0
        for i in range(nc):
            if math.exp(ll[i] / k) >= consistency:
                cand[kept, 0], cand[kept, 1], cand[kept, 2] = cand[i, 0], cand[i, 1], cand[i, 2]
                count[kept] = count[i] + landmark
                kept += 1
        nc = kept
    cap = cand.shape[0]
    room = cap - nc
    if room >= max(1, cap // 4):  # refill in batches, not every frame
        fresh = _from_vision_nb(posts, crossings, marks, poles, obs, room, True, state)
        for i in range(fresh.shape[0]):
            cand[nc, 0], cand[nc, 1], cand[nc, 2] = fresh[i, 0], fresh[i, 1], fresh[i, 2]
            count[nc] = 0
            nc += 1
    return nc
