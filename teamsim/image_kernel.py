"""Compiled renderer of one robot's camera image (the scene, before image effects).

The camera has no roll (the head has yaw and pitch joints only, see
:mod:`cognition.camera`), so an image row is a plane through the optical centre that meets
the ground in a straight line, and along a row the ground point is a *linear* function of
the column. The background is drawn row by row from that fact:

* **floor**: the columns whose ray meets the floor inside the hall form one interval; the
  carpet (field plus border strip) is a sub-interval, anti-aliased at its ends; the smooth
  brightness texture is sampled every :data:`STRIDE` pixels and interpolated;
* **paint**: every straight line, penalty mark and the centre circle is intersected
  analytically with the row's ground line, giving exact column intervals whose coverage is
  accumulated over :data:`SUBROWS` sub-rows (anti-aliasing in both directions); lines keep
  their true width in perspective;
* **hall**: the other columns (and every row above the horizon) are cast against the four
  walls and the ceiling.

Objects (robots, ball, goal posts, crossbars, nets, corner poles) are then drawn far to
near by casting the rays of the pixels inside each object's projected bounding box against
the object's solids (:mod:`teamsim.image_objects`). Bounding boxes of objects that reach
behind the camera's near plane grow to the whole image, so near-plane clipping is exact.

All geometry is in the **world frame** (m, rad); pixel (i, j) has its centre at
(u, v) = (i + 0.5, j + 0.5). The camera pose comes from :func:`cognition.camera.camera_pose_nb`,
the same function the percept synthesis uses, so the image agrees with the camera model.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.camera import camera_pose_nb
from teamsim.image_objects import axis_cylinder, blend, mesh_alpha, plane_panel, sphere
from teamsim.image_venue import GEO, C
from teamsim.percept_parts import CAM, OBS, OC

STRIDE = 8
"""Columns between two samples of the floor texture."""
SUBROWS = 4
"""Sub-rows per image row for the coverage of paint."""
NEAR = 0.01
"""Near plane (m of depth): objects closer than this are cut."""
_LIGHT = (0.3, 0.2, 0.933)  # unit vector toward the hall lights (world frame)

# object kinds in the draw list
_ROBOT, _BALL, _GOAL, _POLE = 0, 1, 2, 3


@nb.njit(cache=True, inline="always")
def _slab(a, b, lo_v, hi_v, lo, hi):  # pragma: no cover - compiled
    """Intersect [lo, hi] with {u : lo_v <= a + b u <= hi_v}."""
    if abs(b) < 1e-15:
        if lo_v <= a <= hi_v:
            return lo, hi
        return 1.0, 0.0
    u1, u2 = (lo_v - a) / b, (hi_v - a) / b
    if u1 > u2:
        u1, u2 = u2, u1
    return max(lo, u1), min(hi, u2)


@nb.njit(cache=True, inline="always")
def _add(cov, lo, hi, w):  # pragma: no cover - compiled
    """Add coverage ``w`` over the continuous column interval [lo, hi] (within [0, width])."""
    ia = int(math.floor(lo))
    ib = int(math.floor(hi))
    n = cov.shape[0]
    if ia == ib:
        if ia < n:
            cov[ia] += w * (hi - lo)
        return
    cov[ia] += w * (ia + 1.0 - lo)
    for i in range(ia + 1, min(ib, n)):
        cov[i] += w
    if ib < n:
        cov[ib] += w * (hi - ib)


@nb.njit(cache=True, inline="always")
def _texel(tex, x, y):  # pragma: no cover - compiled
    """Nearest texel of ``tex`` at texel coordinates (x, y), clamped to the texture."""
    return tex[min(max(int(y), 0), tex.shape[0] - 1), min(max(int(x), 0), tex.shape[1] - 1)]


@nb.njit(cache=True, error_model="numpy", fastmath=True)
def _ground_rows(px, py, k, m, cam, fx, fy, cx, cy, width, height):  # pragma: no cover - compiled
    """Rows [j0, j1] a ground polygon (first ``k`` points of px, py) covers, (1, 0) if none.

    The polygon is clipped to the near plane before projection; columns entirely left or
    right of the image also give (1, 0).
    """
    qx = np.empty(2 * k + 2)
    qy = np.empty(2 * k + 2)
    qz = np.empty(2 * k + 2)
    ax = np.empty(k)
    ay = np.empty(k)
    az = np.empty(k)
    for n in range(k):
        dx, dy, dz = px[n] - cam[0], py[n] - cam[1], -cam[2]
        ax[n] = m[0, 0] * dx + m[1, 0] * dy + m[2, 0] * dz
        ay[n] = m[0, 1] * dx + m[1, 1] * dy + m[2, 1] * dz
        az[n] = m[0, 2] * dx + m[1, 2] * dy + m[2, 2] * dz
    cnt = 0
    for n in range(k):
        nn = (n + 1) % k
        ina, inb = ax[n] >= NEAR, ax[nn] >= NEAR
        if ina:
            qx[cnt], qy[cnt], qz[cnt] = ax[n], ay[n], az[n]
            cnt += 1
        if ina != inb:
            s = (NEAR - ax[n]) / (ax[nn] - ax[n])
            qx[cnt], qy[cnt], qz[cnt] = NEAR, ay[n] + s * (ay[nn] - ay[n]), az[n] + s * (az[nn] - az[n])
            cnt += 1
    if cnt == 0:
        return 1, 0
    vmin, vmax, umin, umax = 1e18, -1e18, 1e18, -1e18
    for n in range(cnt):
        u = cx - fx * qy[n] / qx[n]
        v = cy - fy * qz[n] / qx[n]
        vmin, vmax = min(vmin, v), max(vmax, v)
        umin, umax = min(umin, u), max(umax, u)
    if umax < 0.0 or umin > width or vmax < 0.0 or vmin > height:
        return 1, 0
    return max(0, int(math.floor(vmin)) - 1), min(int(height) - 1, int(math.floor(vmax)) + 1)


@nb.njit(cache=True, error_model="numpy", fastmath=True)
def _box_pixels(x0, x1, y0, y1, z0, z1, m, cam, fx, fy, cx, cy, width, height):  # pragma: no cover - compiled
    """Pixel box [i0, i1) x [j0, j1) that holds an axis-aligned world box; empty if unseen."""
    umin, umax, vmin, vmax = 1e18, -1e18, 1e18, -1e18
    behind, front = 0, 0
    for c in range(8):
        x = x1 if c & 1 else x0
        y = y1 if c & 2 else y0
        z = z1 if c & 4 else z0
        dx, dy, dz = x - cam[0], y - cam[1], z - cam[2]
        q0 = m[0, 0] * dx + m[1, 0] * dy + m[2, 0] * dz
        if q0 < NEAR:
            behind += 1
            continue
        front += 1
        q1 = m[0, 1] * dx + m[1, 1] * dy + m[2, 1] * dz
        q2 = m[0, 2] * dx + m[1, 2] * dy + m[2, 2] * dz
        u, v = cx - fx * q1 / q0, cy - fy * q2 / q0
        umin, umax = min(umin, u), max(umax, u)
        vmin, vmax = min(vmin, v), max(vmax, v)
    w, h = int(width), int(height)
    if front == 0:
        return 0, 0, 0, 0
    if behind > 0:
        return 0, w, 0, h
    i0, i1 = max(0, int(math.floor(umin)) - 1), min(w, int(math.floor(umax)) + 2)
    j0, j1 = max(0, int(math.floor(vmin)) - 1), min(h, int(math.floor(vmax)) + 2)
    if i0 >= i1 or j0 >= j1:
        return 0, 0, 0, 0
    return i0, i1, j0, j1


@nb.njit(cache=True, error_model="numpy", fastmath=True)
def render_nb(
    obs, r, occ, ball, cams, geo, col, strips, circles, floor, walls, posts, poles, ico, img
):  # pragma: no cover - compiled
    """Render robot ``r``'s camera image into ``img`` (H x W x 3 uint8, RGB)."""
    rot = np.empty((3, 3))
    pos = np.empty(3)
    m = np.empty((3, 3))
    cam = np.empty(3)
    ci = int(obs[r, OBS.CAM])
    fx, fy, cx, cy = cams[ci, CAM.FX], cams[ci, CAM.FY], cams[ci, CAM.CX], cams[ci, CAM.CY]
    width, height = cams[ci, CAM.W], cams[ci, CAM.H]
    W, H = int(width), int(height)
    camera_pose_nb(
        geo[GEO.NECK], cams[ci, CAM.OFFX], cams[ci, CAM.OFFZ], cams[ci, CAM.TILT], obs[r, OBS.YAW],
        obs[r, OBS.PITCH], rot, pos,
    )  # fmt: skip
    ct, st = math.cos(obs[r, OBS.TH]), math.sin(obs[r, OBS.TH])
    for k in range(3):  # camera -> world
        m[0, k] = ct * rot[0, k] - st * rot[1, k]
        m[1, k] = st * rot[0, k] + ct * rot[1, k]
        m[2, k] = rot[2, k]
    cam[0] = obs[r, OBS.X] + ct * pos[0] - st * pos[1]
    cam[1] = obs[r, OBS.Y] + st * pos[0] + ct * pos[1]
    cam[2] = pos[2]
    # ray of pixel (u, v): d0 + u du + v dv (camera-frame x component 1); du has no z part
    d0 = np.empty(3)
    du = np.empty(3)
    dv = np.empty(3)
    for k in range(3):
        d0[k] = m[k, 0] + m[k, 1] * cx / fx + m[k, 2] * cy / fy
        du[k] = -m[k, 1] / fx
        dv[k] = -m[k, 2] / fy
    _background(cam, d0, du, dv, m, fx, fy, cx, cy, W, H, geo, col, strips, circles, floor, walls, img)
    _objects(obs, r, occ, ball, cam, d0, du, dv, m, fx, fy, cx, cy, W, H, geo, col, posts, poles, ico, img)


@nb.njit(cache=True, error_model="numpy", fastmath=True)
def _background(cam, d0, du, dv, m, fx, fy, cx, cy, W, H, geo, col, strips, circles, floor, walls, img):  # pragma: no cover
    """Floor, paint and hall of the whole image."""
    flat = img.reshape(H, W * 3)
    hc = cam[2]
    hx, hy = geo[GEO.HALL_X], geo[GEO.HALL_Y]
    kx, ky = geo[GEO.CARPET_X], geo[GEO.CARPET_Y]
    n_s, n_c = strips.shape[0], circles.shape[0]
    rows = np.empty((n_s + n_c, 2), dtype=np.int64)
    px = np.empty(8)
    py = np.empty(8)
    for f in range(n_s):
        ax, ay, ex, ey = strips[f, 0], strips[f, 1], strips[f, 2], strips[f, 3]
        nx, ny, ln, w = strips[f, 4], strips[f, 5], strips[f, 6], strips[f, 7]
        px[0], py[0] = ax + nx * w, ay + ny * w
        px[1], py[1] = ax + ex * ln + nx * w, ay + ey * ln + ny * w
        px[2], py[2] = ax + ex * ln - nx * w, ay + ey * ln - ny * w
        px[3], py[3] = ax - nx * w, ay - ny * w
        rows[f, 0], rows[f, 1] = _ground_rows(px, py, 4, m, cam, fx, fy, cx, cy, W, H)
    for f in range(n_c):
        rad = (circles[f, 2] + circles[f, 3]) / math.cos(math.pi / 8)
        for k in range(8):
            a = 2.0 * math.pi * k / 8
            px[k], py[k] = circles[f, 0] + rad * math.cos(a), circles[f, 1] + rad * math.sin(a)
        rows[n_s + f, 0], rows[n_s + f, 1] = _ground_rows(px, py, 8, m, cam, fx, fy, cx, cy, W, H)
    bright = np.ones(W, dtype=np.float32)
    samp = np.ones(W // STRIDE + 2, dtype=np.float32)
    ws = np.empty(W)
    wz = np.empty(W)
    cov = np.zeros(W)
    rgb = np.empty((3, W), dtype=np.int32)
    texel = geo[GEO.FLOOR_TEXEL]
    grass = geo[GEO.GRASS] > 0.5
    inv_s = 1.0 / SUBROWS
    for j in range(H):
        v = j + 0.5
        rx, ry, rz = d0[0] + v * dv[0], d0[1] + v * dv[1], d0[2] + v * dv[2]
        ua, ub = 1.0, 0.0
        if rz < -1e-12:
            t = -hc / rz
            g0x, g0y, gux, guy = cam[0] + t * rx, cam[1] + t * ry, t * du[0], t * du[1]
            ua, ub = _slab(g0x, gux, -hx, hx, 0.0, float(W))
            ua, ub = _slab(g0y, guy, -hy, hy, ua, ub)
        i0 = max(0, int(math.ceil(ua - 0.5)))
        i1 = min(W - 1, int(math.floor(ub - 0.5)))
        if i1 >= i0:
            # paint coverage of this row
            for f in range(n_s + n_c):
                if j < rows[f, 0] or j > rows[f, 1]:
                    continue
                for s in range(SUBROWS):
                    vs = j + (s + 0.5) * inv_s
                    sz = d0[2] + vs * dv[2]
                    if sz >= -1e-12:
                        continue
                    ts = -hc / sz
                    sx = cam[0] + ts * (d0[0] + vs * dv[0])
                    sy = cam[1] + ts * (d0[1] + vs * dv[1])
                    sux, suy = ts * du[0], ts * du[1]
                    if f < n_s:
                        qx, qy = sx - strips[f, 0], sy - strips[f, 1]
                        ex, ey, nx, ny = strips[f, 2], strips[f, 3], strips[f, 4], strips[f, 5]
                        w = strips[f, 7]
                        lo, hi = _slab(nx * qx + ny * qy, nx * sux + ny * suy, -w, w, 0.0, float(W))
                        lo, hi = _slab(ex * qx + ey * qy, ex * sux + ey * suy, 0.0, strips[f, 6], lo, hi)
                        if hi > lo:
                            _add(cov, lo, hi, inv_s)
                    else:
                        c = f - n_s
                        qx, qy = sx - circles[c, 0], sy - circles[c, 1]
                        qa = sux * sux + suy * suy
                        qb = 2.0 * (qx * sux + qy * suy)
                        q0 = qx * qx + qy * qy
                        ro, ri = circles[c, 2] + circles[c, 3], circles[c, 2] - circles[c, 3]
                        disc = qb * qb - 4.0 * qa * (q0 - ro * ro)
                        if disc <= 0.0 or qa < 1e-18:
                            continue
                        sq = math.sqrt(disc)
                        o1, o2 = (-qb - sq) / (2.0 * qa), (-qb + sq) / (2.0 * qa)
                        disc_i = qb * qb - 4.0 * qa * (q0 - ri * ri)
                        if disc_i > 0.0:
                            sq = math.sqrt(disc_i)
                            n1, n2 = (-qb - sq) / (2.0 * qa), (-qb + sq) / (2.0 * qa)
                        else:
                            n1, n2 = o2, o2
                        lo, hi = max(o1, 0.0), min(n1, float(W))
                        if hi > lo:
                            _add(cov, lo, hi, inv_s)
                        lo, hi = max(n2, 0.0), min(o2, float(W))
                        if hi > lo:
                            _add(cov, lo, hi, inv_s)
            # floor pixels
            t = -hc / rz
            g0x, g0y, gux, guy = cam[0] + t * rx + hx, cam[1] + t * ry + hy, t * du[0], t * du[1]
            ca, cb = _slab(g0x - hx, gux, -kx, kx, -1e9, 1e9)
            ca, cb = _slab(g0y - hy, guy, -ky, ky, ca, cb)
            _floor_row(
                rgb[0], rgb[1], rgb[2], cov, bright, samp, ca, cb, col, floor, g0x / texel, g0y / texel,
                gux / texel, guy / texel, grass,
            )  # fmt: skip
        # hall: columns outside the floor interval
        if i1 < i0:
            _hall(rgb, 0, W, cam, rx, ry, rz, du, geo, col, walls, ws, wz)
        else:
            _hall(rgb, 0, i0, cam, rx, ry, rz, du, geo, col, walls, ws, wz)
            _hall(rgb, i1 + 1, W, cam, rx, ry, rz, du, geo, col, walls, ws, wz)
        _interleave(flat[j], rgb[0], rgb[1], rgb[2])


@nb.njit(cache=True, error_model="numpy", fastmath=True)
def _floor_row(r_out, g_out, b_out, cov, bright, samp, ca, cb, col, floor, tx0, ty0, tdx, tdy, grass):  # pragma: no cover
    """Floor colours of a whole row into the channel rows ``*_out`` (all of length W).

    The ground point of column u is (tx0 + u tdx, ty0 + u tdy) in floor texels; the carpet
    covers columns [ca, cb]; ``cov`` holds the paint coverage; ``bright`` (W) and ``samp``
    (W / STRIDE + 2) are scratch. Loops run over whole rows so that they vectorize.
    """
    w = r_out.shape[0]
    if grass:  # texture every STRIDE columns, linear in between
        for k in range(samp.shape[0]):
            u = k * STRIDE + 0.5
            samp[k] = _texel(floor, tx0 + u * tdx, ty0 + u * tdy)
        for i in range(w):
            k = i // STRIDE
            f = np.float32((i - k * STRIDE) * (1.0 / STRIDE))
            bright[i] = samp[k] + f * (samp[k + 1] - samp[k])
    gr, gg, gb = col[C.GREEN, 0], col[C.GREEN, 1], col[C.GREEN, 2]
    fr, fg, fb = col[C.FLOOR, 0], col[C.FLOOR, 1], col[C.FLOOR, 2]
    wr, wg, wb = col[C.WHITE, 0], col[C.WHITE, 1], col[C.WHITE, 2]
    for i in range(w):
        u = i + 0.5
        k = min(max(min(u - ca, cb - u) + 0.5, 0.0), 1.0)
        p = min(cov[i], 1.0)
        br = bright[i]
        cr = fr + k * (gr - fr)
        cg = fg + k * (gg - fg)
        cb_ = fb + k * (gb - fb)
        cr += p * (wr - cr)
        cg += p * (wg - cg)
        cb_ += p * (wb - cb_)
        r_out[i] = np.int32(min(cr * br + 0.5, 255.0))
        g_out[i] = np.int32(min(cg * br + 0.5, 255.0))
        b_out[i] = np.int32(min(cb_ * br + 0.5, 255.0))
        cov[i] = 0.0


@nb.njit(cache=True, error_model="numpy", fastmath=True)
def _interleave(row, r_in, g_in, b_in):  # pragma: no cover - compiled
    """Write three channel rows into an interleaved RGB image row."""
    for i in range(r_in.shape[0]):
        row[3 * i] = r_in[i]
        row[3 * i + 1] = g_in[i]
        row[3 * i + 2] = b_in[i]


@nb.njit(cache=True, error_model="numpy", fastmath=True)
def _hall(rgb, i_start, i_end, cam, rx, ry, rz, du, geo, col, walls, ws, wz):  # pragma: no cover - compiled
    """Walls and ceiling for columns [i_start, i_end) of a row (ray at u: r + u du) into ``rgb``.

    ``ws`` and ``wz`` are scratch rows for the wall texture coordinates.
    """
    if i_end <= i_start:
        return
    hx, hy, wall_h, inv = geo[GEO.HALL_X], geo[GEO.HALL_Y], geo[GEO.WALL_H], 1.0 / geo[GEO.WALL_TEXEL]
    th, tw = walls.shape[0], walls.shape[1]
    cx, cy, cz = cam[0], cam[1], cam[2]
    for i in range(i_start, i_end):  # where the ray meets a wall, in texels (row -1: above the wall)
        u = i + 0.5
        dx, dy = rx + u * du[0], ry + u * du[1]
        dx = dx if abs(dx) > 1e-12 else 1e-12
        dy = dy if abs(dy) > 1e-12 else 1e-12
        tx = ((hx if dx > 0.0 else -hx) - cx) / dx
        ty = ((hy if dy > 0.0 else -hy) - cy) / dy
        yh = cy + tx * dy
        xh = cx + ty * dx
        s1 = 2.0 * hx + (yh + hy) if dx > 0.0 else 4.0 * hx + 2.0 * hy + (hy - yh)
        s2 = (xh + hx) if dy < 0.0 else 2.0 * hx + 2.0 * hy + (hx - xh)
        on_x = tx < ty
        t = tx if on_x else ty
        ws[i] = min(max((s1 if on_x else s2) * inv, 0.0), tw - 1.0)
        wz[i] = min((wall_h - (cz + t * rz)) * inv, th - 1.0)
    cr, cg, cb = np.int32(col[C.CEILING, 0]), np.int32(col[C.CEILING, 1]), np.int32(col[C.CEILING, 2])
    for i in range(i_start, i_end):
        if wz[i] < 0.0:
            rgb[0, i], rgb[1, i], rgb[2, i] = cr, cg, cb
            continue
        p = walls[np.int32(wz[i]), np.int32(ws[i])]
        rgb[0, i] = p & 255
        rgb[1, i] = (p >> 8) & 255
        rgb[2, i] = (p >> 16) & 255


@nb.njit(cache=True, error_model="numpy", fastmath=True)
def _objects(obs, r, occ, ball, cam, d0, du, dv, m, fx, fy, cx, cy, W, H, geo, col, posts, poles, ico, img):  # pragma: no cover
    """Robots, ball, goals and poles, far to near."""
    n_rob = occ.shape[0]
    n = n_rob + 1 + 2 + poles.shape[0]
    kind = np.empty(n, dtype=np.int64)
    index = np.empty(n, dtype=np.int64)
    key = np.empty(n)
    cnt = 0
    for k in range(n_rob):
        if k == r or occ[k, OC.PRESENT] < 0.5:
            continue
        kind[cnt], index[cnt] = _ROBOT, k
        key[cnt] = math.hypot(occ[k, OC.X] - cam[0], occ[k, OC.Y] - cam[1]) - occ[k, OC.R]
        cnt += 1
    if ball[4] > 0.5:
        kind[cnt], index[cnt] = _BALL, 0
        key[cnt] = math.hypot(ball[0] - cam[0], ball[1] - cam[1]) - geo[GEO.BALL_R]
        cnt += 1
    for g in range(2):
        kind[cnt], index[cnt] = _GOAL, g
        key[cnt] = min(
            math.hypot(posts[2 * g, 0] - cam[0], posts[2 * g, 1] - cam[1]),
            math.hypot(posts[2 * g + 1, 0] - cam[0], posts[2 * g + 1, 1] - cam[1]),
        ) - geo[GEO.POST_R]  # fmt: skip
        cnt += 1
    for k in range(poles.shape[0]):
        kind[cnt], index[cnt] = _POLE, k
        key[cnt] = math.hypot(poles[k, 0] - cam[0], poles[k, 1] - cam[1]) - geo[GEO.POLE_R]
        cnt += 1
    order = np.argsort(-key[:cnt])
    inv_f = 1.0 / fx
    for o in order:
        kd, idx = kind[o], index[o]
        if kd == _ROBOT:
            _robot(obs, occ, idx, cam, d0, du, dv, m, fx, fy, cx, cy, W, H, col, inv_f, img)
        elif kd == _BALL:
            _ball(ball, cam, d0, du, dv, m, fx, fy, cx, cy, W, H, geo, col, ico, inv_f, img)
        elif kd == _GOAL:
            _goal(idx, cam, d0, du, dv, m, fx, fy, cx, cy, W, H, geo, col, posts, inv_f, img)
        else:
            _pole(idx, cam, d0, du, dv, m, fx, fy, cx, cy, W, H, geo, col, poles, inv_f, img)


@nb.njit(cache=True, error_model="numpy", fastmath=True)
def _robot(obs, occ, k, cam, d0, du, dv, m, fx, fy, cx, cy, W, H, col, inv_f, img):  # pragma: no cover
    ox, oy, rad, h = occ[k, OC.X], occ[k, OC.Y], occ[k, OC.R], occ[k, OC.H]
    i0, i1, j0, j1 = _box_pixels(ox - rad, ox + rad, oy - rad, oy + rad, 0.0, h, m, cam, fx, fy, cx, cy, W, H)
    team = C.TEAM1 if obs[k, OBS.TEAM] > 0.5 else C.TEAM0
    hd_x, hd_y = math.cos(obs[k, OBS.TH]), math.sin(obs[k, OBS.TH])
    standing = h >= 0.4
    for j in range(j0, j1):
        v = j + 0.5
        rx, ry, rz = d0[0] + v * dv[0], d0[1] + v * dv[1], d0[2] + v * dv[2]
        for i in range(i0, i1):
            u = i + 0.5
            dx, dy = rx + u * du[0], ry + u * du[1]
            cov, t, n1, n2, z = axis_cylinder(cam[0], cam[1], cam[2], dx, dy, rz, ox, oy, rad, 0.0, h, inv_f)
            if cov > 0.0:
                f = z / h
                c = C.BODY
                if standing:
                    if f < 0.08 or 0.34 < f < 0.40:
                        c = C.JOINT
                    elif 0.45 <= f < 0.77:
                        c = team
                    elif 0.85 < f < 0.92 and n1 * hd_x + n2 * hd_y > 0.5:
                        c = C.VISOR
                elif f > 0.5:
                    c = team
                a = math.sqrt(dx * dx + dy * dy)
                shade = 0.62 + 0.38 * max(0.0, -(n1 * dx + n2 * dy) / a)
                blend(img, j, i, cov, col[c, 0] * shade, col[c, 1] * shade, col[c, 2] * shade)
                continue
            if cam[2] > h and rz < 0.0:  # the top of a low (fallen) robot
                tt = (h - cam[2]) / rz
                hx_, hy_ = cam[0] + tt * dx - ox, cam[1] + tt * dy - oy
                if hx_ * hx_ + hy_ * hy_ <= rad * rad:
                    cc = team if not standing else C.BODY
                    blend(img, j, i, 1.0, col[cc, 0] * 0.95, col[cc, 1] * 0.95, col[cc, 2] * 0.95)


@nb.njit(cache=True, error_model="numpy", fastmath=True)
def _ball(ball, cam, d0, du, dv, m, fx, fy, cx, cy, W, H, geo, col, ico, inv_f, img):  # pragma: no cover
    br = geo[GEO.BALL_R]
    bx, by = ball[0], ball[1]
    i0, i1, j0, j1 = _box_pixels(bx - br, bx + br, by - br, by + br, 0.0, 2 * br, m, cam, fx, fy, cx, cy, W, H)
    patches = geo[GEO.MODERN_BALL] > 0.5
    # pattern orientation: rolled by the distance travelled along x and y
    a1, a2 = bx / br, by / br
    c1, s1, c2, s2 = math.cos(a1), math.sin(a1), math.cos(a2), math.sin(a2)
    lx, ly, lz = _LIGHT
    for j in range(j0, j1):
        v = j + 0.5
        rx, ry, rz = d0[0] + v * dv[0], d0[1] + v * dv[1], d0[2] + v * dv[2]
        for i in range(i0, i1):
            u = i + 0.5
            dx, dy = rx + u * du[0], ry + u * du[1]
            cov, t, nx, ny, nz = sphere(cam[0], cam[1], cam[2], dx, dy, rz, bx, by, br, br, inv_f)
            if cov <= 0.0:
                continue
            c = C.BALL_A
            if patches:
                # body-fixed normal: undo the roll about y (a1) then about x (-a2)
                px = c1 * nx - s1 * nz
                pz = s1 * nx + c1 * nz
                py = c2 * ny + s2 * pz
                pz = -s2 * ny + c2 * pz
                best = -1.0
                for q in range(ico.shape[0]):
                    best = max(best, px * ico[q, 0] + py * ico[q, 1] + pz * ico[q, 2])
                if best > 0.93:
                    c = C.BALL_B
            shade = 0.45 + 0.55 * max(0.0, nx * lx + ny * ly + nz * lz)
            blend(img, j, i, cov, col[c, 0] * shade, col[c, 1] * shade, col[c, 2] * shade)


@nb.njit(cache=True, error_model="numpy", fastmath=True)
def _goal(g, cam, d0, du, dv, m, fx, fy, cx, cy, W, H, geo, col, posts, inv_f, img):  # pragma: no cover
    """Goal ``g`` (0: at -x, 1: at +x): net (transparent), then posts and crossbar."""
    sgn = -1.0 if g == 0 else 1.0
    hl, depth, gh = geo[GEO.HALF_LENGTH], geo[GEO.GOAL_DEPTH], geo[GEO.GOAL_H]
    pr, hw, spacing = geo[GEO.POST_R], geo[GEO.GOAL_HALF_W], geo[GEO.NET_SPACING]
    xa, xb = sgn * (hl - pr), sgn * (hl + depth)
    i0, i1, j0, j1 = _box_pixels(min(xa, xb), max(xa, xb), -hw - pr, hw + pr, 0.0, gh, m, cam, fx, fy, cx, cy, W, H)
    gc = C.GOAL_NEG if g == 0 else C.GOAL_POS
    nr, ng, nb_ = col[C.NET, 0], col[C.NET, 1], col[C.NET, 2]
    x_in, x_out = hl, hl + depth
    for j in range(j0, j1):
        v = j + 0.5
        rx, ry, rz = d0[0] + v * dv[0], d0[1] + v * dv[1], d0[2] + v * dv[2]
        for i in range(i0, i1):
            u = i + 0.5
            dx, dy = rx + u * du[0], ry + u * du[1]
            # net panels in the goal's own frame (x' = sgn x >= 0): back, two sides, top
            ox, odx = sgn * cam[0], sgn * dx
            ok, t, a, b = plane_panel(ox, odx, x_out, cam[1], dy, -hw, hw, cam[2], rz, 0.0, gh)
            if ok:
                blend(img, j, i, mesh_alpha(a, b, spacing, t, inv_f), nr, ng, nb_)
            for side in (-hw, hw):
                ok, t, a, b = plane_panel(cam[1], dy, side, ox, odx, x_in, x_out, cam[2], rz, 0.0, gh)
                if ok:
                    blend(img, j, i, mesh_alpha(a, b, spacing, t, inv_f), nr, ng, nb_)
            ok, t, a, b = plane_panel(cam[2], rz, gh, ox, odx, x_in, x_out, cam[1], dy, -hw, hw)
            if ok:
                blend(img, j, i, mesh_alpha(a, b, spacing, t, inv_f), nr, ng, nb_)
            # posts and crossbar: the nearest hit wins
            best_t, best_c, best_s = 1e18, 0.0, 0.0
            for p in range(2 * g, 2 * g + 2):
                cov, t, n1, n2, z = axis_cylinder(
                    cam[0], cam[1], cam[2], dx, dy, rz, posts[p, 0], posts[p, 1], pr, 0.0, gh, inv_f
                )
                if cov > 0.0 and t < best_t:
                    a = math.sqrt(dx * dx + dy * dy)
                    best_t, best_c, best_s = t, cov, 0.65 + 0.35 * max(0.0, -(n1 * dx + n2 * dy) / a)
            cov, t, n1, n2, y = axis_cylinder(
                cam[0], cam[2], cam[1], dx, rz, dy, posts[2 * g, 0], gh - pr, pr, -hw, hw, inv_f
            )
            if cov > 0.0 and t < best_t:
                best_t, best_c, best_s = t, cov, 0.55 + 0.45 * max(0.0, n2)
            if best_c > 0.0:
                blend(img, j, i, best_c, col[gc, 0] * best_s, col[gc, 1] * best_s, col[gc, 2] * best_s)


@nb.njit(cache=True, error_model="numpy", fastmath=True)
def _pole(k, cam, d0, du, dv, m, fx, fy, cx, cy, W, H, geo, col, poles, inv_f, img):  # pragma: no cover
    """Corner pole ``k``: three bands, the colours of the goal at its end of the field."""
    pr, ph = geo[GEO.POLE_R], geo[GEO.POLE_H]
    ox, oy = poles[k, 0], poles[k, 1]
    i0, i1, j0, j1 = _box_pixels(ox - pr, ox + pr, oy - pr, oy + pr, 0.0, ph, m, cam, fx, fy, cx, cy, W, H)
    near_c = C.GOAL_NEG if ox < 0.0 else C.GOAL_POS
    far_c = C.GOAL_POS if ox < 0.0 else C.GOAL_NEG
    for j in range(j0, j1):
        v = j + 0.5
        rx, ry, rz = d0[0] + v * dv[0], d0[1] + v * dv[1], d0[2] + v * dv[2]
        for i in range(i0, i1):
            u = i + 0.5
            dx, dy = rx + u * du[0], ry + u * du[1]
            cov, t, n1, n2, z = axis_cylinder(cam[0], cam[1], cam[2], dx, dy, rz, ox, oy, pr, 0.0, ph, inv_f)
            if cov > 0.0:
                c = far_c if ph / 3.0 <= z < 2.0 * ph / 3.0 else near_c
                a = math.sqrt(dx * dx + dy * dy)
                shade = 0.65 + 0.35 * max(0.0, -(n1 * dx + n2 * dy) / a)
                blend(img, j, i, cov, col[c, 0] * shade, col[c, 1] * shade, col[c, 2] * shade)
