"""The compiled Kalman ball frame (:func:`kalman_ball.own_frame_nb`) against a plain numpy Kalman
filter on the ball percepts of a recorded match: the same state and covariance to 1e-9 on
every frame (prediction with rolling friction, the move into the new robot frame, the
Darmstadt measurement covariance, nearest-percept gating and the Joseph-form update)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cognition.worldmodel.ball import GATE, RESTART_AFTER, KalmanBallModel
from cognition.worldmodel.kalman_ball import own_frame_nb
from teamsim.match import Match, MatchConfig
from teamsim.referee import RefereeParams


def _predict(x, p, dt, dec, acc_sigma):
    speed = math.hypot(x[2], x[3])
    new = max(0.0, speed - dec * dt)
    k = new / speed if speed > 1e-9 else 0.0
    travel = 0.5 * speed / max(dec, 1e-9) if speed > 1e-9 and new == 0.0 else 0.5 * (1.0 + k) * dt
    xo = np.array([x[0] + travel * x[2], x[1] + travel * x[3], k * x[2], k * x[3]])
    f = np.eye(4)
    f[0, 2] = f[1, 3] = dt
    i2, q = np.eye(2), acc_sigma**2
    big_q = q * np.block([[dt**3 / 3 * i2, dt**2 / 2 * i2], [dt**2 / 2 * i2, dt * i2]])
    return xo, f @ p @ f.T + big_q


def _move(x, p, dx, dy, dth):
    c, s = math.cos(dth), math.sin(dth)
    r = np.array([[c, s], [-s, c]])
    g = np.block([[r, np.zeros((2, 2))], [np.zeros((2, 2)), r]])
    return np.concatenate([r @ (x[:2] - (dx, dy)), r @ x[2:]]), g @ p @ g.T


def _size(radius_px, focal, ball_r, height):
    if not radius_px > 0.0:
        return math.nan, math.inf
    big_d = ball_r * math.sqrt(1.0 + (focal / radius_px) ** 2)
    d = math.sqrt(max(big_d**2 - height**2, 1e-6))
    return d, big_d / radius_px * big_d / d


def _camera(bx, by, height, sa, sb, d_s, sd_s):
    """Darmstadt eqs. 8-15."""
    d_p = max(math.hypot(bx, by), 1e-3)
    beta, alpha = math.atan2(by, bx), math.atan2(height, d_p)
    var_f = (height / math.tan(alpha + sa) - height / math.tan(alpha)) ** 2
    d_f = d_p
    if math.isfinite(d_s) and math.isfinite(sd_s):
        k = var_f / (var_f + sd_s**2)
        d_f, var_f = d_p + k * (d_s - d_p), (1.0 - k) * var_f
    rot = np.array([[math.cos(beta), -math.sin(beta)], [math.sin(beta), math.cos(beta)]])
    cov = rot @ np.diag([var_f, (math.tan(sb) * d_f) ** 2]) @ rot.T
    return d_f * np.array([math.cos(beta), math.sin(beta)]), cov


def _update(x, p, z, r):
    h = np.hstack([np.eye(2), np.zeros((2, 2))])
    s = h @ p @ h.T + r
    k = np.linalg.solve(s, h @ p).T  # p h^T s^-1 (s symmetric)
    xo = x + k @ (z - h @ x)
    ikh = np.eye(4) - k @ h
    po = ikh @ p @ ikh.T + k @ r @ k.T
    return xo, 0.5 * (po + po.T)


def reference_frame(x, p, has, rejected, args):
    """The frame of :func:`own_frame_nb`, plainly; returns (x, p, has, rejected, seen)."""
    dt, dec, acc, dx, dy, dth, rows, fx, fy, height, focal, ball_r, fixed, size_px, at_pred, vel_var = args
    if has:
        x, p = _move(*_predict(x, p, dt, dec, acc), dx, dy, dth)
    if rows.shape[0] == 0:
        return x, p, has, rejected, False
    zs, rs = [], []
    for row in rows:
        sa, sb = (fixed, fixed) if fixed > 0 else (row[13], row[14])
        d_s, sd_s = _size(row[15], focal, ball_r, height)
        z, r = _camera(row[0] - fx, row[1] - fy, height, sa, sb, d_s, sd_s * size_px)
        if has and at_pred:
            d_pred = max(math.hypot(x[0] - fx, x[1] - fy), 1e-3)
            rho = focal * ball_r / math.sqrt(max(d_pred**2 + height**2 - ball_r**2, 1e-6))
            beta = math.atan2(z[1], z[0])
            _, r = _camera(d_pred * math.cos(beta), d_pred * math.sin(beta), height, sa, sb, d_pred,
                           _size(rho, focal, ball_r, height)[1] * size_px)  # fmt: skip
        zs.append(z + np.array([fx, fy]))
        rs.append(r)
    fresh_p = np.zeros((4, 4))
    if not has:
        fresh_p[:2, :2], fresh_p[2, 2], fresh_p[3, 3] = rs[0], vel_var, vel_var
        return np.array([*zs[0], 0.0, 0.0]), fresh_p, True, rejected, True
    m2 = [float((z - x[:2]) @ np.linalg.solve(p[:2, :2] + r, z - x[:2])) for z, r in zip(zs, rs, strict=True)]
    best = int(np.argmin(m2))
    if m2[best] <= GATE:
        return *_update(x, p, zs[best], rs[best]), True, 0, True
    if rejected + 1 >= RESTART_AFTER:
        fresh_p[:2, :2], fresh_p[2, 2], fresh_p[3, 3] = rs[best], vel_var, vel_var
        return np.array([*zs[best], 0.0, 0.0]), fresh_p, True, 0, True
    return x, p, True, rejected + 1, False


@pytest.mark.slow(seconds=4)
def test_the_compiled_ball_frame_equals_a_plain_kalman_filter() -> None:
    cfg = MatchConfig(seed=6, percepts="harsh", referee=RefereeParams(half_seconds=20.0))
    m = Match(cfg)
    models = [KalmanBallModel(0.05) for _ in m.world.robots]
    states = [(np.zeros(4), np.zeros((4, 4)), False, 0, -1.0) for _ in m.world.robots]
    outcomes = {"started": 0, "updated": 0, "rejected": 0, "predicted": 0}
    frames_seen = 0
    while not m.finished and m.time < 45.0:
        before = m.frames
        m.step()
        if m.frames == before:
            continue
        for i, frame in enumerate(m.last_frames):
            if frame is None:
                continue
            model = models[i]
            prm = model.params
            x, p, has, rejected, last_t = states[i]
            dt = 0.0 if last_t < 0 else frame.time - last_t
            rows, fx, fy, height, focal = model._ball_rows(frame.percepts)
            o = frame.odometry
            fixed = prm.fixed_sigma if prm.sigma_mode == "fixed" else -1.0
            args = (dt, prm.rolling_deceleration, prm.accel_sigma, o.dx, o.dy, o.dtheta, rows, fx, fy, height, focal,
                    model.ball_radius, fixed, prm.size_sigma_px, prm.sigmas_at_prediction,
                    prm.initial_velocity_sigma**2)  # fmt: skip
            xr, pr, has_r, rej_r, seen_r = reference_frame(x.copy(), p.copy(), has, rejected, args)
            xk, pk, status = x.copy(), p.copy(), np.array([int(has), rejected], dtype=np.int64)
            seen_k = own_frame_nb(xk, pk, status, dt, *args[1:14], args[14], GATE, RESTART_AFTER, args[15])
            assert (seen_k, bool(status[0]), int(status[1])) == (seen_r, has_r, rej_r)
            if has_r:
                np.testing.assert_allclose(xk, xr, rtol=1e-9, atol=1e-9)
                np.testing.assert_allclose(pk, pr, rtol=1e-9, atol=1e-12)
            kind = (
                "started" if seen_r and not has else "updated" if seen_r else "rejected" if rows.size else "predicted"
            )
            outcomes[kind] += 1
            states[i] = (xk, pk, bool(status[0]), int(status[1]), frame.time)
            frames_seen += 1
    assert frames_seen > 1000
    # every branch of the frame was compared (harsh percepts: false balls get gated out)
    assert min(outcomes.values()) > 0, outcomes
