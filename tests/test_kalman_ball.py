"""Kalman ball core (Darmstadt V): rolling friction, odometry, eqs. 8-15, consistent updates."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from cognition.worldmodel.kalman_ball import (
    KalmanBallParams,
    camera_measurement,
    move_robot,
    predict,
    size_distance,
    update,
)


def test_a_rolling_ball_stops_after_v_squared_over_2a():
    x, p = np.array([0.0, 0.0, 2.0, 0.0]), np.eye(4) * 1e-4
    dt = 1 / 30
    for _ in range(int(1.0 / dt)):
        x, p = predict(x, p, dt, 1.0, 0.5)
    assert abs(x[2] - 1.0) < 1e-9 and abs(x[0] - 1.5) < 1e-6  # 1 s at mean speed 1.5 m/s
    for _ in range(200):
        x, p = predict(x, p, dt, 1.0, 0.5)
    assert x[2] == 0.0 and abs(x[0] - 2.0) < 1e-6  # stopped after v^2 / (2 a) = 2 m
    assert p[0, 0] > 1e-4 and np.all(np.linalg.eigvalsh(p) > 0)  # uncertainty grew


def test_moving_the_robot_moves_the_ball_the_other_way():
    x = np.array([1.0, 0.0, 0.5, 0.0])
    p = np.diag([0.04, 0.01, 0.2, 0.1])
    y, q = move_robot(x, p, 0.0, 0.0, math.pi / 2)  # robot turns left by 90 degrees
    assert np.allclose(y, [0.0, -1.0, 0.0, -0.5])
    assert np.isclose(q[1, 1], 0.04) and np.isclose(q[0, 0], 0.01) and np.isclose(np.trace(q), np.trace(p))
    y, _ = move_robot(x, p, 0.4, 0.1, 0.0)
    assert np.allclose(y[:2], [0.6, -0.1]) and np.allclose(y[2:], x[2:])


def test_projection_sigma_grows_with_distance_and_fusion_never_hurts():
    sig = math.radians(2.0)
    radial = []
    for d in (0.5, 1.0, 2.0, 4.0, 6.0):
        _, r = camera_measurement(d, 0.0, 0.45, sig, sig)
        radial.append(r[0, 0])
        _, rf = camera_measurement(d, 0.0, 0.45, sig, sig, size_distance=d, size_sigma=0.1 * d)
        assert rf[0, 0] <= min(r[0, 0], (0.1 * d) ** 2) + 1e-12  # eq. 11: (1 - k) var_p
        assert np.isclose(rf[1, 1], (math.tan(sig) * d) ** 2)  # eq. 12, lateral
    assert all(a < b for a, b in itertools.pairwise(radial))
    # eq. 8 by hand at 2 m
    a = math.atan2(0.45, 2.0)
    _, r = camera_measurement(2.0, 0.0, 0.45, sig, sig)
    assert np.isclose(math.sqrt(r[0, 0]), abs(0.45 / math.tan(a + sig) - 0.45 / math.tan(a)))


def test_covariance_is_rotated_by_the_bearing():
    sig_a, sig_b = math.radians(3.0), math.radians(0.5)
    z, r = camera_measurement(0.0, 3.0, 0.45, sig_a, sig_b)  # ball to the left
    assert np.allclose(z, [0.0, 3.0])
    w, v = np.linalg.eigh(r)
    major = v[:, np.argmax(w)]
    assert abs(abs(major[1]) - 1.0) < 1e-9  # the distance uncertainty points along the bearing
    z, r = camera_measurement(2.0, 2.0, 0.45, sig_a, sig_b)
    w, v = np.linalg.eigh(r)
    major = v[:, np.argmax(w)]
    assert abs(abs(major @ np.array([1.0, 1.0]) / math.sqrt(2)) - 1.0) < 1e-9


def test_updates_are_consistent_and_beat_single_percepts():
    """Measurements drawn from N(truth, R) with R from eqs. 8-15: the normalised error
    squared (NEES) of the position averages 2 (two dimensions), and the filtered error is
    well below the error of one percept."""
    rng = np.random.default_rng(0)
    h, sig_a, sig_b = 0.45, math.radians(2.0), math.radians(2.0)
    nees, filtered, single = [], [], []
    for _ in range(400):
        truth = np.array([rng.uniform(0.5, 4.0), rng.uniform(-1.5, 1.5)])
        _, r = camera_measurement(truth[0], truth[1], h, sig_a, sig_b)
        chol = np.linalg.cholesky(r)
        x = p = None
        for k in range(20):
            z = truth + chol @ rng.standard_normal(2)
            if k == 0:
                single.append(float(np.hypot(*(z - truth))))
                x, p = np.r_[z, 0.0, 0.0], np.diag([10.0, 10.0, 1e-6, 1e-6])
            else:
                x, p = predict(x, p, 1 / 30, 1.0, 0.0)
            x, p = update(x, p, z, r)
        e = x[:2] - truth
        nees.append(float(e @ np.linalg.solve(p[:2, :2], e)))
        filtered.append(float(np.hypot(*e)))
    assert 1.7 < np.mean(nees) < 2.3, np.mean(nees)
    assert np.mean(filtered) < 0.35 * np.mean(single)


def test_full_state_update_from_a_teammate_pulls_velocity():
    x, p = np.array([1.0, 0.0, 0.0, 0.0]), np.diag([1.0, 1.0, 4.0, 4.0])
    z, r = np.array([1.2, 0.1, 1.0, -0.5]), np.diag([0.01, 0.01, 0.04, 0.04])
    y, q = update(x, p, z, r)
    assert np.allclose(y, z, atol=0.02) and np.all(np.diag(q) < np.diag(r) + 1e-12)


def test_size_distance_inverts_the_pinhole_radius():
    f, rad, h = 560.0, 0.05, 0.45
    for d in (0.5, 2.0, 5.0):
        big_d = math.hypot(d, h)
        rho = f * rad / math.sqrt(big_d**2 - rad**2)
        est, sd = size_distance(rho, f, rad, h)
        assert abs(est - d) < 1e-3 * d and sd > 0
    assert math.isnan(size_distance(0.0, f, rad, h)[0])


def test_bad_parameters_are_clear_errors():
    with pytest.raises(ValueError, match="sigma_mode"):
        KalmanBallParams(sigma_mode="magic")
    with pytest.raises(ValueError, match="fixed_sigma"):
        KalmanBallParams(fixed_sigma=0.0)
