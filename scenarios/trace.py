"""The per-frame trace of one run, stored as Parquet (pyarrow) so that metrics can be computed later.

One row per traced robot and cognition frame (:data:`TRACE_COLUMNS`; poses in the robot's team
frame, metres and radians). The file's schema metadata (key ``teamsim``) holds, as JSON, what
the rows alone do not: the scenario, variant and seed, the recovery thresholds, the expanded
timeline and the match's whole event log (kidnaps, penalties, returns, goals, game states). A
new metric can therefore be computed from stored runs without simulating again::

    from scenarios.trace import Trace
    t = Trace.read("out/study/traces/kidnap-standing/reset/seed-0003.parquet")
    frame = t.frame()          # a pandas DataFrame with TRACE_COLUMNS
    kidnaps = t.log("kidnap")  # the event log's kidnap entries
"""

from __future__ import annotations

import io
import json
import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

TRACE_COLUMNS = (
    "time",  # s since the match start
    "number",  # player number (home team)
    "true_x", "true_y", "true_theta",  # true pose (team frame)
    "est_x", "est_y", "est_theta",  # the localization's estimate (team frame)
    "cov_xx", "cov_xy", "cov_yy", "cov_tt",  # its covariance (m^2, rad^2)
    "lost",  # 1 when the localization flags itself lost
    "penalized",  # 1 while the referee has the robot off the field
    "picked_up",  # 1 while the robot is carried (penalties, placements, sensed kidnaps)
    "ball_true_x", "ball_true_y",  # the true ball (team frame)
    "ball_est_x", "ball_est_y",  # the Kalman ball (team frame via the estimate; NaN before it has one)
    "ball_level",  # 0 invalid, 1 suspicious, 2 valid
    "loc_cpu_us",  # CPU time of this frame's localization update (us; timing, machine-dependent)
    "game_state",  # GameController state (0 INITIAL .. 3 PLAYING, 4 FINISHED)
    "mirrored",  # 1 when the estimate is nearer the mirrored true pose (-x, -y, theta + pi) than the true one
)  # fmt: skip
_META_KEY = b"teamsim"


@dataclass
class Trace:
    """A run's trace: ``table`` (frames x :data:`TRACE_COLUMNS`, float64) and ``meta`` (module docstring)."""

    table: NDArray[np.float64]
    meta: dict[str, Any]

    def column(self, name: str) -> NDArray[np.float64]:
        """One column of the table."""
        return self.table[:, TRACE_COLUMNS.index(name)]

    def robot(self, number: int) -> Trace:
        """The rows of one player."""
        return Trace(self.table[self.column("number") == number], self.meta)

    def log(self, kind: str) -> list[dict[str, Any]]:
        """The event log's entries of one kind (JSON dicts with ``time`` and the details)."""
        return [e for e in self.meta["log"] if e["kind"] == kind]

    def errors(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """Per row: position error (m) and heading error (rad) against the truth, and the same
        against the mirrored truth (-x, -y, theta + pi), the pose the field's symmetry confuses."""
        ex, ey, et = self.column("est_x"), self.column("est_y"), self.column("est_theta")
        tx, ty, tt = self.column("true_x"), self.column("true_y"), self.column("true_theta")
        d = np.hypot(ex - tx, ey - ty)
        a = np.abs(np.mod(et - tt + math.pi, 2 * math.pi) - math.pi)
        dm = np.hypot(ex + tx, ey + ty)
        am = np.abs(np.mod(et - tt, 2 * math.pi) - math.pi)
        return d, a, dm, am

    def frame(self) -> Any:
        """The table as a pandas DataFrame (needs the studies extra)."""
        import pandas as pd

        return pd.DataFrame(self.table, columns=list(TRACE_COLUMNS))

    def to_parquet(self) -> bytes:
        """The trace as Parquet bytes (zstd-compressed; the metadata in the schema)."""
        import pyarrow as pa
        import pyarrow.parquet as pq

        arrays = [pa.array(self.table[:, i]) for i in range(len(TRACE_COLUMNS))]
        table = pa.Table.from_arrays(arrays, names=list(TRACE_COLUMNS))
        table = table.replace_schema_metadata({_META_KEY: json.dumps(self.meta, sort_keys=True).encode()})
        buf = io.BytesIO()
        pq.write_table(table, buf, compression="zstd")
        return buf.getvalue()

    @classmethod
    def from_parquet(cls, data: bytes) -> Trace:
        """A trace from the bytes of :meth:`to_parquet`."""
        import pyarrow.parquet as pq

        table = pq.read_table(io.BytesIO(data))
        meta = json.loads((table.schema.metadata or {}).get(_META_KEY, b"{}"))
        missing = [c for c in TRACE_COLUMNS if c not in table.column_names]
        if missing:
            raise ValueError(f"not a teamsim trace: the columns {missing} are missing")
        cols = [table.column(c).to_numpy() for c in TRACE_COLUMNS]
        return cls(np.column_stack(cols) if cols[0].size else np.zeros((0, len(TRACE_COLUMNS))), meta)

    @classmethod
    def read(cls, path: str | Path) -> Trace:
        """A trace from a Parquet file."""
        return cls.from_parquet(Path(path).read_bytes())


def trace_path(folder: Path, scenario: str, variant: str, seed: int) -> Path:
    """Where a study keeps the trace of one run."""
    return folder / "traces" / scenario / variant / f"seed-{seed:04d}.parquet"


def write_atomic(path: Path, data: bytes) -> None:
    """Write ``data`` to ``path`` through a temporary file and a rename (never a half-written file)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_bytes(data)
    os.replace(tmp, path)
