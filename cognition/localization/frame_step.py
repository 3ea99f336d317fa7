"""The particle filter's whole frame in one compiled call (two at some resamplings), for the built-in strategies.

:meth:`ParticleFilter._update <cognition.localization.particle_filter.ParticleFilter>` runs a
frame as a sequence of steps: pack the observations (:mod:`.sensor`), the frame up to the
pose (:func:`.kernels.frame_nb`), the injection strategy's ``observe``, the safety net
(:func:`watch_nb`), and at a resampling the strategy's ``count`` and ``share``, the binomial
draw of the number of poses to inject, the resampling (:func:`.resample.resample_nb`) and the
strategy's ``inject``. Each step is a Python call around a kernel, some twenty microseconds per
robot-frame in all (``ParticleFilter._update_by_steps``). :func:`frame_step_nb` runs the same
steps in one call, in the same order, with the same random streams and the same arithmetic,
so a filter gives the same numbers to the bit on either path (``tests/test_frame_step.py``).
One draw stays in Python: the number of poses to inject comes from the filter's numpy
``Generator``, which numba takes as an argument only through Python code (about 14 µs a call,
more than the whole frame's Python). So at a resampling with a share above 0 the kernel
returns before resampling, the caller draws, and :func:`resample_step_nb` finishes the frame.

The built-in strategies (:mod:`.strategy`, :mod:`.amcl`, :mod:`.resetting`, :mod:`.maturing`)
differ in a few numbers, which :func:`knobs` reads from the strategy and the parameters, not
in code: whether the evidence averages of AMCL are kept, the share while lost (sensor
resetting), the adaptive count's floor (CMU III.D), the candidates' buffer (particle
maturing; empty for the others) and where injected poses come from (:data:`SOURCES`). A
strategy of another class (a user's subclass of :class:`~.strategy.Injection`) keeps the
Python steps. The game-controller events, the pose record and the safety net's rare
relocalization stay in Python. Poses are (x m, y m, theta rad) in the team frame.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.localization import kernels as K  # noqa: N812 - short kernel namespace
from cognition.localization.amcl import AMCLInjection
from cognition.localization.kld import bin_masses_nb, kld_count_nb
from cognition.localization.maturing import Maturing, inject_matured_nb, mature_nb, maturing_margin, move_candidates_nb
from cognition.localization.params import LocalizationParams
from cognition.localization.resample import resample_nb
from cognition.localization.resetting import SensorResetting, _from_vision_nb
from cognition.localization.sensor import pack_nb
from cognition.localization.strategy import Injection

MIRROR_RADIUS = 3.0
"""Injected poses (from vision, matured candidates, the safety net's random ones) within this
distance of the estimate's mirror image, and nearer to it than to the estimate, are mirrored
onto the estimate. Distances between poses are in metres with the heading difference counted
at :data:`MIRROR_HEADING_SCALE`."""
MIRROR_HEADING_SCALE = 1.0
"""Metres per radian of heading difference in the mirror guard's pose distance: a pose at the
estimate's position but turned by 180 degrees is pi m from it."""
WATCH_MIN_FRAMES = 5
"""Observed frames the safety net needs in its window before it may act."""
WATCH_MIN_SPAN = 0.8
"""Share of ``relocalize_seconds`` the safety net's window must span before it may act."""

SOURCES = {"none": 0.0, "uniform": 1.0, "vision": 2.0, "matured": 3.0}
"""Where a strategy's injected poses come from: nowhere (``mcl``, ``lowvar``), uniform over the
field (AMCL), vision (sensor resetting), the matured candidates (particle maturing)."""

(
    C_LOST_SPREAD, C_INTERVAL, C_WINDOW, C_RELOCALIZE_SHARE, C_PARTICLES, C_INJECTION_MAX, C_ALPHA_SLOW,
    C_ALPHA_FAST, C_AVERAGES, C_LOST_SHARE, C_COUNT_FLOOR, C_KLD, C_KLD_MIN, C_KLD_EPSILON, C_KLD_Z, C_KLD_BIN_XY,
    C_KLD_BIN_THETA, C_LOW_VARIANCE, C_JITTER_XY, C_JITTER_THETA, C_SOURCE, C_CONSISTENCY, C_THRESHOLD,
    C_ANY_FEATURE, C_HALF_LENGTH, C_HALF_WIDTH, C_MARGIN, N_KNOBS,
) = range(28)  # fmt: skip
"""Entries of the knob array (:func:`knobs`)."""

R_HEAD, R_COUNT, R_UNEXPLAINED, R_OBSERVED, R_RELOCALIZE = range(5)
"""Entries of the safety net's state (:func:`watch_nb`)."""

_BUILT_IN: dict[type[Injection], float] = {
    Injection: SOURCES["none"],
    AMCLInjection: SOURCES["uniform"],
    SensorResetting: SOURCES["vision"],
    Maturing: SOURCES["matured"],
}


def knobs(
    injection: Injection, params: LocalizationParams, low_variance: bool, half_length: float, half_width: float
) -> NDArray[np.float64] | None:
    """The numbers :func:`frame_step_nb` runs ``injection`` (a built-in strategy, exactly of its
    class) with; ``None`` for any other strategy, which keeps the Python steps."""
    source = _BUILT_IN.get(type(injection))
    if source is None:
        return None
    p = params
    k = np.zeros(N_KNOBS)
    k[C_LOST_SPREAD], k[C_INTERVAL] = p.lost_spread, p.resample_interval
    k[C_WINDOW], k[C_RELOCALIZE_SHARE] = p.relocalize_seconds, p.relocalize_share
    k[C_PARTICLES], k[C_INJECTION_MAX] = p.particles, p.injection_max
    k[C_ALPHA_SLOW], k[C_ALPHA_FAST] = p.alpha_slow, p.alpha_fast
    k[C_AVERAGES] = 1.0 if source != SOURCES["none"] else 0.0  # AMCL and the strategies built on it
    k[C_LOST_SHARE] = p.reset_probability if source in (SOURCES["vision"], SOURCES["matured"]) else -1.0
    k[C_COUNT_FLOOR] = p.floor_particles if source == SOURCES["vision"] else 0.0
    k[C_KLD], k[C_KLD_MIN] = (1.0 if p.kld else 0.0), p.kld_min_particles
    k[C_KLD_EPSILON], k[C_KLD_Z] = p.kld_epsilon, p.kld_z
    k[C_KLD_BIN_XY], k[C_KLD_BIN_THETA] = p.kld_bin_xy, p.kld_bin_theta
    k[C_LOW_VARIANCE] = 1.0 if low_variance else 0.0
    k[C_JITTER_XY], k[C_JITTER_THETA] = p.resample_jitter_xy, p.resample_jitter_theta
    k[C_SOURCE], k[C_CONSISTENCY], k[C_THRESHOLD] = source, p.maturing_consistency, p.maturing_threshold
    k[C_ANY_FEATURE] = 1.0 if p.reset_from_any_feature else 0.0
    k[C_HALF_LENGTH], k[C_HALF_WIDTH] = half_length, half_width
    k[C_MARGIN] = maturing_margin(p)
    return k


@nb.njit(cache=True, error_model="python", fastmath=False)
def watch_nb(now, unexplained, observed, window, share, times, bad, seen, state):  # pragma: no cover - compiled
    """The safety net's window (:mod:`.particle_filter`): add the frame at ``now`` (s) with
    ``unexplained`` of its ``observed`` observations, drop the frames older than ``window``
    seconds, and set ``state[R_RELOCALIZE]`` (emptying the window) when at least
    :data:`WATCH_MIN_FRAMES` frames spanning :data:`WATCH_MIN_SPAN` of the window are in it and
    at least ``share`` of their observations were unexplained. ``times``, ``bad``, ``seen`` are
    a ring buffer (``state``: head, frames in it, its sums of unexplained and observed); the
    caller keeps a free place in it (:func:`grow_ring`). Nothing happens for ``window`` <= 0."""
    if window <= 0.0:
        return
    cap = times.shape[0]
    head, count = state[R_HEAD], state[R_COUNT]
    j = (head + count) % cap
    times[j], bad[j], seen[j] = now, unexplained, observed
    count += 1
    u, o = state[R_UNEXPLAINED] + unexplained, state[R_OBSERVED] + observed  # integers: exact sums
    start = now - window
    while times[head] < start:  # the frame just added is never older than the window
        u -= bad[head]
        o -= seen[head]
        head = (head + 1) % cap
        count -= 1
    if count >= WATCH_MIN_FRAMES and now - times[head] >= WATCH_MIN_SPAN * window and u >= share * o:
        state[R_RELOCALIZE] = 1
        head = count = u = o = 0
    state[R_HEAD], state[R_COUNT], state[R_UNEXPLAINED], state[R_OBSERVED] = head, count, u, o


def grow_ring(
    times: NDArray[np.float64], bad: NDArray[np.int64], seen: NDArray[np.int64], state: NDArray[np.int64]
) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.int64]]:
    """The ring buffer of :func:`watch_nb` with room for one more frame: the same arrays when
    they have it, else arrays of twice the size holding the frames in order from index 0."""
    cap = times.shape[0]
    count = int(state[R_COUNT])
    if count < cap:
        return times, bad, seen
    order = (int(state[R_HEAD]) + np.arange(count)) % cap
    out = (np.zeros(2 * cap), np.zeros(2 * cap, dtype=np.int64), np.zeros(2 * cap, dtype=np.int64))
    out[0][:count], out[1][:count], out[2][:count] = times[order], bad[order], seen[order]
    state[R_HEAD] = 0
    return out


@nb.njit(cache=True, error_model="python", fastmath=False)
def away_from_mirror_nb(poses, rows, x, y, th):  # pragma: no cover - compiled
    """Mirror (px, py, ptheta) -> (-px, -py, ptheta + pi) every pose of ``poses[rows]`` that lies
    within :data:`MIRROR_RADIUS` of the mirror image (-x, -y, th + pi) of the estimate
    (x, y, th) and nearer to it than to the estimate, in place (``ParticleFilter.away_from_mirror``,
    row by row). A pose and its mirror image explain every percept alike; of the two, the one
    nearer the estimate is kept.

    The distance counts the heading (:data:`MIRROR_HEADING_SCALE`) as well as the position.
    Near the centre spot the estimate and its mirror image are close in position, so the
    position alone cannot tell them apart: a pose beside the estimate facing its way must stay,
    and one beside it facing the other way (the mirror image of a pose beside the estimate's
    mirror image) must be turned back, or a robot at kickoff is flipped by 180 degrees."""
    k = MIRROR_HEADING_SCALE
    for r in rows:
        px, py = poses[r, 0], poses[r, 1]
        de = np.mod(poses[r, 2] - th + math.pi, 2.0 * math.pi) - math.pi  # heading from the estimate's
        dm = np.mod(de, 2.0 * math.pi) - math.pi  # from the mirror image's (th + pi)
        d_mirror = math.sqrt((px + x) ** 2 + (py + y) ** 2 + (k * dm) ** 2)
        d_estimate = math.sqrt((px - x) ** 2 + (py - y) ** 2 + (k * de) ** 2)
        if d_mirror < MIRROR_RADIUS and d_mirror < d_estimate:
            poses[r, 0] = -px
            poses[r, 1] = -py
            poses[r, 2] = np.mod(poses[r, 2] + 2.0 * math.pi, 2.0 * math.pi) - math.pi


@nb.njit(cache=True, error_model="python", fastmath=False)
def _inject_nb(
    parts, slots, m, source, obs, x, y, th, own_half, kn, posts, crossings, marks, poles, geo, cand, ages, advantage,
    nc, state,
):  # fmt: skip  # pragma: no cover - compiled
    """The strategy's injection into ``parts[slots[:m]]``; returns how many poses it wrote. Poses
    from vision and matured candidates go through :func:`away_from_mirror_nb` with the estimate
    (``x``, ``y``, ``th``)."""
    if source == 1:  # AMCL: uniform poses (mirrored pairs, or the own half)
        fresh = np.empty((m, 3))
        K.uniform_set_nb(fresh, 0, m, kn[C_HALF_LENGTH], kn[C_HALF_WIDTH], own_half, state)
        for i in range(m):
            parts[slots[i], 0], parts[slots[i], 1], parts[slots[i], 2] = fresh[i, 0], fresh[i, 1], fresh[i, 2]
        return m
    if source == 2:  # sensor resetting: poses from vision
        fresh = _from_vision_nb(posts, crossings, marks, poles, obs, m, kn[C_ANY_FEATURE] > 0.5, geo, state)
        got = fresh.shape[0]
        away_from_mirror_nb(fresh, np.arange(got), x, y, th)
        for i in range(got):
            parts[slots[i], 0], parts[slots[i], 1], parts[slots[i], 2] = fresh[i, 0], fresh[i, 1], fresh[i, 2]
        return got
    if source == 3:  # particle maturing: poses around the matured candidates
        got = inject_matured_nb(
            parts, slots[:m], cand, ages, advantage, nc, int(kn[C_THRESHOLD]), kn[C_MARGIN], state
        )  # fmt: skip
        if got:
            away_from_mirror_nb(parts, slots[:m], x, y, th)
        return got
    return 0


@nb.njit(cache=True, error_model="python", fastmath=False)
def frame_step_nb(
    parts, spare, n, logw, w, w_pose, ll, scratch, prev, pose_par, pose_out, evidence_out, motion, state,
    hough, posts, crossings, lines, marks, poles, cross_grid, line_grid, geo, rows, offsets, table, packed, blind,
    dx, dy, dth, now, own_half, kn, last_resample, times, bad, seen, watch, averages, cand, ages, advantage, in_use,
    slots,
):  # fmt: skip  # pragma: no cover - compiled
    """One frame of a particle filter with a built-in strategy (module docstring), up to the
    resampling, and the resampling too when it injects nothing.

    ``parts`` (its first ``n`` rows in use), ``logw``, ``w``: the particle set; ``spare``: the
    buffer the resampling draws into; ``w_pose`` receives the weights of the pose (before any
    resampling), ``evidence_out`` (as many entries as percept rows) each observation's mean
    likelihood. ``rows``, ``offsets``: the percept table and its kinds' offsets
    (:meth:`~cognition.percepts.Percepts.table_and_offsets`; no rows, or ``blind``: no
    observations), ``table``: :func:`~.sensor.sensor_table`; ``packed`` (as many rows as
    percept rows) receives the observation rows (:func:`~.sensor.pack_nb`). ``kn``: :func:`knobs`;
    ``last_resample`` (1 entry, s), the safety net's ring and state (:func:`watch_nb`), the AMCL
    ``averages`` (w_slow, w_fast), the maturing candidates (``cand``, ``ages``, ``advantage``, ``in_use``) are
    updated in place; ``slots`` is work space. The other arguments are those of
    :func:`.kernels.frame_nb`.

    Returns the pose (x, y, theta), its spread, the number of observations, the share of
    particles to replace at a resampling (-1: no resampling in this frame), the count to draw,
    and, when the share is 0 and the resampling has run here (the new set is in ``spare``),
    whether the safety net asks the caller to relocalize now (it has cleared its flag). With a
    share above 0 the caller draws the number of poses to inject with the filter's numpy
    ``Generator`` (numba would take a ``Generator`` argument only through Python code, about 14
    microseconds a call) and finishes with :func:`resample_step_nb`.
    """
    n_rows = offsets[-1] - offsets[0]
    obs = packed[:0] if blind or n_rows == 0 else packed[: pack_nb(rows, offsets, table, packed)]
    k = obs.shape[0]
    ev, raw, x, y, th, spread, unexplained = K.frame_nb(
        parts, n, dx, dy, dth, motion, state, obs, hough, posts, crossings, lines, marks, poles, cross_grid, line_grid,
        geo, ll, scratch, logw, w, prev, pose_par, pose_out, evidence_out[:k],
    )  # fmt: skip
    if cand.shape[0] > 0:  # the maturing candidates (Maturing.observe)
        if k:
            in_use[0] = mature_nb(
                cand, ages, advantage, in_use[0], obs, pose_out[:3], dx, dy, dth, kn[C_CONSISTENCY], hough, posts,
                crossings, lines, marks, poles, cross_grid, line_grid, geo, state,
            )  # fmt: skip
        else:
            move_candidates_nb(cand, in_use[0], dx, dy, dth)
    lost = spread > kn[C_LOST_SPREAD]
    for i in range(n):
        w_pose[i] = w[i]
    if k:
        watch_nb(now, unexplained, k, kn[C_WINDOW], kn[C_RELOCALIZE_SHARE], times, bad, seen, watch)
    if not (k and now - last_resample[0] >= kn[C_INTERVAL]):
        return x, y, th, spread, k, -1.0, n, False
    last_resample[0] = now
    w_avg, w_raw = math.exp(ev / k), math.exp(raw / k)
    particles = int(kn[C_PARTICLES])
    n_new = n
    if kn[C_COUNT_FLOOR] > 0.0:  # sensor resetting's adaptive count (SensorResetting.count)
        lo = int(kn[C_COUNT_FLOOR])
        n_new = min(particles, max(lo, math.ceil(lo / max(w_avg, 1e-3))))
    share = 0.0
    if kn[C_AVERAGES] > 0.5:  # AMCLInjection.share
        averages[0] += kn[C_ALPHA_SLOW] * (w_raw - averages[0])
        averages[1] += kn[C_ALPHA_FAST] * (w_raw - averages[1])
        if averages[0] > 0.0:
            share = min(kn[C_INJECTION_MAX], max(0.0, 1.0 - averages[1] / averages[0]))
        if kn[C_LOST_SHARE] >= 0.0 and lost:  # resetting_share
            share = max(share, kn[C_LOST_SHARE])
    if kn[C_KLD] > 0.5:  # KLD while tracking; a search gets every particle
        if lost or share > 0.0 or watch[R_RELOCALIZE]:
            n_new = particles
        else:
            lo = min(int(kn[C_KLD_MIN]), particles)
            masses = bin_masses_nb(parts, w, n, kn[C_KLD_BIN_XY], kn[C_KLD_BIN_THETA])
            n_new = kld_count_nb(masses, lo, particles, kn[C_KLD_EPSILON], kn[C_KLD_Z])
    if share > 0.0:
        return x, y, th, spread, k, share, n_new, False
    _, relocalize = resample_step_nb(
        parts, n, w, logw, spare, n_new, 0, slots, state, kn, obs, x, y, th, own_half, posts, crossings, marks,
        poles, geo, watch, averages, cand, ages, advantage, in_use,
    )  # fmt: skip
    return x, y, th, spread, k, 0.0, n_new, relocalize


@nb.njit(cache=True, error_model="python", fastmath=False)
def resample_step_nb(
    parts, n, w, logw, spare, n_new, m_inj, slots, state, kn, obs, x, y, th, own_half, posts, crossings, marks,
    poles, geo, watch, averages, cand, ages, advantage, in_use,
):  # fmt: skip  # pragma: no cover - compiled
    """The resampling of :func:`frame_step_nb`: draw ``n_new`` particles into ``spare``, inject
    ``m_inj`` poses from the strategy's source, restart the AMCL averages after an injection,
    and clear the safety net's flag. Returns (poses injected, whether to relocalize now)."""
    resample_nb(
        parts, n, w, logw, spare, n_new, kn[C_LOW_VARIANCE] > 0.5, kn[C_JITTER_XY], kn[C_JITTER_THETA], m_inj,
        slots, state,
    )  # fmt: skip
    injected = 0
    if m_inj > 0:
        injected = _inject_nb(
            spare, slots, m_inj, int(kn[C_SOURCE]), obs, x, y, th, own_half, kn, posts, crossings, marks, poles, geo,
            cand, ages, advantage, in_use[0], state,
        )  # fmt: skip
        if injected:  # Injection.restart
            averages[0] = averages[1] = 0.0
    relocalize = watch[R_RELOCALIZE] != 0
    watch[R_RELOCALIZE] = 0
    return injected, relocalize
