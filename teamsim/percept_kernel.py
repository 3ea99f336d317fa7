"""Compiled core of percept synthesis: all robots of one camera frame in one numba call.

For each observing robot the kernel builds the camera pose from the head angles
(:func:`cognition.camera.camera_pose_nb`), decides which landmarks and objects are visible
(in front of the camera, inside the image, within range, not hidden behind other robots),
draws detections, false positives and the Darmstadt angular noise (paper section IV.B,
eqs. 3-6 for the sigmas, eq. 8 and 12-15 for the reported covariance), and writes one row per
percept (columns of :class:`cognition.percepts.Col`) into ``out``.

Everything here is in the **world frame** (m, rad) except the rows, which are robot-frame
measurements. Inputs are packed arrays built by :mod:`teamsim.percepts`; see the ``O_*``,
``F_*``, ``K_*`` and ``C_*`` index constants below. Random numbers come from pre-drawn
buffers of standard normals and uniforms with a shared cursor, so one seed gives one
result.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.camera import camera_pose_nb
from cognition.percepts import N_COLS, Col, Kind
from teamsim.percept_params import VECTOR_FIELDS

# observer columns
O_X, O_Y, O_TH, O_YAW, O_PITCH, O_YAWR, O_PITCHR, O_CAM, O_WALK, O_ACTIVE, O_SIGN, O_TEAM = range(12)
N_OBS_COLS = 12
# occluder columns (same robot index as observers)
OC_X, OC_Y, OC_R, OC_H, OC_PRESENT = range(5)
# camera columns
C_TILT, C_OFFX, C_OFFZ, C_FX, C_FY, C_CX, C_CY, C_W, C_H = range(9)
N_CAM_COLS = 9
# field-map rows: x, y, a, b, mirror index, partner   (a, b: line end / orientation, kind / goal)
F_X, F_Y, F_A, F_B, F_PERM, F_PARTNER = range(6)
N_FMAP_COLS = 6
# group order in fidx (start of group g is fidx[g], end fidx[g + 1])
G_POST, G_CROSS, G_LINE, G_MARK, G_POLE, G_CIRCLE = range(6)
# constants vector
K_NECK, K_GOAL_H, K_POST_R, K_POLE_R, K_BALL_R, K_CIRCLE_X, K_CIRCLE_Y, K_HX, K_HY, K_DISTINCT, K_NPT = range(11)
N_CONSTS = 11

_P = {name: i for i, name in enumerate(VECTOR_FIELDS)}
P_SA, P_SB, P_CT, P_CP = _P["sigma_alpha_base"], _P["sigma_beta_base"], _P["c_tilt"], _P["c_pan"]
P_SAM, P_SBM, P_SHARED = _P["sigma_alpha_moving"], _P["sigma_beta_moving"], _P["shared_noise_fraction"]
P_FIXED, P_FIXED_SIGMA, P_ORIENT = _P["reported_fixed"], _P["fixed_sigma"], _P["orientation_sigma"]
P_RAD_SIGMA, P_CIRCLE_MIN, P_MIN_LINE = _P["ball_radius_sigma_px"], _P["circle_min_visible"], _P["min_line_length"]
P_HEAD_DET, P_WALK_DET, P_BALL_DET = _P["head_speed_detection"], _P["walking_detection"], _P["ball_speed_detection"]
P_MAX_OCC, P_PH_CROSS, P_PH_MARK = _P["max_occlusion"], _P["phantom_crossing_rate"], _P["phantom_mark_rate"]
P_BG_POST, P_FEET_BALL, P_FALSE_BALL = _P["background_post_rate"], _P["feet_ball_rate"], _P["false_ball_rate"]
P_CONFUSE, P_TEAM_UNK, P_TEAM_WRONG = _P["crossing_confusion"], _P["robot_team_unknown"], _P["robot_team_wrong"]
P_DET = {k: _P[f"{k}.rate"] for k in ("post", "cross", "line", "circle", "mark", "ball", "robot", "pole")}
P_DET_POST, P_DET_CROSS, P_DET_LINE, P_DET_CIRCLE = P_DET["post"], P_DET["cross"], P_DET["line"], P_DET["circle"]
P_DET_MARK, P_DET_BALL, P_DET_ROBOT, P_DET_POLE = P_DET["mark"], P_DET["ball"], P_DET["robot"], P_DET["pole"]

# per-observer context vector used by the helpers below
(X_CX, X_CY, X_HC, X_X, X_Y, X_CT, X_ST, X_SA, X_SB, X_EA, X_EB, X_SH, X_IND, X_PCX, X_PCY, X_SAR, X_SBR,
 X_FX, X_FY, X_PPX, X_PPY, X_W, X_H) = range(23)  # fmt: skip
N_CTX = 23

MAX_PIECES = 6
NEAR = 0.01  # m, near plane of the camera
K_POST, K_CROSS, K_LINE, K_CIRCLE = int(Kind.POST), int(Kind.CROSS), int(Kind.LINE), int(Kind.CIRCLE)
K_MARK, K_BALL, K_ROBOT, K_POLE = int(Kind.MARK), int(Kind.BALL), int(Kind.ROBOT), int(Kind.POLE)
C_XX, C_XY, C_YY = int(Col.VAR_XX), int(Col.VAR_XY), int(Col.VAR_YY)


def draws_bound(n_observers: int, fidx: NDArray[np.int64]) -> tuple[int, int]:
    """Upper bounds of (normals, uniforms) one kernel call consumes."""
    points = int(fidx[G_CIRCLE] - fidx[G_POST]) - int(fidx[G_LINE + 1] - fidx[G_LINE])
    lines = int(fidx[G_LINE + 1] - fidx[G_LINE])
    per = 16 + 5 * points + 5 * MAX_PIECES * lines + 8 * n_observers
    return n_observers * per, n_observers * per


@nb.njit(cache=True, inline="always")
def _wrap(a: float) -> float:  # pragma: no cover - compiled
    a = (a + math.pi) % (2.0 * math.pi)
    if a <= 0.0:
        a += 2.0 * math.pi
    return a - math.pi


@nb.njit(cache=True, inline="always")
def _rate(prm: NDArray[np.float64], base: int, d: float) -> float:  # pragma: no cover - compiled
    full, far = prm[base + 1], prm[base + 2]
    if d <= full:
        return prm[base]
    if d >= far:
        return 0.0
    return prm[base] * (far - d) / (far - full)


@nb.njit(cache=True)
def _emit(out, row, x, y, u, v, sub, ctx, h, truth):  # pragma: no cover - compiled
    """Write a point row measured at robot-frame (x, y), ``h`` below the camera (covariance there)."""
    sa, sb = ctx[X_SAR], ctx[X_SBR]
    cov = _cov(x, y, ctx[X_PCX], ctx[X_PCY], h, sa, sb)
    for c in range(N_COLS):
        out[row, c] = np.nan
    out[row, 0] = x
    out[row, 1] = y
    out[row, 2] = u
    out[row, 3] = v
    out[row, 9] = sub
    out[row, C_XX] = cov[0]
    out[row, C_XY] = cov[1]
    out[row, C_YY] = cov[2]
    out[row, 13] = sa
    out[row, 14] = sb
    out[row, 16] = truth
    out[row, 17] = -1.0


@nb.njit(cache=True)
def _set_cov(out, row, x, y, ctx, h):  # pragma: no cover - compiled
    """Overwrite a row's covariance with the one at robot-frame (x, y)."""
    cov = _cov(x, y, ctx[X_PCX], ctx[X_PCY], h, ctx[X_SAR], ctx[X_SBR])
    out[row, C_XX], out[row, C_XY], out[row, C_YY] = cov[0], cov[1], cov[2]


@nb.njit(cache=True)
def _cov(x, y, cx, cy, h, sa, sb):  # pragma: no cover - compiled
    """Darmstadt eqs. 8, 12-15 for a point measured at robot-frame (x, y)."""
    dx, dy = x - cx, y - cy
    d = math.hypot(dx, dy)
    alpha = math.atan2(h, d)
    sd = abs(h / math.tan(alpha) - h / math.tan(min(alpha + sa, 0.5 * math.pi - 1e-9)))
    sy = math.tan(sb) * d
    b = math.atan2(dy, dx)
    c, s = math.cos(b), math.sin(b)
    a, e = sd * sd, sy * sy
    return (c * c * a + s * s * e, c * s * (a - e), s * s * a + c * c * e)


@nb.njit(cache=True)
def synthesize_nb(
    obs: NDArray[np.float64],
    occ: NDArray[np.float64],
    ball: NDArray[np.float64],
    cams: NDArray[np.float64],
    fmap: NDArray[np.float64],
    fidx: NDArray[np.int64],
    fconst: NDArray[np.float64],
    prm: NDArray[np.float64],
    normals: NDArray[np.float64],
    uniforms: NDArray[np.float64],
    cursor: NDArray[np.int64],
    out: NDArray[np.float64],
    offsets: NDArray[np.int64],
    cam_rows: NDArray[np.float64],
) -> int:  # pragma: no cover - compiled
    """Write the percepts of every active observer; returns the number of rows written."""
    n_obs = obs.shape[0]
    rot = np.empty((3, 3))
    pos = np.empty(3)
    m = np.empty((3, 3))
    od = np.empty(n_obs)
    ob = np.empty(n_obs)
    ow = np.empty(n_obs)
    oh = np.empty(n_obs)
    oflag = np.zeros(n_obs, dtype=np.bool_)
    seen = np.empty(n_obs, dtype=np.int64)
    plo = np.empty(MAX_PIECES)
    phi = np.empty(MAX_PIECES)
    nlo = np.empty(MAX_PIECES)
    nhi = np.empty(MAX_PIECES)
    q = np.empty(3)
    dq = np.empty(3)
    ctx = np.empty(N_CTX)
    shared_f = prm[P_SHARED]
    sh, ind = math.sqrt(shared_f), math.sqrt(1.0 - shared_f)
    neck, goal_h, post_r = fconst[K_NECK], fconst[K_GOAL_H], fconst[K_POST_R]
    pole_r, ball_r = fconst[K_POLE_R], fconst[K_BALL_R]
    distinct = fconst[K_DISTINCT] > 0.5
    npt = int(fconst[K_NPT])
    max_occ = prm[P_MAX_OCC]
    row = 0
    for r in range(n_obs):
        for k in range(offsets.shape[1]):
            offsets[r, k] = row
        if obs[r, O_ACTIVE] < 0.5:
            for c in range(cam_rows.shape[1]):
                cam_rows[r, c] = np.nan
            continue
        X, Y, TH = obs[r, O_X], obs[r, O_Y], obs[r, O_TH]
        ci = int(obs[r, O_CAM])
        fx, fy, cx, cy = cams[ci, C_FX], cams[ci, C_FY], cams[ci, C_CX], cams[ci, C_CY]
        W, H = cams[ci, C_W], cams[ci, C_H]
        yaw, pitch = obs[r, O_YAW], obs[r, O_PITCH]
        camera_pose_nb(neck, cams[ci, C_OFFX], cams[ci, C_OFFZ], cams[ci, C_TILT], yaw, pitch, rot, pos)
        for i in range(3):
            for j in range(3):
                cam_rows[r, 3 * i + j] = rot[i, j]
            cam_rows[r, 9 + i] = pos[i]
        cam_rows[r, 12], cam_rows[r, 13], cam_rows[r, 14], cam_rows[r, 15] = fx, fy, cx, cy
        cam_rows[r, 16], cam_rows[r, 17] = W, H
        ct, st = math.cos(TH), math.sin(TH)
        Cx = X + ct * pos[0] - st * pos[1]
        Cy = Y + st * pos[0] + ct * pos[1]
        hc = pos[2]
        for i in range(3):
            m[i, 0] = rot[0, i] * ct - rot[1, i] * st
            m[i, 1] = rot[0, i] * st + rot[1, i] * ct
            m[i, 2] = rot[2, i]
        sign = obs[r, O_SIGN]
        team = obs[r, O_TEAM]
        walking = obs[r, O_WALK] > 0.5
        yr, pr = obs[r, O_YAWR], obs[r, O_PITCHR]
        sa = prm[P_SA] + prm[P_CT] * abs(pr) + (prm[P_SAM] if walking else 0.0)
        sb = prm[P_SB] + prm[P_CP] * abs(yr) + (prm[P_SBM] if walking else 0.0)
        if prm[P_FIXED] > 0.5:
            sa_rep, sb_rep = prm[P_FIXED_SIGMA], prm[P_FIXED_SIGMA]
        else:
            sa_rep, sb_rep = sa, sb
        motion = 1.0 / (1.0 + prm[P_HEAD_DET] * math.hypot(yr, pr))
        if walking:
            motion *= prm[P_WALK_DET]
        ctx[X_CX], ctx[X_CY], ctx[X_HC], ctx[X_X], ctx[X_Y], ctx[X_CT], ctx[X_ST] = Cx, Cy, hc, X, Y, ct, st
        ctx[X_SA], ctx[X_SB], ctx[X_SH], ctx[X_IND] = sa, sb, sh, ind
        ctx[X_EA], ctx[X_EB] = normals[cursor[0]], normals[cursor[0] + 1]
        cursor[0] += 2
        ctx[X_PCX], ctx[X_PCY], ctx[X_SAR], ctx[X_SBR] = pos[0], pos[1], sa_rep, sb_rep
        ctx[X_FX], ctx[X_FY], ctx[X_PPX], ctx[X_PPY], ctx[X_W], ctx[X_H] = fx, fy, cx, cy, W, H
        # occluders as seen from the optical centre
        for j in range(n_obs):
            oflag[j] = False
            if j == r or occ[j, OC_PRESENT] < 0.5:
                continue
            ox, oy = occ[j, OC_X] - Cx, occ[j, OC_Y] - Cy
            d = math.hypot(ox, oy)
            if d <= occ[j, OC_R] + 1e-3:
                continue
            od[j] = d
            ob[j] = math.atan2(oy, ox)
            ow[j] = math.asin(occ[j, OC_R] / d)
            oh[j] = occ[j, OC_H]
            oflag[j] = True

        # ---- posts ------------------------------------------------------------------------
        offsets[r, K_POST] = row
        for i in range(fidx[G_POST], fidx[G_POST + 1]):
            px, py = fmap[i, F_X], fmap[i, F_Y]
            ok, u, v, d, b = _look(m, ctx, px, py, 0.0)
            if not ok or d > prm[P_DET_POST + 2]:
                continue
            frac = _occlusion(d, b, math.asin(min(1.0, post_r / d)), 0.0, hc, od, ob, ow, oh, oflag, -1)
            if frac > max_occ:
                continue
            p = _rate(prm, P_DET_POST, d) * motion * (1.0 - frac)
            if uniforms[cursor[1]] >= p:
                cursor[1] += 1
                continue
            cursor[1] += 1
            k = int(fmap[i, F_PARTNER])
            qx, qy = fmap[k, F_X], fmap[k, F_Y]
            ok2, u_other, _, _, _ = _look(m, ctx, qx, qy, 0.0)
            side = 0.0
            if ok2:
                side = 1.0 if u_other > u else 2.0
            else:
                ok_top, ut, _, _, _ = _look(m, ctx, px, py, goal_h)
                span = math.hypot(qx - px, qy - py)
                f = min(0.3 / span, 0.5)
                okb, ub, _, _, _ = _look(m, ctx, px + f * (qx - px), py + f * (qy - py), goal_h)
                if ok_top and okb:
                    side = 1.0 if ub > ut else 2.0
            ok_m, mx, my = _measure(px, py, 0.0, ctx, normals, cursor)
            if not ok_m:
                continue
            truth = fmap[i, F_PERM] if sign < 0 else float(i - fidx[G_POST])
            _emit(out, row, mx, my, u, v, side, ctx, hc, truth)
            tu, tv = _pixel(m, ctx, px, py, goal_h)
            out[row, 6], out[row, 7] = tu, tv
            if distinct:
                g = fmap[i, F_B]
                out[row, 17] = g if sign > 0 else 1.0 - g
            row += 1
        if uniforms[cursor[1]] < prm[P_BG_POST]:
            # a post-like object beyond the carpet, at a random column of the image
            ur = uniforms[cursor[1] + 1] * W
            dcx, dcy = 1.0, (cx - ur) / fx
            bx = rot[0, 0] * dcx + rot[0, 1] * dcy
            by = rot[1, 0] * dcx + rot[1, 1] * dcy
            bearing = math.atan2(by, bx) + TH
            ux, uy = math.cos(bearing), math.sin(bearing)
            t_exit = _exit_distance(Cx, Cy, ux, uy, fconst[K_HX], fconst[K_HY])
            dist = t_exit + 0.5 + 2.5 * uniforms[cursor[1] + 2]
            px, py = Cx + dist * ux, Cy + dist * uy
            ok, u, v, d, b = _look(m, ctx, px, py, 0.0)
            if ok:
                ok_m, mx, my = _measure(px, py, 0.0, ctx, normals, cursor)
                if ok_m:
                    _emit(out, row, mx, my, u, v, 0.0, ctx, hc, -1.0)
                    tu, tv = _pixel(m, ctx, px, py, goal_h)
                    out[row, 6], out[row, 7] = tu, tv
                    row += 1
        cursor[1] += 3

        # ---- crossings --------------------------------------------------------------------
        offsets[r, K_CROSS] = row
        for i in range(fidx[G_CROSS], fidx[G_CROSS + 1]):
            px, py = fmap[i, F_X], fmap[i, F_Y]
            ok, u, v, d, b = _look(m, ctx, px, py, 0.0)
            if not ok or d > prm[P_DET_CROSS + 2]:
                continue
            if _occlusion(d, b, 0.0, 0.0, hc, od, ob, ow, oh, oflag, -1) > 0.0:
                continue
            p = _rate(prm, P_DET_CROSS, d) * motion
            draw = uniforms[cursor[1]]
            confuse = uniforms[cursor[1] + 1]
            cursor[1] += 2
            if draw >= p:
                continue
            kind = int(fmap[i, F_B])
            if confuse < prm[P_CONFUSE]:
                kind = 1 if kind != 1 else 0  # L <-> T, X -> T
            orient = _crossing_orientation(kind, fmap[i, F_A] - TH + prm[P_ORIENT] * normals[cursor[0]])
            cursor[0] += 1
            ok_m, mx, my = _measure(px, py, 0.0, ctx, normals, cursor)
            if not ok_m:
                continue
            truth = fmap[i, F_PERM] if sign < 0 else float(i - fidx[G_CROSS])
            _emit(out, row, mx, my, u, v, float(kind), ctx, hc, truth)
            out[row, 8] = orient
            row += 1
        if uniforms[cursor[1]] < prm[P_PH_CROSS]:
            ok, wx, wy = _random_ground(rot, pos, X, Y, ct, st, W, H, fx, fy, cx, cy, uniforms, cursor)
            if ok and math.hypot(wx - Cx, wy - Cy) <= prm[P_DET_CROSS + 2]:
                kind = min(2, int(3.0 * uniforms[cursor[1] + 1]))
                orient = _crossing_orientation(kind, (2.0 * uniforms[cursor[1] + 2] - 1.0) * math.pi)
                mx, my = ct * (wx - X) + st * (wy - Y), -st * (wx - X) + ct * (wy - Y)
                u, v = _pixel(m, ctx, wx, wy, 0.0)
                _emit(out, row, mx, my, u, v, float(kind), ctx, hc, -1.0)
                out[row, 8] = orient
                row += 1
        cursor[1] += 3

        # ---- lines ------------------------------------------------------------------------
        offsets[r, K_LINE] = row
        line_max = prm[P_DET_LINE + 2]
        for i in range(fidx[G_LINE], fidx[G_LINE + 1]):
            x1, y1, x2, y2 = fmap[i, F_X], fmap[i, F_Y], fmap[i, F_A], fmap[i, F_B]
            ax, ay = x1 - Cx, y1 - Cy
            bx, by = x2 - x1, y2 - y1
            for a in range(3):
                q[a] = m[a, 0] * ax + m[a, 1] * ay - m[a, 2] * hc
                dq[a] = m[a, 0] * bx + m[a, 1] * by
            lo, hi = 0.0, 1.0
            lo, hi = _clip(q[0] - NEAR, dq[0], lo, hi)
            lo, hi = _clip(cx * q[0] - fx * q[1], cx * dq[0] - fx * dq[1], lo, hi)
            lo, hi = _clip((W - cx) * q[0] + fx * q[1], (W - cx) * dq[0] + fx * dq[1], lo, hi)
            lo, hi = _clip(cy * q[0] - fy * q[2], cy * dq[0] - fy * dq[2], lo, hi)
            lo, hi = _clip((H - cy) * q[0] + fy * q[2], (H - cy) * dq[0] + fy * dq[2], lo, hi)
            if hi <= lo:
                continue
            # within range of the optical centre: |a + t b| <= line_max
            qa, qb, qc = bx * bx + by * by, 2.0 * (ax * bx + ay * by), ax * ax + ay * ay - line_max * line_max
            disc = qb * qb - 4.0 * qa * qc
            if qa <= 0.0 or disc <= 0.0:
                continue
            sq = math.sqrt(disc)
            lo = max(lo, (-qb - sq) / (2.0 * qa))
            hi = min(hi, (-qb + sq) / (2.0 * qa))
            if hi <= lo:
                continue
            npieces = 1
            plo[0], phi[0] = lo, hi
            for j in range(n_obs):
                if not oflag[j] or npieces == 0:
                    continue
                olo, ohi = _shadow_interval(ax, ay, bx, by, od[j], ob[j], ow[j], oh[j], hc)
                if ohi <= olo:
                    continue
                nn = 0
                for k in range(npieces):
                    a0, a1 = plo[k], phi[k]
                    if ohi <= a0 or olo >= a1:
                        if nn < MAX_PIECES:
                            nlo[nn], nhi[nn] = a0, a1
                            nn += 1
                        continue
                    if olo > a0 and nn < MAX_PIECES:
                        nlo[nn], nhi[nn] = a0, olo
                        nn += 1
                    if ohi < a1 and nn < MAX_PIECES:
                        nlo[nn], nhi[nn] = ohi, a1
                        nn += 1
                npieces = nn
                for k in range(nn):
                    plo[k], phi[k] = nlo[k], nhi[k]
            seg_len = math.sqrt(qa)
            for k in range(npieces):
                if (phi[k] - plo[k]) * seg_len < prm[P_MIN_LINE]:
                    continue
                e1x, e1y = x1 + plo[k] * bx, y1 + plo[k] * by
                e2x, e2y = x1 + phi[k] * bx, y1 + phi[k] * by
                dnear = _point_segment_distance(Cx, Cy, e1x, e1y, e2x, e2y)
                p = _rate(prm, P_DET_LINE, dnear) * motion
                draw = uniforms[cursor[1]]
                cursor[1] += 1
                if draw >= p:
                    continue
                ok1, m1x, m1y = _measure(e1x, e1y, 0.0, ctx, normals, cursor)
                ok2, m2x, m2y = _measure(e2x, e2y, 0.0, ctx, normals, cursor)
                if not (ok1 and ok2):
                    continue
                ddx, ddy = m2x - m1x, m2y - m1y
                dd = ddx * ddx + ddy * ddy
                tn = 0.0 if dd <= 0.0 else min(1.0, max(0.0, -(m1x * ddx + m1y * ddy) / dd))
                nx, ny = m1x + tn * ddx, m1y + tn * ddy
                u1, v1 = _pixel(m, ctx, e1x, e1y, 0.0)
                u2, v2 = _pixel(m, ctx, e2x, e2y, 0.0)
                truth = fmap[i, F_PERM] if sign < 0 else float(i - fidx[G_LINE])
                _emit(out, row, m1x, m1y, u1, v1, 0.0, ctx, hc, truth)
                _set_cov(out, row, nx, ny, ctx, hc)
                out[row, 4], out[row, 5], out[row, 6], out[row, 7] = m2x, m2y, u2, v2
                out[row, 8] = _line_direction(ddx, ddy)
                row += 1

        # ---- centre circle ----------------------------------------------------------------
        offsets[r, K_CIRCLE] = row
        n_circle = fidx[G_CIRCLE + 1] - fidx[G_CIRCLE]
        if n_circle > 0:
            visible = 0
            circ_max = prm[P_DET_CIRCLE + 2]
            for i in range(fidx[G_CIRCLE], fidx[G_CIRCLE + 1]):
                ok, u, v, d, b = _look(m, ctx, fmap[i, F_X], fmap[i, F_Y], 0.0)
                if ok and d <= circ_max and _occlusion(d, b, 0.0, 0.0, hc, od, ob, ow, oh, oflag, -1) <= 0.0:
                    visible += 1
            draw = uniforms[cursor[1]]
            cursor[1] += 1
            if visible > 0 and visible >= prm[P_CIRCLE_MIN] * n_circle:
                ccx, ccy = fconst[K_CIRCLE_X], fconst[K_CIRCLE_Y]
                d = math.hypot(ccx - Cx, ccy - Cy)
                if draw < _rate(prm, P_DET_CIRCLE, d) * motion:
                    ok_m, mx, my = _measure(ccx, ccy, 0.0, ctx, normals, cursor)
                    if ok_m:
                        u, v = _pixel(m, ctx, ccx, ccy, 0.0)
                        _emit(out, row, mx, my, u, v, 0.0, ctx, hc, 0.0)
                        row += 1

        # ---- penalty marks ----------------------------------------------------------------
        offsets[r, K_MARK] = row
        for i in range(fidx[G_MARK], fidx[G_MARK + 1]):
            px, py = fmap[i, F_X], fmap[i, F_Y]
            ok, u, v, d, b = _look(m, ctx, px, py, 0.0)
            if not ok or d > prm[P_DET_MARK + 2]:
                continue
            if _occlusion(d, b, 0.0, 0.0, hc, od, ob, ow, oh, oflag, -1) > 0.0:
                continue
            draw = uniforms[cursor[1]]
            cursor[1] += 1
            if draw >= _rate(prm, P_DET_MARK, d) * motion:
                continue
            ok_m, mx, my = _measure(px, py, 0.0, ctx, normals, cursor)
            if ok_m:
                truth = fmap[i, F_PERM] if sign < 0 else float(i - fidx[G_MARK])
                _emit(out, row, mx, my, u, v, 0.0, ctx, hc, truth)
                row += 1
        if uniforms[cursor[1]] < prm[P_PH_MARK]:
            ok, wx, wy = _random_ground(rot, pos, X, Y, ct, st, W, H, fx, fy, cx, cy, uniforms, cursor)
            if ok and math.hypot(wx - Cx, wy - Cy) <= prm[P_DET_MARK + 2]:
                mx, my = ct * (wx - X) + st * (wy - Y), -st * (wx - X) + ct * (wy - Y)
                u, v = _pixel(m, ctx, wx, wy, 0.0)
                _emit(out, row, mx, my, u, v, 0.0, ctx, hc, -1.0)
                row += 1
        cursor[1] += 3

        # ---- robots (decided before the ball: false balls appear at seen robots' feet) ------
        n_seen = 0
        for j in range(n_obs):
            if not oflag[j]:
                continue
            px, py = occ[j, OC_X], occ[j, OC_Y]
            ok, u, v, d, b = _look(m, ctx, px, py, 0.0)
            if not ok or d > prm[P_DET_ROBOT + 2]:
                continue
            frac = _occlusion(d, b, ow[j], 0.0, hc, od, ob, ow, oh, oflag, j)
            if frac > max_occ:
                continue
            draw = uniforms[cursor[1]]
            cursor[1] += 1
            if draw < _rate(prm, P_DET_ROBOT, d) * motion * (1.0 - frac):
                seen[n_seen] = j
                n_seen += 1

        # ---- ball ---------------------------------------------------------------------------
        offsets[r, K_BALL] = row
        if ball[4] > 0.5:
            px, py = ball[0], ball[1]
            ok, u, v, d, b = _look(m, ctx, px, py, ball_r)
            if ok and d <= prm[P_DET_BALL + 2]:
                frac = _occlusion(d, b, math.asin(min(1.0, ball_r / d)), ball_r, hc, od, ob, ow, oh, oflag, -1)
                if frac <= max_occ:
                    speed = math.hypot(ball[2], ball[3])
                    p = _rate(prm, P_DET_BALL, d) * motion * (1.0 - frac) / (1.0 + prm[P_BALL_DET] * speed)
                    draw = uniforms[cursor[1]]
                    cursor[1] += 1
                    if draw < p:
                        row = _ball_row(out, row, px, py, u, v, 0.0, ctx, ball_r, prm[P_RAD_SIGMA], normals, cursor)
        for s in range(n_seen):
            j = seen[s]
            draw = uniforms[cursor[1]]
            cursor[1] += 1
            if draw >= prm[P_FEET_BALL]:
                continue
            gap = occ[j, OC_R] + ball_r
            px = occ[j, OC_X] - gap * math.cos(ob[j])
            py = occ[j, OC_Y] - gap * math.sin(ob[j])
            ok, u, v, d, b = _look(m, ctx, px, py, ball_r)
            if ok:
                row = _ball_row(out, row, px, py, u, v, -1.0, ctx, ball_r, prm[P_RAD_SIGMA], normals, cursor)
        if uniforms[cursor[1]] < prm[P_FALSE_BALL]:
            ok, wx, wy = _random_ground(rot, pos, X, Y, ct, st, W, H, fx, fy, cx, cy, uniforms, cursor)
            if ok and math.hypot(wx - Cx, wy - Cy) <= prm[P_DET_BALL + 2]:
                ok, u, v, d, b = _look(m, ctx, wx, wy, ball_r)
                if ok:
                    row = _ball_row(out, row, wx, wy, u, v, -1.0, ctx, ball_r, prm[P_RAD_SIGMA], normals, cursor)
        cursor[1] += 3

        # ---- robots -------------------------------------------------------------------------
        offsets[r, K_ROBOT] = row
        for s in range(n_seen):
            j = seen[s]
            px, py = occ[j, OC_X], occ[j, OC_Y]
            ok_m, mx, my = _measure(px, py, 0.0, ctx, normals, cursor)
            guess = uniforms[cursor[1]]
            cursor[1] += 1
            if not ok_m:
                continue
            same = obs[j, O_TEAM] == team
            if guess < prm[P_TEAM_UNK]:
                sub = 0.0
            elif guess < prm[P_TEAM_UNK] + prm[P_TEAM_WRONG]:
                sub = 2.0 if same else 1.0
            else:
                sub = 1.0 if same else 2.0
            u, v = _pixel(m, ctx, px, py, 0.0)
            number0 = j - int(obs[j, O_TEAM]) * npt
            truth = float((0 if same else 1) * npt + number0)
            _emit(out, row, mx, my, u, v, sub, ctx, hc, truth)
            u2, v2 = _pixel(m, ctx, px, py, oh[j])
            out[row, 6], out[row, 7] = u2, v2
            row += 1

        # ---- corner poles -------------------------------------------------------------------
        offsets[r, K_POLE] = row
        for i in range(fidx[G_POLE], fidx[G_POLE + 1]):
            px, py = fmap[i, F_X], fmap[i, F_Y]
            ok, u, v, d, b = _look(m, ctx, px, py, 0.0)
            if not ok or d > prm[P_DET_POLE + 2]:
                continue
            frac = _occlusion(d, b, math.asin(min(1.0, pole_r / d)), 0.0, hc, od, ob, ow, oh, oflag, -1)
            if frac > max_occ:
                continue
            draw = uniforms[cursor[1]]
            cursor[1] += 1
            if draw >= _rate(prm, P_DET_POLE, d) * motion * (1.0 - frac):
                continue
            ok_m, mx, my = _measure(px, py, 0.0, ctx, normals, cursor)
            if ok_m:
                truth = fmap[i, F_PERM] if sign < 0 else float(i - fidx[G_POLE])
                _emit(out, row, mx, my, u, v, 0.0, ctx, hc, truth)
                row += 1
        offsets[r, K_POLE + 1] = row
    return row


@nb.njit(cache=True)
def _look(m, ctx, px, py, pz):  # pragma: no cover - compiled
    """(in image, u, v, ground distance from the optical centre, world bearing) of a world point."""
    dx, dy, dz = px - ctx[X_CX], py - ctx[X_CY], pz - ctx[X_HC]
    fx, fy, cx, cy, W, H = ctx[X_FX], ctx[X_FY], ctx[X_PPX], ctx[X_PPY], ctx[X_W], ctx[X_H]
    q0 = m[0, 0] * dx + m[0, 1] * dy + m[0, 2] * dz
    d = math.hypot(dx, dy)
    b = math.atan2(dy, dx)
    if q0 <= NEAR:
        return False, np.nan, np.nan, d, b
    q1 = m[1, 0] * dx + m[1, 1] * dy + m[1, 2] * dz
    q2 = m[2, 0] * dx + m[2, 1] * dy + m[2, 2] * dz
    u = cx - fx * q1 / q0
    v = cy - fy * q2 / q0
    ok = 0.0 <= u < W and 0.0 <= v < H
    return ok, u, v, d, b


@nb.njit(cache=True)
def _pixel(m, ctx, px, py, pz):  # pragma: no cover - compiled
    """Pixel of a world point (NaN behind the camera)."""
    dx, dy, dz = px - ctx[X_CX], py - ctx[X_CY], pz - ctx[X_HC]
    fx, fy, cx, cy = ctx[X_FX], ctx[X_FY], ctx[X_PPX], ctx[X_PPY]
    q0 = m[0, 0] * dx + m[0, 1] * dy + m[0, 2] * dz
    if q0 <= 1e-9:
        return np.nan, np.nan
    q1 = m[1, 0] * dx + m[1, 1] * dy + m[1, 2] * dz
    q2 = m[2, 0] * dx + m[2, 1] * dy + m[2, 2] * dz
    return cx - fx * q1 / q0, cy - fy * q2 / q0


@nb.njit(cache=True)
def _measure(px, py, pz, ctx, normals, cursor):  # pragma: no cover - compiled
    """Robot-frame position of a world point seen through noisy viewing angles (Darmstadt IV.B)."""
    Cx, Cy, X, Y, ct, st = ctx[X_CX], ctx[X_CY], ctx[X_X], ctx[X_Y], ctx[X_CT], ctx[X_ST]
    sa, sb, sh, ind = ctx[X_SA], ctx[X_SB], ctx[X_SH], ctx[X_IND]
    ea_s, eb_s = ctx[X_EA], ctx[X_EB]
    dx, dy = px - Cx, py - Cy
    h = ctx[X_HC] - pz
    alpha = math.atan2(h, math.hypot(dx, dy))
    beta = math.atan2(dy, dx)
    a2 = alpha + sa * (sh * ea_s + ind * normals[cursor[0]])
    b2 = beta + sb * (sh * eb_s + ind * normals[cursor[0] + 1])
    cursor[0] += 2
    if a2 <= 1e-4 or h <= 0.0:
        return False, np.nan, np.nan
    a2 = min(a2, 0.5 * math.pi - 1e-6)
    d2 = h / math.tan(a2)
    wx, wy = Cx + d2 * math.cos(b2) - X, Cy + d2 * math.sin(b2) - Y
    return True, ct * wx + st * wy, -st * wx + ct * wy


@nb.njit(cache=True)
def _ball_row(out, row, px, py, u, v, truth, ctx, ball_r, rad_sigma, normals, cursor):  # pragma: no cover
    """Write a ball row (projection plus noisy image radius); returns the next row."""
    ok_m, mx, my = _measure(px, py, ball_r, ctx, normals, cursor)
    noise = normals[cursor[0]]
    cursor[0] += 1
    if not ok_m:
        return row
    hc = ctx[X_HC]
    dist3 = math.sqrt((px - ctx[X_CX]) ** 2 + (py - ctx[X_CY]) ** 2 + (ball_r - hc) ** 2)
    f_mean = 0.5 * (ctx[X_FX] + ctx[X_FY])
    rad = f_mean * ball_r / math.sqrt(max(dist3 * dist3 - ball_r * ball_r, 1e-12))
    rad = max(0.5, rad + rad_sigma * noise)
    _emit(out, row, mx, my, u, v, 0.0, ctx, hc - ball_r, truth)
    out[row, 15] = rad
    return row + 1


@nb.njit(cache=True)
def _occlusion(d, b, w, z, hc, od, ob, ow, oh, oflag, skip):  # pragma: no cover - compiled
    """Hidden fraction of an object at distance d, bearing b, angular half-width w, height z.

    With ``w == 0`` the object is a point: 1.0 if hidden, else 0.0.
    """
    frac = 0.0
    for j in range(od.shape[0]):
        if not oflag[j] or j == skip or od[j] >= d:
            continue
        if hc - (hc - z) * od[j] / d >= oh[j]:
            continue  # the line of sight passes above this robot
        rel = _wrap(ob[j] - b)
        if w <= 0.0:
            if abs(rel) < ow[j]:
                return 1.0
            continue
        lo = max(-w, rel - ow[j])
        hi = min(w, rel + ow[j])
        if hi > lo:
            frac += (hi - lo) / (2.0 * w)
    return min(frac, 1.0)


@nb.njit(cache=True)
def _clip(g0, g1, lo, hi):  # pragma: no cover - compiled
    """Intersect [lo, hi] with {t : g0 + t g1 >= 0}."""
    if abs(g1) < 1e-15:
        return (lo, hi) if g0 >= 0.0 else (1.0, 0.0)
    t = -g0 / g1
    if g1 > 0.0:
        return max(lo, t), hi
    return lo, min(hi, t)


@nb.njit(cache=True)
def _shadow_interval(ax, ay, bx, by, od, ob, ow, oh, hc):  # pragma: no cover - compiled
    """Parameters [lo, hi] of the ground segment a + t b (relative to the camera) hidden by a robot."""
    lo, hi = 0.0, 1.0
    c1, s1 = math.cos(ob - ow), math.sin(ob - ow)
    c2, s2 = math.cos(ob + ow), math.sin(ob + ow)
    cc, sc = math.cos(ob), math.sin(ob)
    lo, hi = _clip(c1 * ay - s1 * ax, c1 * by - s1 * bx, lo, hi)  # left of the right tangent
    lo, hi = _clip(ax * s2 - ay * c2, bx * s2 - by * c2, lo, hi)  # right of the left tangent
    lo, hi = _clip(ax * cc + ay * sc - od, bx * cc + by * sc, lo, hi)  # behind the robot
    if oh < hc:
        end = od * hc / (hc - oh)  # a lying robot's shadow ends here
        lo, hi = _clip(end - (ax * cc + ay * sc), -(bx * cc + by * sc), lo, hi)
    return lo, hi


@nb.njit(cache=True)
def _point_segment_distance(px, py, x1, y1, x2, y2):  # pragma: no cover - compiled
    dx, dy = x2 - x1, y2 - y1
    dd = dx * dx + dy * dy
    t = 0.0 if dd <= 0.0 else min(1.0, max(0.0, ((px - x1) * dx + (py - y1) * dy) / dd))
    return math.hypot(x1 + t * dx - px, y1 + t * dy - py)


@nb.njit(cache=True)
def _line_direction(dx, dy):  # pragma: no cover - compiled
    """Undirected direction of (dx, dy) in [0, pi)."""
    a = math.atan2(dy, dx) % math.pi
    return 0.0 if a >= math.pi - 1e-12 else a


@nb.njit(cache=True)
def _crossing_orientation(kind, a):  # pragma: no cover - compiled
    """Wrap a crossing orientation: (-pi, pi] for L and T, [0, pi/2) for X."""
    if kind == 2:
        q = a % (0.5 * math.pi)
        return 0.0 if q >= 0.5 * math.pi - 1e-12 else q
    return _wrap(a)


@nb.njit(cache=True)
def _exit_distance(x, y, ux, uy, hx, hy):  # pragma: no cover - compiled
    """Distance from (x, y) along (ux, uy) to the border of the box |x| <= hx, |y| <= hy."""
    t = 1e9
    if ux > 1e-12:
        t = min(t, (hx - x) / ux)
    elif ux < -1e-12:
        t = min(t, (-hx - x) / ux)
    if uy > 1e-12:
        t = min(t, (hy - y) / uy)
    elif uy < -1e-12:
        t = min(t, (-hy - y) / uy)
    return max(t, 0.0)


@nb.njit(cache=True)
def _random_ground(rot, pos, X, Y, ct, st, W, H, fx, fy, cx, cy, uniforms, cursor):  # pragma: no cover
    """A random image pixel's ground point (world frame); uses uniforms[cursor+1], [cursor+2]."""
    ur = uniforms[cursor[1] + 1] * W
    vr = uniforms[cursor[1] + 2] * H
    d0, d1, d2 = 1.0, (cx - ur) / fx, (cy - vr) / fy
    rx = rot[0, 0] * d0 + rot[0, 1] * d1 + rot[0, 2] * d2
    ry = rot[1, 0] * d0 + rot[1, 1] * d1 + rot[1, 2] * d2
    rz = rot[2, 0] * d0 + rot[2, 1] * d1 + rot[2, 2] * d2
    if rz >= -1e-9:
        return False, 0.0, 0.0
    t = -pos[2] / rz
    gx, gy = pos[0] + t * rx, pos[1] + t * ry
    return True, X + ct * gx - st * gy, Y + st * gx + ct * gy
