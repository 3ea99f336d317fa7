"""The match's event log and the scripted events a scenario can schedule.

:class:`EventLog` is an append-only list of :class:`LogEvent` (time, kind, details). Two
runs with one seed and one configuration produce equal logs; the log is the reference for
determinism checks and for match summaries.

Scripted events (all times in seconds since the match start, poses in the world frame):

=================  ==============================================================
event              effect
=================  ==============================================================
Kidnap             teleport a robot to a given pose (or a random pose on the field);
                   its cognition is not told; ``sense_pickup`` sets ``picked_up``
                   for the carry time
PlaceBall          put the ball at a position with a velocity
ForcePenalty       penalise a robot with an SPL penalty code
ForceFall          make a robot fall for a given duration
=================  ==============================================================
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from cognition.gamestate import Penalty


@dataclass(frozen=True)
class LogEvent:
    """One entry of the event log."""

    time: float
    """Simulated time (s since match start)."""
    kind: str
    """What happened (``goal``, ``penalty``, ``state``, ...)."""
    details: tuple[tuple[str, Any], ...] = ()
    """Sorted (key, value) pairs describing it."""

    def get(self, key: str, default: Any = None) -> Any:
        """A detail by name."""
        return dict(self.details).get(key, default)

    def to_json(self) -> dict[str, Any]:
        """A JSON-ready dict (tuples become lists)."""
        return {"time": self.time, "kind": self.kind, **{k: _jsonable(v) for k, v in self.details}}

    def __str__(self) -> str:
        items = " ".join(f"{k}={v}" for k, v in self.details)
        return f"{self.time:8.2f}s {self.kind} {items}".rstrip()


@dataclass
class EventLog:
    """Append-only list of :class:`LogEvent`.

    ``sink``, if given, is called with every event as it is recorded (e.g. to append it to
    a JSON-lines file), so a long run loses nothing already computed if it is interrupted.
    """

    events: list[LogEvent] = field(default_factory=list)
    sink: Callable[[LogEvent], None] | None = None

    def add(self, time: float, kind: str, **details: Any) -> LogEvent:
        """Record an event."""
        ev = LogEvent(time, kind, tuple(sorted(details.items())))
        self.events.append(ev)
        if self.sink is not None:
            self.sink(ev)
        return ev

    def of_kind(self, kind: str) -> list[LogEvent]:
        """All events of one kind, in order."""
        return [e for e in self.events if e.kind == kind]


def _jsonable(v: Any) -> Any:
    if isinstance(v, tuple):
        return [_jsonable(x) for x in v]
    return v


def _check_time(owner: str, time: float) -> None:
    if not isinstance(time, int | float) or not math.isfinite(time) or time < 0:
        raise ValueError(f"{owner}.time must be a finite number >= 0, got {time!r}")


def _check_robot(owner: str, team: int, number: int) -> None:
    if team not in (0, 1):
        raise ValueError(f"{owner}.team must be 0 or 1, got {team!r}")
    if not isinstance(number, int) or number < 1:
        raise ValueError(f"{owner}.number must be a player number >= 1, got {number!r}")


@dataclass(frozen=True)
class Kidnap:
    """Teleport a robot without telling its cognition."""

    time: float
    team: int
    number: int
    pose: tuple[float, float, float] | None = None
    """Target pose (x m, y m, theta rad, world frame); ``None`` draws one on the field."""
    sense_pickup: bool = False
    """Whether the robot's ``picked_up`` signal turns on while it is carried."""

    def __post_init__(self) -> None:
        _check_time("Kidnap", self.time)
        _check_robot("Kidnap", self.team, self.number)
        if self.pose is not None and not all(math.isfinite(v) for v in self.pose):
            raise ValueError(f"Kidnap.pose must be finite, got {self.pose}")


@dataclass(frozen=True)
class PlaceBall:
    """Put the ball somewhere (world frame), optionally rolling."""

    time: float
    x: float
    y: float
    vx: float = 0.0
    vy: float = 0.0

    def __post_init__(self) -> None:
        _check_time("PlaceBall", self.time)
        if not all(math.isfinite(v) for v in (self.x, self.y, self.vx, self.vy)):
            raise ValueError("PlaceBall position and velocity must be finite")


@dataclass(frozen=True)
class ForcePenalty:
    """Penalise a robot (as if the referee called it)."""

    time: float
    team: int
    number: int
    code: int = Penalty.REQUEST_FOR_PICKUP

    def __post_init__(self) -> None:
        _check_time("ForcePenalty", self.time)
        _check_robot("ForcePenalty", self.team, self.number)
        if self.code not in Penalty._value2member_map_ or self.code == Penalty.NONE:
            raise ValueError(f"ForcePenalty.code {self.code!r} is not an SPL penalty code")


@dataclass(frozen=True)
class ForceFall:
    """Make a robot fall; it lies for ``duration`` seconds."""

    time: float
    team: int
    number: int
    duration: float = 4.0

    def __post_init__(self) -> None:
        _check_time("ForceFall", self.time)
        _check_robot("ForceFall", self.team, self.number)
        if not math.isfinite(self.duration) or self.duration <= 0:
            raise ValueError(f"ForceFall.duration must be > 0, got {self.duration!r}")


ScriptedEvent = Kidnap | PlaceBall | ForcePenalty | ForceFall
