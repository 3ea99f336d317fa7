"""Compiled particle-filter steps: random numbers, motion model, likelihood, resampling, pose.

The branch-free stand-ins for libm's atan2, sin and cos, exp and log that let the particle
loops vectorize are in :mod:`cognition.localization.approx`. (numba caches per file; an edit of
a kernel in another file recompiles its callers because :mod:`cognition.kernel_cache` stamps
each file's cache with the files it imports.)

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

**Observation likelihood** (the models of :mod:`cognition.localization.sensor`):
Loop order is observation outside, particles inside, and each observation type has its
own particle loops: a branch-free loop finds each particle's grid cell, a scalar loop
gathers the associated map landmark of every particle, then a branch-free loop does the
arithmetic, which the compiler vectorizes. Bearings use :func:`fast_atan2`, a polynomial
with an error below 2e-5 rad (far below any bearing sigma), and rotations
:func:`fast_sincos`: a libm call per particle and observation would dominate the cost and
stop vectorization. For the same reason the exponentials and logarithms of the particle loops
are :func:`~.approx.fast_exp` and :func:`~.approx.log_into_nb` (numba has no vector math library here), within
1 and 2 ulp of libm's, and the sums over particles run in loops of their own (without
reassociation a sum keeps its loop scalar). The confidence floor of NimbRo eq. 9 needs the
likelihood itself: the factors (floor + c exp(q)) of a particle are multiplied in linear
space (each is at least the floor, so a few cannot underflow) and turned into a logarithm
every :data:`_BATCH` observations.

The per-observation log-likelihood q follows CMU Alg. 3:
q = -((d_obs - d_exp) / sigma_d)^2 / 2 - (bearing difference / sigma_b)^2 / 2 (plus the
orientation term of crossings and lines), clamped at -1e4.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from cognition.fastmath import FASTMATH
from cognition.localization.approx import fast_atan2, fast_exp, fast_sincos, log_into_nb

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


@nb.njit(cache=True, inline="always")
def rand_index(state, n):  # pragma: no cover - compiled
    """Uniform integer in [0, n) (n >= 1) from ``state`` (:func:`rand_u` scaled, clamped)."""
    return min(int(rand_u(state) * n), n - 1)


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


_BATCH = 8
_PI = math.pi
_INV_PI = 1.0 / math.pi
_SQRT12 = math.sqrt(12.0)


@nb.njit(cache=True, inline="always", fastmath=FASTMATH)
def _q(px, py, th, mx, my, dist, bear, inv_sr, inv_sb):  # pragma: no cover - compiled
    """log of CMU Alg. 3 for a landmark at (mx, my) seen from the particle (px, py, th)."""
    ex, ey = mx - px, my - py
    dd = (dist - math.sqrt(ex * ex + ey * ey)) * inv_sr
    db = wrap(bear + th - fast_atan2(ey, ex)) * inv_sb
    return -0.5 * (dd * dd + db * db)


@nb.njit(cache=True, inline="always", fastmath=FASTMATH)
def _flat_cell(gx, gy, x0, y0, inv_cell, nx, ny):  # pragma: no cover - compiled
    """Row-major index (row * nx + column) of the grid cell of field point (gx, gy), clamped to
    the nx x ny grid (a non-finite point maps to cell 0: the conversion to int never sees NaN
    or inf); branch-free, so that the loops computing it vectorize."""
    fx = (gx - x0) * inv_cell
    fy = (gy - y0) * inv_cell
    fx = min(fx if fx >= 0.0 else 0.0, nx - 1.0)  # also NaN -> 0
    fy = min(fy if fy >= 0.0 else 0.0, ny - 1.0)
    return int(fy) * nx + int(fx)


@nb.njit(cache=True, inline="always")
def _crossing_turn(seen: float, kind: float, partial: float) -> tuple[float, float, float, float]:  # pragma: no cover
    """How a crossing seen as ``seen`` compares with a map crossing of ``kind`` (0 L, 1 T, 2 X).

    Returns (f, a, b, p): the orientation difference d counts as ``| |wrap(f (d - a))| / f - b |``,
    and p is added to the log-likelihood. The same kind: the full turn (L, T) or modulo 90 degrees
    (X), p = 0. A larger kind (a partial view) adds p = ``partial`` (log of its weight): a T seen
    on an X (one arm not seen) has its stem along one of the X's arms, modulo 90 degrees; an L
    seen on an X its bisector 45 degrees from the X's lines, modulo 90; an L seen on a T (the stem
    and one half of the bar) its bisector 45 degrees to either side of the stem.
    """
    p = 0.0 if kind == seen else partial
    if kind == 2.0:
        return 4.0, (0.25 * _PI if seen == 0.0 else 0.0), 0.0, p
    if kind == 1.0 and seen == 0.0:
        return 1.0, 0.0, 0.25 * _PI, p
    return 1.0, 0.0, 0.0, p


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def log_likelihood_nb(
    parts, n, obs, hough, posts, crossings, lines, marks, poles, cross_grid, line_grid, geo, out, scratch, w, obs_ev
):  # pragma: no cover - compiled
    """Sum over observations of each particle's log-likelihood into ``out[:n]``.

    ``parts``: N x 3 particle poses (team frame); ``obs``: K x N_O rows
    (:class:`~cognition.localization.sensor.O`); ``hough``: 1 to use the NimbRo line model
    (else 0), then its sigmas of rho, theta, u-bar and spread; map arrays from
    :class:`~cognition.localization.fieldmodel.FieldModel`; ``scratch``: at least 6 x N, whose
    row 5 receives the log-likelihoods without the floors (for kidnapping detection; the other
    rows are not touched);
    ``w``: N normalised prior weights, with which ``obs_ev[k]`` (K entries) receives each
    observation's mean likelihood without the floors (how well the particles explain it).
    """
    # contiguous copies of the poses and work arrays of the function's own: strided columns of
    # ``parts`` and rows of one shared buffer (which the compiler must assume may overlap) keep
    # the particle loops from vectorizing (a quarter of the time on recorded match frames)
    px, py, th = np.empty(n), np.empty(n), np.empty(n)
    for i in range(n):
        px[i], py[i], th[i] = parts[i, 0], parts[i, 1], parts[i, 2]
    k_obs = obs.shape[0]
    q, prod, acc, cs, sn = np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    raw = np.empty(n)
    lx, ly, lo, lf = np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    la, lb, lp = np.empty(n), np.empty(n), np.empty(n)
    cq = np.empty(n)
    for i in range(n):
        prod[i] = 1.0
        acc[i] = 0.0
        raw[i] = 0.0
    x0, y0, inv_cell, nx, ny = geo[0], geo[1], 1.0 / geo[2], int(geo[3]), int(geo[4])
    plane = nx * ny
    lines_flat = line_grid.reshape(line_grid.size)  # C-contiguous (FieldModel): a view
    cell = np.empty(n, dtype=np.int64)
    need = False
    for k in range(k_obs):
        need = need or obs[k, 0] in (1.0, 2.0, 4.0, 5.0)
    if need:  # rotation of each particle, for placing observations on the field
        for i in range(n):
            sn[i], cs[i] = fast_sincos(th[i])
    for k in range(k_obs):
        t = int(obs[k, 0])
        ox, oy = obs[k, 1], obs[k, 2]
        dist, bear = obs[k, 14], obs[k, 15]
        inv_sr, inv_sb, inv_so = 1.0 / obs[k, 5], 1.0 / obs[k, 6], 1.0 / max(obs[k, 7], 1e-9)
        oa, ob = obs[k, 3], obs[k, 4]
        partial = obs[k, 17]
        if t == 0:  # goal post: the most likely of its candidate posts
            for i in range(n):
                q[i] = -1e4
            side, goal = oa, ob
            for j in range(posts.shape[0]):
                if (side > 0.5 and posts[j, 2] != side) or (goal > -0.5 and posts[j, 3] != goal):
                    continue
                mx, my = posts[j, 0], posts[j, 1]
                for i in range(n):
                    q[i] = max(q[i], _q(px[i], py[i], th[i], mx, my, dist, bear, inv_sr, inv_sb))
        elif t == 3:  # centre circle
            for i in range(n):
                q[i] = _q(px[i], py[i], th[i], 0.0, 0.0, dist, bear, inv_sr, inv_sb)
        elif t == 1:  # crossing of the same kind nearest to where the particle puts it
            known = oa >= 0.0 and oa < cross_grid.shape[0]  # never index with an unchecked kind
            grid = cross_grid[int(oa) if known else 0]
            if not known or grid[0, 0] < 0:  # unknown kind, or no crossing of this kind on the field
                q[:] = -1e4
            else:
                flat = grid.reshape(grid.size)
                for i in range(n):  # vectorized: the grid cell of the placement
                    gx = px[i] + cs[i] * ox - sn[i] * oy
                    gy = py[i] + sn[i] * ox + cs[i] * oy
                    cell[i] = _flat_cell(gx, gy, x0, y0, inv_cell, nx, ny)
                for i in range(n):  # gathers (scalar): the associated crossing, maybe of a larger kind
                    j = flat[cell[i]]
                    lx[i], ly[i], lo[i] = crossings[j, 0], crossings[j, 1], crossings[j, 2]
                    lf[i], la[i], lb[i], lp[i] = _crossing_turn(oa, crossings[j, 3], partial)
                for i in range(n):  # arithmetic (vectorized)
                    v = _q(px[i], py[i], th[i], lx[i], ly[i], dist, bear, inv_sr, inv_sb)
                    do = (abs(wrap(lf[i] * (ob + th[i] - lo[i] - la[i])) / lf[i]) - lb[i]) * inv_so
                    q[i] = v - 0.5 * do * do + lp[i]
        elif t == 2 and hough[0] < 0.5:  # line: CMU nearest-point model (both classes exist)
            arc = obs[k, 13] * _SQRT12 <= geo[5]  # short enough to be a straight piece of the circle
            for i in range(n):  # vectorized: the grid cell (row-major in the class's plane) of the placement
                g = oa + th[i]
                g -= _PI * math.floor(g * _INV_PI)  # [0, pi)
                cls = 0 if min(g, _PI - g) <= 0.25 * _PI else 1
                gx = px[i] + cs[i] * ox - sn[i] * oy
                gy = py[i] + sn[i] * ox + cs[i] * oy
                cell[i] = cls * plane + _flat_cell(gx, gy, x0, y0, inv_cell, nx, ny)
            # a loop of its own: inside the cell loop the compiler vectorized it differently in the fused
            # frame (.frame_step) than here, and the two frames' evidence differed in the last bits
            for i in range(n):  # vectorized: the centre circle's tangent at the placement (short lines)
                cq[i] = -1e4
                if arc:  # off the circle, and turned from its tangent
                    g = oa + th[i]
                    g -= _PI * math.floor(g * _INV_PI)  # [0, pi), as above: the same sums to the bit
                    gx = px[i] + cs[i] * ox - sn[i] * oy
                    gy = py[i] + sn[i] * ox + cs[i] * oy
                    dr = (math.sqrt(gx * gx + gy * gy) - geo[5]) * inv_sr
                    dc = g - fast_atan2(gy, gx) - 0.5 * _PI
                    dc = (dc - _PI * math.floor(dc * _INV_PI + 0.5)) * inv_so
                    cq[i] = -0.5 * (dr * dr + dc * dc)
            foot = obs[k, 16] > 0.5
            u_lo, u_hi = (0.0, 1.0) if foot else (-1e9, 1e9)  # the map segment, or its whole line
            for i in range(n):  # gathers (scalar): the associated line's point nearest the particle
                j = max(lines_flat[cell[i]], 0)  # -1 (no line of the class) cannot occur on a field with lines
                x1, y1 = lines[j, 0], lines[j, 1]
                dx, dy = lines[j, 2] - x1, lines[j, 3] - y1
                u = min(max(((px[i] - x1) * dx + (py[i] - y1) * dy) * lines[j, 6], u_lo), u_hi)
                lx[i], ly[i], lo[i] = x1 + u * dx, y1 + u * dy, lines[j, 4]
            # the foot was not seen: only the distance across the observed line is compared (along
            # its normal (nxo, nyo), robot frame), with the expected foot from the map line
            nxo, nyo = -math.sin(oa), math.cos(oa)
            s_obs = nxo * ox + nyo * oy
            for i in range(n):  # arithmetic (vectorized)
                if foot:
                    v = _q(px[i], py[i], th[i], lx[i], ly[i], dist, bear, inv_sr, inv_sb)
                else:
                    ex, ey = lx[i] - px[i], ly[i] - py[i]
                    e = (nxo * (cs[i] * ex + sn[i] * ey) + nyo * (cs[i] * ey - sn[i] * ex) - s_obs) * inv_sr
                    v = -0.5 * e * e
                g = oa + th[i]
                do = g - _PI * math.floor(g * _INV_PI) - lo[i]
                do = (do - _PI * math.floor(do * _INV_PI + 0.5)) * inv_so
                q[i] = max(v - 0.5 * do * do, cq[i])
        elif t == 2:  # line: NimbRo Hough model (eq. 7)
            for i in range(n):
                q[i] = _hough_q(px[i], py[i], th[i], cs[i], sn[i], obs[k], hough, lines)
        else:  # penalty mark (4) or corner pole (5): the nearest one to where the particle puts it
            arr = marks if t == 4 else poles
            for i in range(n):
                gx = px[i] + cs[i] * ox - sn[i] * oy
                gy = py[i] + sn[i] * ox + cs[i] * oy
                bj, bd = -1, 1e300
                for j in range(arr.shape[0]):
                    dd = (arr[j, 0] - gx) ** 2 + (arr[j, 1] - gy) ** 2
                    if dd < bd:
                        bj, bd = j, dd
                q[i] = -1e4 if bj < 0 else _q(px[i], py[i], th[i], arr[bj, 0], arr[bj, 1], dist, bear, inv_sr, inv_sb)
        conf, floor = obs[k, 8], obs[k, 9]
        base = floor + (1.0 - conf)
        for i in range(n):
            raw[i] += max(q[i], -1e4)
        for i in range(n):  # vectorized; the sum below is ordered (no reassociation)
            lf[i] = fast_exp(q[i])
        e = 0.0
        if base > 0.0:
            for i in range(n):
                prod[i] *= base + conf * lf[i]
        else:
            for i in range(n):
                acc[i] += max(q[i], -1e4)
        for i in range(n):
            e += w[i] * lf[i]
        obs_ev[k] = e
        if (k + 1) % _BATCH == 0:
            log_into_nb(prod, q, n)
            for i in range(n):
                acc[i] += q[i]
                prod[i] = 1.0
    log_into_nb(prod, q, n)
    for i in range(n):
        out[i] = acc[i] + q[i]
        scratch[5, i] = raw[i]


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def _hough_q(px, py, th, c, s, ob, hough, lines):  # pragma: no cover - compiled
    """NimbRo eq. 7 for one particle: the map line of the observed orientation class nearest
    in Hough space, compared by theta, rho, mean position u-bar and spread sigma(u)."""
    g = ob[3] + th
    g -= _PI * math.floor(g / _PI)
    cls = 0 if min(g, _PI - g) <= 0.25 * _PI else 1
    best = 1e300
    q = -1e4
    sn_o, cn_o = math.sin(ob[11]), math.cos(ob[11])
    for j in range(lines.shape[0]):
        if lines[j, 5] != cls:
            continue
        nth = lines[j, 4] + 0.5 * _PI - th  # the normal, robot frame
        ax, ay = lines[j, 0] - px, lines[j, 1] - py
        rx, ry = c * ax + s * ay, -s * ax + c * ay  # end point 1, robot frame
        bx, by = lines[j, 2] - px, lines[j, 3] - py
        sx, sy = c * bx + s * by, -s * bx + c * by  # end point 2, robot frame
        rho = math.cos(nth) * rx + math.sin(nth) * ry
        if rho < 0.0:
            rho, nth = -rho, nth + _PI
        d_rho = (rho - ob[10]) / hough[1]
        d_th = wrap(nth - ob[11]) / hough[2]
        m = d_rho * d_rho + d_th * d_th
        if m >= best:
            continue
        u1, u2 = rx * sn_o - ry * cn_o, sx * sn_o - sy * cn_o
        lo, hi = min(u1, u2), max(u1, u2)
        d_u = (min(max(ob[12], lo), hi) - ob[12]) / hough[3]
        d_s = (min(ob[13], (hi - lo) / math.sqrt(12.0)) - ob[13]) / hough[4]
        best = m
        q = -0.5 * (m + d_u * d_u + d_s * d_s)
    return q


@nb.njit(cache=True, error_model="python", fastmath=False)
def predict_nb(parts, n, dx, dy, dth, sig, state):  # pragma: no cover - compiled
    """CMU Alg. 2 on particles [0, n). ``sig``: sigma_mx, sigma_mtheta, sigma_mytheta, floor_xy, floor_theta.

    The draws come first, in the order (x, y, theta) per particle, in a loop of their own: each
    depends on the one before through ``state``, and mixed into the arithmetic they kept the
    motion itself (rotation, wrap) from being vectorized (5.6 against 4.6 µs for 300 particles,
    the same numbers to the bit)."""
    sx = max(sig[0] * abs(dx), sig[3])
    sy = max(sig[0] * abs(dy), sig[3])
    st = max(math.hypot(sig[1] * dth, sig[2] * dy), sig[4])
    nx, ny, nt = np.empty(n), np.empty(n), np.empty(n)
    for i in range(n):
        nx[i] = rand_n(state)
        ny[i] = rand_n(state)
        nt[i] = rand_n(state)
    px, py, th = np.empty(n), np.empty(n), np.empty(n)  # contiguous, see log_likelihood_nb
    for i in range(n):
        px[i], py[i], th[i] = parts[i, 0], parts[i, 1], parts[i, 2]
    for i in range(n):
        mx = dx + sx * nx[i]
        my = dy + sy * ny[i]
        mt = dth + st * nt[i]
        s, c = fast_sincos(th[i])
        px[i] += c * mx - s * my
        py[i] += s * mx + c * my
        th[i] = wrap(th[i] + mt)
    for i in range(n):
        parts[i, 0], parts[i, 1], parts[i, 2] = px[i], py[i], th[i]


@nb.njit(cache=True, error_model="python", fastmath=False)
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
    for i in range(n):  # vectorized
        v = logw[i] if math.isfinite(logw[i]) else lo
        logw[i] = v - m
        w[i] = fast_exp(v - m)
    total = 0.0
    for i in range(n):  # ordered sum
        total += w[i]
    shift = math.log(total / n)
    for i in range(n):
        w[i] /= total
        logw[i] -= shift  # log(n w): mean 1, so the next update's mean is the evidence
    return m + shift


@nb.njit(cache=True, error_model="python", fastmath=False)
def _cluster_nb(px, py, cth, sth, n, w, seed, r2):  # pragma: no cover - compiled
    """Weight and weighted sums (x, y, cos theta, sin theta) of the particles within sqrt(``r2``)
    m of particle ``seed``; ``px``, ``py``, ``cth``, ``sth``: the particles' x, y, cos theta
    and sin theta (contiguous). A particle outside adds zeros, so the loop has no branch."""
    sx, sy = px[seed], py[seed]
    cw = mx = my = mc = ms = 0.0
    for i in range(n):
        ex, ey = px[i] - sx, py[i] - sy
        wi = w[i] if ex * ex + ey * ey <= r2 else 0.0
        cw += wi
        mx += wi * px[i]
        my += wi * py[i]
        mc += wi * cth[i]
        ms += wi * sth[i]
    return cw, mx, my, mc, ms


@nb.njit(cache=True, error_model="python", fastmath=False)
def pose_nb(parts, n, w, prev, radius, near_xy, near_th, jump_weight, out):  # pragma: no cover - compiled
    """CMU III.E pose extraction. Returns (x, y, theta, spread, cluster weight) in ``out[:5]``
    and the 3 x 3 covariance around the pose in ``out[5:14]``.

    ``prev``: previous estimate (x, y, theta, valid); the heaviest particle within
    ``near_xy`` m and ``near_th`` rad of it seeds the cluster, else the heaviest overall. If
    the cluster weighs less than ``jump_weight`` the heaviest overall seeds it instead, if its
    cluster weighs more (the paper allows the jump; jumping to a lighter cluster would follow
    a few injected poses away from an estimate the cloud still supports).
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
    seed = best_near if best_near >= 0 else best_all
    px, py, cth, sth = np.empty(n), np.empty(n), np.empty(n), np.empty(n)  # contiguous, for the sums
    for i in range(n):
        px[i], py[i] = parts[i, 0], parts[i, 1]
    for i in range(n):
        sth[i], cth[i] = fast_sincos(parts[i, 2])
    cw, mx, my, mc, ms = _cluster_nb(px, py, cth, sth, n, w, seed, r2)
    if cw < jump_weight and seed != best_all:
        cw2, mx2, my2, mc2, ms2 = _cluster_nb(px, py, cth, sth, n, w, best_all, r2)
        if cw2 > cw:  # jump only to a heavier cluster
            seed, cw, mx, my, mc, ms = best_all, cw2, mx2, my2, mc2, ms2
    if not cw > 0.0:  # weights that are not a distribution (cannot happen after normalise_nb): the seed
        cw, mx, my, mc, ms = 1.0, parts[seed, 0], parts[seed, 1], math.cos(parts[seed, 2]), math.sin(parts[seed, 2])
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


@nb.njit(cache=True, error_model="python", fastmath=False)
def gaussian_set_nb(out, start, m, centres, sig_xy, sig_th, state):  # pragma: no cover - compiled
    """Fill rows [start, start + m) of ``out`` with poses spread around ``centres`` (K x 3),
    taken in turn, with Gaussian noise."""
    k = centres.shape[0]
    for i in range(m):
        c = centres[i % k]
        out[start + i, 0] = c[0] + sig_xy * rand_n(state)
        out[start + i, 1] = c[1] + sig_xy * rand_n(state)
        out[start + i, 2] = wrap(c[2] + sig_th * rand_n(state))


@nb.njit(cache=True, error_model="python", fastmath=False)
def _choose_into(idx, n, m, state):  # pragma: no cover - compiled
    """``idx[:m]``: ``m`` distinct indices drawn uniformly from 0..n-1 (0 <= m <= n), in random
    order: the first ``m`` steps of a Fisher-Yates shuffle of ``idx[:n]``, set to 0..n-1 first,
    with the filter's own ``state``."""
    for i in range(n):
        idx[i] = i
    for i in range(m):
        j = i + rand_index(state, n - i)
        idx[i], idx[j] = idx[j], idx[i]


@nb.njit(cache=True, error_model="python", fastmath=False)
def choose_nb(n, m, state):  # pragma: no cover - compiled
    """:func:`_choose_into` into a new array; returns the ``m`` indices."""
    idx = np.empty(n, dtype=np.int64)
    _choose_into(idx, n, m, state)
    return idx[:m].copy()


@nb.njit(cache=True, error_model="python", fastmath=False)
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


@nb.njit(cache=True, error_model="python", fastmath=False)
def frame_nb(
    parts,
    n,
    dx,
    dy,
    dth,
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
    obs_ev,
):  # pragma: no cover - compiled
    """One frame up to the pose, in one call: :func:`predict_nb` with the odometry (dx, dy m,
    dth rad), the observation update (``obs`` may have no rows), :func:`normalise_nb` and
    :func:`pose_nb` with ``pose_par`` (cluster radius, near xy, near theta, jump weight,
    unexplained level). Updates ``prev`` to the new pose; ``obs_ev`` receives each
    observation's mean likelihood without the floors under the prior weights (see
    :func:`log_likelihood_nb`). Returns the log evidence of the observations (mean likelihood
    over the prior weights) with and without the likelihood floors, the pose's x, y, theta and
    spread (``pose_out[:4]``) and how many observations are unexplained (``obs_ev`` below the
    unexplained level)."""
    predict_nb(parts, n, dx, dy, dth, motion, state)
    if obs.shape[0] > 0:
        log_likelihood_nb(
            parts, n, obs, hough, posts, crossings, lines, marks, poles, cross_grid, line_grid, geo, ll, scratch, w,
            obs_ev,
        )  # fmt: skip
    raw_evidence = 0.0
    if obs.shape[0] > 0:  # log mean over the prior weights of exp(raw), stably
        m = -1e300
        for i in range(n):
            m = max(m, logw[i] + scratch[5, i])
        e = np.empty(n)
        for i in range(n):  # vectorized
            e[i] = fast_exp(logw[i] + scratch[5, i] - m)
        total = 0.0
        for i in range(n):  # ordered sum
            total += e[i]
        raw_evidence = m + math.log(total / n)
        for i in range(n):
            logw[i] += ll[i]
    evidence = normalise_nb(logw, n, w)
    pose_nb(parts, n, w, prev, pose_par[0], pose_par[1], pose_par[2], pose_par[3], pose_out)
    prev[0], prev[1], prev[2], prev[3] = pose_out[0], pose_out[1], pose_out[2], 1.0
    unexplained = 0
    for k in range(obs.shape[0]):
        if obs_ev[k] < pose_par[4]:
            unexplained += 1
    return evidence, raw_evidence, pose_out[0], pose_out[1], pose_out[2], pose_out[3], unexplained
