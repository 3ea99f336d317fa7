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
are fixed angles (``fixed``: 5 or 15 degrees in the paper's Table I).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from cognition.params import check_choice, check_non_negative, check_positive

SIGMA_MODES = ("adaptive", "fixed")
_I4 = np.eye(4)
_H = np.hstack([np.eye(2), np.zeros((2, 2))])


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
    team_inflation: float = 2.0
    """Factor on a teammate's covariance (pose errors, timing; Darmstadt V.B)."""

    def __post_init__(self) -> None:
        o = "KalmanBallParams"
        check_positive(o, size_sigma_px=self.size_sigma_px, fixed_sigma=self.fixed_sigma,
                       initial_velocity_sigma=self.initial_velocity_sigma, team_threshold=self.team_threshold,
                       team_inflation=self.team_inflation)  # fmt: skip
        check_non_negative(o, rolling_deceleration=self.rolling_deceleration, accel_sigma=self.accel_sigma)
        check_choice(o, "sigma_mode", self.sigma_mode, SIGMA_MODES)


def predict(
    x: NDArray[np.float64], p: NDArray[np.float64], dt: float, deceleration: float, accel_sigma: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Roll the ball for ``dt`` s: speed falls by ``deceleration`` dt (not below 0).

    The mean follows the friction; the covariance is propagated as for constant velocity,
    so that the velocity of a resting ball stays uncertain (it may be kicked any time)."""
    speed = math.hypot(x[2], x[3])
    new_speed = max(0.0, speed - deceleration * dt)
    k = new_speed / speed if speed > 1e-9 else 0.0
    travel = 0.5 * (1.0 + k) * dt  # mean speed over the step times dt, per unit of velocity
    if speed > 1e-9 and new_speed == 0.0:
        travel = 0.5 * speed / max(deceleration, 1e-9)  # it stops within the step
    f = np.eye(4)
    f[0, 2] = f[1, 3] = travel
    f[2, 2] = f[3, 3] = k
    fc = np.eye(4)  # friction slows the mean, not the uncertainty: a resting ball may be kicked
    fc[0, 2] = fc[1, 3] = dt
    q = np.zeros((4, 4))  # continuous white acceleration of spectral density accel_sigma^2
    q[0, 0] = q[1, 1] = dt**3 / 3.0
    q[0, 2] = q[2, 0] = q[1, 3] = q[3, 1] = dt**2 / 2.0
    q[2, 2] = q[3, 3] = dt
    return f @ x, fc @ p @ fc.T + (accel_sigma**2) * q


def move_robot(
    x: NDArray[np.float64], p: NDArray[np.float64], dx: float, dy: float, dtheta: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Express the state in the robot frame after the robot moved by (dx, dy, dtheta)."""
    c, s = math.cos(dtheta), math.sin(dtheta)
    r = np.array([[c, s], [-s, c]])  # rotation by -dtheta
    g = np.zeros((4, 4))
    g[:2, :2] = g[2:, 2:] = r
    out = x.copy()
    out[:2] = r @ (x[:2] - np.array([dx, dy]))
    out[2:] = r @ x[2:]
    return out, g @ p @ g.T


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
    d_p = max(math.hypot(bx, by), 1e-3)
    beta = math.atan2(by, bx)
    alpha = math.atan2(height, d_p)
    sd_p = abs(height / math.tan(alpha + sigma_alpha) - height / math.tan(alpha))  # eq. 8
    d_f, var_f = d_p, sd_p * sd_p
    if size_distance is not None and math.isfinite(size_distance) and math.isfinite(size_sigma):
        k = var_f / (var_f + size_sigma * size_sigma)  # eq. 9
        d_f = d_p + k * (size_distance - d_p)  # eq. 10
        var_f = (1.0 - k) * var_f  # eq. 11
    sd_y = math.tan(sigma_beta) * d_f  # eq. 12
    m = np.array([[math.cos(beta), -math.sin(beta)], [math.sin(beta), math.cos(beta)]])  # eq. 14
    r = m @ np.diag([var_f, sd_y * sd_y]) @ m.T  # eqs. 13, 15
    return np.array([d_f * math.cos(beta), d_f * math.sin(beta)]), r


def update(
    x: NDArray[np.float64], p: NDArray[np.float64], z: NDArray[np.float64], r: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Kalman update with a position (2) or a full-state (4) measurement ``z`` of covariance ``r``."""
    h = _H if z.shape[0] == 2 else _I4
    s = h @ p @ h.T + r
    k = np.linalg.solve(s.T, (p @ h.T).T).T  # p h^T s^-1
    x_new = x + k @ (z - h @ x)
    i_kh = _I4 - k @ h
    p_new = i_kh @ p @ i_kh.T + k @ r @ k.T  # Joseph form: stays symmetric and positive
    return x_new, 0.5 * (p_new + p_new.T)


def size_distance(radius_px: float, focal_px: float, ball_radius: float, height: float) -> tuple[float, float]:
    """Ground distance (m) from the ball's image radius and its sd for ``size_sigma_px`` = 1.

    The pinhole relation gives the distance D from the optical centre, D = r sqrt(1 + (f /
    rho)^2); the ground distance is sqrt(D^2 - height^2). Multiply the returned sd by the
    radius sd in pixels.
    """
    if not radius_px > 0.0:
        return math.nan, math.inf
    big_d = ball_radius * math.sqrt(1.0 + (focal_px / radius_px) ** 2)
    d = math.sqrt(max(big_d * big_d - height * height, 1e-6))
    sd_big = big_d / radius_px  # dD / drho for one pixel
    return d, sd_big * big_d / d
