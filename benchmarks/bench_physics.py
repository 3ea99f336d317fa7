"""Physics + referee throughput for a 5 v 5 match, and the match real-time factor.

Figures printed (and written as JSON with ``--json PATH``):

=========================  ===============================================================
figure                     meaning
=========================  ===============================================================
physics_steps_per_s        World.step + Referee.update per wall second, robots walking on
                           fixed commands, no cognition (100 Hz physics, 2 sub-steps), after
                           a 1 s warm-up run that loads the compiled walking kernels
physics_real_time_factor   simulated seconds per wall second of that loop
match_steps_per_s          physics steps per wall second of the default Match (scripted
                           players on truth beliefs, percepts synthesized) at 30 Hz
match_real_time_factor     simulated seconds per wall second of that match
=========================  ===============================================================

Usage: ``python -m benchmarks.bench_physics [--seconds 120] [--players 5] [--json out.json]``
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import time
from pathlib import Path

from cognition.representations import HeadRequest, WalkRequest
from teamsim.match import Match, MatchConfig
from teamsim.referee import RefereeParams


def bench_physics(seconds: float, players: int) -> dict[str, float]:
    """World + referee only: every robot walks in a slow circle (commands fixed per robot)."""
    match = Match(MatchConfig(players_per_team=players, referee=RefereeParams(half_seconds=10_000)))
    world, referee = match.world, match.referee
    for i, robot in enumerate(world.robots):
        turn = 0.3 + 0.05 * i
        robot.command(WalkRequest(forward=0.2, turn=turn * (1 if i % 2 else -1)), None, HeadRequest())
    steps = round(seconds / world.dt)
    t = match.time
    start = time.perf_counter()
    for k in range(steps):
        events = world.step(t)
        t = (k + 1) * world.dt
        referee.update(t, events)
    wall = time.perf_counter() - start
    return {"physics_steps_per_s": steps / wall, "physics_real_time_factor": seconds / wall}


def bench_match(seconds: float, players: int) -> dict[str, float]:
    """The default match (scripted players on truth beliefs, cognition at 30 Hz) for ``seconds`` of simulated time."""
    match = Match(MatchConfig(players_per_team=players))
    start = time.perf_counter()
    match.run(until=seconds)
    wall = time.perf_counter() - start
    return {"match_steps_per_s": match.steps / wall, "match_real_time_factor": match.time / wall}


def main(argv: list[str] | None = None) -> dict[str, object]:
    """Run both benchmarks, print the figures and optionally write JSON."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=120.0, help="simulated seconds per benchmark")
    parser.add_argument("--players", type=int, default=5, help="players per team")
    parser.add_argument("--json", type=Path, default=None, help="write the figures to this JSON file")
    args = parser.parse_args(argv)
    if not math.isfinite(args.seconds) or args.seconds <= 0:
        parser.error("--seconds must be > 0")
    figures: dict[str, object] = {
        "players_per_team": args.players,
        "simulated_seconds": args.seconds,
        "python": platform.python_version(),
        "machine": platform.machine(),
    }
    bench_physics(1.0, args.players)  # loads the compiled kernels (numba's cache) before anything is timed
    figures.update(bench_physics(args.seconds, args.players))
    figures.update(bench_match(args.seconds, args.players))
    for key, value in figures.items():
        print(f"{key:28s} {value:,.1f}" if isinstance(value, float) else f"{key:28s} {value}")
    if args.json is not None:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(figures, indent=2))
    return figures


if __name__ == "__main__":
    main()
