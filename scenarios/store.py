"""The result tables of a study: one row per run and one per scripted event, appended as runs finish.

A sweep (:mod:`scenarios.sweep`) writes into its output directory:

===============  ======================================================================================
file             contents
===============  ======================================================================================
``runs.csv``     one row per (scenario, variant, seed) run: status, error, the per-run metrics
                 (:data:`RUN_COLUMNS`)
``events.csv``   one row per scripted event of a run (kidnap, penalty, ...): the per-event metrics
                 (:data:`EVENT_COLUMNS`)
``traces/``      one Parquet file per run with the per-frame trace (:mod:`scenarios.trace`)
===============  ======================================================================================

A run's event rows are written before its run row, each line in one ``write`` followed by a
flush and ``fsync``, so a sweep killed at any moment leaves at most one torn last line and
perhaps event rows of a run without its run row. :func:`read_rows` repairs both (the torn line
is cut off, orphaned event rows are dropped and the file rewritten) and says so in its return
value; a damaged line before the last one is corruption and raises :class:`StoreError` naming
the file and line. A run counts as done when its run row exists, failed or not.

Units: seconds (``*_s``), metres (``*_m``), degrees (``*_deg``), microseconds (``*_us``).
Columns in :data:`TIMING_COLUMNS` hold wall-clock or CPU timings: they differ between two
otherwise identical sweeps; every other column is a pure function of (scenario, variant, seed).
"""

from __future__ import annotations

import csv
import io
import math
import os
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

KEY_COLUMNS = ("scenario", "variant", "seed")
"""The columns that name a run."""

RUN_COLUMNS = (
    *KEY_COLUMNS,
    "status",  # "ok" or "failed"
    "error",  # failed runs: the exception, one line ("" when ok)
    "sim_s",  # simulated seconds
    "frames",  # traced robot frames (all traced robots)
    "pos_rmse_m",  # position RMSE over traced frames on the field (not penalised, not carried)
    "pos_p90_m",  # 90th percentile of the position error
    "heading_rmse_deg",
    "heading_p90_deg",
    "share_over_0_5m",  # share of frames with position error > 0.5 m
    "share_over_30deg",  # share of frames with heading error > 30 deg
    "mirror_flips",  # times the estimate went from the true side to nearer the mirrored pose
    "mirror_share",  # share of frames nearer the mirrored pose than the true one
    "lost_share",  # share of frames the localization flagged itself lost
    "ball_rmse_m",  # Kalman ball (team frame) against the true ball, frames with a ball estimate
    "ball_frames",  # frames in the ball RMSE
    "goals_for",  # goals of the home team (the team whose variant varies)
    "goals_against",
    "loc_cpu_us",  # mean CPU time of one localization update (timing)
    "wall_s",  # wall-clock seconds of the run (timing)
)
EVENT_COLUMNS = (
    *KEY_COLUMNS,
    "event",  # index in the scenario's timeline (expanded repetitions count separately)
    "kind",  # kidnap, penalty, fall, ball
    "team",
    "number",
    "time_s",  # when the event happened (s since the match start)
    "detail",  # kidnap: target pose "x y theta"; penalty: the penalty name
    "start_s",  # when the relocalization clock starts: the event time, or a penalised robot's return
    "horizon_s",  # the longest recovery time observable: from start_s to the next event of this robot or the end
    "relocalize_s",  # time from start_s until the error is below 0.5 m and 30 deg for 1 s (= horizon_s if censored)
    "relocalized",  # 1 if that happened within the horizon, 0 if censored
    "relocalize_sym_s",  # the same, counting the field's mirror pose as correct
    "relocalized_sym",
    "error_before_m",  # mean position error in the second before the event (NaN if not traced then)
    "error_after_m",  # position error at the first traced frame from start_s on
    "penalty_s",  # penalties: seconds until the robot was returned (NaN for other events)
    "back_in_play_s",  # penalties: penalty_s + relocalize_s (censored with relocalized)
    "goals_conceded_short",  # penalties: goals against the robot's team while it was out
)
TIMING_COLUMNS = ("loc_cpu_us", "wall_s")
"""Columns that measure time on the machine, not in the simulation."""

_INT_COLUMNS = {"seed", "frames", "ball_frames", "event", "team", "number", "relocalized", "relocalized_sym",
                "goals_conceded_short"}  # fmt: skip
"""Integer columns; the others are numbers that are NaN where a metric was not asked for or does not apply."""
_TEXT_COLUMNS = {"scenario", "variant", "status", "error", "kind", "detail"}


class StoreError(ValueError):
    """A result table that cannot be resumed from (a damaged line other than the last, a wrong header)."""


@dataclass
class Rows:
    """The rows read back from a study directory."""

    runs: list[dict[str, Any]] = field(default_factory=list)
    events: list[dict[str, Any]] = field(default_factory=list)
    repairs: list[str] = field(default_factory=list)
    """What :func:`read_rows` had to repair (one sentence each)."""

    def done(self) -> set[tuple[str, str, int]]:
        """Keys (scenario, variant, seed) of the runs that have a run row."""
        return {(r["scenario"], r["variant"], int(r["seed"])) for r in self.runs}


def run_key(row: Mapping[str, Any]) -> tuple[str, str, int]:
    """(scenario, variant, seed) of a row."""
    return (str(row["scenario"]), str(row["variant"]), int(row["seed"]))


def _format(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "1" if value else "0"
    if isinstance(value, float):
        return "nan" if math.isnan(value) else repr(value)
    return str(value)


def _parse(column: str, text: str) -> Any:
    if column in _TEXT_COLUMNS:
        return text
    if column in _INT_COLUMNS:
        return int(text) if text else 0
    return float(text) if text else math.nan


def _line(columns: tuple[str, ...], row: Mapping[str, Any]) -> str:
    missing = [c for c in columns if c not in row]
    if missing:
        raise ValueError(f"row lacks column(s) {missing}")
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerow([_format(row[c]) for c in columns])
    return buf.getvalue()


class RowWriter:
    """Appends rows to ``runs.csv`` and ``events.csv`` in ``folder`` (module docstring)."""

    def __init__(self, folder: Path):
        folder.mkdir(parents=True, exist_ok=True)
        self.folder = folder
        self._runs = self._open(folder / "runs.csv", RUN_COLUMNS)
        self._events = self._open(folder / "events.csv", EVENT_COLUMNS)

    @staticmethod
    def _open(path: Path, columns: tuple[str, ...]) -> io.TextIOWrapper:
        new = not path.exists() or path.stat().st_size == 0
        fh = path.open("a", encoding="utf-8", newline="")
        if new:
            fh.write(",".join(columns) + "\n")
            fh.flush()
        return fh

    def add(self, run: Mapping[str, Any], events: Iterable[Mapping[str, Any]]) -> None:
        """Write one finished run: its event rows first, then its run row, each synced to disk."""
        text = "".join(_line(EVENT_COLUMNS, e) for e in events)
        if text:
            self._write(self._events, text)
        self._write(self._runs, _line(RUN_COLUMNS, run))

    @staticmethod
    def _write(fh: io.TextIOWrapper, text: str) -> None:
        fh.write(text)
        fh.flush()
        os.fsync(fh.fileno())

    def close(self) -> None:
        """Close both files."""
        self._runs.close()
        self._events.close()

    def __enter__(self) -> RowWriter:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _read_table(path: Path, columns: tuple[str, ...], repairs: list[str]) -> list[dict[str, Any]]:
    """Rows of one CSV table; a torn last line is cut off the file (and noted in ``repairs``)."""
    if not path.exists():
        return []
    data = path.read_bytes()
    lines = data.splitlines(keepends=True)
    if not lines:
        return []
    header = lines[0].decode("utf-8", errors="replace").strip()
    if header != ",".join(columns):
        raise StoreError(
            f"{path} line 1 is not the header of a teamsim study table (expected {','.join(columns)[:80]}...); "
            "it was written by another program or another teamsim version; use a new --out directory"
        )
    rows: list[dict[str, Any]] = []
    offset = len(lines[0])
    last = len(lines) - 1
    for i, raw in enumerate(lines[1:], start=1):
        try:
            if not raw.endswith(b"\n"):
                raise ValueError("the line has no end")
            (values,) = list(csv.reader([raw.decode("utf-8")]))
            if len(values) != len(columns):
                raise ValueError(f"{len(values)} fields instead of {len(columns)}")
            rows.append({c: _parse(c, v) for c, v in zip(columns, values, strict=True)})
        except (ValueError, UnicodeDecodeError) as exc:
            if i != last:
                raise StoreError(
                    f"{path} line {i + 1} is damaged ({exc}) but lines follow it: the table is corrupt, not torn by a "
                    f"stopped sweep; repair or remove line {i + 1} and run again"
                ) from exc
            with path.open("r+b") as fh:
                fh.truncate(offset)
            repairs.append(f"{path.name}: line {i + 1} was torn by a stopped sweep; dropped it")
            break
        offset += len(raw)
    return rows


def _rewrite(path: Path, columns: tuple[str, ...], rows: Iterable[Mapping[str, Any]]) -> None:
    tmp = path.with_suffix(".csv.tmp")
    tmp.write_text(",".join(columns) + "\n" + "".join(_line(columns, r) for r in rows), encoding="utf-8")
    os.replace(tmp, path)


def drop_runs(folder: Path, keys: set[tuple[str, str, int]]) -> None:
    """Remove the run and event rows of the runs ``keys`` (failed runs about to run again)."""
    rows = read_rows(folder)
    if (folder / "runs.csv").exists():
        _rewrite(folder / "runs.csv", RUN_COLUMNS, [r for r in rows.runs if run_key(r) not in keys])
    if (folder / "events.csv").exists():
        _rewrite(folder / "events.csv", EVENT_COLUMNS, [e for e in rows.events if run_key(e) not in keys])


def read_rows(folder: Path) -> Rows:
    """The rows in ``folder`` (empty if it holds none), repaired for resuming (module docstring)."""
    repairs: list[str] = []
    runs = _read_table(folder / "runs.csv", RUN_COLUMNS, repairs)
    events = _read_table(folder / "events.csv", EVENT_COLUMNS, repairs)
    done = {run_key(r) for r in runs}
    orphans = [e for e in events if run_key(e) not in done]
    if orphans:
        events = [e for e in events if run_key(e) in done]
        _rewrite(folder / "events.csv", EVENT_COLUMNS, events)
        keys = sorted({run_key(e) for e in orphans})
        repairs.append(f"events.csv: dropped {len(orphans)} event row(s) of {len(keys)} unfinished run(s)")
    seen: set[tuple[str, str, int]] = set()
    for r in runs:
        k = run_key(r)
        if k in seen:
            raise StoreError(f"{folder / 'runs.csv'} holds run {k} twice; it was edited or two sweeps shared it")
        seen.add(k)
    return Rows(runs, events, repairs)
