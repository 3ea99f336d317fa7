"""Study metrics on hand-made trajectories: a known recovery time is measured to the frame, a
censored run is censored, the mirror-aware form accepts the mirrored pose, per-run figures."""

from __future__ import annotations

import math

import numpy as np
import pytest

from scenarios.metrics import event_rows, recovery_time, run_row
from scenarios.store import EVENT_COLUMNS, RUN_COLUMNS
from scenarios.trace import TRACE_COLUMNS, Trace

HZ = 30.0


def _trace(errors: list[tuple[float, float, float]], duration: float, log=(), timeline=(), mirror_from=None) -> Trace:
    """A one-robot trace at 30 Hz: true pose fixed at (1, 0.5, 0.2); ``errors`` are (from time s,
    position error m along x, heading error rad) pieces; ``mirror_from``: estimate at the mirrored pose."""
    n = round(duration * HZ) + 1
    t = np.arange(n) / HZ
    table = np.zeros((n, len(TRACE_COLUMNS)))
    col = {c: i for i, c in enumerate(TRACE_COLUMNS)}
    table[:, col["time"]] = t
    table[:, col["number"]] = 1
    table[:, col["true_x"]], table[:, col["true_y"]], table[:, col["true_theta"]] = 1.0, 0.5, 0.2
    ex = np.full(n, 1.0)
    eth = np.full(n, 0.2)
    for start, dx, dth in errors:
        ex[t >= start - 1e-9] = 1.0 + dx
        eth[t >= start - 1e-9] = 0.2 + dth
    table[:, col["est_x"]], table[:, col["est_y"]], table[:, col["est_theta"]] = ex, 0.5, eth
    if mirror_from is not None:
        m = t >= mirror_from - 1e-9
        table[m, col["est_x"]], table[m, col["est_y"]], table[m, col["est_theta"]] = -1.0, -0.5, 0.2 - math.pi
    table[:, col["ball_est_x"]] = np.nan
    table[:, col["ball_est_y"]] = np.nan
    table[:, col["loc_cpu_us"]] = 100.0
    meta = {
        "scenario": "hand", "digest": "x", "variant": "v", "seed": 7, "duration": duration,
        "recovery": {"error_m": 0.5, "error_deg": 30.0, "hold_s": 1.0},
        "metrics": ["localization", "recovery", "ball", "goals"], "traced": [1],
        "timeline": list(timeline), "log": list(log), "score": [0, 0],
    }  # fmt: skip
    return Trace(table, meta)


def _kidnap(time: float) -> tuple[dict, dict]:
    ev = {"kind": "Kidnap", "time": time, "team": 0, "number": 1, "pose": [1.0, 0.5, 0.2], "sense_pickup": False}
    log = {"time": time, "kind": "kidnap", "team": 0, "number": 1, "x": 1.0, "y": 0.5, "theta": 0.2}
    return ev, log


def test_recovery_time_is_measured_to_the_frame():
    t = np.arange(0, 601) / HZ  # 0 .. 20 s
    good = t >= 7.0 + 11 / HZ  # good from frame 221 on
    secs, ok = recovery_time(t, good, 5.0, 15.0, 1.0)
    assert ok and secs == pytest.approx(2.0 + 11 / HZ, abs=1e-9)
    # a good stretch shorter than the hold does not count
    good2 = good.copy()
    good2[(t >= 6.0) & (t < 6.9)] = True
    assert recovery_time(t, good2, 5.0, 15.0, 1.0) == (pytest.approx(2.0 + 11 / HZ), True)
    # good only when too little of the horizon is left to hold it: censored at the horizon
    late = t >= 19.5
    assert recovery_time(t, late, 5.0, 15.0, 1.0) == (15.0, False)
    assert recovery_time(t, np.zeros_like(late), 5.0, 10.0, 1.0) == (10.0, False)


def test_a_kidnap_row_from_a_hand_made_trajectory():
    ev, log = _kidnap(8.0)
    # error 0.05 m before, 2 m and 90 deg after the kidnap, 0.2 m / 10 deg from 13.5 s on
    tr = _trace([(8.0, 2.0, math.pi / 2), (13.5, 0.2, math.radians(10))], 30.0, log=[log], timeline=[ev])
    tr.table[tr.column("time") < 8.0, TRACE_COLUMNS.index("est_x")] = 1.05
    (row,) = event_rows(tr)
    assert set(row) == set(EVENT_COLUMNS)
    assert row["kind"] == "kidnap" and row["event"] == 0 and row["time_s"] == 8.0 and row["start_s"] == 8.0
    assert row["horizon_s"] == pytest.approx(22.0)
    assert row["relocalized"] == 1 and row["relocalize_s"] == pytest.approx(5.5, abs=1e-9)
    assert row["relocalize_sym_s"] == pytest.approx(5.5, abs=1e-9)
    assert row["error_before_m"] == pytest.approx(0.05) and row["error_after_m"] == pytest.approx(2.0)
    assert math.isnan(row["penalty_s"]) and math.isnan(row["back_in_play_s"])


def test_a_robot_that_stays_lost_is_censored_at_the_next_event():
    (ev1, log1), (ev2, log2) = _kidnap(5.0), _kidnap(12.0)
    tr = _trace([(5.0, 3.0, 0.0), (14.5, 0.0, 0.0)], 20.0, log=[log1, log2], timeline=[ev1, ev2])
    first, second = event_rows(tr)
    assert first["relocalized"] == 0 and first["horizon_s"] == pytest.approx(7.0)
    assert first["relocalize_s"] == pytest.approx(7.0)  # censored: the horizon, not a recovery
    assert second["relocalized"] == 1 and second["relocalize_s"] == pytest.approx(2.5, abs=1e-9)


def test_the_mirrored_pose_counts_only_in_the_mirror_aware_form():
    ev, log = _kidnap(4.0)
    tr = _trace([], 20.0, log=[log], timeline=[ev], mirror_from=4.0)
    (row,) = event_rows(tr)
    assert row["relocalized"] == 0 and row["relocalize_s"] == pytest.approx(16.0)
    assert row["relocalized_sym"] == 1 and row["relocalize_sym_s"] == pytest.approx(0.0)
    run = run_row(tr)
    assert run["mirror_flips"] == 1
    assert run["mirror_share"] == pytest.approx(np.mean(tr.column("time") >= 4.0 - 1e-9))


def test_a_penalty_clock_starts_at_the_return_and_counts_goals_short_handed():
    ev = {"kind": "ForcePenalty", "time": 5.0, "team": 0, "number": 1, "code": 5}
    log = [
        {"time": 5.0, "kind": "penalty", "team": 0, "number": 1, "code": "ILLEGAL_POSITION", "reason": "script"},
        {"time": 9.0, "kind": "goal", "team": 1, "score": [0, 1]},
        {"time": 50.0, "kind": "unpenalized", "team": 0, "number": 1, "x": 0.0, "y": 3.0},
        {"time": 55.0, "kind": "goal", "team": 1, "score": [0, 2]},
    ]
    tr = _trace([(50.0, 1.5, 0.0), (53.0, 0.1, 0.0)], 80.0, log=log, timeline=[ev])
    pen = (tr.column("time") >= 5.0) & (tr.column("time") < 50.0)
    tr.table[pen, TRACE_COLUMNS.index("penalized")] = 1.0
    tr.table[pen, TRACE_COLUMNS.index("est_x")] = 40.0  # whatever it believes while out does not count
    (row,) = event_rows(tr)
    assert row["detail"] == "illegal_position" and row["penalty_s"] == pytest.approx(45.0)
    assert row["start_s"] == pytest.approx(50.0) and row["horizon_s"] == pytest.approx(30.0)
    assert row["relocalize_s"] == pytest.approx(3.0, abs=1e-9) and row["back_in_play_s"] == pytest.approx(48.0)
    assert row["goals_conceded_short"] == 1
    assert row["error_before_m"] == pytest.approx(0.0) and row["error_after_m"] == pytest.approx(1.5)
    run = run_row(tr)
    on = ~pen
    assert run["frames"] == tr.table.shape[0]
    d = np.abs(tr.column("est_x") - 1.0)[on]
    assert run["pos_rmse_m"] == pytest.approx(math.sqrt(np.mean(d**2)))  # penalised frames left out
    assert run["goals_for"] == 0 and run["goals_against"] == 2


def test_run_row_figures_on_a_known_error_profile():
    tr = _trace([(0.0, 0.3, math.radians(20)), (10.0, 0.6, math.radians(40))], 20.0)
    row = run_row(tr)
    assert set(row) == set(RUN_COLUMNS)
    n = tr.table.shape[0]
    late = np.count_nonzero(tr.column("time") >= 10.0 - 1e-9)
    assert row["share_over_0_5m"] == pytest.approx(late / n)
    assert row["share_over_30deg"] == pytest.approx(late / n)
    assert row["pos_rmse_m"] == pytest.approx(math.sqrt((0.09 * (n - late) + 0.36 * late) / n))
    assert row["pos_p90_m"] == pytest.approx(0.6)
    assert row["heading_rmse_deg"] == pytest.approx(math.sqrt((400 * (n - late) + 1600 * late) / n))
    assert row["mirror_flips"] == 0 and row["loc_cpu_us"] == pytest.approx(100.0)
    assert math.isnan(row["ball_rmse_m"]) and row["ball_frames"] == 0
