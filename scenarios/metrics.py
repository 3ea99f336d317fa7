"""Metrics of a run, computed from its trace (:mod:`scenarios.trace`), never by the brains.

**Relocalized** (CMU and Darmstadt kidnapping experiments): the position error is below
``recovery.error_m`` (0.5 m) and the heading error below ``recovery.error_deg`` (30 degrees) in
every traced frame for ``recovery.hold_s`` (1 s). The *mirror-aware* form also accepts the
mirrored pose (-x, -y, theta + pi): with goals of one colour nothing tells a kidnapped robot
which half it is in. The time to relocalize is measured from the event (a penalised robot: from
its return to the field) to the first frame of the first such stretch, to the frame; a robot
that does not relocalize before its next event or the end of the run is **censored** at that
horizon (``relocalized = 0``, ``relocalize_s = horizon_s``), and reports must treat it as such
(Kaplan-Meier, :mod:`scenarios.report`).

Per run (frames of the traced robots while on the field, neither penalised nor carried):
position and heading RMSE and 90th percentile, share of frames over the recovery bounds, flips
to the mirrored pose (the estimate enters the state "nearer the mirrored pose and off the true
one by more than ``error_m``"), share of frames in that state, share flagged lost, ball RMSE
(team frame; frames after the ball was first estimated, leaving out 0.5 s after each scripted
ball placement, as in the Darmstadt paper's Table I set-up), goals, and the mean CPU time of a
localization update.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from scenarios.trace import Trace

BALL_SETTLE_S = 0.5
"""Seconds after a scripted ball placement that the ball RMSE leaves out (a real kick does not teleport the ball)."""
_ROBOT_EVENTS = {"Kidnap": "kidnap", "ForcePenalty": "penalty", "ForceFall": "fall"}
_LOG_KIND = {"kidnap": "kidnap", "penalty": "penalty", "fall": "forced_fall"}


def recovery_time(
    times: NDArray[np.float64], good: NDArray[np.bool_], start: float, horizon: float, hold: float
) -> tuple[float, bool]:
    """Seconds from ``start`` until ``good`` holds for ``hold`` seconds, and whether that happened
    within ``horizon`` seconds of ``start``; (``horizon``, False) when censored.

    ``times`` are the frame times (s, increasing). A stretch counts once its frames cover
    ``hold`` seconds; it must start at or after ``start`` and be complete by ``start + horizon``.
    """
    end = start + horizon
    sel = (times >= start - 1e-9) & (times <= end + 1e-9)
    t, g = times[sel], good[sel]
    run_start = -1
    for i in range(t.size):
        if not g[i]:
            run_start = -1
            continue
        if run_start < 0:
            run_start = i
        if t[i] - t[run_start] >= hold - 1e-9:
            return float(t[run_start] - start), True
    return float(horizon), False


def _on_field(tr: Trace) -> NDArray[np.bool_]:
    return (tr.column("penalized") < 0.5) & (tr.column("picked_up") < 0.5)


def _good(tr: Trace) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """Per frame: relocalized (plain) and relocalized counting the mirror (see the module docstring)."""
    rec = tr.meta["recovery"]
    d, a, dm, am = tr.errors()
    lim_a = math.radians(rec["error_deg"])
    on = _on_field(tr)
    plain = on & (d < rec["error_m"]) & (a < lim_a)
    return plain, plain | (on & (dm < rec["error_m"]) & (am < lim_a))


def _mirrored(tr: Trace) -> NDArray[np.bool_]:
    d, _, dm, _ = tr.errors()
    return (dm < d) & (d > tr.meta["recovery"]["error_m"])


def _goals(tr: Trace) -> tuple[int, int]:
    goals = tr.log("goal")
    home = sum(1 for g in goals if g["team"] == 0)
    return home, len(goals) - home


def run_row(tr: Trace) -> dict[str, Any]:
    """The run's row (:data:`scenarios.store.RUN_COLUMNS`) from its trace."""
    m = tr.meta
    wanted = set(m["metrics"])
    nan = math.nan
    row: dict[str, Any] = {"scenario": m["scenario"], "variant": m["variant"], "seed": m["seed"], "status": "ok",
                           "error": "", "sim_s": m["duration"], "frames": int(tr.table.shape[0])}  # fmt: skip
    on = _on_field(tr)
    d, a, _, _ = tr.errors()
    loc = {k: nan for k in ("pos_rmse_m", "pos_p90_m", "heading_rmse_deg", "heading_p90_deg", "share_over_0_5m",
                            "share_over_30deg", "mirror_share", "lost_share")}  # fmt: skip
    flips = nan
    if "localization" in wanted and on.any():
        flips = 0
        dd, aa = d[on], np.degrees(a[on])
        mirrored = _mirrored(tr)
        rec = m["recovery"]
        loc.update(
            pos_rmse_m=float(np.sqrt(np.mean(dd**2))), pos_p90_m=float(np.percentile(dd, 90)),
            heading_rmse_deg=float(np.sqrt(np.mean(aa**2))), heading_p90_deg=float(np.percentile(aa, 90)),
            share_over_0_5m=float(np.mean(dd > rec["error_m"])), share_over_30deg=float(np.mean(aa > rec["error_deg"])),
            mirror_share=float(np.mean(mirrored[on])), lost_share=float(np.mean(tr.column("lost")[on] > 0.5)),
        )  # fmt: skip
        for number in m["traced"]:
            sel = (tr.column("number") == number) & on
            flags = mirrored[sel].astype(np.int8)
            flips += int(np.count_nonzero(np.diff(flags) == 1)) + int(flags[:1].sum())
    row.update(loc, mirror_flips=flips)
    row["ball_rmse_m"], row["ball_frames"] = _ball_rmse(tr) if "ball" in wanted else (nan, 0)
    row["goals_for"], row["goals_against"] = _goals(tr) if "goals" in wanted else (nan, nan)
    cpu = tr.column("loc_cpu_us")
    row["loc_cpu_us"] = float(np.nanmean(cpu)) if cpu.size and np.isfinite(cpu).any() else nan
    row["wall_s"] = nan
    return row


def _ball_rmse(tr: Trace) -> tuple[float, int]:
    placed = np.array([e["time"] for e in tr.log("ball_placed")])
    sq: list[NDArray[np.float64]] = []
    for number in tr.meta["traced"]:
        r = tr.robot(number)
        t = r.column("time")
        ex, ey = r.column("ball_est_x"), r.column("ball_est_y")
        have = np.isfinite(ex) & np.isfinite(ey)
        if not have.any():
            continue
        after = t >= t[np.argmax(have)]
        settling = np.zeros(t.size, dtype=bool)
        for p in placed:
            settling |= (t >= p) & (t < p + BALL_SETTLE_S)
        use = have & after & ~settling & _on_field(r)
        sq.append((ex[use] - r.column("ball_true_x")[use]) ** 2 + (ey[use] - r.column("ball_true_y")[use]) ** 2)
    allsq = np.concatenate(sq) if sq else np.zeros(0)
    return (float(np.sqrt(allsq.mean())), int(allsq.size)) if allsq.size else (math.nan, 0)


def event_rows(tr: Trace) -> list[dict[str, Any]]:
    """One row per scripted robot event of the timeline (:data:`scenarios.store.EVENT_COLUMNS`)."""
    m = tr.meta
    nan = math.nan
    timeline = m["timeline"]
    robot_times: dict[tuple[int, int], list[float]] = {}
    for e in timeline:
        if e["kind"] in _ROBOT_EVENTS:
            robot_times.setdefault((e["team"], e["number"]), []).append(e["time"])
    for e in tr.log("penalty"):  # the referee's own penalties end a horizon too
        robot_times.setdefault((e["team"], e["number"]), []).append(e["time"])
    returns = tr.log("unpenalized") + tr.log("penalty_cleared")
    goals = tr.log("goal")
    rows = []
    for index, e in enumerate(timeline):
        kind = _ROBOT_EVENTS.get(e["kind"])
        if kind is None:
            continue
        team, number, t0 = e["team"], e["number"], e["time"]
        applied = [x for x in tr.log(_LOG_KIND[kind]) if x["team"] == team and x["number"] == number
                   and abs(x["time"] - t0) < 0.05 and (kind != "penalty" or x.get("reason") == "script")]  # fmt: skip
        row: dict[str, Any] = {"scenario": m["scenario"], "variant": m["variant"], "seed": m["seed"], "event": index,
                               "kind": kind, "team": team, "number": number, "time_s": t0}  # fmt: skip
        row.update({c: nan for c in ("start_s", "horizon_s", "relocalize_s", "relocalize_sym_s", "error_before_m",
                                     "error_after_m", "penalty_s", "back_in_play_s")})  # fmt: skip
        row.update(relocalized=0, relocalized_sym=0, goals_conceded_short=0)
        if kind == "kidnap":
            row["detail"] = " ".join(f"{v:.3f}" for v in e["pose"]) if e.get("pose") else ""
        elif kind == "penalty":
            from cognition.gamestate import Penalty

            row["detail"] = Penalty(e["code"]).name.lower()
        else:
            row["detail"] = f"{e['duration']:g} s"
        if not applied:
            row["detail"] += " (not applied: the robot was already penalised)"
            rows.append(row)
            continue
        start = t0
        if kind == "penalty":
            back = [x["time"] for x in returns if x["team"] == team and x["number"] == number and x["time"] > t0]
            if not back:  # still out at the end of the run
                row["penalty_s"] = m["duration"] - t0
                row["goals_conceded_short"] = sum(1 for g in goals if g["team"] != team and g["time"] >= t0)
                rows.append(row)
                continue
            start = min(back)
            row["penalty_s"] = start - t0
            row["goals_conceded_short"] = sum(1 for g in goals if g["team"] != team and t0 <= g["time"] < start)
        later = [t for t in robot_times.get((team, number), []) if t > start + 1e-9]
        horizon = min([*later, m["duration"]]) - start
        row["start_s"], row["horizon_s"] = start, horizon
        if team == 0 and number in m["traced"] and "recovery" in m["metrics"]:
            _recovery(tr.robot(number), row, t0, start, horizon)
            if kind == "penalty":
                row["back_in_play_s"] = row["penalty_s"] + row["relocalize_s"]
        rows.append(row)
    return rows


def _recovery(r: Trace, row: dict[str, Any], t0: float, start: float, horizon: float) -> None:
    """Fill the recovery columns of ``row`` from one robot's trace."""
    hold = r.meta["recovery"]["hold_s"]
    t = r.column("time")
    plain, sym = _good(r)
    row["relocalize_s"], ok = recovery_time(t, plain, start, horizon, hold)
    row["relocalize_sym_s"], ok_sym = recovery_time(t, sym, start, horizon, hold)
    row["relocalized"], row["relocalized_sym"] = int(ok), int(ok_sym)
    d, _, _, _ = r.errors()
    on = _on_field(r)
    before = on & (t >= t0 - 1.0) & (t < t0)
    row["error_before_m"] = float(d[before].mean()) if before.any() else math.nan
    after = np.flatnonzero(on & (t >= start - 1e-9))
    row["error_after_m"] = float(d[after[0]]) if after.size else math.nan
