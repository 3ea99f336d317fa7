"""Scenario files: what a study simulates, read from TOML (``tomllib``) and checked before anything runs.

A scenario is data (PettingZoo MPE's ``make_world`` / ``reset_world`` split and HULKs' scripted
simulator scenarios are the models): the match, the brains of both teams, a timeline of events
and the metrics to collect. :func:`load` reads a file or a built-in name (``scenarios/builtin``)
and returns a :class:`Scenario`; one runner (:mod:`scenarios.runner`) plays it for a variant and
a seed. Every error is a :class:`ScenarioError` naming the file, the key path and what is allowed.

==================  ==========  ================================================================================
key                 default     meaning
==================  ==========  ================================================================================
description         ""          one paragraph for ``teamsim scenario list`` and the report
duration            (required)  simulated seconds of one run, (0, 3600]
seeds               10          seeds a study runs by default (``--seeds`` overrides), 1..10000
variants            (required)  a list of localization variants (``mcl``, ``lowvar``, ``amcl``, ``reset``,
                                ``maturing``, ``odometry``, ``oracle``), or tables ``[variants.NAME]`` with
                                ``localization``, ``localization_params``, ``ball`` (Kalman ball params),
                                ``observation`` (``percepts`` or ``images``: overrides the match's),
                                ``vision`` (:class:`~cognition.vision.VisionParams`, for ``images``) and
                                ``modules`` (providers of the other slots of the cognition frame, e.g.
                                ``{ obstacles = "grid", goal = "none" }``: :mod:`cognition.pipeline`)
match               {}          :class:`~teamsim.match.MatchConfig` keys (field, players_per_team, percepts,
                                referee, ...) except ``seed``, ``events``, ``cognition``, ``players`` (the brains
                                are the teams' and the variants')
home / away         observer    the teams (below); the **home** team runs the variant under study
timeline            []          events, each ``[[timeline]]`` table with a ``kind`` (below)
metrics             all         which groups to compute: ``localization``, ``recovery``, ``ball``, ``goals``
recovery            0.5, 30, 1  ``error_m``, ``error_deg``, ``hold_s``: relocalized means both errors below
                                their bounds for ``hold_s`` seconds
==================  ==========  ================================================================================

A team table: ``brain`` is ``observer`` (the experiment's robot: it stands or walks a ``loop``
steered by the truth, its head ``sweep``-ing or on the true ``ball``, while its cognition stack
runs on its sensor frames only), ``scripted`` (the scripted team play acting on its own beliefs),
``truth`` (scripted team play on true beliefs) or ``random`` (random walkers). ``variant`` is the
away team's localization (home: the variant under study). ``trace`` lists the player numbers
whose frames are traced (home only; default all). ``start`` maps player numbers to a known start
pose ``[x, y, theta]``: the robot is put there before the first frame and an observer's
localization starts there.

Timeline kinds (``time`` s; ``every`` and ``until`` repeat an entry; poses and positions in the
world frame, metres and radians; ``team`` is ``home`` or ``away``):

==========  =============================================================================================
kind        keys
==========  =============================================================================================
kidnap      team, number, and ``pose = [x, y, theta]`` or ``region`` (``field``, ``own-half``,
            ``opponent-half``, or ``{x = [lo, hi], y = [lo, hi]}``; heading uniform); ``pickup``
            (the robot senses being carried, for the referee's carry time)
penalty     team, number, ``code``: an SPL penalty code or name (``illegal_position``, ...)
ball        ``at = [x, y]`` or ``region``; ``velocity = [vx, vy]`` or ``roll_to`` (a region: the
            ball is rolled so that it stops there)
fall        team, number, ``duration`` (s)
==========  =============================================================================================

Random draws (regions) come from a generator seeded by the run's seed alone, so every variant
meets the same events (paired seeds).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from cognition.field import FIELD_PRESETS
from cognition.gamestate import Penalty
from cognition.localization import VARIANTS, LocalizationParams
from cognition.params import Range, check_choice, check_number, from_mapping
from cognition.pipeline import CognitionConfig, providers
from cognition.vision import VisionParams
from cognition.worldmodel.kalman_ball import KalmanBallParams
from teamsim.events import ForceFall, ForcePenalty, Kidnap, PlaceBall, ScriptedEvent
from teamsim.match import MatchConfig

BRAINS = ("observer", "scripted", "truth", "random")
DRIVES = ("stand", "loop")
HEADS = ("sweep", "ball")
KINDS = ("kidnap", "penalty", "ball", "fall")
METRICS = ("localization", "recovery", "ball", "goals")
REGIONS = ("field", "own-half", "opponent-half")
TEAMS = {"home": 0, "away": 1}
RESERVED_MATCH_KEYS = ("seed", "events", "cognition", "players")
MODULE_SLOTS = ("ball", "hypotheses", "team_ball", "obstacles", "goal")
"""Slots of the cognition frame a variant's ``modules`` table may set (localization and vision
have their own keys)."""
MAX_DURATION = 3600.0
MAX_SEEDS = 10_000
MAX_EVENTS = 1000
"""Most events one run may expand to (``every`` repetitions included)."""
DEFAULT_LOOP = ((-3.0, -1.8), (-1.0, -1.8), (-1.0, 1.2), (-3.0, 1.2))
"""The observer's walking loop (world frame, m): a rectangle in the own half."""
_PENALTIES = {p.name.lower(): int(p) for p in Penalty if p != Penalty.NONE}
_MARGIN = 0.3
"""Random poses keep this far inside the field lines (m)."""


class ScenarioError(ValueError):
    """A scenario file that cannot run; the message names the file, the key and what is allowed."""


@dataclass(frozen=True)
class Variant:
    """One thing a study compares: a localization variant with its parameters and the Kalman ball's."""

    name: str
    localization: str
    localization_params: LocalizationParams = field(default_factory=LocalizationParams)
    ball: KalmanBallParams = field(default_factory=KalmanBallParams)
    observation: str | None = None
    """``percepts`` or ``images`` for this variant's runs (``None``: the match's observation)."""
    vision: VisionParams = field(default_factory=VisionParams)
    """The home brains' vision (used with ``images``)."""
    modules: tuple[tuple[str, str], ...] = ()
    """(slot, provider) of the cognition frame's other slots (:data:`MODULE_SLOTS`); the rest keep
    their default providers."""

    def cognition(self) -> CognitionConfig:
        """The home brains' cognition frame: this variant's localization, Kalman ball, vision and
        module providers; every other slot at its default provider."""
        return CognitionConfig(
            localization=self.localization,
            localization_params=self.localization_params,
            ball_params=self.ball,
            vision=self.vision.method,
            vision_params=self.vision,
            **dict(self.modules),
        )


@dataclass(frozen=True)
class Team:
    """The brains of one team (module docstring)."""

    brain: str = "observer"
    variant: str = "maturing"
    drive: str = "stand"
    head: str = "sweep"
    loop: tuple[tuple[float, float], ...] = DEFAULT_LOOP
    trace: tuple[int, ...] = ()
    start: tuple[tuple[int, tuple[float, float, float]], ...] = ()


@dataclass(frozen=True)
class Region:
    """A box of positions (world frame, m) and a heading interval (rad)."""

    x: tuple[float, float]
    y: tuple[float, float]
    theta: tuple[float, float] = (-math.pi, math.pi)

    def draw(self, rng: np.random.Generator) -> tuple[float, float, float]:
        """A uniform pose in the box."""
        return (float(rng.uniform(*self.x)), float(rng.uniform(*self.y)), float(rng.uniform(*self.theta)))


@dataclass(frozen=True)
class Entry:
    """One timeline entry as written (``every`` expands it in :meth:`Scenario.events`)."""

    kind: str
    time: float
    every: float = 0.0
    until: float = 0.0
    team: int = 0
    number: int = 1
    pose: tuple[float, float, float] | None = None
    region: Region | None = None
    pickup: bool = False
    code: int = int(Penalty.REQUEST_FOR_PICKUP)
    at: tuple[float, float] | None = None
    velocity: tuple[float, float] = (0.0, 0.0)
    roll_to: Region | None = None
    duration: float = 4.0


@dataclass(frozen=True)
class Recovery:
    """When a robot counts as relocalized (module docstring)."""

    error_m: float = 0.5
    error_deg: float = 30.0
    hold_s: float = 1.0


@dataclass(frozen=True)
class Scenario:
    """A checked scenario (module docstring); build it with :func:`load` or :func:`parse`."""

    name: str
    source: str
    """The file it came from (``builtin:NAME`` for the packaged ones)."""
    description: str
    duration: float
    seeds: int
    variants: tuple[Variant, ...]
    custom_variants: bool
    """True when the file defines its variants as tables (``--variant`` names those)."""
    match: MatchConfig
    """The match without seed and events (:meth:`config` adds them)."""
    home: Team
    away: Team
    timeline: tuple[Entry, ...]
    metrics: tuple[str, ...]
    recovery: Recovery
    digest: str
    """SHA-256 of the scenario's content (a study refuses to mix rows of two different scenarios)."""

    def variant(self, name: str) -> Variant:
        """The variant called ``name``: one of the file's tables, or any localization variant."""
        for v in self.variants:
            if v.name == name:
                return v
        if not self.custom_variants and name in VARIANTS:
            return Variant(name, name)
        allowed = [v.name for v in self.variants] if self.custom_variants else list(VARIANTS)
        raise ScenarioError(f"scenario {self.name}: unknown variant {name!r}; valid: {allowed}")

    def traced(self) -> tuple[int, ...]:
        """Home player numbers whose frames are traced."""
        return self.home.trace or tuple(range(1, self.match.players_per_team + 1))

    def events(self, seed: int) -> tuple[ScriptedEvent, ...]:
        """The timeline for ``seed``: repetitions expanded, regions drawn (same for every variant)."""
        rng = np.random.default_rng([seed, 0x5C3E])
        out: list[ScriptedEvent] = []
        decel = self.match.physics.ball_rolling_decel
        for e in self.timeline:
            t = e.time
            while t <= min(e.until if e.every > 0 else e.time, self.duration):
                out.append(_event(e, t, rng, decel))
                t = t + e.every if e.every > 0 else math.inf
        return tuple(sorted(out, key=lambda ev: ev.time))

    def config(self, seed: int) -> MatchConfig:
        """The match of one run: the scenario's match with the seed and that seed's events."""
        return dataclasses.replace(self.match, seed=seed, events=self.events(seed))


def _event(e: Entry, t: float, rng: np.random.Generator, decel: float) -> ScriptedEvent:
    if e.kind == "kidnap":
        pose = e.pose if e.pose is not None else e.region.draw(rng)  # type: ignore[union-attr]
        return Kidnap(t, e.team, e.number, pose, e.pickup)
    if e.kind == "penalty":
        return ForcePenalty(t, e.team, e.number, e.code)
    if e.kind == "fall":
        return ForceFall(t, e.team, e.number, e.duration)
    x, y = e.at if e.at is not None else e.region.draw(rng)[:2]  # type: ignore[union-attr]
    vx, vy = e.velocity
    if e.roll_to is not None:  # the speed at which a ball decelerating at `decel` stops at the target
        tx, ty, _ = e.roll_to.draw(rng)
        dist = math.hypot(tx - x, ty - y)
        speed = math.sqrt(2.0 * decel * dist)
        vx, vy = (speed * (tx - x) / dist, speed * (ty - y) / dist) if dist > 0 else (0.0, 0.0)
    return PlaceBall(t, x, y, vx, vy)


# -- reading --------------------------------------------------------------------------------
def builtin_names() -> list[str]:
    """Names of the scenarios shipped with teamsim."""
    folder = resources.files("scenarios") / "builtin"
    return sorted(p.name.removesuffix(".toml") for p in folder.iterdir() if p.name.endswith(".toml"))


def load(name_or_path: str | Path) -> Scenario:
    """A built-in scenario by name, or a TOML file by path; :class:`ScenarioError` if it is bad."""
    text = str(name_or_path)
    if text in builtin_names():
        data = (resources.files("scenarios") / "builtin" / f"{text}.toml").read_bytes()
        return parse(data, f"builtin:{text}", text)
    path = Path(name_or_path)
    if not path.exists():
        raise ScenarioError(f"no scenario {text!r}: not a built-in scenario ({', '.join(builtin_names())}) nor a file")
    if not path.is_file():
        raise ScenarioError(f"scenario file {path} is not a file")
    return parse(path.read_bytes(), str(path), path.stem)


def parse(data: bytes, source: str, name: str) -> Scenario:
    """Check and build a scenario from the bytes of a TOML file (``source`` names it in errors)."""
    try:
        doc = tomllib.loads(data.decode("utf-8"))
    except UnicodeDecodeError as exc:
        raise ScenarioError(f"scenario file {source} is not UTF-8 text ({exc})") from None
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"scenario file {source} is not valid TOML: {exc}") from None
    try:
        return _build(doc, source, name, hashlib.sha256(json.dumps(doc, sort_keys=True).encode()).hexdigest())
    except ScenarioError:
        raise
    except (ValueError, TypeError) as exc:
        raise ScenarioError(f"scenario file {source}: {exc}") from None


def _keys(table: Any, where: str, allowed: tuple[str, ...], required: tuple[str, ...] = ()) -> dict[str, Any]:
    if not isinstance(table, dict):
        raise TypeError(f"{where}: expected a table, got {_kind(table)}")
    unknown = sorted(set(table) - set(allowed))
    if unknown:
        raise ValueError(f"{where}: unknown key(s) {unknown}; valid keys: {sorted(allowed)}")
    missing = [k for k in required if k not in table]
    if missing:
        raise ValueError(f"{where}: missing key(s) {missing}")
    return table


def _kind(v: Any) -> str:
    return f"{type(v).__name__} {v!r}"[:80]


def _split(where: str) -> tuple[str, str]:
    """``a.b.c`` as (``a.b``, ``c``); a top-level key belongs to ``scenario``."""
    owner, _, name = where.rpartition(".")
    return owner or "scenario", name


def _number(v: Any, where: str, low: float, high: float, low_open: bool = False) -> float:
    return float(check_number(*_split(where), v, Range(low, high, low_open=low_open)))


def _integer(v: Any, where: str, low: int, high: int) -> int:
    return int(check_number(*_split(where), v, Range(low, high), integer=True))


def _choice(v: Any, where: str, allowed: tuple[str, ...] | list[str]) -> str:
    check_choice(*_split(where), v, allowed)
    return str(v)


def _numbers(v: Any, where: str, n: int, limit: float) -> tuple[float, ...]:
    if not isinstance(v, list) or len(v) != n:
        raise TypeError(f"{where}: expected a list of {n} numbers, got {_kind(v)}")
    return tuple(_number(x, f"{where}[{i}]", -limit, limit) for i, x in enumerate(v))


def _build(doc: dict[str, Any], source: str, name: str, digest: str) -> Scenario:
    top = ("description", "duration", "seeds", "variants", "match", "home", "away", "timeline", "metrics", "recovery")
    _keys(doc, "top level", top, ("duration", "variants"))
    description = doc.get("description", "")
    if not isinstance(description, str):
        raise TypeError(f"description: expected a string, got {_kind(description)}")
    duration = _number(doc["duration"], "duration", 0.0, MAX_DURATION, low_open=True)
    seeds = _integer(doc.get("seeds", 10), "seeds", 1, MAX_SEEDS)
    match = _match(doc.get("match", {}))
    n = match.players_per_team
    dims = FIELD_PRESETS[match.field]
    carpet = (dims.length / 2 + dims.border_strip, dims.width / 2 + dims.border_strip)
    inner = (dims.length / 2 - _MARGIN, dims.width / 2 - _MARGIN)
    variants, custom = _variants(doc["variants"])
    home = _team(doc.get("home", {}), "home", n, carpet, home=True)
    away = _team(doc.get("away", {}), "away", n, carpet, home=False)
    raw = doc.get("timeline", [])
    if not isinstance(raw, list):
        raise TypeError(f"timeline: expected an array of tables ([[timeline]]), got {_kind(raw)}")
    timeline = tuple(_entry(e, f"timeline[{i}]", n, carpet, inner, duration) for i, e in enumerate(raw))
    expanded = sum(1 + (int((min(e.until, duration) - e.time) // e.every) if e.every > 0 else 0) for e in timeline)
    if expanded > MAX_EVENTS:
        raise ValueError(f"timeline: expands to {expanded} events; at most {MAX_EVENTS}")
    metrics = doc.get("metrics", list(METRICS))
    if not isinstance(metrics, list) or not metrics:
        raise TypeError(f"metrics: expected a non-empty list of {list(METRICS)}, got {_kind(metrics)}")
    metrics = tuple(_choice(m, f"metrics[{i}]", METRICS) for i, m in enumerate(metrics))
    rec = _keys(doc.get("recovery", {}), "recovery", ("error_m", "error_deg", "hold_s"))
    recovery = Recovery(
        _number(rec.get("error_m", 0.5), "recovery.error_m", 0.0, 100.0, low_open=True),
        _number(rec.get("error_deg", 30.0), "recovery.error_deg", 0.0, 180.0, low_open=True),
        _number(rec.get("hold_s", 1.0), "recovery.hold_s", 0.0, MAX_DURATION),
    )
    return Scenario(name, source, description, duration, seeds, variants, custom, match, home, away, timeline,
                    metrics, recovery, digest)  # fmt: skip


def _match(table: Any) -> MatchConfig:
    names = tuple(f.name for f in dataclasses.fields(MatchConfig) if f.name not in RESERVED_MATCH_KEYS)
    _keys(table, "match", names)
    return MatchConfig.from_mapping(table)


def _variants(raw: Any) -> tuple[tuple[Variant, ...], bool]:
    if isinstance(raw, list):
        if not raw:
            raise ValueError("variants: the list is empty")
        names = [_choice(v, f"variants[{i}]", VARIANTS) for i, v in enumerate(raw)]
        if len(set(names)) != len(names):
            raise ValueError(f"variants: {names} names a variant twice")
        return tuple(Variant(v, v) for v in names), False
    if not isinstance(raw, dict) or not raw:
        raise TypeError(f"variants: expected a list of localization variants or [variants.NAME] tables, got {raw!r}")
    out = []
    for vname, table in raw.items():
        where = f"variants.{vname}"
        keys = ("localization", "localization_params", "ball", "observation", "vision", "modules")
        t = _keys(table, where, keys, ("localization",))
        loc = _choice(t["localization"], f"{where}.localization", VARIANTS)
        lp = LocalizationParams.from_mapping(t.get("localization_params", {}))
        bp = from_mapping(KalmanBallParams, t.get("ball", {}), f"{where}.ball")
        obs = _choice(t["observation"], f"{where}.observation", ("percepts", "images")) if "observation" in t else None
        vp = from_mapping(VisionParams, t.get("vision", {}), f"{where}.vision")
        modules = _keys(t.get("modules", {}), f"{where}.modules", MODULE_SLOTS)
        for slot, provider in modules.items():
            _choice(provider, f"{where}.modules.{slot}", providers(slot))
        out.append(Variant(vname, loc, lp, bp, obs, vp, tuple(sorted(modules.items()))))
    return tuple(out), True


def _team(table: Any, where: str, n: int, carpet: tuple[float, float], home: bool) -> Team:
    keys = ("brain", "drive", "head", "loop", "trace", "start") + (() if home else ("variant",))
    t = _keys(table, where, keys)
    brain = _choice(t.get("brain", "observer"), f"{where}.brain", BRAINS)
    variant = _choice(t.get("variant", "maturing"), f"{where}.variant", VARIANTS)
    drive = _choice(t.get("drive", "stand"), f"{where}.drive", DRIVES)
    head = _choice(t.get("head", "sweep"), f"{where}.head", HEADS)
    loop = DEFAULT_LOOP
    if "loop" in t:
        if not isinstance(t["loop"], list) or len(t["loop"]) < 2:
            raise TypeError(f"{where}.loop: expected a list of at least 2 [x, y] points, got {_kind(t['loop'])}")
        loop = tuple(_xy(p, f"{where}.loop[{i}]", carpet) for i, p in enumerate(t["loop"]))  # type: ignore[misc]
    trace = tuple(t.get("trace", ()))
    if not home and "trace" in t:
        raise ValueError(f"{where}.trace: only the home team is traced")
    for i, k in enumerate(trace):
        _player(k, f"{where}.trace[{i}]", n)
    start_table = t.get("start", {})
    if not isinstance(start_table, dict):
        raise TypeError(f"{where}.start: expected a table of player number = [x, y, theta], got {_kind(start_table)}")
    start = []
    for key, pose in start_table.items():
        if not key.isdigit():
            raise ValueError(f"{where}.start: key {key!r} is not a player number (1..{n})")
        k = _player(int(key), f"{where}.start.{key}", n)
        start.append((k, _pose(pose, f"{where}.start.{key}", carpet)))
    if brain in ("random", "truth") and home:
        raise ValueError(f"{where}.brain: the home team runs the variant under study; {brain!r} does not localize")
    return Team(brain, variant, drive, head, loop, trace, tuple(sorted(start)))


def _player(k: Any, where: str, n: int) -> int:
    if isinstance(k, bool) or not isinstance(k, int) or not 1 <= k <= n:
        raise ValueError(f"{where}: player {k!r} does not exist; the teams have players 1..{n}")
    return k


def _xy(p: Any, where: str, carpet: tuple[float, float]) -> tuple[float, float]:
    x, y = _numbers(p, where, 2, 1e6)
    if abs(x) > carpet[0] or abs(y) > carpet[1]:
        raise ValueError(f"{where}: ({x:g}, {y:g}) is off the carpet (|x| <= {carpet[0]:g} m, |y| <= {carpet[1]:g} m)")
    return (x, y)


def _pose(p: Any, where: str, carpet: tuple[float, float]) -> tuple[float, float, float]:
    if not isinstance(p, list) or len(p) != 3:
        raise TypeError(f"{where}: expected a pose [x, y, theta], got {_kind(p)}")
    x, y = _xy(p[:2], where, carpet)
    return (x, y, _number(p[2], f"{where}[2]", -2 * math.pi, 2 * math.pi))


def _region(v: Any, where: str, carpet: tuple[float, float], inner: tuple[float, float]) -> Region:
    hx, hy = inner
    if isinstance(v, str):
        _choice(v, where, REGIONS)
        return {"field": Region((-hx, hx), (-hy, hy)), "own-half": Region((-hx, -_MARGIN), (-hy, hy)),
                "opponent-half": Region((_MARGIN, hx), (-hy, hy))}[v]  # fmt: skip
    t = _keys(v, where, ("x", "y", "theta"), ("x", "y"))
    xs = _numbers(t["x"], f"{where}.x", 2, 1e6)
    ys = _numbers(t["y"], f"{where}.y", 2, 1e6)
    th = _numbers(t.get("theta", [-math.pi, math.pi]), f"{where}.theta", 2, 2 * math.pi)
    for lo, hi, lim, axis in ((*xs, carpet[0], "x"), (*ys, carpet[1], "y")):
        if lo > hi or abs(lo) > lim or abs(hi) > lim:
            raise ValueError(
                f"{where}.{axis}: [{lo:g}, {hi:g}] must be ordered and on the carpet (|{axis}| <= {lim:g})"
            )
    if th[0] > th[1]:
        raise ValueError(f"{where}.theta: [{th[0]:g}, {th[1]:g}] must be ordered")
    return Region(xs, ys, th)  # type: ignore[arg-type]


_ENTRY_KEYS = {
    "kidnap": ("team", "number", "pose", "region", "pickup"),
    "penalty": ("team", "number", "code"),
    "ball": ("at", "region", "velocity", "roll_to"),
    "fall": ("team", "number", "duration"),
}


def _entry(
    raw: Any, where: str, n: int, carpet: tuple[float, float], inner: tuple[float, float], duration: float
) -> Entry:
    if not isinstance(raw, dict):
        raise TypeError(f"{where}: expected a table, got {_kind(raw)}")
    kind = _choice(raw.get("kind"), f"{where}.kind", KINDS)
    t = _keys(raw, where, ("kind", "time", "every", "until", *_ENTRY_KEYS[kind]), ("time",))
    time = _number(t["time"], f"{where}.time", 0.0, duration)
    every = _number(t.get("every", 0.0), f"{where}.every", 0.0, MAX_DURATION)
    until = _number(t.get("until", duration), f"{where}.until", time, MAX_DURATION) if every > 0 else 0.0
    if "until" in t and every <= 0:
        raise ValueError(f"{where}.until: only with 'every' (a repeating entry)")
    e: dict[str, Any] = {"kind": kind, "time": time, "every": every, "until": until}
    if kind != "ball":
        if "team" not in t or "number" not in t:
            raise ValueError(f"{where}: a {kind} needs 'team' (home or away) and 'number'")
        e["team"] = TEAMS[_choice(t["team"], f"{where}.team", list(TEAMS))]
        e["number"] = _player(t["number"], f"{where}.number", n)
    if kind == "kidnap":
        if ("pose" in t) == ("region" in t):
            raise ValueError(f"{where}: a kidnap needs either 'pose' or 'region' (one of them)")
        if "pose" in t:
            e["pose"] = _pose(t["pose"], f"{where}.pose", carpet)
        else:
            e["region"] = _region(t["region"], f"{where}.region", carpet, inner)
        pickup = t.get("pickup", False)
        if not isinstance(pickup, bool):
            raise TypeError(f"{where}.pickup: expected true or false, got {_kind(pickup)}")
        e["pickup"] = pickup
    elif kind == "penalty":
        code = t.get("code", "request_for_pickup")
        if isinstance(code, str) and code.lower() in _PENALTIES:
            code = _PENALTIES[code.lower()]
        if isinstance(code, bool) or code not in _PENALTIES.values():
            raise ValueError(
                f"{where}.code: unknown penalty {code!r}; valid: {sorted(_PENALTIES.values())} or {sorted(_PENALTIES)}"
            )
        e["code"] = int(code)
    elif kind == "fall":
        e["duration"] = _number(t.get("duration", 4.0), f"{where}.duration", 0.0, MAX_DURATION, low_open=True)
    else:
        if ("at" in t) == ("region" in t):
            raise ValueError(f"{where}: a ball entry needs either 'at' or 'region' (one of them)")
        if "velocity" in t and "roll_to" in t:
            raise ValueError(f"{where}: give 'velocity' or 'roll_to', not both")
        if "at" in t:
            e["at"] = _xy(t["at"], f"{where}.at", carpet)
        else:
            e["region"] = _region(t["region"], f"{where}.region", carpet, inner)
        if "velocity" in t:
            e["velocity"] = _numbers(t["velocity"], f"{where}.velocity", 2, 50.0)
        if "roll_to" in t:
            e["roll_to"] = _region(t["roll_to"], f"{where}.roll_to", carpet, inner)
    return Entry(**e)


def describe(s: Scenario) -> str:
    """Two lines for ``teamsim scenario list``."""
    m = s.match
    entries = f"{len(s.timeline)} timeline entr{'y' if len(s.timeline) == 1 else 'ies'}"
    variants = ", ".join(v.name for v in s.variants)
    head = f"{s.name}: {m.players_per_team} v {m.players_per_team}, {s.duration:g} s, {entries}, variants {variants}"
    return head + ("\n    " + " ".join(s.description.split()) if s.description else "")


def mapping_of(s: Scenario) -> Mapping[str, Any]:
    """What identifies a scenario in a study directory (name, source, digest)."""
    return {"name": s.name, "source": s.source, "digest": s.digest}
