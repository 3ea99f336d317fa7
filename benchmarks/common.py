"""Pieces the benchmark scripts share: one robot's recorded frames and the JSON output."""

from __future__ import annotations

import json
import platform
from pathlib import Path

from cognition.representations import SensorFrame
from teamsim.match import Match, MatchConfig


def record_robot_frames(seconds: float, robot: int = 2, seed: int = 1) -> tuple[Match, list[SensorFrame]]:
    """The sensor frames of robot ``robot`` during ``seconds`` of a default 5 v 5 match."""
    m = Match(MatchConfig(seed=seed))
    frames: list[SensorFrame] = []
    last = None
    while m.time < seconds:
        m.step()
        f = m.last_frames[robot]
        if f is not None and f is not last:
            frames.append(f)
            last = f
    return m, frames


def write_figures(path: Path | None, figures: dict[str, float]) -> None:
    """Write ``{"figures": ..., "meta": ...}`` to ``path`` (nothing if ``None``)."""
    if path is None:
        return
    path.parent.mkdir(parents=True, exist_ok=True)
    meta = {"python": platform.python_version(), "machine": platform.machine(), "processor": platform.processor()}
    path.write_text(json.dumps({"figures": figures, "meta": meta}, indent=2))
