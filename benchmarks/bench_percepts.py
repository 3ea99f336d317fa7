"""Cost of percept synthesis for every robot of a 5 v 5 match, per cognition frame.

Scenes are recorded from a real match (scripted players on truth beliefs, ``--seconds`` of
play), then synthesized again and again; the budget of the camera-model issue is 10
microseconds per robot-frame with the ``default`` preset.

Figures printed (and written as JSON with ``--json PATH``), per preset:

=============================  ==========================================================
figure                         meaning
=============================  ==========================================================
<preset>_us_per_robot_frame    PerceptSynthesizer.synthesize, median over repeats, divided
                               by the number of robots (all robots of one frame per call)
<preset>_us_per_frame          the same per call (all robots)
<preset>_percepts_per_robot    mean percepts per robot-frame in those scenes
capture_us_per_robot_frame     Match.capture: reading the world into a Scene plus synthesis
match_rtf_percepts             real-time factor of a match with percepts (default preset)
match_rtf_no_camera            the same match with ``observation="none"``
=============================  ==========================================================

Usage: ``python -m benchmarks.bench_percepts [--seconds 60] [--repeats 7] [--json out.json]``
"""

from __future__ import annotations

import argparse
import json
import platform
import statistics
import time
from pathlib import Path

import numpy as np

from teamsim.match import Match, MatchConfig
from teamsim.percept_params import PerceptParams
from teamsim.percepts import PerceptSynthesizer, Scene

BUDGET_US = 10.0


def record_scenes(seconds: float, players: int, every: int = 1) -> list[Scene]:
    """Scenes of every ``every``-th cognition frame of a match (copies of the packed arrays)."""
    match = Match(MatchConfig(players_per_team=players, observation="none"))
    scenes: list[Scene] = []
    last = -1
    while match.time < seconds:
        match.step()
        if match.frames != last:
            last = match.frames
            if last % every:
                continue
            live = match.scene()
            s = Scene(players)
            s.observers[:] = live.observers
            s.occluders[:] = live.occluders
            s.ball[:] = live.ball
            s.turn_rates[:] = live.turn_rates
            scenes.append(s)
    return scenes


def bench_synthesis(scenes: list[Scene], preset: str, repeats: int) -> dict[str, float]:
    """Median time of synthesizing all recorded scenes, per robot-frame and per frame."""
    match = Match(MatchConfig(players_per_team=scenes[0].players_per_team, observation="none"))
    syn = PerceptSynthesizer(match.field, PerceptParams.preset(preset), np.random.default_rng(0))
    syn.synthesize(scenes[0])  # compile / load the cache
    robots = scenes[0].observers.shape[0]
    times = []
    count = 0
    for _ in range(repeats):
        count = 0
        start = time.perf_counter()
        for s in scenes:
            for p in syn.synthesize(s):
                count += len(p)
        times.append(time.perf_counter() - start)
    per_frame = statistics.median(times) / len(scenes)
    return {
        f"{preset}_us_per_robot_frame": per_frame / robots * 1e6,
        f"{preset}_us_per_frame": per_frame * 1e6,
        f"{preset}_percepts_per_robot": count / (len(scenes) * robots),
    }


def bench_capture(seconds: float, players: int) -> dict[str, float]:
    """Match.capture (scene from the world + synthesis) timed inside a running match."""
    match = Match(MatchConfig(players_per_team=players))
    match.capture()
    total, calls = 0.0, 0
    while match.time < seconds:
        match.step()
        if match.steps % 3 == 0:
            start = time.perf_counter()
            match.capture()
            total += time.perf_counter() - start
            calls += 1
    return {"capture_us_per_robot_frame": total / calls / (2 * players) * 1e6}


def bench_match(seconds: float, players: int) -> dict[str, float]:
    """Real-time factor with and without the camera model."""
    out = {}
    for key, observation in (("match_rtf_percepts", "percepts"), ("match_rtf_no_camera", "none")):
        match = Match(MatchConfig(players_per_team=players, observation=observation))
        start = time.perf_counter()
        match.run(until=seconds)
        out[key] = match.time / (time.perf_counter() - start)
    return out


def main(argv: list[str] | None = None) -> dict[str, object]:
    """Run the benchmarks, print the figures and optionally write JSON."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=60.0, help="simulated seconds of recorded play")
    parser.add_argument("--players", type=int, default=5, help="players per team")
    parser.add_argument("--repeats", type=int, default=7, help="timing repeats (median is reported)")
    parser.add_argument("--json", type=Path, default=None, help="write the figures to this JSON file")
    args = parser.parse_args(argv)
    if not args.seconds > 0 or args.repeats < 1:
        parser.error("--seconds must be > 0 and --repeats >= 1")
    figures: dict[str, object] = {
        "players_per_team": args.players,
        "simulated_seconds": args.seconds,
        "python": platform.python_version(),
        "machine": platform.machine(),
    }
    scenes = record_scenes(args.seconds, args.players)
    figures["frames"] = len(scenes)
    for preset in ("ideal", "default", "harsh"):
        figures.update(bench_synthesis(scenes, preset, args.repeats))
    figures.update(bench_capture(args.seconds, args.players))
    figures.update(bench_match(args.seconds, args.players))
    for key, value in figures.items():
        print(f"{key:32s} {value:,.2f}" if isinstance(value, float) else f"{key:32s} {value}")
    cost = figures["default_us_per_robot_frame"]
    verdict = "within" if isinstance(cost, float) and cost <= BUDGET_US else "OVER"
    print(f"budget: {BUDGET_US:.0f} us per robot-frame (default preset) -> {verdict}")
    if args.json is not None:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(figures, indent=2))
    return figures


if __name__ == "__main__":
    main()
