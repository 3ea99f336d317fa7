"""The compiled Kalman ball frame (:func:`kalman_ball.own_frame_nb`) against a plain numpy Kalman
filter on the ball percepts of a recorded match: the same state and covariance to 1e-9 on
every frame (prediction with rolling friction, the move into the new robot frame, the
Darmstadt measurement covariance, nearest-percept gating and the Joseph-form update)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cognition.percepts import N_COLS
from cognition.worldmodel.ball import GATE, RESTART_AFTER, KalmanBallModel
from cognition.worldmodel.kalman_ball import (
    FRAME_PUBLISHED,
    FRAME_SEEN,
    FRAME_TEAM,
    frame_nb,
    own_frame_nb,
    publish_nb,
)
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


def reference_publish(x, p, pose, limits):
    """The end of a ball frame in plain Python: back onto the carpet (the boards stop the ball
    and its velocity across them), then the finiteness check and the published sd and field
    position (the Python this module ran before :func:`publish_nb`)."""
    x = x.copy()
    if pose is not None and limits is not None:
        c, s = math.cos(pose[2]), math.sin(pose[2])
        fx, fy = pose[0] + c * x[0] - s * x[1], pose[1] + s * x[0] + c * x[1]
        if math.isfinite(fx) and math.isfinite(fy) and not (abs(fx) <= limits[0] and abs(fy) <= limits[1]):
            vx, vy = c * x[2] - s * x[3], s * x[2] + c * x[3]
            if abs(fx) > limits[0]:
                fx, vx = math.copysign(limits[0], fx), 0.0
            if abs(fy) > limits[1]:
                fy, vy = math.copysign(limits[1], fy), 0.0
            dx, dy = fx - pose[0], fy - pose[1]
            x = np.array([c * dx + s * dy, -s * dx + c * dy, c * vx + s * vy, -s * vx + c * vy])
    with np.errstate(invalid="ignore"):  # inf - inf in the sum: not finite, as intended
        total = float(x.sum() + p.sum())
    if not math.isfinite(total):
        return x, None
    sd = math.sqrt(max(0.0, 0.5 * float(p[0, 0] + p[1, 1])))
    fx = fy = math.nan
    if pose is not None:
        c, s = math.cos(pose[2]), math.sin(pose[2])
        fx, fy = pose[0] + c * x[0] - s * x[1], pose[1] + s * x[0] + c * x[1]
    return x, (sd, fx, fy)


def test_publishing_a_ball_equals_the_plain_python_step() -> None:
    """:func:`publish_nb` against :func:`reference_publish` on random states, to the bit: on and
    off the carpet (past a side, an end, a corner), without a pose or limits, and non-finite."""
    rng = np.random.default_rng(5)
    limits = (5.2, 3.7)
    kinds = {"kept": 0, "moved": 0, "dropped": 0, "no pose": 0, "no limits": 0}
    for trial in range(3000):
        x = rng.normal(0.0, 4.0, 4)
        a = rng.normal(0.0, 0.5, (4, 4))
        p = a @ a.T
        pose = (rng.uniform(-5, 5), rng.uniform(-3.5, 3.5), rng.uniform(-math.pi, math.pi))
        use_pose, use_limits = trial % 7 != 0, trial % 11 != 0
        if trial % 13 == 0:
            (x if trial % 2 else p)[rng.integers(0, 4), ...] = rng.choice([math.nan, math.inf, -math.inf])
        pose_arg = pose if use_pose else None
        lim_arg = limits if use_limits else None
        x_ref, out_ref = reference_publish(x, p, pose_arg, lim_arg)
        xk, out = x.copy(), np.zeros(3)
        lim = lim_arg if lim_arg is not None else (-1.0, -1.0)
        ok = publish_nb(xk, p, use_pose, *(pose if use_pose else (0.0, 0.0, 0.0)), lim[0], lim[1], out)
        assert ok == (out_ref is not None)
        assert np.array_equal(xk, x_ref, equal_nan=True)
        if out_ref is not None:
            assert np.array_equal(out, np.array(out_ref), equal_nan=True)
        moved = not np.array_equal(x, x_ref, equal_nan=True)
        kinds["dropped" if out_ref is None else "moved" if moved else "kept"] += 1
        kinds["no pose"] += not use_pose
        kinds["no limits"] += not use_limits
    assert min(kinds.values()) > 20, kinds


def test_the_frame_kernel_is_the_own_frame_then_the_team_check_or_publishing() -> None:
    """:func:`frame_nb` against :func:`own_frame_nb` followed by :func:`publish_nb`, to the bit,
    on random states and percepts: it stops before publishing (``FRAME_TEAM``) exactly when no
    percept updated the state, teammates may be used and the position variance exceeds the
    threshold."""
    rng = np.random.default_rng(11)
    limits = (5.2, 3.7)
    kinds = {"seen": 0, "team": 0, "published": 0, "kept out of the team": 0}
    for trial in range(2000):
        x = rng.normal(0.0, 2.0, 4)
        a = rng.normal(0.0, 0.4, (4, 4))
        p = a @ a.T
        rows = np.zeros((trial % 3, N_COLS))
        for r in rows:
            r[0], r[1] = x[0] + rng.normal(0.0, 0.3 if trial % 5 else 3.0), x[1] + rng.normal(0.0, 0.3)
            r[13], r[14], r[15] = 0.02, 0.03, rng.uniform(2.0, 10.0)
        status = np.array([1, trial % 5], dtype=np.int64)
        threshold = 0.25 if trial % 4 else -1.0
        pose = (rng.uniform(-4, 4), rng.uniform(-3, 3), rng.uniform(-math.pi, math.pi))
        own = (0.033, 1.0, 0.3, 0.01, -0.02, 0.05, rows, 0.05, 0.0, 0.45, 280.0, 0.05, -1.0, 0.6, True, GATE,
               RESTART_AFTER, 1.0)  # fmt: skip
        xr, pr, sr, out_r = x.copy(), p.copy(), status.copy(), np.zeros(3)
        seen = own_frame_nb(xr, pr, sr, *own)
        team = not seen and threshold >= 0.0 and pr[0, 0] + pr[1, 1] > threshold
        ok = not team and publish_nb(xr, pr, True, *pose, *limits, out_r)
        xk, pk, sk, out_k = x.copy(), p.copy(), status.copy(), np.zeros(3)
        flags = frame_nb(xk, pk, sk, *own, threshold, True, *pose, *limits, out_k)
        assert flags == (FRAME_TEAM if team else (FRAME_SEEN if seen else 0) | (FRAME_PUBLISHED if ok else 0))
        assert np.array_equal(xk, xr) and np.array_equal(pk, pr) and np.array_equal(sk, sr)
        assert np.array_equal(out_k, out_r)
        kinds["seen" if seen else "team" if team else "published"] += 1
        kinds["kept out of the team"] += not seen and threshold < 0.0
    assert min(kinds.values()) > 20, kinds
