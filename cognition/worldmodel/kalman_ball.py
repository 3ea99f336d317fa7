"""Kalman ball with adaptive observation noise (Darmstadt paper, Sec. V).

The state is the ball's position and velocity in **robot coordinates** (eq. 7: px, py in m,
vx, vy in m/s; +x forward, +y left), so the estimate does not suffer from errors of the own
pose. The functional core:

* :func:`predict`: the ball rolls with a constant deceleration (rolling friction) and a
  white random acceleration as process noise;
* :func:`move_robot`: the state is carried into the new robot frame with the odometry
  (dx, dy, dtheta in the previous robot frame);
* :func:`camera_measurement`: the measurement and its covariance from one ball percept.
  The ground-projection distance d_p has sd sigma_dp = |h / tan(alpha_p + sigma_alpha) -
  h / tan(alpha_p)| (eq. 8, h the height of the camera above the ball centre, alpha_p the
  depression angle); the size-based distance d_s (from the image radius) is fused with it
  by the optimal gain k = sigma_dp^2 / (sigma_dp^2 + sigma_ds^2) (eqs. 9-11); the lateral sd
  is sigma_y = tan(sigma_beta) d_f (eq. 12); diag(sigma_df^2, sigma_y^2) is rotated by the
  bearing beta_p (eqs. 13-15);
* :func:`update`: the Kalman update with a position (camera) or a full-state (teammate)
  measurement.

The sigmas come from the percept (``adaptive``, the Darmstadt model the camera reports) or
are fixed angles (``fixed``: 5 or 15 degrees in the paper's Table I). The arithmetic is
compiled (numba, explicit small-matrix loops) so that a frame costs a few microseconds.

======================  ========  ==============  ===========================================
KalmanBallParams        default   range           meaning
======================  ========  ==============  ===========================================
rolling_deceleration    1.0       [0, 100]        deceleration of a rolling ball (m/s^2)
accel_sigma             0.3       [0, 100]        process noise: white acceleration (m/s^1.5)
size_sigma_px           0.6       (0, 100]        sd of the ball's image radius (px)
sigma_mode              adaptive                  ``adaptive`` (percept sigmas) or ``fixed``
fixed_sigma             5 deg     (0, pi/2]       angular sd in ``fixed`` mode (rad)
initial_velocity_sigma  1.0       (0, 100]        velocity sd of a newly seen ball (m/s)
team_threshold          0.25      (0, 10000]      own variance (m^2) above which team balls count
sigmas_at_prediction    true      true/false      eqs. 8-12 at the predicted distance
team_inflation          2.0       (0, 1000]       factor on a teammate's covariance
======================  ========  ==============  ===========================================

Every value is checked against its range when the parameters are built
(:func:`cognition.params.check_ranges`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.params import Ranges, check_choice, check_ranges, non_negative, positive

SIGMA_MODES = ("adaptive", "fixed")


@dataclass(frozen=True)
class KalmanBallParams:
    """Tuning of the Kalman ball (m, s, rad)."""

    rolling_deceleration: float = 1.0
    """Deceleration of a rolling ball (m/s^2; the simulator's turf uses 1.0)."""
    accel_sigma: float = 0.3
    """Process noise: a white random acceleration of spectral density accel_sigma^2
    (m^2/s^3), independent of the frame rate; the position variance of an unseen ball grows
    as accel_sigma^2 t^3 / 3 (suspicious after about 2 s, invalid after about 4 s)."""
    size_sigma_px: float = 0.6
    """sd of the ball's measured image radius (px), for the size-based distance."""
    sigma_mode: str = "adaptive"
    """``adaptive``: the percept's own angular sigmas; ``fixed``: ``fixed_sigma`` for both."""
    fixed_sigma: float = math.radians(5.0)
    """Angular sd used in ``fixed`` mode (rad)."""
    initial_velocity_sigma: float = 1.0
    """sd of the velocity of a newly seen ball (m/s)."""
    team_threshold: float = 0.25
    """Own position variance (trace, m^2) above which a teammate's estimate is used."""
    sigmas_at_prediction: bool = True
    """Evaluate eqs. 8-12 at the predicted distance instead of the measured one (once the
    filter runs). With the measured distance, near readings get smaller variances than far
    ones, which biases the fused estimate toward the robot (-0.28 m at 2.7 m in the
    ``ball-noise`` scenario); the paper does not say which it used."""
    team_inflation: float = 2.0
    """Factor on a teammate's covariance (pose errors, timing; Darmstadt V.B)."""

    RANGES: ClassVar[Ranges] = {
        "rolling_deceleration": non_negative(100.0),
        "accel_sigma": non_negative(100.0),
        "size_sigma_px": positive(100.0),
        "fixed_sigma": positive(math.pi / 2),
        "initial_velocity_sigma": positive(100.0),
        "team_threshold": positive(10_000.0),
        "team_inflation": positive(1000.0),
    }

    def __post_init__(self) -> None:
        check_ranges(self)
        check_choice("KalmanBallParams", "sigma_mode", self.sigma_mode, SIGMA_MODES)


@nb.njit(cache=True, error_model="python", fastmath=False)
def _mul(a, b, out):  # pragma: no cover - compiled
    """out = a b for small dense matrices (no BLAS needed)."""
    for i in range(a.shape[0]):
        for j in range(b.shape[1]):
            acc = 0.0
            for k in range(a.shape[1]):
                acc += a[i, k] * b[k, j]
            out[i, j] = acc


@nb.njit(cache=True, error_model="python", fastmath=False)
def _sandwich_into(g, p, t, out):  # pragma: no cover - compiled
    """out = g p g^T, with ``t`` (rows of g x columns of p) as scratch; ``out`` may be ``p``
    itself (p is read only into ``t``), not ``g``."""
    _mul(g, p, t)
    for i in range(g.shape[0]):
        for j in range(g.shape[0]):
            acc = 0.0
            for k in range(t.shape[1]):
                acc += t[i, k] * g[j, k]
            out[i, j] = acc


@nb.njit(cache=True, error_model="python", fastmath=False)
def _sandwich(g, p):  # pragma: no cover - compiled
    """g p g^T."""
    out = np.empty((g.shape[0], g.shape[0]))
    _sandwich_into(g, p, np.empty((g.shape[0], p.shape[1])), out)
    return out


@nb.njit(cache=True, error_model="python", fastmath=False)
def _inverse(a):  # pragma: no cover - compiled
    """Inverse of a small symmetric positive-definite matrix (Gauss-Jordan, partial pivoting)."""
    n = a.shape[0]
    m = a.copy()
    inv = np.eye(n)
    for c in range(n):
        piv = c
        for r in range(c + 1, n):
            if abs(m[r, c]) > abs(m[piv, c]):
                piv = r
        if piv != c:
            for k in range(n):
                m[c, k], m[piv, k] = m[piv, k], m[c, k]
                inv[c, k], inv[piv, k] = inv[piv, k], inv[c, k]
        d = m[c, c]
        for k in range(n):
            m[c, k] /= d
            inv[c, k] /= d
        for r in range(n):
            if r != c:
                f = m[r, c]
                for k in range(n):
                    m[r, k] -= f * m[c, k]
                    inv[r, k] -= f * inv[c, k]
    return inv


@nb.njit(cache=True, error_model="python", fastmath=False)
def _predict_into(x, p, dt, deceleration, accel_sigma, fc, t):  # pragma: no cover - compiled
    """:func:`predict` in place in ``x`` and ``p``; ``fc`` and ``t`` (4 x 4) are scratch."""
    speed = math.sqrt(x[2] * x[2] + x[3] * x[3])
    new_speed = max(0.0, speed - deceleration * dt)
    k = new_speed / speed if speed > 1e-9 else 0.0
    travel = 0.5 * (1.0 + k) * dt  # mean speed over the step times dt, per unit of velocity
    if speed > 1e-9 and new_speed == 0.0:
        travel = 0.5 * speed / max(deceleration, 1e-9)  # it stops within the step
    x[0], x[1], x[2], x[3] = x[0] + travel * x[2], x[1] + travel * x[3], k * x[2], k * x[3]
    for i in range(4):  # friction slows the mean, not the uncertainty: a resting ball may be kicked
        for j in range(4):
            fc[i, j] = 1.0 if i == j else 0.0
    fc[0, 2] = dt
    fc[1, 3] = dt
    _sandwich_into(fc, p, t, p)
    q = accel_sigma * accel_sigma  # continuous white acceleration of spectral density q
    for a in range(2):
        p[a, a] += q * dt**3 / 3.0
        p[a, a + 2] += q * dt**2 / 2.0
        p[a + 2, a] += q * dt**2 / 2.0
        p[a + 2, a + 2] += q * dt


@nb.njit(cache=True, error_model="python", fastmath=False)
def _predict_nb(x, p, dt, deceleration, accel_sigma):  # pragma: no cover - compiled
    xo, po = x.astype(np.float64), p.astype(np.float64)  # copies, float even for integer input
    _predict_into(xo, po, dt, deceleration, accel_sigma, np.empty((4, 4)), np.empty((4, 4)))
    return xo, po


@nb.njit(cache=True, error_model="python", fastmath=False)
def _move_into(x, p, dx, dy, dtheta, g, t):  # pragma: no cover - compiled
    """:func:`move_robot` in place in ``x`` and ``p``; ``g`` and ``t`` (4 x 4) are scratch."""
    c, s = math.cos(dtheta), math.sin(dtheta)
    for i in range(4):
        for j in range(4):
            g[i, j] = 0.0
    g[0, 0] = g[1, 1] = g[2, 2] = g[3, 3] = c  # rotation by -dtheta on both blocks
    g[0, 1] = g[2, 3] = s
    g[1, 0] = g[3, 2] = -s
    px, py = x[0] - dx, x[1] - dy
    x[0], x[1], x[2], x[3] = c * px + s * py, -s * px + c * py, c * x[2] + s * x[3], -s * x[2] + c * x[3]
    _sandwich_into(g, p, t, p)


@nb.njit(cache=True, error_model="python", fastmath=False)
def _move_nb(x, p, dx, dy, dtheta):  # pragma: no cover - compiled
    xo, po = x.astype(np.float64), p.astype(np.float64)  # copies, float even for integer input
    _move_into(xo, po, dx, dy, dtheta, np.empty((4, 4)), np.empty((4, 4)))
    return xo, po


@nb.njit(cache=True, error_model="python", fastmath=False)
def _update_into(x, p, z, r, work):  # pragma: no cover - compiled
    """:func:`update` in place in ``x`` and ``p``; ``work`` (5 x 4 x 4) is scratch."""
    m = z.shape[0]
    s = p[:m, :m] + r  # H p H^T + R with H = [I 0] (m = 2) or I (m = 4)
    si = _inverse(s)
    k = work[0, :, :m]
    _mul(p[:, :m], si, k)  # p H^T s^-1
    innovation = work[1, 0, :m]
    for j in range(m):
        innovation[j] = z[j] - x[j]
    for i in range(4):
        for j in range(m):
            x[i] += k[i, j] * innovation[j]
    ikh = work[2]
    for i in range(4):
        for j in range(4):
            ikh[i, j] = 1.0 if i == j else 0.0
    for i in range(4):
        for j in range(m):
            ikh[i, j] -= k[i, j]
    a, b = work[3], work[4]
    _sandwich_into(ikh, p, work[1], a)  # Joseph form: stays symmetric and positive
    _sandwich_into(k, r, work[1, :, :m], b)
    for i in range(4):
        for j in range(4):
            p[i, j] = 0.5 * ((a[i, j] + b[i, j]) + (a[j, i] + b[j, i]))


@nb.njit(cache=True, error_model="python", fastmath=False)
def _update_nb(x, p, z, r):  # pragma: no cover - compiled
    xo, po = x.astype(np.float64), p.astype(np.float64)  # copies, float even for integer input
    _update_into(xo, po, z, r, np.empty((5, 4, 4)))
    return xo, po


def predict(
    x: NDArray[np.float64], p: NDArray[np.float64], dt: float, deceleration: float, accel_sigma: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Roll the ball for ``dt`` s: speed falls by ``deceleration`` dt (not below 0).

    The mean follows the friction; the covariance is propagated as for constant velocity,
    so that the velocity of a resting ball stays uncertain (it may be kicked any time)."""
    return _predict_nb(x, p, float(dt), float(deceleration), float(accel_sigma))


def move_robot(
    x: NDArray[np.float64], p: NDArray[np.float64], dx: float, dy: float, dtheta: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Express the state in the robot frame after the robot moved by (dx, dy, dtheta)."""
    return _move_nb(x, p, float(dx), float(dy), float(dtheta))


@nb.njit(cache=True, error_model="python", fastmath=False)
def _camera_nb(bx, by, height, sigma_alpha, sigma_beta, size_distance, size_sigma):  # pragma: no cover
    d_p = max(math.sqrt(bx * bx + by * by), 1e-3)
    beta = math.atan2(by, bx)
    alpha = math.atan2(height, d_p)
    sd_p = abs(height / math.tan(alpha + sigma_alpha) - height / math.tan(alpha))  # eq. 8
    d_f, var_f = d_p, sd_p * sd_p
    if math.isfinite(size_distance) and math.isfinite(size_sigma):
        k = var_f / (var_f + size_sigma * size_sigma)  # eq. 9
        d_f = d_p + k * (size_distance - d_p)  # eq. 10
        var_f = (1.0 - k) * var_f  # eq. 11
    sd_y = math.tan(sigma_beta) * d_f  # eq. 12
    c, s = math.cos(beta), math.sin(beta)  # eq. 14
    vy = sd_y * sd_y
    r = np.array(
        [[c * c * var_f + s * s * vy, c * s * (var_f - vy)], [c * s * (var_f - vy), s * s * var_f + c * c * vy]]
    )
    return np.array([d_f * c, d_f * s]), r  # eqs. 13, 15


def camera_measurement(
    bx: float,
    by: float,
    height: float,
    sigma_alpha: float,
    sigma_beta: float,
    size_distance: float | None = None,
    size_sigma: float = math.inf,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Measurement (ball position, robot frame) and its 2 x 2 covariance (Darmstadt eqs. 8-15).

    ``(bx, by)``: the percept's ground position (m); ``height``: camera height above the ball
    centre (m); ``sigma_alpha``, ``sigma_beta``: angular sds (rad); ``size_distance``: the
    size-based ground distance (m) with sd ``size_sigma``, or ``None``.
    """
    d_s = math.nan if size_distance is None else float(size_distance)
    return _camera_nb(
        float(bx), float(by), float(height), float(sigma_alpha), float(sigma_beta), d_s, float(size_sigma)
    )


def update(
    x: NDArray[np.float64], p: NDArray[np.float64], z: NDArray[np.float64], r: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Kalman update with a position (2) or a full-state (4) measurement ``z`` of covariance ``r``."""
    if z.shape[0] not in (2, 4) or r.shape != (z.shape[0], z.shape[0]):
        raise ValueError(f"measurement must have 2 or 4 entries with a matching covariance, got {z.shape}, {r.shape}")
    return _update_nb(
        np.ascontiguousarray(x, dtype=np.float64), np.ascontiguousarray(p, dtype=np.float64),
        np.ascontiguousarray(z, dtype=np.float64), np.ascontiguousarray(r, dtype=np.float64),
    )  # fmt: skip


def size_distance(radius_px: float, focal_px: float, ball_radius: float, height: float) -> tuple[float, float]:
    """Ground distance (m) from the ball's image radius and its sd for ``size_sigma_px`` = 1.

    The pinhole relation gives the distance D from the optical centre, D = r sqrt(1 + (f /
    rho)^2); the ground distance is sqrt(D^2 - height^2). Multiply the returned sd by the
    radius sd in pixels.
    """
    return _size_nb(float(radius_px), float(focal_px), float(ball_radius), float(height))


@nb.njit(cache=True, error_model="python", fastmath=False)
def _size_nb(radius_px, focal_px, ball_radius, height):  # pragma: no cover - compiled
    if not radius_px > 0.0:
        return math.nan, math.inf
    big_d = ball_radius * math.sqrt(1.0 + (focal_px / radius_px) ** 2)
    d = math.sqrt(max(big_d * big_d - height * height, 1e-6))
    sd_big = big_d / radius_px  # dD / drho for one pixel
    return d, sd_big * big_d / d


@nb.njit(cache=True, error_model="python", fastmath=False)
def predict_move_nb(x, p, dt, deceleration, accel_sigma, dx, dy, dtheta):  # pragma: no cover - compiled
    """:func:`predict` then :func:`move_robot` in one call."""
    xo, po = x.astype(np.float64), p.astype(np.float64)  # copies, float even for integer input
    g, t = np.empty((4, 4)), np.empty((4, 4))
    _predict_into(xo, po, dt, deceleration, accel_sigma, g, t)
    _move_into(xo, po, dx, dy, dtheta, g, t)
    return xo, po


@nb.njit(cache=True, error_model="python", fastmath=False)
def measure_rows_nb(
    rows, foot_x, foot_y, height, focal, ball_radius, fixed_sigma, size_sigma_px, use_prediction, pred_x, pred_y
):  # pragma: no cover - compiled
    """Measurements (K x 2) and covariances (K x 2 x 2), robot frame, of ball percept rows.

    Distances are taken from the camera's foot (``foot_x``, ``foot_y``); ``fixed_sigma`` > 0
    replaces the percepts' angular sigmas; with ``use_prediction`` eqs. 8-12 are evaluated
    at the predicted position (``pred_x``, ``pred_y``) instead of the measured one.
    """
    k = rows.shape[0]
    zs = np.empty((k, 2))
    rs = np.empty((k, 2, 2))
    for i in range(k):
        sa = fixed_sigma if fixed_sigma > 0.0 else rows[i, 13]
        sb = fixed_sigma if fixed_sigma > 0.0 else rows[i, 14]
        d_s, sd_s = _size_nb(rows[i, 15], focal, ball_radius, height)
        bx, by = rows[i, 0] - foot_x, rows[i, 1] - foot_y
        z, r = _camera_nb(bx, by, height, sa, sb, d_s, sd_s * size_sigma_px)
        if use_prediction:
            px, py = pred_x - foot_x, pred_y - foot_y
            d_pred = max(math.sqrt(px * px + py * py), 1e-3)
            rho = focal * ball_radius / math.sqrt(max(d_pred * d_pred + height * height - ball_radius**2, 1e-6))
            _, sd_pred = _size_nb(rho, focal, ball_radius, height)
            beta = math.atan2(z[1], z[0])
            _, r = _camera_nb(d_pred * math.cos(beta), d_pred * math.sin(beta), height, sa, sb, d_pred,
                              sd_pred * size_sigma_px)  # fmt: skip
        zs[i, 0], zs[i, 1] = z[0] + foot_x, z[1] + foot_y
        rs[i] = r
    return zs, rs


@nb.njit(cache=True, error_model="python", fastmath=False)
def _nearest(x, p, zs, rs):  # pragma: no cover - compiled
    """Index of the measurement (of ``zs``, ``rs``) nearest to the prediction by Mahalanobis
    distance, and that distance squared (1e300 without measurements)."""
    best, best_m2 = 0, 1e300
    for i in range(zs.shape[0]):
        ex, ey = zs[i, 0] - x[0], zs[i, 1] - x[1]
        a, b, d = p[0, 0] + rs[i, 0, 0], p[0, 1] + rs[i, 0, 1], p[1, 1] + rs[i, 1, 1]
        m2 = (d * ex * ex - 2.0 * b * ex * ey + a * ey * ey) / max(a * d - b * b, 1e-18)
        if m2 < best_m2:
            best, best_m2 = i, m2
    return best, best_m2


@nb.njit(cache=True, error_model="python", fastmath=False)
def gated_update_nb(x, p, zs, rs, gate):  # pragma: no cover - compiled
    """Update with the measurement (of ``zs``, ``rs``) nearest to the prediction by Mahalanobis
    distance, if that distance squared is at most ``gate``. Returns (x, p, updated, best index)."""
    best, best_m2 = _nearest(x, p, zs, rs)
    if best_m2 > gate:
        return x, p, False, best
    xo, po = _update_nb(x, p, zs[best].copy(), rs[best].copy())
    return xo, po, True, best


@nb.njit(cache=True, error_model="python", fastmath=False)
def _start_nb(x, p, z, r, velocity_var):  # pragma: no cover - compiled
    """A new state at measurement ``z`` (2) with covariance ``r`` (2 x 2), at rest with
    velocity variance ``velocity_var``, into ``x`` and ``p``."""
    x[0], x[1], x[2], x[3] = z[0], z[1], 0.0, 0.0
    for i in range(4):
        for j in range(4):
            p[i, j] = 0.0
    for i in range(2):
        for j in range(2):
            p[i, j] = r[i, j]
    p[2, 2] = p[3, 3] = velocity_var


@nb.njit(cache=True, error_model="python", fastmath=False)
def own_frame_nb(
    x,
    p,
    status,
    dt,
    deceleration,
    accel_sigma,
    dx,
    dy,
    dtheta,
    rows,
    foot_x,
    foot_y,
    height,
    focal,
    ball_radius,
    fixed_sigma,
    size_sigma_px,
    sigmas_at_prediction,
    gate,
    restart_after,
    velocity_var,
):  # pragma: no cover - compiled
    """One frame of a robot's own ball sensing in one call, state ``x`` (4) and ``p`` (4 x 4)
    updated in place; ``status`` holds (1 if there is a state, consecutive rejected percepts).

    With a state: :func:`predict_move_nb` over ``dt`` s and the odometry. Then, given ball
    percept ``rows`` (possibly none): :func:`measure_rows_nb` (at the prediction when
    ``sigmas_at_prediction``), and a new state at the first percept if there was none, else
    :func:`gated_update_nb`; ``restart_after`` rejections in a row restart the state at the
    latest best percept. Returns True when a percept updated or started the state.
    """
    has = status[0] == 1
    work = np.empty((5, 4, 4))  # scratch of the steps below, which work in place
    if has:  # predict_move_nb
        _predict_into(x, p, dt, deceleration, accel_sigma, work[0], work[1])
        _move_into(x, p, dx, dy, dtheta, work[0], work[1])
    if rows.shape[0] == 0:
        return False
    zs, rs = measure_rows_nb(
        rows, foot_x, foot_y, height, focal, ball_radius, fixed_sigma, size_sigma_px, has and sigmas_at_prediction,
        x[0] if has else 0.0, x[1] if has else 0.0,
    )  # fmt: skip
    if not has:
        _start_nb(x, p, zs[0], rs[0], velocity_var)
        status[0] = 1
        return True
    best, best_m2 = _nearest(x, p, zs, rs)  # gated_update_nb
    if not best_m2 > gate:
        _update_into(x, p, zs[best], rs[best], work)
        status[1] = 0
        return True
    status[1] += 1  # an outlier, or the ball was moved: restart after restart_after in a row
    if status[1] >= restart_after:
        status[1] = 0
        _start_nb(x, p, zs[best], rs[best], velocity_var)
        return True
    return False


@nb.njit(cache=True, error_model="python", fastmath=False)
def publish_nb(x, p, has_pose, px, py, pth, lim_x, lim_y, out):  # pragma: no cover - compiled
    """The end of a frame of :class:`cognition.worldmodel.ball.KalmanBallModel` in one call.

    With a pose (``has_pose``; ``px``, ``py`` m and ``pth`` rad, team frame) and limits
    (``lim_x``, ``lim_y`` > 0, m): a state whose field position lies beyond them is put back on
    the limit and loses its velocity across it, in place in ``x`` (robot frame). Then, if every
    entry of ``x`` and ``p`` is finite, ``out`` receives the position sd (m, the root of half
    the trace of the position block, at least 0) and the field position (x, y, team frame; NaN
    without a pose), and the call returns True; a non-finite state returns False.
    """
    if has_pose and lim_x > 0.0:
        c, s = math.cos(pth), math.sin(pth)
        fx, fy = px + c * x[0] - s * x[1], py + s * x[0] + c * x[1]
        if math.isfinite(fx) and math.isfinite(fy) and not (abs(fx) <= lim_x and abs(fy) <= lim_y):
            vx, vy = c * x[2] - s * x[3], s * x[2] + c * x[3]  # field frame
            if abs(fx) > lim_x:
                fx, vx = math.copysign(lim_x, fx), 0.0
            if abs(fy) > lim_y:
                fy, vy = math.copysign(lim_y, fy), 0.0
            dx, dy = fx - px, fy - py
            x[0], x[1], x[2], x[3] = c * dx + s * dy, -s * dx + c * dy, c * vx + s * vy, -s * vx + c * vy
    total = 0.0
    for i in range(4):
        total += x[i]
    for i in range(4):
        for j in range(4):
            total += p[i, j]
    if not math.isfinite(total):
        return False
    out[0] = math.sqrt(max(0.0, 0.5 * (p[0, 0] + p[1, 1])))
    out[1] = out[2] = math.nan
    if has_pose:
        c, s = math.cos(pth), math.sin(pth)
        out[1] = px + c * x[0] - s * x[1]
        out[2] = py + s * x[0] + c * x[1]
    return True


FRAME_SEEN = 1
"""A :func:`frame_nb` flag: a percept updated or started the state."""
FRAME_TEAM = 2
"""A :func:`frame_nb` flag: not published, a teammate's ball is to be used first."""
FRAME_PUBLISHED = 4
"""A :func:`frame_nb` flag: the state was published (finite); without it, and without
``FRAME_TEAM``, the state is no longer finite."""


@nb.njit(cache=True, error_model="python", fastmath=False)
def frame_nb(
    x,
    p,
    status,
    dt,
    deceleration,
    accel_sigma,
    dx,
    dy,
    dtheta,
    rows,
    foot_x,
    foot_y,
    height,
    focal,
    ball_radius,
    fixed_sigma,
    size_sigma_px,
    sigmas_at_prediction,
    gate,
    restart_after,
    velocity_var,
    team_threshold,
    has_pose,
    px,
    py,
    pth,
    lim_x,
    lim_y,
    out,
):  # pragma: no cover - compiled
    """A frame of :class:`cognition.worldmodel.ball.KalmanBallModel` with a state or a percept in
    one call: :func:`own_frame_nb` (the arguments up to ``velocity_var``), then
    :func:`publish_nb` (``has_pose`` to ``out``), unless no percept updated the state, a
    teammate's ball may be used (``team_threshold`` >= 0, m^2) and the position variance (trace
    of the position block, m^2) exceeds ``team_threshold``: then it returns :data:`FRAME_TEAM`
    alone and the caller updates from the teammates before it publishes. Otherwise it returns
    :data:`FRAME_SEEN` if a percept updated or started the state, plus
    :data:`FRAME_PUBLISHED` if the state was finite and published."""
    seen = own_frame_nb(
        x, p, status, dt, deceleration, accel_sigma, dx, dy, dtheta, rows, foot_x, foot_y, height, focal, ball_radius,
        fixed_sigma, size_sigma_px, sigmas_at_prediction, gate, restart_after, velocity_var,
    )  # fmt: skip
    if not seen and team_threshold >= 0.0 and p[0, 0] + p[1, 1] > team_threshold:
        return FRAME_TEAM
    flags = FRAME_SEEN if seen else 0
    if publish_nb(x, p, has_pose, px, py, pth, lim_x, lim_y, out):
        flags |= FRAME_PUBLISHED
    return flags
