"""Compiled renderer of one robot's camera image (the scene, before image effects).

The camera has no roll (the head has yaw and pitch joints only, see
:mod:`cognition.camera`), so an image row is a plane through the optical centre that meets
the ground in a straight line, and along a row the ground point is a *linear* function of
the column. The background is drawn row by row from that fact:

* **floor**: the columns whose ray meets the floor inside the hall form one interval; the
  carpet (field plus border strip) is a sub-interval, anti-aliased at its ends; the smooth
  brightness texture is sampled every :data:`STRIDE` pixels (the nearest texel, or
  bilinearly when it holds the hall's uneven light, ``GEO.LIT``) and interpolated; it
  multiplies the carpet's and the paint's colour, tinted by ``GEO.TINT``;
* **paint**: every straight line, penalty mark and the centre circle is intersected
  analytically with the row's ground line, giving exact column intervals whose coverage is
  accumulated over :data:`SUBROWS` sub-rows (anti-aliasing in both directions); lines keep
  their true width in perspective. A strip's edges are straight image lines, so their
  columns at sub-row v are (N0 + N1 v) / (x . du), set up once per image (:func:`_paint_rows`);
* **hall**: the other columns (and every row above the horizon) are cast against the four
  walls and the ceiling.

:func:`_background` makes two passes: first every row's floor and carpet columns and
texture samples (the texture reads together, so that neighbouring rows share cached
texels), then per row the paint, floor and hall as packed pixels (``0x00BBGGRR``, the
format of the wall texture), written into the RGB image four pixels (three 32-bit words)
at a time (:func:`_put_words`). The per-pixel work is in small branch-free float32 loops
over whole rows, or row slices padded to whole vectors, that the compiler vectorizes
(:func:`_cover`, :func:`_floor_row`, :func:`_hall`); gathers (texture reads) are kept in
separate scalar loops, as vectorized gathers are slow.

Objects (robots, ball, goal posts, crossbars, nets, corner poles) are then drawn far to
near (:func:`_objects`) by :mod:`teamsim.image_objects`, which ray casts only the pixels in
each solid's exact per-row column spans; objects reaching behind the camera's near plane
(:data:`NEAR`) are clipped exactly. Each object is lit by the light map at its foot point
(:func:`_light_at`): its colours are scaled (and tinted) by that gain.

All geometry is in the **world frame** (m, rad); pixel (i, j) has its centre at
(u, v) = (i + 0.5, j + 0.5). The camera pose comes from :func:`cognition.camera.camera_pose_nb`,
the same function the percept synthesis uses, so the image agrees with the camera model.
Colours are 0..255 per channel; the anti-aliasing and texture arithmetic is float32, so
results may differ from a float64 evaluation by rounding (a unit in rare pixels).
"""

from __future__ import annotations

import math
import sys

import numba as nb
import numpy as np

from cognition.camera import camera_pose_nb
from cognition.fastmath import FASTMATH
from teamsim.image_objects import NEAR, VEC, draw_ball, draw_goal, draw_pole, draw_robot, span_window
from teamsim.image_venue import GEO, C
from teamsim.percept_parts import CAM, OBS, OC

__all__ = ["NEAR", "STRIDE", "SUBROWS", "render_nb"]

STRIDE = 8
"""Columns between two samples of the floor texture."""
SUBROWS = 4
"""Sub-rows per image row for the coverage of paint (:func:`_cover` takes four intervals)."""
_LITTLE = sys.byteorder == "little"  # packed pixels are written as little-endian words


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


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def _ground_rows(px, py, k, m, cam, fx, fy, cx, cy, width, height, q):  # pragma: no cover - compiled
    """Rows [j0, j1] a ground polygon (first ``k`` points of px, py) covers, (1, 0) if none.

    The polygon is clipped to the near plane before projection; columns entirely left or
    right of the image also give (1, 0). ``q`` is scratch (at least 6 x (2 k + 2)).
    """
    for n in range(k):
        dx, dy, dz = px[n] - cam[0], py[n] - cam[1], -cam[2]
        q[3, n] = m[0, 0] * dx + m[1, 0] * dy + m[2, 0] * dz
        q[4, n] = m[0, 1] * dx + m[1, 1] * dy + m[2, 1] * dz
        q[5, n] = m[0, 2] * dx + m[1, 2] * dy + m[2, 2] * dz
    cnt = 0
    for n in range(k):
        nn = (n + 1) % k
        ina, inb = q[3, n] >= NEAR, q[3, nn] >= NEAR
        if ina:
            q[0, cnt], q[1, cnt], q[2, cnt] = q[3, n], q[4, n], q[5, n]
            cnt += 1
        if ina != inb:
            s = (NEAR - q[3, n]) / (q[3, nn] - q[3, n])
            q[0, cnt], q[1, cnt], q[2, cnt] = (
                NEAR,
                q[4, n] + s * (q[4, nn] - q[4, n]),
                q[5, n] + s * (q[5, nn] - q[5, n]),
            )
            cnt += 1
    if cnt == 0:
        return 1, 0
    vmin, vmax, umin, umax = 1e18, -1e18, 1e18, -1e18
    for n in range(cnt):
        u = cx - fx * q[1, n] / q[0, n]
        v = cy - fy * q[2, n] / q[0, n]
        vmin, vmax = min(vmin, v), max(vmax, v)
        umin, umax = min(umin, u), max(umax, u)
    if umax < 0.0 or umin > width or vmax < 0.0 or vmin > height:
        return 1, 0
    return max(0, math.floor(vmin) - 1), min(int(height) - 1, math.floor(vmax) + 1)


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def render_nb(
    obs, r, occ, ball, cams, geo, col, strips, circles, floor, light, walls, posts, poles, ico, img
):  # pragma: no cover - compiled
    """Render robot ``r``'s camera image into ``img`` (H x W x 3 uint8, RGB). ``light``: the
    light map (:func:`teamsim.image_venue.light_map`, 1 x 1 when the hall is lit evenly)."""
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
    _objects(obs, r, occ, ball, cam, d0, du, dv, m, fx, fy, cx, cy, W, H, geo, col, light, posts, poles, ico, img)


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def _light_at(light, x, y, geo):  # pragma: no cover - compiled
    """The light map's gain at the world point (x, y) (m), bilinear between texel centres."""
    th, tw = light.shape
    if tw < 2 or th < 2:
        return float(light[0, 0])
    texel = geo[GEO.FLOOR_TEXEL]
    tx = min(max((x + geo[GEO.HALL_X]) / texel - 0.5, 0.0), tw - 1.0001)
    ty = min(max((y + geo[GEO.HALL_Y]) / texel - 0.5, 0.0), th - 1.0001)
    ix, iy = int(tx), int(ty)
    a, b = tx - ix, ty - iy
    t0 = light[iy, ix] + a * (light[iy, ix + 1] - light[iy, ix])
    t1 = light[iy + 1, ix] + a * (light[iy + 1, ix + 1] - light[iy + 1, ix])
    return float(t0 + b * (t1 - t0))


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def _lit_colours(col, gain, tint, out):  # pragma: no cover - compiled
    """The colour table ``col`` lit by ``gain``, tinted (see ``GEO.TINT``), into ``out``."""
    d = gain - 1.0
    for c in range(col.shape[0]):
        out[c, 0] = col[c, 0] * (1.0 + (1.0 + tint) * d)
        out[c, 1] = col[c, 1] * gain
        out[c, 2] = col[c, 2] * (1.0 + (1.0 - tint) * d)
    return out


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def _objects(
    obs, r, occ, ball, cam, d0, du, dv, m, fx, fy, cx, cy, W, H, geo, col, light, posts, poles, ico, img
):  # pragma: no cover
    """Robots (except ``r``), ball, goals and corner poles into ``img``, far to near (by the
    distance from the camera to the nearest point of the object's footprint), each lit by
    the light map at its foot point (a goal: the middle of its goal line)."""
    n_rob = occ.shape[0]
    n = n_rob + 1 + 2 + poles.shape[0]
    kind = np.empty(n, dtype=np.int64)  # 0 robot, 1 ball, 2 goal, 3 pole
    index = np.empty(n, dtype=np.int64)
    key = np.empty(n)
    cnt = 0
    for k in range(n_rob):
        if k == r or occ[k, OC.PRESENT] < 0.5:
            continue
        kind[cnt], index[cnt] = 0, k
        key[cnt] = math.hypot(occ[k, OC.X] - cam[0], occ[k, OC.Y] - cam[1]) - occ[k, OC.R]
        cnt += 1
    if ball[4] > 0.5:
        kind[cnt], index[cnt] = 1, 0
        key[cnt] = math.hypot(ball[0] - cam[0], ball[1] - cam[1]) - geo[GEO.BALL_R]
        cnt += 1
    for g in range(2):
        kind[cnt], index[cnt] = 2, g
        key[cnt] = min(
            math.hypot(posts[2 * g, 0] - cam[0], posts[2 * g, 1] - cam[1]),
            math.hypot(posts[2 * g + 1, 0] - cam[0], posts[2 * g + 1, 1] - cam[1]),
        ) - geo[GEO.POST_R]  # fmt: skip
        cnt += 1
    for k in range(poles.shape[0]):
        kind[cnt], index[cnt] = 3, k
        key[cnt] = math.hypot(poles[k, 0] - cam[0], poles[k, 1] - cam[1]) - geo[GEO.POLE_R]
        cnt += 1
    scr = np.zeros((5, W + VEC), dtype=np.float32)
    lit = light.size > 1
    tint = geo[GEO.TINT]
    lcol = np.empty_like(col)
    for o in np.argsort(-key[:cnt]):
        kd, idx = kind[o], index[o]
        oc = col
        if lit:  # the light at the object's foot point
            if kd == 0:
                px, py = occ[idx, OC.X], occ[idx, OC.Y]
            elif kd == 1:
                px, py = ball[0], ball[1]
            elif kd == 2:
                px, py = (
                    0.5 * (posts[2 * idx, 0] + posts[2 * idx + 1, 0]),
                    0.5 * (posts[2 * idx, 1] + posts[2 * idx + 1, 1]),
                )
            else:
                px, py = poles[idx, 0], poles[idx, 1]
            oc = _lit_colours(col, _light_at(light, px, py, geo), tint, lcol)
        if kd == 0:
            draw_robot(obs, occ, idx, cam, d0, du, dv, m, fx, fy, cx, cy, W, H, oc, img, scr)
        elif kd == 1:
            draw_ball(ball, cam, d0, du, dv, m, fx, fy, cx, cy, W, H, geo, oc, ico, img, scr)
        elif kd == 2:
            draw_goal(idx, cam, d0, du, dv, m, fx, fy, cx, cy, W, H, geo, oc, posts, img, scr)
        else:
            draw_pole(idx, cam, d0, du, dv, m, fx, fy, cx, cy, W, H, geo, oc, poles, img, scr)


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def _paint_rows(cam, m, d0, du, dv, fx, fy, cx, cy, W, H, strips, circles):  # pragma: no cover - compiled
    """Rows that each piece of paint may cover, and the image lines of the strips' edges.

    Returns ``rows`` (one row [j0, j1] per strip, then per circle) and ``edges`` (per strip:
    the column where its edges n . g = -w, +w, e . g = 0, length meet sub-row v is
    (N0 + N1 v) / (x . du) for x = n or e: rows N0, N1 for the four edges, then 1 / (n . du),
    1 / (e . du), 0 where the edge runs along the rows).
    """
    n_s, n_c = strips.shape[0], circles.shape[0]
    rows = np.empty((n_s + n_c, 2), dtype=np.int64)
    edges = np.empty((n_s, 10))
    px = np.empty(8)
    py = np.empty(8)
    q = np.empty((6, 18))
    hc = cam[2]
    for f in range(n_s):
        ax, ay, ex, ey = strips[f, 0], strips[f, 1], strips[f, 2], strips[f, 3]
        nx, ny, ln, w = strips[f, 4], strips[f, 5], strips[f, 6], strips[f, 7]
        px[0], py[0] = ax + nx * w, ay + ny * w
        px[1], py[1] = ax + ex * ln + nx * w, ay + ey * ln + ny * w
        px[2], py[2] = ax + ex * ln - nx * w, ay + ey * ln - ny * w
        px[3], py[3] = ax - nx * w, ay - ny * w
        rows[f, 0], rows[f, 1] = _ground_rows(px, py, 4, m, cam, fx, fy, cx, cy, W, H, q)
        for g in range(2):  # g . (ground point - a) = c at column (c - g . (cam - a) + t g . ray) / (t g . du)
            gx, gy = (nx, ny) if g == 0 else (ex, ey)
            gb = gx * du[0] + gy * du[1]
            edges[f, 8 + g] = 1.0 / gb if abs(gb) > 1e-18 else 0.0
            gc = gx * (cam[0] - ax) + gy * (cam[1] - ay)
            for side in range(2):
                c = (-w if side == 0 else w) if g == 0 else (0.0 if side == 0 else ln)
                kk = -(c - gc) / hc  # with 1 / t = -(d0z + v dvz) / hc
                edges[f, 4 * g + 2 * side] = kk * d0[2] - (gx * d0[0] + gy * d0[1])
                edges[f, 4 * g + 2 * side + 1] = kk * dv[2] - (gx * dv[0] + gy * dv[1])
    for f in range(n_c):
        rad = (circles[f, 2] + circles[f, 3]) / math.cos(math.pi / 8)
        for k in range(8):
            a = 2.0 * math.pi * k / 8
            px[k], py[k] = circles[f, 0] + rad * math.cos(a), circles[f, 1] + rad * math.sin(a)
        rows[n_s + f, 0], rows[n_s + f, 1] = _ground_rows(px, py, 8, m, cam, fx, fy, cx, cy, W, H, q)
    return rows, edges


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def _background(
    cam, d0, du, dv, m, fx, fy, cx, cy, W, H, geo, col, strips, circles, floor, walls, img
):  # pragma: no cover
    """Floor, paint and hall of the whole image into ``img`` (see the module docstring).

    ``cam``: optical centre (world, m); ``m``: camera -> world rotation (columns: optical
    axis, left, up); the ray of pixel centre (u, v) is d0 + u du + v dv; fx, fy, cx, cy:
    pinhole intrinsics (px); W x H: image size (px).
    """
    hc = cam[2]
    hx, hy = geo[GEO.HALL_X], geo[GEO.HALL_Y]
    kx, ky = geo[GEO.CARPET_X], geo[GEO.CARPET_Y]
    rows, edges = _paint_rows(cam, m, d0, du, dv, fx, fy, cx, cy, W, H, strips, circles)
    nblk = (W + STRIDE - 1) // STRIDE
    bright = np.ones(nblk * STRIDE, dtype=np.float32)
    cov = np.zeros(W, dtype=np.float32)
    packed = np.empty(W, dtype=np.uint32)
    sub = np.empty((5, SUBROWS))
    iv = np.empty((2, 2 * SUBROWS))
    fflat = floor.reshape(floor.size)
    wflat = walls.reshape(walls.size)
    ceil = np.uint32(int(col[C.CEILING, 0]) | (int(col[C.CEILING, 1]) << 8) | (int(col[C.CEILING, 2]) << 16))
    # the image as 32-bit words when rows hold whole groups of four pixels and it is aligned
    n3 = W * 3 // 4
    words = np.empty(0, dtype=np.uint32)
    fast = _LITTLE and W % 4 == 0 and img.ctypes.data % 4 == 0
    if fast:
        words = img.reshape(H * W * 3).view(np.uint32)
    flat = img.reshape(H, W * 3)
    texel = geo[GEO.FLOOR_TEXEL]
    grass = geo[GEO.GRASS] > 0.5
    lit = geo[GEO.LIT] > 0.5 and floor.shape[0] > 1 and floor.shape[1] > 1
    tint = geo[GEO.TINT]
    fa = np.empty(nblk + 1, dtype=np.float32)
    fb = np.empty(nblk + 1, dtype=np.float32)
    # pass 1: every row's floor columns [i0, i1], carpet [ca, cb] and texture samples (all the
    # texture reads at once: neighbouring rows read neighbouring texels, and the wall
    # texture of pass 2 does not evict them in between)
    span, carpet = np.empty((H, 2), dtype=np.int64), np.empty((H, 2))
    samps = np.empty((H, nblk + 1), dtype=np.float32)  # rows read only where written
    for j in range(H):
        v = j + 0.5
        rx, ry, rz = d0[0] + v * dv[0], d0[1] + v * dv[1], d0[2] + v * dv[2]
        ua, ub = 1.0, 0.0
        if rz < -1e-12:
            t = -hc / rz
            g0x, g0y, gux, guy = cam[0] + t * rx, cam[1] + t * ry, t * du[0], t * du[1]
            ua, ub = _slab(g0x, gux, -hx, hx, 0.0, float(W))
            ua, ub = _slab(g0y, guy, -hy, hy, ua, ub)
        span[j, 0] = max(0, math.ceil(ua - 0.5))
        span[j, 1] = min(W - 1, math.floor(ub - 0.5))
        if span[j, 1] >= span[j, 0]:
            carpet[j, 0], carpet[j, 1] = _slab(g0x, gux, -kx, kx, -1e9, 1e9)
            carpet[j, 0], carpet[j, 1] = _slab(g0y, guy, -ky, ky, carpet[j, 0], carpet[j, 1])
            if lit:
                _floor_samples_lin(
                    samps[j], packed, fa, fb, fflat, floor.shape[1], floor.shape[0], (g0x + hx) / texel,
                    (g0y + hy) / texel, gux / texel, guy / texel,
                )  # fmt: skip
            elif grass:
                _floor_samples(
                    samps[j], packed, fflat, floor.shape[1], floor.shape[0], (g0x + hx) / texel, (g0y + hy) / texel,
                    gux / texel, guy / texel,
                )  # fmt: skip
    # pass 2: paint, floor, hall, per row
    for j in range(H):
        v = j + 0.5
        rx, ry, rz = d0[0] + v * dv[0], d0[1] + v * dv[1], d0[2] + v * dv[2]
        i0, i1 = span[j, 0], span[j, 1]
        if i1 >= i0:
            plo, phi = _paint_row(cov, j, rows, edges, strips, circles, cam, d0, du, dv, sub, iv)
            _floor_row(packed, cov, bright, samps[j], carpet[j, 0], carpet[j, 1], col, grass, tint, plo, phi)
            if i0 > 0:
                _hall(packed[:i0], 0, cam, rx, ry, rz, du, geo, wflat, walls.shape[1], walls.shape[0], ceil)
            if i1 < W - 1:
                _hall(packed[i1 + 1 :], i1 + 1, cam, rx, ry, rz, du, geo, wflat, walls.shape[1], walls.shape[0], ceil)
        else:
            _hall(packed, 0, cam, rx, ry, rz, du, geo, wflat, walls.shape[1], walls.shape[0], ceil)
        if fast:
            _put_words(words[j * n3 : (j + 1) * n3], packed)
        else:
            _put_bytes(flat[j], packed)


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH, inline="always")
def _paint_row(cov, j, rows, edges, strips, circles, cam, d0, du, dv, sub, iv):  # pragma: no cover - compiled
    """Add the paint coverage of image row ``j`` to ``cov`` (W, float32).

    Every piece of paint gives one column interval per sub-row (two for the annulus):
    strips from the image lines of their edges (``edges``, see :func:`_paint_rows`), the
    circle from the sub-row's ground line (sub[0, s], sub[1, s]) + u (sub[2, s], sub[3, s])
    (sub[4, s] = 0 when the sub-row does not look down). :func:`_cover` then adds the
    intervals' overlaps with the pixels. ``sub`` (5 x SUBROWS) and ``iv`` (2 x 2 SUBROWS:
    interval ends) are scratch. Returns the columns [plo, phi) that may have coverage
    ((W, 0) if none).
    """
    n_s = strips.shape[0]
    plo, phi = cov.shape[0], 0
    hc = cam[2]
    inv_s = 1.0 / SUBROWS
    width = float(cov.shape[0])
    for s in range(SUBROWS):
        vs = j + (s + 0.5) * inv_s
        sz = d0[2] + vs * dv[2]
        sub[4, s] = 1.0 if sz < -1e-12 else 0.0
        ts = -hc / sz if sz < -1e-12 else 0.0
        sub[0, s] = cam[0] + ts * (d0[0] + vs * dv[0])
        sub[1, s] = cam[1] + ts * (d0[1] + vs * dv[1])
        sub[2, s], sub[3, s] = ts * du[0], ts * du[1]
    for f in range(rows.shape[0]):
        if j < rows[f, 0] or j > rows[f, 1]:
            continue
        for k in range(2 * SUBROWS):  # clear the intervals (cheaper than a 2-D slice fill)
            iv[0, k], iv[1, k] = 0.0, 0.0
        for s in range(SUBROWS):
            if sub[4, s] == 0.0:
                continue
            vs = j + (s + 0.5) * inv_s
            if f < n_s:
                lo, hi = 0.0, width
                for g in range(2):
                    inv = edges[f, 8 + g]
                    if inv != 0.0:
                        u1 = (edges[f, 4 * g] + edges[f, 4 * g + 1] * vs) * inv
                        u2 = (edges[f, 4 * g + 2] + edges[f, 4 * g + 3] * vs) * inv
                        lo, hi = max(lo, min(u1, u2)), min(hi, max(u1, u2))
                    else:  # the edges run along the row: all of it or nothing
                        gx, gy = (strips[f, 4], strips[f, 5]) if g == 0 else (strips[f, 2], strips[f, 3])
                        a = gx * (sub[0, s] - strips[f, 0]) + gy * (sub[1, s] - strips[f, 1])
                        c0, c1 = (-strips[f, 7], strips[f, 7]) if g == 0 else (0.0, strips[f, 6])
                        if a < c0 or a > c1:
                            lo, hi = 1.0, 0.0
                if hi > lo:
                    iv[0, s], iv[1, s] = lo, hi
            else:
                c = f - n_s
                sx, sy, sux, suy = sub[0, s], sub[1, s], sub[2, s], sub[3, s]
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
                lo, hi = max(o1, 0.0), min(n1, width)
                if hi > lo:
                    iv[0, s], iv[1, s] = lo, hi
                lo, hi = max(n2, 0.0), min(o2, width)
                if hi > lo:
                    iv[0, SUBROWS + s], iv[1, SUBROWS + s] = lo, hi
        a, b = _cover(cov, iv, 0, inv_s)
        plo, phi = min(plo, a), max(phi, b)
        if f >= n_s:
            a, b = _cover(cov, iv, SUBROWS, inv_s)
            plo, phi = min(plo, a), max(phi, b)
    return plo, phi


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH, inline="always")
def _cover(cov, iv, k0, w):  # pragma: no cover - compiled
    """Add ``w`` times the overlap of each pixel [i, i + 1] with the column intervals
    [iv[0, k], iv[1, k]] (k = k0 .. k0 + 3; (0, 0) is empty) to ``cov``; vectorizes.
    Returns the columns [a, b) it wrote to ((W, 0) if none)."""
    l0, l1, l2, l3 = iv[0, k0], iv[0, k0 + 1], iv[0, k0 + 2], iv[0, k0 + 3]
    h0, h1, h2, h3 = iv[1, k0], iv[1, k0 + 1], iv[1, k0 + 2], iv[1, k0 + 3]
    lo, hi = 1e9, -1.0
    for a, b in ((l0, h0), (l1, h1), (l2, h2), (l3, h3)):
        if b > a:
            lo, hi = min(lo, a), max(hi, b)
    if hi < lo:
        return cov.shape[0], 0
    x0, n = span_window(int(lo), min(int(hi) + 1, cov.shape[0]), cov.shape[0])
    f = np.float32
    l0, l1, l2, l3, h0, h1, h2, h3 = f(l0), f(l1), f(l2), f(l3), f(h0), f(h1), f(h2), f(h3)
    zero, one, w32 = f(0.0), f(1.0), f(w)
    seg = cov[x0 : x0 + n]
    for k in range(n):
        x = f(x0 + k)
        x1 = x + one
        c = max(zero, min(x1, h0) - max(x, l0)) + max(zero, min(x1, h1) - max(x, l1))
        c += max(zero, min(x1, h2) - max(x, l2)) + max(zero, min(x1, h3) - max(x, l3))
        seg[k] += w32 * c
    return x0, x0 + n


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def _floor_samples(samp, idx, tex, tw, th, tx0, ty0, tdx, tdy):  # pragma: no cover - compiled
    """Floor texture every STRIDE columns of a row into ``samp`` (blocks + 1): column u is at
    (tx0 + u tdx, ty0 + u tdy) texels of ``tex`` (the texture flattened, ``th`` x ``tw``),
    the nearest texel, clamped. ``idx`` (uint32, at least as long) is scratch: the indices
    come first (that loop vectorizes), then the gather."""
    twm, thm = tw - 1.0, th - 1.0
    n = samp.shape[0]
    for k in range(n):
        u = k * STRIDE + 0.5
        x = min(max(tx0 + u * tdx, 0.0), twm)
        y = min(max(ty0 + u * tdy, 0.0), thm)
        idx[k] = np.uint32(np.int32(y) * np.int32(tw) + np.int32(x))
    for k in range(n):
        samp[k] = tex[idx[k]]


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def _floor_samples_lin(samp, idx, fa, fb, tex, tw, th, tx0, ty0, tdx, tdy):  # pragma: no cover - compiled
    """As :func:`_floor_samples`, but bilinear between the four nearest texel centres (the
    texture at least 2 x 2); ``fa``, ``fb`` (float32, blocks + 1) are scratch for the weights.
    The first loop (float32, vectorizes) finds the texels and weights, the second gathers."""
    f = np.float32
    xm, ym, zero = f(tw - 1.0001), f(th - 1.0001), f(0.0)
    x0, y0 = f(tx0 + 0.5 * tdx - 0.5), f(ty0 + 0.5 * tdy - 0.5)  # texel centres at integers
    dx, dy = f(STRIDE * tdx), f(STRIDE * tdy)
    tw32 = np.int32(tw)
    n = samp.shape[0]
    for k in range(n):
        x = min(max(x0 + f(k) * dx, zero), xm)
        y = min(max(y0 + f(k) * dy, zero), ym)
        ix, iy = np.int32(x), np.int32(y)
        idx[k] = np.uint32(iy * tw32 + ix)
        fa[k] = x - f(ix)
        fb[k] = y - f(iy)
    for k in range(n):
        i = idx[k]
        t00, t10, t01, t11 = tex[i], tex[i + 1], tex[i + tw32], tex[i + tw32 + 1]
        a = fa[k]
        t0 = t00 + a * (t10 - t00)
        t1 = t01 + a * (t11 - t01)
        samp[k] = t0 + fb[k] * (t1 - t0)


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH, inline="always")
def _floor_row(out, cov, bright, samp, ca, cb, col, grass, tint, plo, phi):  # pragma: no cover - compiled
    """Floor colours of a whole row as packed pixels into ``out`` (W, uint32); clears ``cov``.

    The carpet covers columns [ca, cb]; ``cov`` (W) holds the paint coverage, zero outside
    columns [plo, phi); ``samp`` the brightness every STRIDE columns (:func:`_floor_samples`),
    interpolated linearly into ``bright`` (W rounded up to whole STRIDE blocks) if ``grass``.
    A brightness l scales green by l, red by 1 + (1 + ``tint``)(l - 1) and blue by
    1 + (1 - ``tint``)(l - 1) (exactly l in every channel for ``tint`` 0).
    Loops run over whole rows (or the painted run) so that they vectorize. The common row,
    all carpet, is shaded without the carpet's edge, then its paint is mixed in.
    """
    w = out.shape[0]
    if grass:  # linear between the samples
        for k in range(samp.shape[0] - 1):
            a = samp[k]
            d = samp[k + 1] - a
            for q in range(STRIDE):
                bright[k * STRIDE + q] = a + np.float32(q * (1.0 / STRIDE)) * d
    f0, f1, h = np.float32(0.0), np.float32(1.0), np.float32(0.5)
    top = np.float32(255.0)
    gr, gg, gb = np.float32(col[C.GREEN, 0]), np.float32(col[C.GREEN, 1]), np.float32(col[C.GREEN, 2])
    wr, wg, wb = np.float32(col[C.WHITE, 0]), np.float32(col[C.WHITE, 1]), np.float32(col[C.WHITE, 2])
    t32 = np.float32(tint)
    if ca <= -0.5 and cb >= w + 0.5:  # all carpet: k = 1 in every column
        for i in range(w):
            br = bright[i]
            dt = t32 * (br - f1)
            r8 = np.int32(min(gr * (br + dt) + h, top))
            g8 = np.int32(min(gg * br + h, top))
            b8 = np.int32(min(gb * (br - dt) + h, top))
            out[i] = r8 | (g8 << 8) | (b8 << 16)
        if phi > plo:
            seg, o, bs = cov[plo:phi], out[plo:phi], bright[plo:phi]
            for i in range(phi - plo):
                p = min(seg[i], f1)
                br = bs[i]
                dt = t32 * (br - f1)
                r8 = np.int32(min((gr + p * (wr - gr)) * (br + dt) + h, top))
                g8 = np.int32(min((gg + p * (wg - gg)) * br + h, top))
                b8 = np.int32(min((gb + p * (wb - gb)) * (br - dt) + h, top))
                o[i] = r8 | (g8 << 8) | (b8 << 16)
                seg[i] = f0
        return
    fr, fg, fb = np.float32(col[C.FLOOR, 0]), np.float32(col[C.FLOOR, 1]), np.float32(col[C.FLOOR, 2])
    ca32, cb32 = np.float32(max(ca, -1e7)), np.float32(min(cb, 1e7))
    for i in range(w):
        u = np.float32(i) + h
        k = min(max(min(u - ca32, cb32 - u) + h, f0), f1)
        p = min(cov[i], f1)
        br = bright[i]
        dt = t32 * (br - f1)
        cr = fr + k * (gr - fr)
        cg = fg + k * (gg - fg)
        cb_ = fb + k * (gb - fb)
        cr += p * (wr - cr)
        cg += p * (wg - cg)
        cb_ += p * (wb - cb_)
        r8 = np.int32(min(cr * (br + dt) + h, top))
        g8 = np.int32(min(cg * br + h, top))
        b8 = np.int32(min(cb_ * (br - dt) + h, top))
        out[i] = r8 | (g8 << 8) | (b8 << 16)
        cov[i] = f0


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def _hall(out, i_start, cam, rx, ry, rz, du, geo, walls, tw, th, ceil):  # pragma: no cover - compiled
    """Walls and ceiling as packed pixels into ``out`` (a row slice starting at column ``i_start``).

    The ray at column u is r + u du; ``walls`` is the wall texture flattened (``th`` x ``tw``,
    packed), ``ceil`` the packed ceiling colour. The first loop finds the texel of every
    pixel (float32, one division: the nearer wall is found by cross-multiplying) and
    vectorizes; the second gathers the texels (gathers inside the first loop are slow).
    """
    f = np.float32
    hx, hy, wall_h, inv = f(geo[GEO.HALL_X]), f(geo[GEO.HALL_Y]), f(geo[GEO.WALL_H]), f(1.0 / geo[GEO.WALL_TEXEL])
    cx, cy, cz = f(cam[0]), f(cam[1]), f(cam[2])
    twm, thm, tw32 = f(tw - 1.0), f(th - 1.0), np.int32(tw)
    rx32, ry32, rz32, dux, duy = f(rx), f(ry), f(rz), f(du[0]), f(du[1])
    zero, eps = f(0.0), f(1e-12)
    s_px, s_py = f(2.0) * hx + hy, f(4.0) * hx + f(3.0) * hy  # wall +x (from its corner -y), wall -x (from +y)
    s_ny, s_my = hx, f(3.0) * hx + f(2.0) * hy  # wall -y (from -x), wall +y (from +x)
    base = f(i_start + 0.5)
    above = np.uint32(1 << 31)
    for k in range(out.shape[0]):  # where the ray meets a wall, in texels (negative row: above the wall)
        u = base + f(k)
        dx, dy = rx32 + u * dux, ry32 + u * duy
        dx = dx if abs(dx) > eps else eps
        dy = dy if abs(dy) > eps else eps
        gx = (hx if dx > zero else -hx) - cx  # the sign of dx: the ray meets the plane in front
        gy = (hy if dy > zero else -hy) - cy
        on_x = abs(gx * dy) < abs(gy * dx)  # the x wall is the nearer
        t = (gx if on_x else gy) / (dx if on_x else dy)
        yh = cy + t * dy
        xh = cx + t * dx
        s1 = s_px + yh if dx > zero else s_py - yh
        s2 = s_ny + xh if dy < zero else s_my - xh
        ws = min(max((s1 if on_x else s2) * inv, zero), twm)
        wz = min((wall_h - (cz + t * rz32)) * inv, thm)
        idx = np.uint32(np.int32(max(wz, zero)) * tw32 + np.int32(ws))
        out[k] = idx | above if wz < zero else idx
    for k in range(out.shape[0]):
        o = out[k]
        p = walls[o & 0x7FFFFFFF]
        out[k] = ceil if o >> 31 else p


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def _put_words(words, p):  # pragma: no cover - compiled
    """Write packed pixels ``p`` (W, a multiple of 4) into an RGB row seen as 3 W / 4 words."""
    for q in range(p.shape[0] // 4):
        p0, p1, p2, p3 = p[4 * q], p[4 * q + 1], p[4 * q + 2], p[4 * q + 3]
        words[3 * q] = p0 | (p1 << 24)
        words[3 * q + 1] = (p1 >> 8) | (p2 << 16)
        words[3 * q + 2] = (p2 >> 16) | (p3 << 8)


@nb.njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def _put_bytes(row, p):  # pragma: no cover - compiled
    """Write packed pixels ``p`` into an interleaved RGB image row (any width)."""
    for i in range(p.shape[0]):
        row[3 * i] = p[i] & 255
        row[3 * i + 1] = (p[i] >> 8) & 255
        row[3 * i + 2] = (p[i] >> 16) & 255
