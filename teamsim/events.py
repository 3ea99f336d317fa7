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

Their fields (checked when an event is built; a :class:`~teamsim.match.MatchConfig` then
checks that poses lie on its own field's carpet and player numbers within its teams):

============  ====================================  ==================================================
field         range                                 meaning
============  ====================================  ==================================================
time          [0, 1000000]                          when the event happens (s since the match start)
team          [0, 1]                                team index
number        [1, 20]                               player number
pose          ([-60, 60], [-60, 60], [-2pi, 2pi])   Kidnap: x, y (m) and theta (rad), or None (random)
sense_pickup  true/false                            Kidnap: whether ``picked_up`` turns on
x             [-60, 60]                             PlaceBall: position (m)
y             [-60, 60]
vx            [-50, 50]                             PlaceBall: velocity (m/s)
vy            [-50, 50]
code          [1, 15]                               ForcePenalty: an SPL penalty code other than NONE
                                                    (:class:`cognition.gamestate.Penalty`)
duration      (0, 3600]                             ForceFall: time lying on the ground (s)
============  ====================================  ==================================================
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, ClassVar

from cognition.field import FieldDimensions
from cognition.gamestate import MAX_NUM_PLAYERS, Penalty
from teamsim.params import Range, Ranges, check_ranges, from_mapping, non_negative, positive


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


_FIELD_RANGES = FieldDimensions.RANGES
CARPET_LIMIT = max(_FIELD_RANGES["length"].high, _FIELD_RANGES["width"].high) / 2 + _FIELD_RANGES["border_strip"].high
"""No carpet reaches further than this from the field centre (m): the largest field
:class:`~cognition.field.FieldDimensions` accepts plus its widest border strip. A match checks
its events against its own carpet (:class:`teamsim.match.MatchConfig`)."""
_TIME = non_negative(1e6)
_TEAM = Range(0, 1)
_NUMBER = Range(1, MAX_NUM_PLAYERS)
_XY = Range(-CARPET_LIMIT, CARPET_LIMIT)
_THETA = Range(-2 * math.pi, 2 * math.pi)
_SPEED = Range(-50.0, 50.0)
_PENALTY_CODES = tuple(int(p) for p in Penalty if p != Penalty.NONE)


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

    RANGES: ClassVar[Ranges] = {"time": _TIME, "team": _TEAM, "number": _NUMBER, "pose": (_XY, _XY, _THETA)}

    def __post_init__(self) -> None:
        check_ranges(self)


@dataclass(frozen=True)
class PlaceBall:
    """Put the ball somewhere (world frame), optionally rolling."""

    time: float
    x: float
    y: float
    vx: float = 0.0
    vy: float = 0.0

    RANGES: ClassVar[Ranges] = {"time": _TIME, "x": _XY, "y": _XY, "vx": _SPEED, "vy": _SPEED}

    def __post_init__(self) -> None:
        check_ranges(self)


@dataclass(frozen=True)
class ForcePenalty:
    """Penalise a robot (as if the referee called it)."""

    time: float
    team: int
    number: int
    code: int = Penalty.REQUEST_FOR_PICKUP

    RANGES: ClassVar[Ranges] = {
        "time": _TIME,
        "team": _TEAM,
        "number": _NUMBER,
        "code": Range(min(_PENALTY_CODES), max(_PENALTY_CODES)),
    }

    def __post_init__(self) -> None:
        check_ranges(self)
        if self.code not in _PENALTY_CODES:
            raise ValueError(f"ForcePenalty.code must be an SPL penalty code {list(_PENALTY_CODES)}, got {self.code!r}")


@dataclass(frozen=True)
class ForceFall:
    """Make a robot fall; it lies for ``duration`` seconds."""

    time: float
    team: int
    number: int
    duration: float = 4.0

    RANGES: ClassVar[Ranges] = {"time": _TIME, "team": _TEAM, "number": _NUMBER, "duration": positive(3600.0)}

    def __post_init__(self) -> None:
        check_ranges(self)


ScriptedEvent = Kidnap | PlaceBall | ForcePenalty | ForceFall

EVENT_KINDS: dict[str, type[Kidnap] | type[PlaceBall] | type[ForcePenalty] | type[ForceFall]] = {
    "kidnap": Kidnap,
    "place_ball": PlaceBall,
    "penalty": ForcePenalty,
    "fall": ForceFall,
}
"""The ``kind`` names of scripted events in a plain mapping (:func:`event_from_mapping`)."""


def event_from_mapping(data: Any, where: str = "event") -> ScriptedEvent:
    """A scripted event from a plain mapping such as ``{"kind": "kidnap", "time": 8.0, "team": 0,
    "number": 1, "pose": [1.0, 0.5, 0.0]}`` (a JSON config's ``events`` entry); the other keys
    are the event's fields (module table). Errors name ``where`` and the key."""
    if not isinstance(data, dict):
        raise TypeError(f"{where}: expected a mapping with a 'kind', got {type(data).__name__}")
    rest = dict(data)
    kind = rest.pop("kind", None)
    if kind not in EVENT_KINDS:
        raise ValueError(f"{where}.kind: unknown event kind {kind!r}; valid: {sorted(EVENT_KINDS)}")
    cls = EVENT_KINDS[kind]
    return from_mapping(cls, rest, where)  # type: ignore[return-value]
