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
(:func:`inject_matured_nb`); :class:`Maturing` is the filter's injection strategy (variant ``maturing``).

**A candidate must also beat the estimate** (``maturing_beat_estimate``, not in the paper). Each
frame scores the candidates and the filter's own pose estimate with the filter's sensor model
(with its floors); a matured candidate is injected only when its per-observation
log-likelihood minus the estimate's, averaged over the frames it was kept, exceeds
``maturing_margin`` (the filter itself would clearly have preferred it on what the robot saw).
The rule is for frames where the estimate is right but one observation fits it badly (on
images: a line cut by the image border, whose nearest point is the cut end rather than the
map line's foot point): a wrong candidate seeded from such frames (often turned by 90 degrees)
stayed consistent, was injected whenever the evidence dipped, made the robot look lost, being
lost injected more of it, and within a few frames the estimate jumped to it. In 5 v 5 image
matches with 150 s halves (seeds 1 and 3) the estimate jumped from under 0.3 m to over 1 m
error 13 times per match without the rule and once with it; without it, 10-minute halves
(seeds 1 and 2) saw about 50 such jumps per match, and a robot that had jumped often settled on
the mirrored pose for a minute or two. A robot that really was moved is explained far worse by its
estimate than by candidates near its true pose, which pass the margin within their maturing
frames (the kidnapping studies recover as before).

Everything per frame is one compiled call (:func:`mature_nb`, or :func:`move_candidates_nb`
on a frame without observations): the candidates live in a fixed buffer (C x 3 poses,
team frame, m and rad; C ages in frames; C x 2 advantages over the estimate: summed
per-observation log-likelihood difference and kept frames), the first ``nc`` rows in use.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.localization import kernels as K  # noqa: N812 - short kernel namespace
from cognition.localization.amcl import AMCLInjection
from cognition.localization.params import LocalizationParams
from cognition.localization.resetting import _from_vision_nb, resetting_share
from cognition.localization.sensor import O, T
from cognition.localization.strategy import FilterView
from cognition.representations import RobotPose

_TYPE = int(O.TYPE)
_LINE = int(T.LINE)


def maturing_margin(params: LocalizationParams) -> float:
    """The mean advantage a matured candidate must exceed (``maturing_margin``), NaN when
    ``maturing_beat_estimate`` is off (every matured candidate may be injected, as in the paper)."""
    return params.maturing_margin if params.maturing_beat_estimate else math.nan


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
    advantage,
    nc,
    obs,
    estimate,
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
    state,
):  # pragma: no cover - compiled
    """One frame of the candidates (module docstring) in place; returns the new ``nc``.

    ``cand`` (C x 3), ``count`` (C) and ``advantage`` (C x 2: summed advantage, kept frames) are
    the buffers, ``obs`` the frame's observation rows (K >= 1, :class:`~cognition.localization.sensor.O`),
    ``estimate`` the filter's pose this frame (x, y, theta; team frame), the map arrays those of
    :class:`~cognition.localization.fieldmodel.FieldModel`, ``state`` the filter's xorshift64* state.
    """
    move_candidates_nb(cand, nc, dx, dy, dth)
    k = obs.shape[0]
    if nc:
        # one call scores the candidates and the estimate: with the filter's floors into ``own``
        # (the advantage) and, in row 5 of the work space, as pure Gaussians (the strict
        # consistency test: confidence 1 and no floor give the same sum to the bit)
        both = np.empty((nc + 1, 3))
        for i in range(nc):
            both[i, 0], both[i, 1], both[i, 2] = cand[i, 0], cand[i, 1], cand[i, 2]
        both[nc, 0], both[nc, 1], both[nc, 2] = estimate[0], estimate[1], estimate[2]
        own, work = np.empty(nc + 1), np.empty((6, nc + 1))
        K.log_likelihood_nb(
            both, nc + 1, obs, hough, posts, crossings, lines, marks, poles, cross_grid, line_grid, geo, own, work,
            np.full(nc + 1, 1.0 / (nc + 1)), np.empty(k),
        )  # fmt: skip
        strict = work[5]
        landmark = 0
        for r in range(k):
            if obs[r, _TYPE] != _LINE:
                landmark = 1
        kept = 0
        for i in range(nc):
            if math.exp(strict[i] / k) >= consistency:
                cand[kept, 0], cand[kept, 1], cand[kept, 2] = cand[i, 0], cand[i, 1], cand[i, 2]
                count[kept] = count[i] + landmark
                advantage[kept, 0] = advantage[i, 0] + (own[i] - own[nc]) / k
                advantage[kept, 1] = advantage[i, 1] + 1.0
                kept += 1
        nc = kept
    cap = cand.shape[0]
    room = cap - nc
    if room >= max(1, cap // 4):  # refill in batches, not every frame
        fresh = _from_vision_nb(posts, crossings, marks, poles, obs, room, True, geo, state)
        for i in range(fresh.shape[0]):
            cand[nc, 0], cand[nc, 1], cand[nc, 2] = fresh[i, 0], fresh[i, 1], fresh[i, 2]
            count[nc] = 0
            advantage[nc, 0] = advantage[nc, 1] = 0.0
            nc += 1
    return nc


@nb.njit(cache=True, error_model="python", fastmath=False)
def inject_matured_nb(parts, slots, cand, count, advantage, nc, threshold, margin, state):  # pragma: no cover
    """Replace the particles at ``slots`` by poses around the matured candidates (the first
    ``nc`` rows of ``cand`` whose ``count`` reaches ``threshold`` and whose mean advantage over
    the estimate, ``advantage[:, 0] / advantage[:, 1]``, exceeds ``margin`` (NaN: no such test);
    taken in turn; Gaussian noise of 0.05 m and 0.05 rad, as :func:`kernels.gaussian_set_nb`).
    Returns how many were replaced: all of ``slots``, or 0 when no candidate has matured."""
    ready = np.empty((nc, 3))
    k = 0
    for i in range(nc):
        if count[i] >= threshold and not (advantage[i, 0] <= margin * advantage[i, 1]):
            ready[k, 0], ready[k, 1], ready[k, 2] = cand[i, 0], cand[i, 1], cand[i, 2]
            k += 1
    if k == 0:
        return 0
    for i in range(slots.shape[0]):
        c = ready[i % k]
        j = slots[i]
        parts[j, 0] = c[0] + 0.05 * K.rand_n(state)
        parts[j, 1] = c[1] + 0.05 * K.rand_n(state)
        parts[j, 2] = K.wrap(c[2] + 0.05 * K.rand_n(state))
    return slots.shape[0]


class Maturing(AMCLInjection):
    """Darmstadt VI particle maturing (module docstring) as the filter's injection: the AMCL
    share (at least ``reset_probability`` while lost, as in sensor resetting) is filled with
    poses around the candidates that have matured; with none matured nothing is injected."""

    name = "maturing"

    def __init__(self, params: LocalizationParams) -> None:
        super().__init__(params)
        self.cand = np.zeros((params.maturing_candidates, 3))
        """Candidate poses (buffer; the first :attr:`nc` rows are in use)."""
        self.ages = np.zeros(params.maturing_candidates, dtype=np.int64)
        """Consistent frames with a landmark of each candidate."""
        self.advantage = np.zeros((params.maturing_candidates, 2))
        """Each candidate's summed per-observation log-likelihood minus the estimate's over its kept
        frames, and the number of those frames."""
        self.in_use = np.zeros(1, dtype=np.int64)
        """:attr:`nc` as an array, which the compiled frame (:mod:`.frame_step`) updates in place."""

    @property
    def nc(self) -> int:
        """Candidates in use (the first rows of :attr:`cand`)."""
        return int(self.in_use[0])

    @nc.setter
    def nc(self, value: int) -> None:
        self.in_use[0] = value

    def observe(self, pf: FilterView, obs: NDArray[np.float64], dx: float, dy: float, dth: float) -> None:
        """Move the candidates by the odometry and, on a frame with observations, score, drop
        and refill them (:func:`mature_nb`) against the filter's estimate of this frame."""
        if obs.shape[0]:
            self.nc = mature_nb(
                self.cand, self.ages, self.advantage, self.nc, obs, pf.estimate, dx, dy, dth,
                self.params.maturing_consistency, pf.hough_params, *pf.maps, pf.kernel_state,
            )  # fmt: skip
        else:
            move_candidates_nb(self.cand, self.nc, dx, dy, dth)

    def share(self, w_raw: float, lost: bool) -> float:
        return resetting_share(super().share(w_raw, lost), lost, self.params.reset_probability)

    def inject(self, pf: FilterView, slots: NDArray[np.int64], obs: NDArray[np.float64], pose: RobotPose) -> int:
        threshold = self.params.maturing_threshold
        got = int(
            inject_matured_nb(
                pf.parts, slots, self.cand, self.ages, self.advantage, self.nc, threshold, maturing_margin(self.params),
                pf.kernel_state,
            )
        )  # fmt: skip
        if got:
            pf.parts[slots] = pf.away_from_mirror(pf.parts[slots], pose)
        return got

    def forget(self) -> None:
        super().forget()
        self.nc = 0

    def side_switch(self) -> None:
        c = self.cand[: self.nc]
        c[:, :2] *= -1.0
        c[:, 2] = np.mod(c[:, 2] + 2.0 * math.pi, 2.0 * math.pi) - math.pi
