"""The summary of a match: score, goals, kickoffs, penalties, returns, messages, percepts,
localization errors and timing, as printed by ``teamsim match`` and written to ``summary.json``.

Times are game seconds since the start of the match; team indices are 0 (home) and 1 (away).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from cognition.gamestate import Penalty
from teamsim.brains import LocalizationSummary


@dataclass
class MatchSummary:
    """The outcome of a match, as printed by ``teamsim match``."""

    seed: int
    players_per_team: int
    field: str
    score: tuple[int, int]
    goals: list[tuple[float, int, int]]
    """(time s, team index, half) per goal."""
    kickoffs: list[tuple[float, int]]
    penalties: list[tuple[float, int, int, int]]
    """(time s, team index, player number, penalty code)."""
    returns: list[tuple[float, int, int]]
    half_time: float | None
    side_switch: bool
    set_plays: int
    placements: int
    messages_sent: tuple[int, int]
    percepts_per_frame: float
    """Mean number of percepts per robot and cognition frame (0 without a camera model)."""
    images: int
    """Camera images delivered to brains (0 unless ``observation`` is ``images``)."""
    sim_seconds: float
    wall_seconds: float
    physics_steps: int
    localization: LocalizationSummary | None = None
    """Pose-estimate errors of the localizing brains (``None`` if no brain reports a pose)."""
    rejected_inputs: dict[str, int] = field(default_factory=dict)
    """Sensor inputs the brains could not use, summed over all robots, by kind (e.g.
    ``odometry_nonfinite``, ``team_message_off_field``; :mod:`cognition.inputs`)."""
    network: dict[str, Any] | None = None
    """GameController traffic of a match run by :mod:`teamsim.gc_bridge` (mode, address, packets
    received, rejected by reason, sent); ``None`` for a match without the bridge."""

    @property
    def real_time_factor(self) -> float:
        """Simulated seconds per wall-clock second."""
        return self.sim_seconds / self.wall_seconds if self.wall_seconds > 0 else math.inf

    def penalties_by_code(self) -> dict[str, int]:
        """Number of penalties per SPL penalty name."""
        out: dict[str, int] = {}
        for _, _, _, code in self.penalties:
            name = Penalty(code).name
            out[name] = out.get(name, 0) + 1
        return dict(sorted(out.items()))

    def deterministic_dict(self) -> dict[str, Any]:
        """Everything except wall-clock figures (equal for equal seeds and configs)."""
        return {
            "seed": self.seed,
            "players_per_team": self.players_per_team,
            "field": self.field,
            "score": list(self.score),
            "goals": [list(g) for g in self.goals],
            "kickoffs": [list(k) for k in self.kickoffs],
            "penalties": [list(p) for p in self.penalties],
            "returns": [list(r) for r in self.returns],
            "half_time": self.half_time,
            "side_switch": self.side_switch,
            "set_plays": self.set_plays,
            "placements": self.placements,
            "messages_sent": list(self.messages_sent),
            "percepts_per_frame": self.percepts_per_frame,
            "images": self.images,
            "sim_seconds": self.sim_seconds,
            "physics_steps": self.physics_steps,
            "localization": self.localization.to_dict() if self.localization is not None else None,
            "rejected_inputs": dict(self.rejected_inputs),
        }

    def to_dict(self) -> dict[str, Any]:
        """All figures, including wall-clock time and the real-time factor."""
        d = self.deterministic_dict()
        d["wall_seconds"] = self.wall_seconds
        d["real_time_factor"] = self.real_time_factor
        d["penalties_by_code"] = self.penalties_by_code()
        if self.network is not None:
            d["network"] = dict(self.network)
        return d

    def format(self, team_names: tuple[str, str] = ("Home", "Away")) -> str:
        """Human-readable report."""
        lines = [
            f"teamsim match  seed={self.seed}  {self.players_per_team} v {self.players_per_team}  field={self.field}",
            f"final score    {team_names[0]} {self.score[0]} : {self.score[1]} {team_names[1]}",
            "goals:",
        ]
        for t, team, half in self.goals:
            lines.append(f"  {_clock(t)}  {team_names[team]:<5} (half {half})")
        if not self.goals:
            lines.append("  none")
        lines.append(f"kickoffs       {len(self.kickoffs)}")
        if self.half_time is not None:
            lines.append(f"half time      at {_clock(self.half_time)}, sides switched: {self.side_switch}")
        by_code = self.penalties_by_code()
        lines.append(f"penalties      {len(self.penalties)}" + (f"  {by_code}" if by_code else ""))
        for t, team, number, code in self.penalties:
            lines.append(f"  {_clock(t)}  {team_names[team]:<5} #{number}  {Penalty(code).name}")
        lines.append(f"returns        {len(self.returns)}")
        lines.append(f"set plays      {self.set_plays}, manual placements {self.placements}")
        lines.append(f"team messages  {self.messages_sent[0]} / {self.messages_sent[1]}")
        if self.images:
            lines.append(f"camera images  {self.images}")
        else:
            lines.append(f"percepts       {self.percepts_per_frame:.2f} per robot and frame")
        if self.localization is not None:
            lines.append(self.localization.format())
        if self.rejected_inputs:
            counts = ", ".join(f"{kind} {n}" for kind, n in self.rejected_inputs.items())
            lines.append(f"rejected input {sum(self.rejected_inputs.values())} ({counts})")
        if self.network is not None:
            lines.append(_network_line(self.network))
        lines.append(
            f"simulated      {self.sim_seconds:.1f} s in {self.wall_seconds:.1f} s wall "
            f"(real-time factor {self.real_time_factor:.1f}x, {self.physics_steps} physics steps)"
        )
        return "\n".join(lines)


def _network_line(net: dict[str, Any]) -> str:
    """One line on the GameController traffic of :attr:`MatchSummary.network`."""
    where = f"{net.get('mode')} {net.get('host')}:{net.get('port')}"
    reasons = ", ".join(f"{k} {v}" for k, v in net.get("rejected_by_reason", {}).items())
    rejected = f"{net.get('rejected', 0)} rejected" + (f" ({reasons})" if reasons else "")
    status = f"{net.get('sent_status', 0)} status packets, {net.get('sent_team_messages', 0)} team messages"
    if net.get("mode") == "listen":
        return f"gamecontroller {where}: {net.get('received', 0)} packets received, {rejected}; sent {status}"
    return f"gamecontroller {where}: sent {net.get('sent_game_state', 0)} game states, {status}"


def _clock(t: float) -> str:
    return f"{int(t // 60):3d}:{t % 60:05.2f}"
