"""Play one run of a scenario (scenario, variant, seed) and record its per-frame trace.

:func:`simulate` builds the match of :meth:`Scenario.config` (same seed, same events for every
variant), gives the home team the variant under study and the away team its fixed brains, and
runs it for the scenario's duration. After every cognition frame it records one trace row per
traced home robot (:data:`TRACE_COLUMNS`): the truth from the simulator, the estimate from the
brain's published beliefs. Brains never see the trace; the metrics (:mod:`scenarios.metrics`)
are computed from it afterwards.

Frames: poses and ball positions are in the robot's **team frame** (m, rad; +x toward the
opponent goal), so estimate and truth compare directly.

:func:`run` wraps :func:`simulate` for a sweep: it never raises for a failing run (a bad variant
parameter, a crash in a brain) but returns a failed row with the error, and it returns the trace
as Parquet bytes (:mod:`scenarios.trace`) so that the process that writes the results, possibly
on another machine, stores it.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from cognition.brain import Brain
from cognition.pipeline import CognitionConfig
from cognition.worldmodel.beliefs import CognitionBeliefs
from scenarios.metrics import event_rows, run_row
from scenarios.observer import Observer
from scenarios.spec import Scenario, Team, Variant
from scenarios.trace import TRACE_COLUMNS, Trace
from teamsim.brains import random_brains, scripted_brains
from teamsim.match import Match
from teamsim.placement import world_to_team

_LEVEL = {"invalid": 0, "suspicious": 1, "valid": 2}


@dataclass
class RunOutput:
    """What one run produced: its run row, its event rows and its trace (Parquet bytes, or None)."""

    run: dict[str, Any]
    events: list[dict[str, Any]]
    trace: bytes | None


def _brain(team: Team, index: int, number: int, variant: Variant, scenario: Scenario, sign: float) -> Brain:
    """The brain of player ``number`` of team ``index`` (home: the variant under study)."""
    rules = scenario.match.referee.rules
    if team.brain == "random":
        return random_brains(index, number)
    if team.brain == "truth":
        return scripted_brains(None)(index, number)
    home = variant.cognition()
    cognition = home
    if index != 0:  # the away team sees with the same vision; every other module and parameter is its own default
        cognition = CognitionConfig(localization=team.variant, vision=home.vision, vision_params=home.vision_params)
    lp = dataclasses.replace(cognition.localization_params, return_rule=rules)
    cognition = dataclasses.replace(cognition, localization_params=lp)
    if team.brain == "scripted":
        from cognition.behaviors.team_play import ScriptedBrain

        return ScriptedBrain(cognition)
    start = dict(team.start).get(number)
    loop = tuple((sign * x, sign * y) for x, y in team.loop)
    start_team = world_to_team(sign, *start) if start is not None else None
    return Observer(cognition, team.drive, team.head, loop, start_team)


def simulate(scenario: Scenario, variant: str | Variant, seed: int) -> tuple[Trace, Match]:
    """Play one run; returns its trace and the finished match."""
    v = variant if isinstance(variant, Variant) else scenario.variant(variant)
    config = scenario.config(seed)
    if v.observation is not None:
        config = dataclasses.replace(config, observation=v.observation)
    teams = (scenario.home, scenario.away)

    def brains(team: int, number: int) -> Brain:
        return _brain(teams[team], team, number, v, scenario, 1.0 if team == 0 else -1.0)

    m = Match(config, brains=brains)
    for team_index, team in enumerate(teams):  # known start poses, before the first frame
        for number, pose in team.start:
            m.world.robot(team_index, number).teleport(*pose)
    traced = [(i, r) for i, r in enumerate(m.world.robots) if r.team == 0 and r.number in scenario.traced()]
    rows: list[tuple[float, ...]] = []
    cpu = {i: 0.0 for i, _ in traced}
    while True:
        m.advance_frame()  # stops right after a cognition frame: the truth is that frame's
        if m.finished or m.time > scenario.duration + 1e-9:
            break
        sign = m.referee.sign(0)
        bx, by = m.world.ball.position
        for i, robot in traced:
            brain = m.brains[i]
            beliefs = getattr(brain, "beliefs", None)
            if beliefs is None:
                continue
            provider = getattr(brain, "provider", None)
            spent = provider.localization_cpu_seconds if isinstance(provider, CognitionBeliefs) else math.nan
            step_cpu, cpu[i] = spent - cpu[i], spent
            tx, ty, tth = m.referee.team_pose(robot)
            p = beliefs.pose
            c = p.covariance
            mirrored = math.hypot(p.x + tx, p.y + ty) < math.hypot(p.x - tx, p.y - ty)
            ball = beliefs.ball
            rows.append((
                m.time, robot.number, tx, ty, tth, p.x, p.y, p.theta, c[0, 0], c[0, 1], c[1, 1], c[2, 2],
                float(p.lost), float(robot.penalized), float(robot.picked_up), sign * bx, sign * by,
                ball.field_x, ball.field_y, float(_LEVEL[ball.level]), 1e6 * step_cpu, float(m.referee.state),
                float(mirrored),
            ))  # fmt: skip
    table = np.array(rows, dtype=np.float64).reshape(-1, len(TRACE_COLUMNS))
    meta = {
        "scenario": scenario.name,
        "digest": scenario.digest,
        "variant": v.name,
        "seed": seed,
        "duration": scenario.duration,
        "recovery": dataclasses.asdict(scenario.recovery),
        "metrics": list(scenario.metrics),
        "traced": list(scenario.traced()),
        "timeline": [{"kind": type(e).__name__, **dataclasses.asdict(e)} for e in config.events],
        "log": [e.to_json() for e in m.log.events],
        "score": list(m.referee.score),
    }
    return Trace(table, meta), m


def run(scenario: Scenario, variant: str, seed: int, keep_trace: bool = True) -> RunOutput:
    """One run for a sweep: never raises for a failing run (module docstring)."""
    start = time.perf_counter()
    try:
        trace, _ = simulate(scenario, variant, seed)
        row = run_row(trace)
        events = event_rows(trace)
        data = trace.to_parquet() if keep_trace else None
    except Exception as exc:  # any failure of the run is its result; the sweep goes on
        row = failed_row(scenario.name, variant, seed, f"{type(exc).__name__}: {exc}")
        events, data = [], None
    row["wall_s"] = time.perf_counter() - start
    return RunOutput(row, events, data)


def failed_row(scenario: str, variant: str, seed: int, error: str) -> dict[str, Any]:
    """The run row of a run that failed with ``error`` (metrics NaN)."""
    from scenarios.store import RUN_COLUMNS

    row: dict[str, Any] = {c: math.nan for c in RUN_COLUMNS}
    error = " ".join(error.split())[:500]  # one line in the CSV table
    row.update(scenario=scenario, variant=variant, seed=seed, status="failed", error=error, frames=0, ball_frames=0)
    return row
