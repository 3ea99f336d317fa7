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
from cognition.percepts import Kind
from teamsim.percept_parts import (
    CAM,
    CTX,
    FC,
    MAX_PIECES,
    N_CTX,
    NEAR,
    OBS,
    OC,
    F,
    G,
    P,
    ball_row,
    clip,
    crossing_orientation,
    emit,
    exit_distance,
    line_direction,
    look,
    measure,
    pixel,
    point_segment_distance,
    random_ground,
    rate,
    set_cov,
    shadow_interval,
    visible,
)


def draws_bound(n_observers: int, fidx: NDArray[np.int64]) -> tuple[int, int]:
    """Upper bounds of (normals, uniforms) one kernel call consumes."""
    points = int(fidx[G.CIRCLE] - fidx[G.POST]) - int(fidx[G.LINE + 1] - fidx[G.LINE])
    lines = int(fidx[G.LINE + 1] - fidx[G.LINE])
    per = 16 + 5 * points + 5 * MAX_PIECES * lines + 8 * n_observers
    return n_observers * per, n_observers * per


@nb.njit(cache=True, error_model="python", fastmath=False)
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
    # per other robot, from the optical centre: distance, bearing, half-width, height, flag, then
    # (filled at the first line that meets the robot, flag in column 11) the cosines and sines of
    # its right tangent, left tangent and bearing (shadow_interval)
    occg = np.zeros((n_obs, 12))
    seen = np.empty(n_obs, dtype=np.int64)
    plo = np.empty(MAX_PIECES)
    phi = np.empty(MAX_PIECES)
    nlo = np.empty(MAX_PIECES)
    nhi = np.empty(MAX_PIECES)
    q = np.empty(3)
    dq = np.empty(3)
    ctx = np.empty(N_CTX)
    shared_f = prm[P.SHARED]
    sh, ind = math.sqrt(shared_f), math.sqrt(1.0 - shared_f)
    neck, goal_h, post_r = fconst[FC.NECK], fconst[FC.GOAL_H], fconst[FC.POST_R]
    pole_r, ball_r = fconst[FC.POLE_R], fconst[FC.BALL_R]
    distinct = fconst[FC.DISTINCT] > 0.5
    npt = int(fconst[FC.NPT])
    max_occ = prm[P.MAX_OCC]
    row = 0
    for r in range(n_obs):
        for k in range(offsets.shape[1]):
            offsets[r, k] = row
        if obs[r, OBS.ACTIVE] < 0.5:
            for c in range(cam_rows.shape[1]):
                cam_rows[r, c] = np.nan
            continue
        X, Y, TH = obs[r, OBS.X], obs[r, OBS.Y], obs[r, OBS.TH]
        ci = int(obs[r, OBS.CAM])
        fx, fy, cx, cy = cams[ci, CAM.FX], cams[ci, CAM.FY], cams[ci, CAM.CX], cams[ci, CAM.CY]
        W, H = cams[ci, CAM.W], cams[ci, CAM.H]
        yaw, pitch = obs[r, OBS.YAW], obs[r, OBS.PITCH]
        camera_pose_nb(neck, cams[ci, CAM.OFFX], cams[ci, CAM.OFFZ], cams[ci, CAM.TILT], yaw, pitch, rot, pos)
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
        sign = obs[r, OBS.SIGN]
        team = obs[r, OBS.TEAM]
        walking = obs[r, OBS.WALK] > 0.5
        yr, pr = obs[r, OBS.YAWR], obs[r, OBS.PITCHR]
        sa = prm[P.SA] + prm[P.CT] * abs(pr) + (prm[P.SAM] if walking else 0.0)
        sb = prm[P.SB] + prm[P.CP] * abs(yr) + (prm[P.SBM] if walking else 0.0)
        if prm[P.FIXED] > 0.5:
            sa_rep, sb_rep = prm[P.FIXED_SIGMA], prm[P.FIXED_SIGMA]
        else:
            sa_rep, sb_rep = sa, sb
        motion = 1.0 / (1.0 + prm[P.HEAD_DET] * math.hypot(yr, pr))
        if walking:
            motion *= prm[P.WALK_DET]
        ctx[CTX.CX], ctx[CTX.CY], ctx[CTX.HC], ctx[CTX.X], ctx[CTX.Y], ctx[CTX.CT], ctx[CTX.ST] = (
            Cx,
            Cy,
            hc,
            X,
            Y,
            ct,
            st,
        )
        ctx[CTX.SA], ctx[CTX.SB], ctx[CTX.SH], ctx[CTX.IND] = sa, sb, sh, ind
        ctx[CTX.EA], ctx[CTX.EB] = normals[cursor[0]], normals[cursor[0] + 1]
        cursor[0] += 2
        ctx[CTX.PCX], ctx[CTX.PCY], ctx[CTX.SAR], ctx[CTX.SBR] = pos[0], pos[1], sa_rep, sb_rep
        ctx[CTX.FX], ctx[CTX.FY], ctx[CTX.PPX], ctx[CTX.PPY], ctx[CTX.W], ctx[CTX.H] = fx, fy, cx, cy, W, H
        # occluders as seen from the optical centre
        for j in range(n_obs):
            occg[j, 4] = occg[j, 11] = 0.0
            if j == r or occ[j, OC.PRESENT] < 0.5:
                continue
            ox, oy = occ[j, OC.X] - Cx, occ[j, OC.Y] - Cy
            d = math.hypot(ox, oy)
            if d <= occ[j, OC.R] + 1e-3:
                continue
            occg[j, 0], occg[j, 1] = d, math.atan2(oy, ox)
            occg[j, 2], occg[j, 3], occg[j, 4] = math.asin(occ[j, OC.R] / d), occ[j, OC.H], 1.0

        # ---- posts ------------------------------------------------------------------------
        offsets[r, Kind.POST] = row
        for i in range(fidx[G.POST], fidx[G.POST + 1]):
            px, py = fmap[i, F.X], fmap[i, F.Y]
            ok, u, v, d, frac = visible(m, ctx, occg, px, py, 0.0, post_r, prm[P.DET_POST + 2], max_occ, -1)
            if not ok:
                continue
            p = rate(prm, P.DET_POST, d) * motion * (1.0 - frac)
            if uniforms[cursor[1]] >= p:
                cursor[1] += 1
                continue
            cursor[1] += 1
            k = int(fmap[i, F.PARTNER])
            qx, qy = fmap[k, F.X], fmap[k, F.Y]
            ok2, u_other, _, _, _ = look(m, ctx, qx, qy, 0.0)
            side = 0.0
            if ok2:
                side = 1.0 if u_other > u else 2.0
            else:
                ok_top, ut, _, _, _ = look(m, ctx, px, py, goal_h)
                span = math.hypot(qx - px, qy - py)
                f = min(0.3 / span, 0.5)
                okb, ub, _, _, _ = look(m, ctx, px + f * (qx - px), py + f * (qy - py), goal_h)
                if ok_top and okb:
                    side = 1.0 if ub > ut else 2.0
            ok_m, mx, my = measure(px, py, 0.0, ctx, normals, cursor)
            if not ok_m:
                continue
            truth = fmap[i, F.PERM] if sign < 0 else float(i - fidx[G.POST])
            emit(out, row, mx, my, u, v, side, ctx, hc, truth)
            tu, tv = pixel(m, ctx, px, py, goal_h)
            out[row, 6], out[row, 7] = tu, tv
            if distinct:
                g = fmap[i, F.B]
                out[row, 17] = g if sign > 0 else 1.0 - g
            row += 1
        if uniforms[cursor[1]] < prm[P.BG_POST]:
            # a post-like object beyond the carpet, at a random column of the image
            ur = uniforms[cursor[1] + 1] * W
            dcx, dcy = 1.0, (cx - ur) / fx
            bx = rot[0, 0] * dcx + rot[0, 1] * dcy
            by = rot[1, 0] * dcx + rot[1, 1] * dcy
            bearing = math.atan2(by, bx) + TH
            ux, uy = math.cos(bearing), math.sin(bearing)
            t_exit = exit_distance(Cx, Cy, ux, uy, fconst[FC.HX], fconst[FC.HY])
            dist = t_exit + 0.5 + 2.5 * uniforms[cursor[1] + 2]
            px, py = Cx + dist * ux, Cy + dist * uy
            ok, u, v, _, _ = look(m, ctx, px, py, 0.0)
            if ok:
                ok_m, mx, my = measure(px, py, 0.0, ctx, normals, cursor)
                if ok_m:
                    emit(out, row, mx, my, u, v, 0.0, ctx, hc, -1.0)
                    tu, tv = pixel(m, ctx, px, py, goal_h)
                    out[row, 6], out[row, 7] = tu, tv
                    row += 1
        cursor[1] += 3

        # ---- crossings --------------------------------------------------------------------
        offsets[r, Kind.CROSS] = row
        for i in range(fidx[G.CROSS], fidx[G.CROSS + 1]):
            px, py = fmap[i, F.X], fmap[i, F.Y]
            ok, u, v, d, _ = visible(m, ctx, occg, px, py, 0.0, 0.0, prm[P.DET_CROSS + 2], max_occ, -1)
            if not ok:
                continue
            p = rate(prm, P.DET_CROSS, d) * motion
            draw = uniforms[cursor[1]]
            confuse = uniforms[cursor[1] + 1]
            cursor[1] += 2
            if draw >= p:
                continue
            kind = int(fmap[i, F.B])
            if confuse < prm[P.CONFUSE]:
                kind = 1 if kind != 1 else 0  # L <-> T, X -> T
            orient = crossing_orientation(kind, fmap[i, F.A] - TH + prm[P.ORIENT] * normals[cursor[0]])
            cursor[0] += 1
            ok_m, mx, my = measure(px, py, 0.0, ctx, normals, cursor)
            if not ok_m:
                continue
            truth = fmap[i, F.PERM] if sign < 0 else float(i - fidx[G.CROSS])
            emit(out, row, mx, my, u, v, float(kind), ctx, hc, truth)
            out[row, 8] = orient
            row += 1
        if uniforms[cursor[1]] < prm[P.PH_CROSS]:
            ok, wx, wy = random_ground(rot, pos, X, Y, ct, st, W, H, fx, fy, cx, cy, uniforms, cursor)
            if ok and math.hypot(wx - Cx, wy - Cy) <= prm[P.DET_CROSS + 2]:
                kind = min(2, int(3.0 * uniforms[cursor[1] + 1]))
                orient = crossing_orientation(kind, (2.0 * uniforms[cursor[1] + 2] - 1.0) * math.pi)
                mx, my = ct * (wx - X) + st * (wy - Y), -st * (wx - X) + ct * (wy - Y)
                u, v = pixel(m, ctx, wx, wy, 0.0)
                emit(out, row, mx, my, u, v, float(kind), ctx, hc, -1.0)
                out[row, 8] = orient
                row += 1
        cursor[1] += 3

        # ---- lines ------------------------------------------------------------------------
        offsets[r, Kind.LINE] = row
        line_max = prm[P.DET_LINE + 2]
        for i in range(fidx[G.LINE], fidx[G.LINE + 1]):
            x1, y1, x2, y2 = fmap[i, F.X], fmap[i, F.Y], fmap[i, F.A], fmap[i, F.B]
            ax, ay = x1 - Cx, y1 - Cy
            bx, by = x2 - x1, y2 - y1
            for a in range(3):
                q[a] = m[a, 0] * ax + m[a, 1] * ay - m[a, 2] * hc
                dq[a] = m[a, 0] * bx + m[a, 1] * by
            lo, hi = 0.0, 1.0
            lo, hi = clip(q[0] - NEAR, dq[0], lo, hi)
            lo, hi = clip(cx * q[0] - fx * q[1], cx * dq[0] - fx * dq[1], lo, hi)
            lo, hi = clip((W - cx) * q[0] + fx * q[1], (W - cx) * dq[0] + fx * dq[1], lo, hi)
            lo, hi = clip(cy * q[0] - fy * q[2], cy * dq[0] - fy * dq[2], lo, hi)
            lo, hi = clip((H - cy) * q[0] + fy * q[2], (H - cy) * dq[0] + fy * dq[2], lo, hi)
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
                if occg[j, 4] < 0.5 or npieces == 0:
                    continue
                og = occg[j]
                if og[11] == 0.0:  # the robot's tangents, once per observer
                    ob, ow = og[1], og[2]
                    og[5], og[6] = math.cos(ob - ow), math.sin(ob - ow)
                    og[7], og[8] = math.cos(ob + ow), math.sin(ob + ow)
                    og[9], og[10] = math.cos(ob), math.sin(ob)
                    og[11] = 1.0
                olo, ohi = shadow_interval(ax, ay, bx, by, og[0], og[3], hc, og[5], og[6], og[7], og[8], og[9], og[10])
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
                if (phi[k] - plo[k]) * seg_len < prm[P.MIN_LINE]:
                    continue
                e1x, e1y = x1 + plo[k] * bx, y1 + plo[k] * by
                e2x, e2y = x1 + phi[k] * bx, y1 + phi[k] * by
                dnear = point_segment_distance(Cx, Cy, e1x, e1y, e2x, e2y)
                p = rate(prm, P.DET_LINE, dnear) * motion
                draw = uniforms[cursor[1]]
                cursor[1] += 1
                if draw >= p:
                    continue
                ok1, m1x, m1y = measure(e1x, e1y, 0.0, ctx, normals, cursor)
                ok2, m2x, m2y = measure(e2x, e2y, 0.0, ctx, normals, cursor)
                if not (ok1 and ok2):
                    continue
                ddx, ddy = m2x - m1x, m2y - m1y
                dd = ddx * ddx + ddy * ddy
                tn = 0.0 if dd <= 0.0 else min(1.0, max(0.0, -(m1x * ddx + m1y * ddy) / dd))
                nx, ny = m1x + tn * ddx, m1y + tn * ddy
                u1, v1 = pixel(m, ctx, e1x, e1y, 0.0)
                u2, v2 = pixel(m, ctx, e2x, e2y, 0.0)
                truth = fmap[i, F.PERM] if sign < 0 else float(i - fidx[G.LINE])
                emit(out, row, m1x, m1y, u1, v1, 0.0, ctx, hc, truth)
                set_cov(out, row, nx, ny, ctx, hc)
                out[row, 4], out[row, 5], out[row, 6], out[row, 7] = m2x, m2y, u2, v2
                out[row, 8] = line_direction(ddx, ddy)
                row += 1

        # ---- centre circle ----------------------------------------------------------------
        offsets[r, Kind.CIRCLE] = row
        n_circle = fidx[G.CIRCLE + 1] - fidx[G.CIRCLE]
        if n_circle > 0:
            # enough of the circle's points in view (at least one and the share circle_min); the
            # count stops as soon as the answer is known either way
            need = prm[P.CIRCLE_MIN] * n_circle
            circ_max = prm[P.DET_CIRCLE + 2]
            enough = False
            n_visible, left = 0, n_circle
            for i in range(fidx[G.CIRCLE], fidx[G.CIRCLE + 1]):
                left -= 1
                if visible(m, ctx, occg, fmap[i, F.X], fmap[i, F.Y], 0.0, 0.0, circ_max, max_occ, -1)[0]:
                    n_visible += 1
                    if n_visible >= need:
                        enough = True
                        break
                elif n_visible + left < need or n_visible + left == 0:
                    break
            draw = uniforms[cursor[1]]
            cursor[1] += 1
            if enough:
                ccx, ccy = fconst[FC.CIRCLE_X], fconst[FC.CIRCLE_Y]
                d = math.hypot(ccx - Cx, ccy - Cy)
                if draw < rate(prm, P.DET_CIRCLE, d) * motion:
                    ok_m, mx, my = measure(ccx, ccy, 0.0, ctx, normals, cursor)
                    if ok_m:
                        u, v = pixel(m, ctx, ccx, ccy, 0.0)
                        emit(out, row, mx, my, u, v, 0.0, ctx, hc, 0.0)
                        row += 1

        # ---- penalty marks ----------------------------------------------------------------
        offsets[r, Kind.MARK] = row
        for i in range(fidx[G.MARK], fidx[G.MARK + 1]):
            px, py = fmap[i, F.X], fmap[i, F.Y]
            ok, u, v, d, _ = visible(m, ctx, occg, px, py, 0.0, 0.0, prm[P.DET_MARK + 2], max_occ, -1)
            if not ok:
                continue
            draw = uniforms[cursor[1]]
            cursor[1] += 1
            if draw >= rate(prm, P.DET_MARK, d) * motion:
                continue
            ok_m, mx, my = measure(px, py, 0.0, ctx, normals, cursor)
            if ok_m:
                truth = fmap[i, F.PERM] if sign < 0 else float(i - fidx[G.MARK])
                emit(out, row, mx, my, u, v, 0.0, ctx, hc, truth)
                row += 1
        if uniforms[cursor[1]] < prm[P.PH_MARK]:
            ok, wx, wy = random_ground(rot, pos, X, Y, ct, st, W, H, fx, fy, cx, cy, uniforms, cursor)
            if ok and math.hypot(wx - Cx, wy - Cy) <= prm[P.DET_MARK + 2]:
                mx, my = ct * (wx - X) + st * (wy - Y), -st * (wx - X) + ct * (wy - Y)
                u, v = pixel(m, ctx, wx, wy, 0.0)
                emit(out, row, mx, my, u, v, 0.0, ctx, hc, -1.0)
                row += 1
        cursor[1] += 3

        # ---- robots (decided before the ball: false balls appear at seen robots' feet) ------
        n_seen = 0
        for j in range(n_obs):
            if occg[j, 4] < 0.5:
                continue
            px, py = occ[j, OC.X], occ[j, OC.Y]
            ok, u, v, d, frac = visible(m, ctx, occg, px, py, 0.0, occ[j, OC.R], prm[P.DET_ROBOT + 2], max_occ, j)
            if not ok:
                continue
            draw = uniforms[cursor[1]]
            cursor[1] += 1
            if draw < rate(prm, P.DET_ROBOT, d) * motion * (1.0 - frac):
                seen[n_seen] = j
                n_seen += 1

        # ---- ball ---------------------------------------------------------------------------
        offsets[r, Kind.BALL] = row
        if ball[4] > 0.5:
            px, py = ball[0], ball[1]
            ok, u, v, d, frac = visible(m, ctx, occg, px, py, ball_r, ball_r, prm[P.DET_BALL + 2], max_occ, -1)
            if ok:
                speed = math.hypot(ball[2], ball[3])
                p = rate(prm, P.DET_BALL, d) * motion * (1.0 - frac) / (1.0 + prm[P.BALL_DET] * speed)
                draw = uniforms[cursor[1]]
                cursor[1] += 1
                if draw < p:
                    row = ball_row(out, row, px, py, u, v, 0.0, ctx, ball_r, prm[P.RAD_SIGMA], normals, cursor)
        for s in range(n_seen):
            j = seen[s]
            draw = uniforms[cursor[1]]
            cursor[1] += 1
            if draw >= prm[P.FEET_BALL]:
                continue
            gap = occ[j, OC.R] + ball_r
            px = occ[j, OC.X] - gap * math.cos(occg[j, 1])
            py = occ[j, OC.Y] - gap * math.sin(occg[j, 1])
            ok, u, v, _, _ = look(m, ctx, px, py, ball_r)
            if ok:
                row = ball_row(out, row, px, py, u, v, -1.0, ctx, ball_r, prm[P.RAD_SIGMA], normals, cursor)
        if uniforms[cursor[1]] < prm[P.FALSE_BALL]:
            ok, wx, wy = random_ground(rot, pos, X, Y, ct, st, W, H, fx, fy, cx, cy, uniforms, cursor)
            if ok and math.hypot(wx - Cx, wy - Cy) <= prm[P.DET_BALL + 2]:
                ok, u, v, _, _ = look(m, ctx, wx, wy, ball_r)
                if ok:
                    row = ball_row(out, row, wx, wy, u, v, -1.0, ctx, ball_r, prm[P.RAD_SIGMA], normals, cursor)
        cursor[1] += 3

        # ---- robots -------------------------------------------------------------------------
        offsets[r, Kind.ROBOT] = row
        for s in range(n_seen):
            j = seen[s]
            px, py = occ[j, OC.X], occ[j, OC.Y]
            ok_m, mx, my = measure(px, py, 0.0, ctx, normals, cursor)
            guess = uniforms[cursor[1]]
            cursor[1] += 1
            if not ok_m:
                continue
            same = obs[j, OBS.TEAM] == team
            if guess < prm[P.TEAM_UNK]:
                sub = 0.0
            elif guess < prm[P.TEAM_UNK] + prm[P.TEAM_WRONG]:
                sub = 2.0 if same else 1.0
            else:
                sub = 1.0 if same else 2.0
            u, v = pixel(m, ctx, px, py, 0.0)
            number0 = j - int(obs[j, OBS.TEAM]) * npt
            truth = float((0 if same else 1) * npt + number0)
            emit(out, row, mx, my, u, v, sub, ctx, hc, truth)
            u2, v2 = pixel(m, ctx, px, py, occg[j, 3])
            out[row, 6], out[row, 7] = u2, v2
            row += 1

        # ---- corner poles -------------------------------------------------------------------
        offsets[r, Kind.POLE] = row
        for i in range(fidx[G.POLE], fidx[G.POLE + 1]):
            px, py = fmap[i, F.X], fmap[i, F.Y]
            ok, u, v, d, frac = visible(m, ctx, occg, px, py, 0.0, pole_r, prm[P.DET_POLE + 2], max_occ, -1)
            if not ok:
                continue
            draw = uniforms[cursor[1]]
            cursor[1] += 1
            if draw >= rate(prm, P.DET_POLE, d) * motion * (1.0 - frac):
                continue
            ok_m, mx, my = measure(px, py, 0.0, ctx, normals, cursor)
            if ok_m:
                truth = fmap[i, F.PERM] if sign < 0 else float(i - fidx[G.POLE])
                emit(out, row, mx, my, u, v, 0.0, ctx, hc, truth)
                row += 1
        offsets[r, Kind.POLE + 1] = row
    return row
