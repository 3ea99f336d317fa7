"""The compiled observation likelihood of every particle (the models of :mod:`cognition.localization.sensor`).

Loop order is observation outside, particles inside, and each observation type has its
own particle loops: a scalar loop gathers the associated map landmark of every particle,
then a branch-free loop does the arithmetic, which the compiler vectorizes. Bearings use
:func:`fast_atan2`, a polynomial with an error below 2e-5 rad (far below any bearing
sigma), and rotations :func:`fast_sincos`: a libm call per particle and observation would
dominate the cost and stop vectorization. The confidence floor of NimbRo eq. 9 needs the
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

_BATCH = 8
_PI = math.pi
_TWO_PI = 2.0 * math.pi
_INV_TWO_PI = 1.0 / _TWO_PI
_INV_PI = 1.0 / math.pi


@nb.njit(cache=True, inline="always", fastmath=True)
def fast_atan2(y, x):  # pragma: no cover - compiled
    """atan2(y, x) in (-pi, pi] with an absolute error below 2e-5 rad; branch-free."""
    ax, ay = abs(x), abs(y)
    mn, mx = min(ax, ay), max(ax, ay)
    a = mn / max(mx, 1e-300)
    s = a * a
    r = ((((0.0208351 * s - 0.0851330) * s + 0.1801410) * s - 0.3302995) * s + 0.9998660) * a
    r = 0.5 * _PI - r if ay > ax else r
    r = _PI - r if x < 0.0 else r
    return -r if y < 0.0 else r


@nb.njit(cache=True, inline="always", fastmath=True)
def fast_sincos(a):  # pragma: no cover - compiled
    """(sin a, cos a) for any a, absolute error below 1e-6; branch-free polynomials."""
    a = a - _TWO_PI * math.floor((a + _PI) / _TWO_PI)  # [-pi, pi)
    h = 0.5 * a  # [-pi/2, pi/2): sin and cos of the half angle, then double it
    s2 = h * h
    sh = h * (1.0 + s2 * (-1 / 6 + s2 * (1 / 120 + s2 * (-1 / 5040 + s2 * (1 / 362880 - s2 / 39916800)))))
    ch = 1.0 + s2 * (-0.5 + s2 * (1 / 24 + s2 * (-1 / 720 + s2 * (1 / 40320 + s2 * (-1 / 3628800 + s2 / 479001600)))))
    return 2.0 * sh * ch, ch * ch - sh * sh


@nb.njit(cache=True, inline="always", fastmath=True)
def _wrap(a):  # pragma: no cover - compiled
    """Angle wrapped to [-pi, pi)."""
    return a - _TWO_PI * math.floor((a + _PI) * _INV_TWO_PI)


@nb.njit(cache=True, inline="always", fastmath=True)
def _q(px, py, th, mx, my, dist, bear, inv_sr, inv_sb):  # pragma: no cover - compiled
    """log of CMU Alg. 3 for a landmark at (mx, my) seen from the particle (px, py, th)."""
    ex, ey = mx - px, my - py
    dd = (dist - math.sqrt(ex * ex + ey * ey)) * inv_sr
    db = _wrap(bear + th - fast_atan2(ey, ex)) * inv_sb
    return -0.5 * (dd * dd + db * db)


@nb.njit(cache=True, inline="always")
def _cell(gx, gy, x0, y0, inv_cell, nx, ny):  # pragma: no cover - compiled
    """Grid cell (row, column) of field point (gx, gy), clamped to the nx x ny grid."""
    ix = int((gx - x0) * inv_cell)
    iy = int((gy - y0) * inv_cell)
    return min(max(iy, 0), ny - 1), min(max(ix, 0), nx - 1)


@nb.njit(cache=True, error_model="numpy", fastmath=True)
def log_likelihood_nb(
    parts, n, obs, hough, posts, crossings, lines, marks, poles, cross_grid, line_grid, geo, out, scratch
):  # pragma: no cover - compiled
    """Sum over observations of each particle's log-likelihood into ``out[:n]``.

    ``parts``: N x 3 particle poses (team frame); ``obs``: K x N_O rows
    (:class:`~cognition.localization.sensor.O`); ``hough``: 1 to use the NimbRo line model
    (else 0), then its sigmas of rho, theta, u-bar and spread; map arrays from
    :class:`~cognition.localization.fieldmodel.FieldModel`; ``scratch``: 10 x N work space,
    whose row 5 receives the log-likelihoods without the floors (for kidnapping detection).
    """
    px = parts[:n, 0]
    py = parts[:n, 1]
    th = parts[:n, 2]
    k_obs = obs.shape[0]
    q, prod, acc, cs, sn = scratch[0, :n], scratch[1, :n], scratch[2, :n], scratch[3, :n], scratch[4, :n]
    raw = scratch[5, :n]
    lx, ly, lo, lf = scratch[6, :n], scratch[7, :n], scratch[8, :n], scratch[9, :n]
    for i in range(n):
        prod[i] = 1.0
        acc[i] = 0.0
        raw[i] = 0.0
    x0, y0, inv_cell, nx, ny = geo[0], geo[1], 1.0 / geo[2], int(geo[3]), int(geo[4])
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
            grid = cross_grid[int(oa)]
            if grid[0, 0] < 0:  # no crossing of this kind on the field
                q[:] = -1e4
            else:
                for i in range(n):  # gathers (scalar): the associated crossing
                    gx = px[i] + cs[i] * ox - sn[i] * oy
                    gy = py[i] + sn[i] * ox + cs[i] * oy
                    r, c = _cell(gx, gy, x0, y0, inv_cell, nx, ny)
                    j = grid[r, c]
                    lx[i], ly[i], lo[i] = crossings[j, 0], crossings[j, 1], crossings[j, 2]
                    lf[i] = 4.0 if crossings[j, 3] == 2 else 1.0  # X: orientation modulo 90 degrees
                for i in range(n):  # arithmetic (vectorized)
                    v = _q(px[i], py[i], th[i], lx[i], ly[i], dist, bear, inv_sr, inv_sb)
                    do = _wrap(lf[i] * (ob + th[i] - lo[i])) / lf[i] * inv_so
                    q[i] = v - 0.5 * do * do
        elif t == 2 and hough[0] < 0.5:  # line: CMU nearest-point model (both classes exist)
            for i in range(n):  # gathers (scalar): the associated line's point nearest the particle
                g = oa + th[i]
                g -= _PI * math.floor(g * _INV_PI)  # [0, pi)
                cls = 0 if min(g, _PI - g) <= 0.25 * _PI else 1
                gx = px[i] + cs[i] * ox - sn[i] * oy
                gy = py[i] + sn[i] * ox + cs[i] * oy
                r, c = _cell(gx, gy, x0, y0, inv_cell, nx, ny)
                j = line_grid[cls, r, c]
                x1, y1 = lines[j, 0], lines[j, 1]
                dx, dy = lines[j, 2] - x1, lines[j, 3] - y1
                u = min(max(((px[i] - x1) * dx + (py[i] - y1) * dy) * lines[j, 6], 0.0), 1.0)
                lx[i], ly[i], lo[i] = x1 + u * dx, y1 + u * dy, lines[j, 4]
            for i in range(n):  # arithmetic (vectorized)
                v = _q(px[i], py[i], th[i], lx[i], ly[i], dist, bear, inv_sr, inv_sb)
                g = oa + th[i]
                do = g - _PI * math.floor(g * _INV_PI) - lo[i]
                do = (do - _PI * math.floor(do * _INV_PI + 0.5)) * inv_so
                q[i] = v - 0.5 * do * do
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
        if base > 0.0:
            for i in range(n):
                prod[i] *= base + conf * math.exp(max(q[i], -1e4))
        else:
            for i in range(n):
                acc[i] += max(q[i], -1e4)
        if (k + 1) % _BATCH == 0:
            for i in range(n):
                acc[i] += math.log(prod[i])
                prod[i] = 1.0
    for i in range(n):
        out[i] = acc[i] + math.log(prod[i])


@nb.njit(cache=True, error_model="numpy", fastmath=True)
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
        d_th = _wrap(nth - ob[11]) / hough[2]
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
