"""Compiled particle-filter steps: random numbers, motion model, resampling, pose extraction.

* **Random numbers**: each filter owns a xorshift64* state (seeded from its numpy
  Generator), so kernels draw without Python round trips and without any global state;
  normals are looked up in a fixed table of 2^16 standard normals.
* **Motion model** (CMU paper, Alg. 2): the reported odometry (dx, dy, dtheta), robot frame
  of the previous frame, is perturbed per particle with sigmas proportional to the motion:
  sd(dx) = sigma_mx |dx|, sd(dy) = sigma_mx |dy|, sd(dtheta) = sigma_mtheta |dtheta| plus
  sigma_mytheta |dy| (sidesteps are not straight), each with a small floor; then it is
  applied in the particle's frame.
* **Resampling**: multinomial (CMU Alg. 4, Thrun; sorted uniforms merged with the cumulative
  weights) and low-variance resampling (DNT 4.6); resampled particles get Gaussian jitter
  (CMU III.D, scaled to the frame rate, see :mod:`cognition.localization.params`).
* **Pose extraction** (CMU III.E): the heaviest particle near the previous estimate, the
  weighted centroid (circular mean of theta) of the particles within the cluster radius of
  it, the jump rule, the covariance and the weighted spread (for the ``lost`` flag).

Poses are (x m, y m, theta rad) in the team frame; angles are wrapped to [-pi, pi).
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from cognition.localization.likelihood import fast_sincos, log_likelihood_nb

_MUL = np.uint64(0x2545F4914F6CDD1D)
_S12, _S25, _S27, _S11 = np.uint64(12), np.uint64(25), np.uint64(27), np.uint64(11)
_TWO53 = 1.0 / 9007199254740992.0


@nb.njit(cache=True, inline="always")
def rand_u(state):  # pragma: no cover - compiled
    """Uniform in [0, 1) from the xorshift64* ``state`` (uint64 array of length 1)."""
    x = state[0]
    x ^= x >> _S12
    x ^= x << _S25
    x ^= x >> _S27
    state[0] = x
    return float((x * _MUL) >> _S11) * _TWO53


_NORMALS = np.random.default_rng(20261122).standard_normal(1 << 16)
_NORMALS.setflags(write=False)
"""A fixed table of standard normals; :func:`rand_n` picks one with the filter's own state."""
_S48 = np.uint64(48)


@nb.njit(cache=True, inline="always")
def rand_n(state):  # pragma: no cover - compiled
    """Standard normal from ``state``: an entry of the fixed table :data:`_NORMALS` (2^16
    values; plenty for motion noise and jitter, and far cheaper than Box-Muller)."""
    x = state[0]
    x ^= x >> _S12
    x ^= x << _S25
    x ^= x >> _S27
    state[0] = x
    return _NORMALS[(x * _MUL) >> _S48]


@nb.njit(cache=True, inline="always")
def wrap(a):  # pragma: no cover - compiled
    """Angle wrapped to [-pi, pi)."""
    return a - 2.0 * math.pi * math.floor((a + math.pi) / (2.0 * math.pi))


@nb.njit(cache=True)
def predict_nb(parts, n, dx, dy, dth, sig, state):  # pragma: no cover - compiled
    """CMU Alg. 2 on particles [0, n). ``sig``: sigma_mx, sigma_mtheta, sigma_mytheta, floor_xy, floor_theta."""
    sx = max(sig[0] * abs(dx), sig[3])
    sy = max(sig[0] * abs(dy), sig[3])
    st = max(math.hypot(sig[1] * dth, sig[2] * dy), sig[4])
    for i in range(n):
        mx = dx + sx * rand_n(state)
        my = dy + sy * rand_n(state)
        mt = dth + st * rand_n(state)
        s, c = fast_sincos(parts[i, 2])
        parts[i, 0] += c * mx - s * my
        parts[i, 1] += s * mx + c * my
        parts[i, 2] = wrap(parts[i, 2] + mt)


@nb.njit(cache=True)
def normalise_nb(logw, n, w):  # pragma: no cover - compiled
    """Normalised weights of log-weights [0, n) into ``w``; returns log of the mean of exp(logw).

    Afterwards ``logw`` holds log(n w), whose exponentials average 1, so that the value
    returned after the next observation update is the log evidence of that observation.
    Non-finite log-weights count as the smallest finite one, so the result is never NaN.
    """
    m = -1e300
    lo = 1e300
    for i in range(n):
        v = logw[i]
        if math.isfinite(v):
            m = max(m, v)
            lo = min(lo, v)
    if m == -1e300:  # nothing finite: uniform
        for i in range(n):
            logw[i] = 0.0
            w[i] = 1.0 / n
        return 0.0
    total = 0.0
    for i in range(n):
        v = logw[i] if math.isfinite(logw[i]) else lo
        logw[i] = v - m
        w[i] = math.exp(v - m)
        total += w[i]
    shift = math.log(total / n)
    for i in range(n):
        w[i] /= total
        logw[i] -= shift  # log(n w): mean 1, so the next update's mean is the evidence
    return m + shift


@nb.njit(cache=True)
def resample_nb(parts, n, w, out, m, low_variance, jit_xy, jit_th, state):  # pragma: no cover - compiled
    """Draw ``m`` particles from particles [0, n) with normalised weights ``w`` into ``out``.

    Multinomial: ``m`` independent uniforms, generated already sorted (normalised cumulative
    sums of exponentials), merged with the cumulative weights in one pass (the same
    distribution as a binary search per draw, in linear time). Low variance: one random
    offset, step 1 / m. Each drawn particle gets Gaussian jitter.
    """
    cdf = np.empty(n)
    acc = 0.0
    for i in range(n):
        acc += w[i]
        cdf[i] = acc
    cdf[n - 1] = 1.0 + 1e-12
    u = np.empty(m)
    if low_variance:
        r = rand_u(state) / m
        for k in range(m):
            u[k] = r + k / m
    else:
        total = 0.0
        for k in range(m):
            total -= math.log(1.0 - rand_u(state))
            u[k] = total
        total -= math.log(1.0 - rand_u(state))
        for k in range(m):
            u[k] /= total
    j = 0
    for k in range(m):
        while j < n - 1 and cdf[j] < u[k]:
            j += 1
        out[k, 0] = parts[j, 0] + jit_xy * rand_n(state)
        out[k, 1] = parts[j, 1] + jit_xy * rand_n(state)
        out[k, 2] = wrap(parts[j, 2] + jit_th * rand_n(state))


@nb.njit(cache=True)
def pose_nb(parts, n, w, prev, radius, near_xy, near_th, jump_weight, out):  # pragma: no cover - compiled
    """CMU III.E pose extraction. Returns (x, y, theta, spread, cluster weight) in ``out[:5]``
    and the 3 x 3 covariance around the pose in ``out[5:14]``.

    ``prev``: previous estimate (x, y, theta, valid); the heaviest particle within
    ``near_xy`` m and ``near_th`` rad of it seeds the cluster, else the heaviest overall. If
    the cluster weighs less than ``jump_weight`` the heaviest overall seeds it instead.
    """
    best_all, best_near = -1, -1
    for i in range(n):
        if best_all < 0 or w[i] > w[best_all]:
            best_all = i
        ex, ey = parts[i, 0] - prev[0], parts[i, 1] - prev[1]
        near = prev[3] > 0.5 and ex * ex + ey * ey <= near_xy * near_xy
        if near and abs(wrap(parts[i, 2] - prev[2])) <= near_th and (best_near < 0 or w[i] > w[best_near]):
            best_near = i
    r2 = radius * radius
    for attempt in range(2):
        seed = best_near if (attempt == 0 and best_near >= 0) else best_all
        sx, sy = parts[seed, 0], parts[seed, 1]
        cw = 0.0
        mx = 0.0
        my = 0.0
        mc = 0.0
        ms = 0.0
        for i in range(n):
            ex, ey = parts[i, 0] - sx, parts[i, 1] - sy
            if ex * ex + ey * ey <= r2:
                cw += w[i]
                mx += w[i] * parts[i, 0]
                my += w[i] * parts[i, 1]
                sn, cs = fast_sincos(parts[i, 2])
                mc += w[i] * cs
                ms += w[i] * sn
        if cw >= jump_weight or seed == best_all:
            break
    x, y, th = mx / cw, my / cw, math.atan2(ms, mc)
    cxx = cxy = cyy = cxt = cyt = ctt = 0.0
    for i in range(n):
        ex, ey, et = parts[i, 0] - x, parts[i, 1] - y, wrap(parts[i, 2] - th)
        cxx += w[i] * ex * ex
        cxy += w[i] * ex * ey
        cyy += w[i] * ey * ey
        cxt += w[i] * ex * et
        cyt += w[i] * ey * et
        ctt += w[i] * et * et
    out[0], out[1], out[2], out[3], out[4] = x, y, th, math.sqrt(cxx + cyy), cw
    out[5], out[6], out[7] = cxx, cxy, cxt
    out[8], out[9], out[10] = cxy, cyy, cyt
    out[11], out[12], out[13] = cxt, cyt, ctt


@nb.njit(cache=True)
def gaussian_set_nb(out, start, m, centres, sig_xy, sig_th, state):  # pragma: no cover - compiled
    """Fill rows [start, start + m) of ``out`` with poses spread around ``centres`` (K x 3),
    taken in turn, with Gaussian noise."""
    k = centres.shape[0]
    for i in range(m):
        c = centres[i % k]
        out[start + i, 0] = c[0] + sig_xy * rand_n(state)
        out[start + i, 1] = c[1] + sig_xy * rand_n(state)
        out[start + i, 2] = wrap(c[2] + sig_th * rand_n(state))


@nb.njit(cache=True)
def uniform_set_nb(out, start, m, hl, hw, own_half, state):  # pragma: no cover - compiled
    """Fill rows [start, start + m) with uniform poses over the field (x in [-hl, hl] or the own
    half [-hl, 0]) and all headings; without ``own_half`` they come in mirrored pairs
    (x, y, theta) and (-x, -y, theta + pi), so neither half is favoured."""
    i = 0
    while i < m:
        x = -hl + rand_u(state) * (hl if own_half else 2.0 * hl)
        y = -hw + rand_u(state) * 2.0 * hw
        th = wrap(2.0 * math.pi * rand_u(state))
        out[start + i, 0], out[start + i, 1], out[start + i, 2] = x, y, th
        i += 1
        if not own_half and i < m:
            out[start + i, 0], out[start + i, 1], out[start + i, 2] = -x, -y, wrap(th + math.pi)
            i += 1


@nb.njit(cache=True)
def frame_nb(
    parts,
    n,
    odo,
    motion,
    state,
    obs,
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
    logw,
    w,
    prev,
    pose_par,
    pose_out,
):  # pragma: no cover - compiled
    """One frame up to the pose, in one call: :func:`predict_nb` with ``odo`` (dx, dy,
    dtheta), the observation update (``obs`` may have no rows), :func:`normalise_nb` and
    :func:`pose_nb` with ``pose_par`` (cluster radius, near xy, near theta, jump weight).
    Updates ``prev`` to the new pose. Returns the log evidence of the observations (mean
    likelihood over the prior weights) with and without the likelihood floors."""
    predict_nb(parts, n, odo[0], odo[1], odo[2], motion, state)
    if obs.shape[0] > 0:
        log_likelihood_nb(
            parts, n, obs, hough, posts, crossings, lines, marks, poles, cross_grid, line_grid, geo, ll, scratch
        )
    raw_evidence = 0.0
    if obs.shape[0] > 0:  # log mean over the prior weights of exp(raw), stably
        m = -1e300
        for i in range(n):
            m = max(m, logw[i] + scratch[5, i])
        total = 0.0
        for i in range(n):
            total += math.exp(logw[i] + scratch[5, i] - m)
        raw_evidence = m + math.log(total / n)
        for i in range(n):
            logw[i] += ll[i]
    evidence = normalise_nb(logw, n, w)
    pose_nb(parts, n, w, prev, pose_par[0], pose_par[1], pose_par[2], pose_par[3], pose_out)
    prev[0], prev[1], prev[2], prev[3] = pose_out[0], pose_out[1], pose_out[2], 1.0
    return evidence, raw_evidence
