"""Compiled drawing of the objects in a rendered camera image: robots, ball, goals, poles.

Used by :mod:`teamsim.image_kernel` (see there for the packed inputs and the draw order).
A pixel's ray is ``cam + t * d`` in the **world frame** (m) with ``d`` = d0 + u du + v dv
for the pixel centre (u, v): its camera-frame x component is 1, so ``t`` is the depth
along the optical axis and ``t / fx`` the width of a pixel there (m). The camera has no
roll, so ``du`` is horizontal and along an image row the ray is linear in the column u.

**Which pixels.** Only the pixels that can be touched are ray cast. An object's rows come
from its bounding box clipped exactly to the near plane (:func:`box_pixels`); in every
row the columns come from linear conditions on the ray:

* a vertical cylinder (robot, post, pole) is seen inside the wedge between its two
  vertical tangent planes through the camera, a horizontal one (crossbar) inside the
  wedge across its axis (:func:`wedge`); the radius is grown by half a pixel's footprint
  so that the anti-aliased fringe is inside;
* a net panel (a rectangle in an axis plane) where the hit's coordinates are in range;
* the ball inside its cone of tangent rays, a quadratic condition per row.

Spans keep one pixel of margin and are padded to whole vectors (:func:`span_window`);
the per-pixel ray test decides, so spans cut work, never pixels.

**How.** Each solid has a row shader (:func:`_robot_row`, :func:`_ball_row`,
:func:`_cyl_row`, :func:`_net_row`): a branch-free float32 loop over the row's span that
the compiler vectorizes (16 lanes), computing coverage (anti-aliased by the ray's distance
to the silhouette in pixel footprints), depth, normal and colour; :func:`_blend_row`
blends the result into the RGB image. Pixels a shader misses get coverage 0, which
leaves them unchanged.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.fastmath import FASTMATH
from teamsim.image_venue import GEO, C
from teamsim.percept_parts import OBS, OC, clip

NEAR = 0.01
"""Near plane (m of depth): object parts closer than this are cut."""
VEC = 16
"""float32 lanes of a vector (AVX-512): row spans are padded to multiples of this."""
_LIGHT = (0.3, 0.2, 0.933)  # unit vector toward the hall lights (world frame)


# ----------------------------------------------------------------------------- pixel spans


@nb.njit(cache=True, inline="always")
def _corner(c, x0, x1, y0, y1, z0, z1, m, cam):  # pragma: no cover - compiled
    """Camera-frame coordinates (depth, left, up) of corner ``c`` (bits: x, y, z) of a world box."""
    dx = (x1 if c & 1 else x0) - cam[0]
    dy = (y1 if c & 2 else y0) - cam[1]
    dz = (z1 if c & 4 else z0) - cam[2]
    return (
        m[0, 0] * dx + m[1, 0] * dy + m[2, 0] * dz,
        m[0, 1] * dx + m[1, 1] * dy + m[2, 1] * dz,
        m[0, 2] * dx + m[1, 2] * dy + m[2, 2] * dz,
    )


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def box_pixels(x0, x1, y0, y1, z0, z1, m, cam, fx, fy, cx, cy, W, H):  # pragma: no cover - compiled
    """Pixel box (i0, i1, j0, j1), columns [i0, i1) and rows [j0, j1), that holds the part of
    the world box [x0, x1] x [y0, y1] x [z0, z1] (m) in front of the near plane, with one
    pixel of margin; (0, 0, 0, 0) if nothing is seen. The box is clipped exactly: its
    corners in front and the points where its edges cross the near plane are projected.
    """
    umin, umax, vmin, vmax = 1e18, -1e18, 1e18, -1e18
    front = 0
    for c in range(8):
        q0, q1, q2 = _corner(c, x0, x1, y0, y1, z0, z1, m, cam)
        if q0 >= NEAR:
            front += 1
            u, v = cx - fx * q1 / q0, cy - fy * q2 / q0
            umin, umax, vmin, vmax = min(umin, u), max(umax, u), min(vmin, v), max(vmax, v)
    if front == 0:
        return 0, 0, 0, 0
    if front < 8:
        for c in range(8):
            a0, a1, a2 = _corner(c, x0, x1, y0, y1, z0, z1, m, cam)
            for bit in (1, 2, 4):
                if c & bit:
                    continue
                b0, b1, b2 = _corner(c | bit, x0, x1, y0, y1, z0, z1, m, cam)
                if (a0 >= NEAR) != (b0 >= NEAR):
                    s = (NEAR - a0) / (b0 - a0)
                    u = cx - fx * (a1 + s * (b1 - a1)) / NEAR
                    v = cy - fy * (a2 + s * (b2 - a2)) / NEAR
                    umin, umax, vmin, vmax = min(umin, u), max(umax, u), min(vmin, v), max(vmax, v)
    umin, umax = max(umin, -4.0), min(umax, W + 4.0)
    vmin, vmax = max(vmin, -4.0), min(vmax, H + 4.0)
    i0, i1 = max(0, math.floor(umin) - 1), min(W, math.floor(umax) + 2)
    j0, j1 = max(0, math.floor(vmin) - 1), min(H, math.floor(vmax) + 2)
    if i0 >= i1 or j0 >= j1:
        return 0, 0, 0, 0
    return i0, i1, j0, j1


@nb.njit(cache=True, inline="always")
def _cols(lo, hi, i0, i1):  # pragma: no cover - compiled
    """Pixels [a, b) of [i0, i1) whose centres may lie in the column interval [lo, hi]."""
    if hi < lo:
        return i0, i0
    a = max(i0, math.floor(max(lo, -4.0)) - 1)
    b = min(i1, math.floor(min(hi, 1e7)) + 2)
    return a, max(a, b)


@nb.njit(cache=True, inline="always")
def span_window(a, b, W):  # pragma: no cover - compiled
    """(start, length) of a run of pixels within [0, W) that holds [a, b), its length a
    multiple of :data:`VEC` (unless W is smaller): vector loops then have no scalar rest."""
    n = (b - a + VEC - 1) // VEC * VEC
    if n >= W:
        return 0, W
    return min(a, W - n), n


@nb.njit(cache=True, inline="always")
def wedge(p1, p2, r):  # pragma: no cover - compiled
    """2-D directions d from the origin whose ray passes within ``r`` of point (p1, p2).

    Returns (ok, c1, c2, e1, e2): the set is {d : c . d >= 0 and e . d >= 0} (between the
    two tangents); ok is False when the origin is within ``r`` of the point (no wedge).
    """
    dd = p1 * p1 + p2 * p2
    if dd <= 1.0001 * r * r:
        return False, 0.0, 0.0, 0.0, 0.0
    n = math.sqrt(dd)
    a1, a2 = p1 / n, p2 / n
    tn = r / math.sqrt(dd - r * r)
    return True, tn * a1 + a2, tn * a2 - a1, tn * a1 - a2, tn * a2 + a1


@nb.njit(cache=True, inline="always")
def _wedge_cols(w, a1, b1, a2, b2, i0, i1):  # pragma: no cover - compiled
    """Pixels of [i0, i1) in the wedge ``w`` (see :func:`wedge`) for the directions
    (a1 + u b1, a2 + u b2) of column u."""
    ok, c1, c2, e1, e2 = w
    if not ok:
        return i0, i1
    lo, hi = clip(c1 * a1 + c2 * a2, c1 * b1 + c2 * b2, -4.0, 1e7)
    lo, hi = clip(e1 * a1 + e2 * a2, e1 * b1 + e2 * b2, lo, hi)
    return _cols(lo, hi, i0, i1)


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH, inline="always")
def _blend_row(seg, scr, n):  # pragma: no cover - compiled
    """Blend ``scr`` (rows r, g, b 0..255, coverage; float32) over ``n`` RGB pixels ``seg``."""
    h, lo, hi = np.float32(0.5), np.float32(0.0), np.float32(255.0)
    for q in range(n):
        al = scr[3, q]
        o = np.float32(seg[3 * q])
        seg[3 * q] = np.uint8(min(hi, max(lo, o + al * (scr[0, q] - o) + h)))
        o = np.float32(seg[3 * q + 1])
        seg[3 * q + 1] = np.uint8(min(hi, max(lo, o + al * (scr[1, q] - o) + h)))
        o = np.float32(seg[3 * q + 2])
        seg[3 * q + 2] = np.uint8(min(hi, max(lo, o + al * (scr[2, q] - o) + h)))


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def draw_robot(obs, occ, k, cam, d0, du, dv, m, fx, fy, cx, cy, W, H, col, img, scr):  # pragma: no cover
    """Robot ``k``: a vertical cylinder with joint, jersey and visor bands (a fallen robot is
    a low cylinder, jersey on top). ``scr``: scratch (at least 4 x (W + VEC) float32)."""
    inv_f = 1.0 / fx
    ox, oy, rad, h = occ[k, OC.X], occ[k, OC.Y], occ[k, OC.R], occ[k, OC.H]
    re = rad + 0.5 * math.hypot(ox - cam[0], oy - cam[1]) * inv_f + 1e-6  # with the AA fringe
    i0, i1, j0, j1 = box_pixels(ox - re, ox + re, oy - re, oy + re, 0.0, h, m, cam, fx, fy, cx, cy, W, H)
    if i0 >= i1:  # not in view
        return
    w = wedge(ox - cam[0], oy - cam[1], re)
    team = C.TEAM1 if obs[k, OBS.TEAM] > 0.5 else C.TEAM0
    standing = h >= 0.4
    top = C.BODY if standing else team
    flat = img.reshape(H, W * 3)
    pal = np.empty((5, 3), dtype=np.float32)  # body, joint, jersey, visor, top
    for q in range(3):
        pal[0, q], pal[1, q], pal[2, q], pal[3, q] = col[C.BODY, q], col[C.JOINT, q], col[team, q], col[C.VISOR, q]
        pal[4, q] = col[top, q] * 0.95
    pr = (rad, h, cam[0] - ox, cam[1] - oy, cam[2], inv_f, math.cos(obs[k, OBS.TH]), math.sin(obs[k, OBS.TH]))
    for j in range(j0, j1):
        v = j + 0.5
        rx, ry, rz = d0[0] + v * dv[0], d0[1] + v * dv[1], d0[2] + v * dv[2]
        a, b = _wedge_cols(w, rx, du[0], ry, du[1], i0, i1)
        if b <= a:
            continue
        cap = cam[2] > h and rz < 0.0
        tt = (h - cam[2]) / rz if cap else 0.0
        a, n = span_window(a, b, W)
        _robot_row(scr, a, n, rx, ry, rz, du[0], du[1], pr, standing, cap, tt, pal)
        _blend_row(flat[j, 3 * a : 3 * (a + n)], scr, n)


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH, inline="always")
def _robot_row(scr, a, n, rx, ry, rz, dux, duy, pr, standing, cap, tt, pal):  # pragma: no cover - compiled
    """Colour and coverage of a robot at pixels a .. a + n - 1 of a row into ``scr`` (rows
    r, g, b, coverage; 0: untouched). The ray at column u is (rx + u dux, ry + u duy, rz);
    ``pr``: radius, height, camera minus axis (x, y), camera height, 1 / fx, heading (cos,
    sin); ``cap``: the camera is above a low robot and the row looks down, meeting its top
    plane at ray parameter ``tt``; ``pal``: see :func:`draw_robot`. The distance to the axis
    comes from a cross product (no cancellation), the normal's length is max(r, dist). The
    anti-aliasing footprint is the one at the silhouette, constant along the row.
    """
    f4 = np.float32
    rad, h, p1, p2, cz, inv_f = f4(pr[0]), f4(pr[1]), f4(pr[2]), f4(pr[3]), f4(pr[4]), f4(pr[5])
    hd_x, hd_y, rx, ry, rz, dux, duy = f4(pr[6]), f4(pr[7]), f4(rx), f4(ry), f4(rz), f4(dux), f4(duy)
    b_r, b_g, b_b, j_r, j_g, j_b = pal[0, 0], pal[0, 1], pal[0, 2], pal[1, 0], pal[1, 1], pal[1, 2]
    t_r, t_g, t_b, v_r, v_g, v_b = pal[2, 0], pal[2, 1], pal[2, 2], pal[3, 0], pal[3, 1], pal[3, 2]
    o_r, o_g, o_b = pal[4, 0], pal[4, 1], pal[4, 2]
    zero, one, half, tiny = f4(0.0), f4(1.0), f4(0.5), f4(1e-18)
    r2 = rad * rad
    inv_h, inv_r = one / h, one / rad
    tt32 = f4(tt)
    base = f4(a) + half
    k_b, k_s, k_t = f4(0.62), f4(0.38), f4(1e-9)
    # pixel footprint (m) at the silhouette, where the tangent ray touches: sqrt(|p|^2 - r^2) / fx
    inv_fp = one / max(f4(math.sqrt(max(pr[2] * pr[2] + pr[3] * pr[3] - pr[0] * pr[0], 0.0))) * inv_f, k_t)
    for q in range(n):
        u = base + f4(q)
        dx, dy = rx + u * dux, ry + u * duy
        aa = max(dx * dx + dy * dy, tiny)
        inv_sa = one / math.sqrt(aa)
        inv_aa = inv_sa * inv_sa
        pd = p1 * dx + p2 * dy
        tc = -pd * inv_aa  # closest approach
        dist = abs(p1 * dy - p2 * dx) * inv_sa
        cov = min((rad - dist) * inv_fp + half, one)
        inside = dist < rad
        t = tc - math.sqrt(max(r2 - dist * dist, zero) * inv_aa)
        t = t if inside else tc
        z = cz + t * rz
        hit = (tc > zero) & (cov > zero) & (z >= zero) & (z <= h)
        h1, h2 = p1 + t * dx, p2 + t * dy
        nrm = rad if inside else dist
        # the normal is h / nrm; at the closest approach (the fringe) h . d = 0
        s = k_b + k_s * max(zero, -(h1 * dx + h2 * dy) * inv_sa * inv_r) if inside else k_b
        f = z * inv_h
        joint = standing & ((f < f4(0.08)) | ((f > f4(0.34)) & (f < f4(0.40))))
        jersey = (standing & (f >= f4(0.45)) & (f < f4(0.77))) | ((not standing) & (f > half))
        visor = standing & (f > f4(0.85)) & (f < f4(0.92)) & (h1 * hd_x + h2 * hd_y > half * nrm)
        c_r = j_r if joint else (t_r if jersey else (v_r if visor else b_r))  # selects, not a gather
        c_g = j_g if joint else (t_g if jersey else (v_g if visor else b_g))
        c_b = j_b if joint else (t_b if jersey else (v_b if visor else b_b))
        hx_, hy_ = p1 + tt32 * dx, p2 + tt32 * dy
        top = cap & (hx_ * hx_ + hy_ * hy_ <= r2)
        scr[0, q] = c_r * s if hit else o_r
        scr[1, q] = c_g * s if hit else o_g
        scr[2, q] = c_b * s if hit else o_b
        scr[3, q] = cov if hit else (one if top else zero)


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def draw_ball(ball, cam, d0, du, dv, m, fx, fy, cx, cy, W, H, geo, col, ico, img, scr):  # pragma: no cover
    """The ball: a shaded sphere, single-coloured or with black patches (``GEO.MODERN_BALL``;
    the patches are centred on the first 12 rows of ``ico``). Per row, the columns inside
    the cone of rays within the grown radius, a quadratic condition in u (the whole box row
    when the cone's trace is unbounded)."""
    inv_f = 1.0 / fx
    br = geo[GEO.BALL_R]
    bx, by = ball[0], ball[1]
    px, py, pz = bx - cam[0], by - cam[1], br - cam[2]
    dist = math.sqrt(px * px + py * py + pz * pz)
    re = br + 0.5 * dist * inv_f + 1e-6
    i0, i1, j0, j1 = box_pixels(bx - re, bx + re, by - re, by + re, br - re, br + re, m, cam, fx, fy, cx, cy, W, H)
    if i0 >= i1:
        return
    cone = dist > 1.0001 * re
    ax, ay, az, c2 = 0.0, 0.0, 0.0, 0.0
    if cone:
        ax, ay, az = px / dist, py / dist, pz / dist
        c2 = 1.0 - (re / dist) ** 2  # cos^2 of the cone's half angle
    qb = ax * du[0] + ay * du[1]
    k2 = qb * qb - c2 * (du[0] * du[0] + du[1] * du[1])
    patches = geo[GEO.MODERN_BALL] > 0.5 and ico.shape[0] > 0
    a1, a2 = bx / br, by / br  # pattern orientation: rolled by the distance travelled along x and y
    sp = (-px, -py, -pz, br, inv_f, math.cos(a1), math.sin(a1), math.cos(a2), math.sin(a2))
    pal = np.empty((2, 3), dtype=np.float32)
    pat = np.empty((3, 12), dtype=np.float32)  # patch centres (the first again if fewer)
    for q in range(3):
        pal[0, q], pal[1, q] = col[C.BALL_A, q], col[C.BALL_B, q]
        for k in range(12):
            pat[q, k] = ico[k if k < ico.shape[0] else 0, q]
    flat = img.reshape(H, W * 3)
    for j in range(j0, j1):
        v = j + 0.5
        rx, ry, rz = d0[0] + v * dv[0], d0[1] + v * dv[1], d0[2] + v * dv[2]
        ia, ib = i0, i1
        if cone and k2 < -1e-18:  # (p + qb u)^2 >= c2 |r + u du|^2 is a bounded interval
            p = ax * rx + ay * ry + az * rz
            k1 = p * qb - c2 * (rx * du[0] + ry * du[1])
            k0 = p * p - c2 * (rx * rx + ry * ry + rz * rz)
            disc = k1 * k1 - k2 * k0
            if disc < 0.0:
                continue
            sq = math.sqrt(disc)
            ua, ub = (-k1 + sq) / k2, (-k1 - sq) / k2
            if p + qb * 0.5 * (ua + ub) <= 0.0:  # the cone behind the camera
                continue
            ia, ib = _cols(min(ua, ub), max(ua, ub), i0, i1)
        if ib <= ia:
            continue
        a, n = span_window(ia, ib, W)
        _ball_row(scr, a, n, rx, ry, rz, du[0], du[1], sp, patches, pal, pat)
        _blend_row(flat[j, 3 * a : 3 * (a + n)], scr, n)


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH, inline="always")
def _ball_row(scr, a, n, rx, ry, rz, dux, duy, sp, patches, pal, pat):  # pragma: no cover - compiled
    """Colour and coverage of the ball at pixels a .. a + n - 1 of a row into ``scr`` (see
    :func:`_robot_row`). ``sp``: camera minus centre (x, y, z), radius, 1 / fx, the pattern's
    roll (cos, sin about y, then about x); ``pal``: the two colours; ``pat`` (3 x 12): patch
    centres (body frame); shaded by the light, a patch where the body-fixed normal is within
    acos(0.93) of a centre."""
    f4 = np.float32
    p1, p2, p3, rad, inv_f = f4(sp[0]), f4(sp[1]), f4(sp[2]), f4(sp[3]), f4(sp[4])
    cs1, sn1, cs2, sn2 = f4(sp[5]), f4(sp[6]), f4(sp[7]), f4(sp[8])
    rx, ry, rz, dux, duy = f4(rx), f4(ry), f4(rz), f4(dux), f4(duy)
    lx, ly, lz = f4(_LIGHT[0]), f4(_LIGHT[1]), f4(_LIGHT[2])
    a_r, a_g, a_b, b_r, b_g, b_b = pal[0, 0], pal[0, 1], pal[0, 2], pal[1, 0], pal[1, 1], pal[1, 2]
    zero, one, half = f4(0.0), f4(1.0), f4(0.5)
    r2 = rad * rad
    inv_fp = one / max(
        f4(math.sqrt(max(sp[0] * sp[0] + sp[1] * sp[1] + sp[2] * sp[2] - sp[3] * sp[3], 0.0))) * inv_f, f4(1e-9)
    )
    base = f4(a) + half
    for q in range(n):
        u = base + f4(q)
        dx, dy = rx + u * dux, ry + u * duy
        aa = dx * dx + dy * dy + rz * rz
        inv_sa = one / math.sqrt(aa)
        inv_aa = inv_sa * inv_sa
        tc = -(p1 * dx + p2 * dy + p3 * rz) * inv_aa
        c1, c2, c3 = p2 * rz - p3 * dy, p3 * dx - p1 * rz, p1 * dy - p2 * dx  # p x d: dist |d|
        dist2 = (c1 * c1 + c2 * c2 + c3 * c3) * inv_aa
        dist = math.sqrt(dist2)
        cov = min((rad - dist) * inv_fp + half, one)
        inside = dist < rad
        t = tc - math.sqrt(max(r2 - dist2, zero) * inv_aa)
        t = t if inside else tc
        inv_n = one / max(rad if inside else dist, f4(1e-12))
        nx, ny, nz = (p1 + t * dx) * inv_n, (p2 + t * dy) * inv_n, (p3 + t * rz) * inv_n
        s = f4(0.45) + f4(0.55) * max(zero, nx * lx + ny * ly + nz * lz)
        dark = False
        if patches:  # body-fixed normal: undo the roll about y then about x
            qx = cs1 * nx - sn1 * nz
            qz = sn1 * nx + cs1 * nz
            qy = cs2 * ny + sn2 * qz
            qz = -sn2 * ny + cs2 * qz
            best = -one
            for k in range(12):
                best = max(best, qx * pat[0, k] + qy * pat[1, k] + qz * pat[2, k])
            dark = best > f4(0.93)
        scr[0, q] = (b_r if dark else a_r) * s
        scr[1, q] = (b_g if dark else a_g) * s
        scr[2, q] = (b_b if dark else a_b) * s
        scr[3, q] = cov if (tc > zero) & (cov > zero) else zero


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def draw_goal(g, cam, d0, du, dv, m, fx, fy, cx, cy, W, H, geo, col, posts, img, scr):  # pragma: no cover
    """Goal ``g`` (0: at -x, 1: at +x): the net (transparent: back, sides, top), then posts and
    crossbar (per pixel the nearest of the three). ``scr``: scratch (5 x (W + VEC) float32)."""
    inv_f = 1.0 / fx
    sgn = -1.0 if g == 0 else 1.0
    hl, depth, gh = geo[GEO.HALF_LENGTH], geo[GEO.GOAL_DEPTH], geo[GEO.GOAL_H]
    pr, hw, spacing = geo[GEO.POST_R], geo[GEO.GOAL_HALF_W], geo[GEO.NET_SPACING]
    x_in, x_out = hl, hl + depth
    xa, xb = min(sgn * x_in, sgn * x_out), max(sgn * x_in, sgn * x_out)
    xo = sgn * x_out
    pb = (m, cam, fx, fy, cx, cy, W, H)
    net = (sgn, spacing, inv_f, col[C.NET, 0], col[C.NET, 1], col[C.NET, 2])
    _net(0, 1, 2, x_out, (-hw, hw, 0.0, gh), box_pixels(xo, xo, -hw, hw, 0.0, gh, *pb), net, cam, d0, du, dv, W, img)
    for side in (-hw, hw):
        box = box_pixels(xa, xb, side, side, 0.0, gh, *pb)
        _net(1, 0, 2, side, (x_in, x_out, 0.0, gh), box, net, cam, d0, du, dv, W, img)
    box = box_pixels(xa, xb, -hw, hw, gh, gh, *pb)
    _net(2, 0, 1, gh, (x_in, x_out, -hw, hw), box, net, cam, d0, du, dv, W, img)
    # posts and crossbar: pixel boxes and wedges (radii with the AA fringe)
    p0, p1 = 2 * g, 2 * g + 1
    xp, zb = posts[p0, 0], gh - pr
    r0 = pr + 0.5 * math.hypot(posts[p0, 0] - cam[0], posts[p0, 1] - cam[1]) * inv_f + 1e-6
    r1 = pr + 0.5 * math.hypot(posts[p1, 0] - cam[0], posts[p1, 1] - cam[1]) * inv_f + 1e-6
    r2 = pr + 0.5 * math.hypot(xp - cam[0], zb - cam[2]) * inv_f + 1e-6
    b0 = box_pixels(posts[p0, 0] - r0, posts[p0, 0] + r0, posts[p0, 1] - r0, posts[p0, 1] + r0, 0.0, gh, *pb)
    b1 = box_pixels(posts[p1, 0] - r1, posts[p1, 0] + r1, posts[p1, 1] - r1, posts[p1, 1] + r1, 0.0, gh, *pb)
    b2 = box_pixels(xp - r2, xp + r2, -hw, hw, zb - r2, zb + r2, *pb)
    w0 = wedge(posts[p0, 0] - cam[0], posts[p0, 1] - cam[1], r0)
    w1 = wedge(posts[p1, 0] - cam[0], posts[p1, 1] - cam[1], r1)
    w2 = wedge(xp - cam[0], zb - cam[2], r2)
    gc = C.GOAL_NEG if g == 0 else C.GOAL_POS
    colour = (col[gc, 0], col[gc, 1], col[gc, 2])
    none = (0.0, 0.0)
    flat = img.reshape(H, W * 3)
    jlo, jhi = H, 0
    for bx in (b0, b1, b2):
        if bx[0] < bx[1]:
            jlo, jhi = min(jlo, bx[2]), max(jhi, bx[3])
    for j in range(jlo, jhi):
        v = j + 0.5
        rx, ry, rz = d0[0] + v * dv[0], d0[1] + v * dv[1], d0[2] + v * dv[2]
        s0, e0, s1, e1, s2, e2 = 0, 0, 0, 0, 0, 0
        if b0[2] <= j < b0[3]:
            s0, e0 = _wedge_cols(w0, rx, du[0], ry, du[1], b0[0], b0[1])
        if b1[2] <= j < b1[3]:
            s1, e1 = _wedge_cols(w1, rx, du[0], ry, du[1], b1[0], b1[1])
        if b2[2] <= j < b2[3]:
            s2, e2 = _wedge_cols(w2, rx, du[0], rz, 0.0, b2[0], b2[1])
        a0, n0 = span_window(s0, e0, W) if e0 > s0 else (W, 0)
        a1, n1 = span_window(s1, e1, W) if e1 > s1 else (W, 0)
        a2, n2 = span_window(s2, e2, W) if e2 > s2 else (W, 0)
        lo, hi = min(a0, a1, a2), max(a0 + n0 if n0 else 0, a1 + n1 if n1 else 0, a2 + n2 if n2 else 0)
        if hi <= lo:
            continue
        # the nearest hit per pixel: cast each solid over its window, then blend the whole run once
        scr[3, lo:hi] = 0.0
        scr[4, lo:hi] = 1e30
        post = (rx, du[0], ry, du[1], rz, 0.0)
        if n0 > 0:
            cyl = (cam[0] - posts[p0, 0], cam[1] - posts[p0, 1], cam[2], 0.0, gh)
            _cyl_row(scr, a0, n0, post, cyl, pr, inv_f, False, colour, colour, none)
        if n1 > 0:
            cyl = (cam[0] - posts[p1, 0], cam[1] - posts[p1, 1], cam[2], 0.0, gh)
            _cyl_row(scr, a1, n1, post, cyl, pr, inv_f, False, colour, colour, none)
        if n2 > 0:
            cyl = (cam[0] - xp, cam[2] - zb, cam[1], -hw, hw)
            _cyl_row(scr, a2, n2, (rx, du[0], rz, 0.0, ry, du[1]), cyl, pr, inv_f, True, colour, colour, none)
        _blend_row(flat[j, 3 * lo : 3 * hi], scr[:, lo:hi], hi - lo)


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def _net(n_ax, a_ax, b_ax, plane, rect, box, net, cam, d0, du, dv, W, img):  # pragma: no cover - compiled
    """One net panel: the rectangle where goal-frame coordinate ``n_ax`` (0: x' = sgn x, 1: y,
    2: z) equals ``plane`` and coordinates ``a_ax``, ``b_ax`` lie in ``rect`` = (lo1, hi1,
    lo2, hi2); ``box`` its pixel box; ``net``: sgn, mesh spacing, 1 / fx, colour. The
    columns of a row are where the ray meets the plane in front with both coordinates in
    range: five linear conditions on u."""
    i0, i1, j0, j1 = box
    sgn = net[0]
    lo1, hi1, lo2, hi2 = rect
    o = (sgn * cam[0], cam[1], cam[2])
    g = plane - o[n_ax]
    if g == 0.0:
        return
    sg, ag = (1.0 if g > 0.0 else -1.0), abs(g)
    bu = (sgn * du[0], du[1], 0.0)
    oa, ob = o[a_ax], o[b_ax]
    flat = img.reshape(img.shape[0], W * 3)
    for j in range(j0, j1):
        v = j + 0.5
        ar = (sgn * (d0[0] + v * dv[0]), d0[1] + v * dv[1], d0[2] + v * dv[2])
        an, bn = sg * ar[n_ax], sg * bu[n_ax]  # along the normal toward the plane: > 0 in front
        lo, hi = clip(an, bn, -4.0, 1e7)
        lo, hi = clip(ag * ar[a_ax] - (lo1 - oa) * an, ag * bu[a_ax] - (lo1 - oa) * bn, lo, hi)
        lo, hi = clip((hi1 - oa) * an - ag * ar[a_ax], (hi1 - oa) * bn - ag * bu[a_ax], lo, hi)
        lo, hi = clip(ag * ar[b_ax] - (lo2 - ob) * an, ag * bu[b_ax] - (lo2 - ob) * bn, lo, hi)
        lo, hi = clip((hi2 - ob) * an - ag * ar[b_ax], (hi2 - ob) * bn - ag * bu[b_ax], lo, hi)
        ia, ib = _cols(lo, hi, i0, i1)
        if ib <= ia:
            continue
        x0, n = span_window(ia, ib, W)
        ray = (ar[n_ax], bu[n_ax], ar[a_ax], bu[a_ax], ar[b_ax], bu[b_ax])
        _net_row(flat[j, 3 * x0 : 3 * (x0 + n)], x0, ray, (g, oa, ob), rect, net)


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH, inline="always")
def _net_row(seg, x0, ray, org, rect, net):  # pragma: no cover - compiled
    """Blend a net panel over the RGB pixels ``seg`` (columns x0 ..). The ray at column u has
    the coordinates ray[0] + u ray[1] (along the normal), ray[2] + u ray[3], ray[4] + u ray[5]
    (goal frame); ``org``: plane minus camera along the normal, the camera's two others.
    Opacity 0.7 on the mesh's strings (at least 6 mm or half a pixel wide), else 0.12."""
    f = np.float32
    an, bn, a1, b1, a2, b2 = f(ray[0]), f(ray[1]), f(ray[2]), f(ray[3]), f(ray[4]), f(ray[5])
    g, on1, on2 = f(org[0]), f(org[1]), f(org[2])
    lo1, hi1, lo2, hi2 = f(rect[0]), f(rect[1]), f(rect[2]), f(rect[3])
    sp, inv_sp, hf = f(net[1]), f(1.0 / net[1]), f(0.5 * net[2])
    cr, cg, cb = f(net[3]), f(net[4]), f(net[5])
    zero, one, half, eps, thick = f(0.0), f(1.0), f(0.5), f(1e-12), f(0.006)
    strong, weak, top = f(0.7), f(0.12), f(255.0)
    base = f(x0) + half
    for q in range(seg.shape[0] // 3):
        u = base + f(q)
        dn = an + u * bn
        ok = abs(dn) >= eps
        t = g / (dn if ok else one)
        a = on1 + t * (a1 + u * b1)
        b = on2 + t * (a2 + u * b2)
        hit = ok & (t > zero) & (a >= lo1) & (a <= hi1) & (b >= lo2) & (b <= hi2)
        lim = max(thick, hf * t)
        fa = a * inv_sp
        fa -= math.floor(fa)
        fb = b * inv_sp
        fb -= math.floor(fb)
        mesh = (min(fa, one - fa) * sp < lim) | (min(fb, one - fb) * sp < lim)
        al = (strong if mesh else weak) if hit else zero
        o = f(seg[3 * q])
        seg[3 * q] = np.uint8(min(top, max(zero, o + al * (cr - o) + half)))
        o = f(seg[3 * q + 1])
        seg[3 * q + 1] = np.uint8(min(top, max(zero, o + al * (cg - o) + half)))
        o = f(seg[3 * q + 2])
        seg[3 * q + 2] = np.uint8(min(top, max(zero, o + al * (cb - o) + half)))


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH, inline="always")
def _cyl_row(scr, a, n, ray, cyl, rad, inv_f, bar, colour, colour2, band):  # pragma: no cover - compiled
    """Cast pixels a .. a + n - 1 of a row against a post, crossbar or pole, keeping in ``scr``
    (rows r, g, b, coverage, depth; indexed by column) the nearest hit so far.

    The ray at column u has the components across the axis (ray[0] + u ray[1], ray[2] +
    u ray[3]) and along it ray[4] + u ray[5]; ``cyl``: the camera minus the axis (across),
    the camera along the axis, the axis's extent. Shaded by the angle of incidence, or by
    the normal's upward part if ``bar``; ``colour2`` where the hit's axial coordinate is in
    [band[0], band[1]). Anti-aliased with the pixel footprint at the silhouette.
    """
    f4 = np.float32
    a1, b1, a2, b2, aa_, ba = f4(ray[0]), f4(ray[1]), f4(ray[2]), f4(ray[3]), f4(ray[4]), f4(ray[5])
    p1, p2, oa, lo, hi = f4(cyl[0]), f4(cyl[1]), f4(cyl[2]), f4(cyl[3]), f4(cyl[4])
    r, fi, blo, bhi = f4(rad), f4(inv_f), f4(band[0]), f4(band[1])
    cr, cg, cb, dr, dg, db = f4(colour[0]), f4(colour[1]), f4(colour[2]), f4(colour2[0]), f4(colour2[1]), f4(colour2[2])
    zero, one, half, tiny = f4(0.0), f4(1.0), f4(0.5), f4(1e-18)
    k0, k1 = (f4(0.55), f4(0.45)) if bar else (f4(0.65), f4(0.35))
    r2 = r * r
    inv_fp = one / max(f4(math.sqrt(max(cyl[0] * cyl[0] + cyl[1] * cyl[1] - rad * rad, 0.0))) * fi, f4(1e-9))
    base = f4(a) + half
    sr, sg, sb, sc, sd = scr[0, a : a + n], scr[1, a : a + n], scr[2, a : a + n], scr[3, a : a + n], scr[4, a : a + n]
    for q in range(n):
        u = base + f4(q)
        d1, d2, da = a1 + u * b1, a2 + u * b2, aa_ + u * ba
        aa = max(d1 * d1 + d2 * d2, tiny)
        inv_sa = one / math.sqrt(aa)
        inv_aa = inv_sa * inv_sa
        tc = -(p1 * d1 + p2 * d2) * inv_aa
        dist = abs(p1 * d2 - p2 * d1) * inv_sa
        cov = min((r - dist) * inv_fp + half, one)
        inside = dist < r
        t = tc - math.sqrt(max(r2 - dist * dist, zero) * inv_aa)
        t = t if inside else tc
        ax = oa + t * da
        inv_n = one / max(r if inside else dist, f4(1e-12))
        h1, h2 = (p1 + t * d1) * inv_n, (p2 + t * d2) * inv_n
        s = k0 + k1 * max(zero, h2 if bar else -(h1 * d1 + h2 * d2) * inv_sa)
        alt = (ax >= blo) & (ax < bhi)
        better = (tc > zero) & (cov > zero) & (ax >= lo) & (ax <= hi) & (t < sd[q])
        sr[q] = (dr if alt else cr) * s if better else sr[q]
        sg[q] = (dg if alt else cg) * s if better else sg[q]
        sb[q] = (db if alt else cb) * s if better else sb[q]
        sc[q] = cov if better else sc[q]
        sd[q] = t if better else sd[q]


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def draw_pole(k, cam, d0, du, dv, m, fx, fy, cx, cy, W, H, geo, col, poles, img, scr):  # pragma: no cover
    """Corner pole ``k``: three bands, the colours of the goal at its end of the field (the
    middle one the other goal's). ``scr``: scratch (5 x (W + VEC) float32)."""
    inv_f = 1.0 / fx
    pr, ph = geo[GEO.POLE_R], geo[GEO.POLE_H]
    ox, oy = poles[k, 0], poles[k, 1]
    re = pr + 0.5 * math.hypot(ox - cam[0], oy - cam[1]) * inv_f + 1e-6
    i0, i1, j0, j1 = box_pixels(ox - re, ox + re, oy - re, oy + re, 0.0, ph, m, cam, fx, fy, cx, cy, W, H)
    w = wedge(ox - cam[0], oy - cam[1], re)
    near_c = C.GOAL_NEG if ox < 0.0 else C.GOAL_POS
    far_c = C.GOAL_POS if ox < 0.0 else C.GOAL_NEG
    near, far = (col[near_c, 0], col[near_c, 1], col[near_c, 2]), (col[far_c, 0], col[far_c, 1], col[far_c, 2])
    cyl = (cam[0] - ox, cam[1] - oy, cam[2], 0.0, ph)
    flat = img.reshape(H, W * 3)
    for j in range(j0, j1):
        v = j + 0.5
        rx, ry, rz = d0[0] + v * dv[0], d0[1] + v * dv[1], d0[2] + v * dv[2]
        a, b = _wedge_cols(w, rx, du[0], ry, du[1], i0, i1)
        if b <= a:
            continue
        a, n = span_window(a, b, W)
        scr[3, a : a + n] = 0.0
        scr[4, a : a + n] = 1e30
        _cyl_row(
            scr, a, n, (rx, du[0], ry, du[1], rz, 0.0), cyl, pr, inv_f, False, near, far, (ph / 3.0, 2.0 * ph / 3.0)
        )
        _blend_row(flat[j, 3 * a : 3 * (a + n)], scr[:, a : a + n], n)


def icosahedron() -> NDArray[np.float64]:
    """The 12 unit vertex directions of an icosahedron (centres of a football's pentagons)."""
    g = (1.0 + math.sqrt(5.0)) / 2.0
    v = []
    for a in (-1.0, 1.0):
        for b in (-g, g):
            v += [(0.0, a, b), (a, b, 0.0), (b, 0.0, a)]
    arr = np.array(v, dtype=np.float64)
    return arr / np.linalg.norm(arr, axis=1, keepdims=True)
