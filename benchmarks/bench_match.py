"""Real-time factor of the default 5 v 5 match on one core, and where its time goes.

The whole job a user runs: ``teamsim match``'s default 5 v 5 match (scripted team play, every
robot on its own cognition stack with ``maturing`` localization), played on one CPU core, on
synthesized percepts, on rendered camera images through vision, or on the truth. The
real-time factor is simulated seconds per wall second of ``Match.run`` (and per CPU second of
this process, which another busy core disturbs less).

With ``--stages`` each match is played a second time with a timer around every stage, and the
wall time per robot and cognition frame is printed stage by stage (the timers cost about a
microsecond per stage and frame, so the real-time factor comes from the untimed run):

==================  =============================================================================
stage               what is timed
==================  =============================================================================
physics             ``World.step``: the walking engines, pymunk, kicks and falls
referee             ``Referee.update``: game states, goals, fouls, penalties
percepts            ``PerceptSynthesizer.synthesize``: the synthesized percepts of all robots
render              ``render_nb``: the camera image of the scene (per seeing robot)
effects             ``ImageEffects.apply``: blur, exposure, white balance, noise
image glue          the rest of ``Match.capture_images`` (camera matrices, image objects)
vision              ``Vision.detect``: pixels to percepts
localization        the localizer's ``update`` around its kernels: input checks, game events,
                    the pose record, the safety net, the strategies' decisions (Python)
loc. kernels        the particle filter's compiled calls: the frame of the built-in strategies
                    (packing the observations, motion, sensor model, pose, the maturing
                    candidates, the resampling), or each of these calls of another strategy
kalman ball         ``KalmanBallModel.update``
ball hypotheses     ``BallHypotheses.update``
team                ``TeamState.update`` and ``team_ball``: teammates' messages, the team ball
obstacles           the obstacle model's ``update``
goal model          ``GoalModel.move_robot``, ``add_percepts``, ``estimate``
behaviour           ``ScriptedBrain._act`` and the head control's ``request``
frame glue          everything else of a cognition frame (sensor frames, odometry, beliefs,
                    messages, localization error bookkeeping)
other               the rest of ``Match.run`` (scene building, scripted events, the loop)
==================  =============================================================================

=====================================  ============================================================
figure                                 meaning
=====================================  ============================================================
<obs>_rtf                              simulated / wall seconds, mean over seeds (one core)
<obs>_rtf_min, <obs>_rtf_max           the slowest and the fastest seed (the spread includes this
                                       machine's run-to-run noise, which can reach 10 %)
<obs>_cpu_rtf                          simulated / CPU seconds of this process
<obs>_us_per_robot_frame               wall time per robot and cognition frame (us)
<obs>_position_error_m                 mean localization error (m; not on the truth)
<obs>_heading_error_deg                mean heading error (degrees; not on the truth)
<obs>_stage_<name>_us                  with ``--stages``: time of a stage per robot-frame (us)
=====================================  ============================================================

With several ``--particles`` counts every figure is named ``<obs>_p<count>_...`` instead, and the
counts take turns seed by seed (seed 0 with each count, then seed 1, ...), so that the machine's
changes of speed fall on all of them alike. ``--images ideal`` or ``harsh`` plays the match on
images with that image-effects preset instead of ``default``, and names its figures
``images_ideal_...`` or ``images_harsh_...``: ``ideal`` shows what the pixel path costs without
effects.

Usage: ``python -m benchmarks.bench_match [--observation percepts images none]
[--localization maturing] [--images default] [--particles N [N ...]] [--half-seconds 60]
[--seeds 2] [--core 0] [--stages] [--json out.json]``. The issue figures: the default match on
percepts and, for vision, the same match on images (bar: 5x real time). ``--particles`` plays
the match with other particle counts, to weigh the filter's cost against its accuracy.
"""

from __future__ import annotations

import argparse
import functools
import os
import time
from collections import defaultdict
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from benchmarks.common import write_figures
from cognition.localization import LocalizationParams
from cognition.pipeline import CognitionConfig
from teamsim.match import Match, MatchConfig
from teamsim.referee import RefereeParams

STAGES = (
    "physics", "referee", "percepts", "render", "effects", "image glue", "vision", "localization", "loc. kernels",
    "kalman ball", "ball hypotheses", "team", "obstacles", "goal model", "behaviour", "frame glue", "other",
)  # fmt: skip


def _targets() -> list[tuple[Any, str, str]]:
    """(owner, attribute, stage) of every timed callable (module docstring)."""
    import cognition.behaviors.head_control as head_control
    import cognition.behaviors.team_play as team_play
    import cognition.localization.base as loc_base
    import cognition.localization.kernels as loc_kernels
    import cognition.localization.maturing as maturing
    import cognition.localization.particle_filter as particle_filter
    import cognition.localization.sensor as sensor
    import cognition.modules as modules
    import cognition.worldmodel.ball as ball
    import cognition.worldmodel.goal as goal
    import cognition.worldmodel.hypotheses as hypotheses
    import cognition.worldmodel.obstacles as obstacles
    import cognition.worldmodel.team as team
    import teamsim.images as images
    import teamsim.match as match
    import teamsim.percepts as percepts
    import teamsim.referee as referee
    import teamsim.world as world
    from cognition.vision.vision import Vision
    from teamsim.image_effects import ImageEffects

    return [
        (world.World, "step", "physics"),
        (referee.Referee, "update", "referee"),
        (percepts.PerceptSynthesizer, "synthesize", "percepts"),
        (images, "render_nb", "render"),
        (ImageEffects, "apply", "effects"),
        (match.Match, "capture_images", "image glue"),
        (Vision, "detect", "vision"),
        (loc_base.Localizer, "update", "localization"),
        (particle_filter, "frame_step_nb", "loc. kernels"),  # the built-in strategies' frame (.frame_step)
        (particle_filter, "resample_step_nb", "loc. kernels"),
        (sensor, "pack_nb", "loc. kernels"),  # the Python steps of another strategy
        (loc_kernels, "frame_nb", "loc. kernels"),
        (maturing, "mature_nb", "loc. kernels"),
        (maturing, "move_candidates_nb", "loc. kernels"),
        (maturing, "inject_matured_nb", "loc. kernels"),
        (particle_filter, "resample_nb", "loc. kernels"),
        (ball.KalmanBallModel, "update", "kalman ball"),
        (hypotheses.BallHypotheses, "update", "ball hypotheses"),
        (team.TeamState, "update", "team"),
        (modules, "team_ball", "team"),
        (obstacles.ObstacleSectors, "update", "obstacles"),
        (obstacles.ObstacleGrid, "update", "obstacles"),
        (goal.GoalModel, "move_robot", "goal model"),
        (goal.GoalModel, "add_percepts", "goal model"),
        (goal.GoalModel, "estimate", "goal model"),
        (team_play.ScriptedBrain, "_act", "behaviour"),
        (head_control.HeadControl, "request", "behaviour"),
        (match.Match, "_cognition", "frame glue"),
    ]


@contextmanager
def stage_timers() -> Iterator[dict[str, float]]:
    """Wrap every timed callable (module docstring) while the block runs; the yielded mapping
    receives each stage's *exclusive* wall time (s): time spent in a timed callable called
    from another one counts for the inner stage only."""
    spent: dict[str, float] = defaultdict(float)
    stack: list[float] = []  # time of the callees of each open timer
    patched: list[tuple[Any, str, Any]] = []

    def timed(fn: Callable[..., Any], stage: str) -> Callable[..., Any]:
        @functools.wraps(fn)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            stack.append(0.0)
            start = time.perf_counter()
            try:
                return fn(*args, **kwargs)
            finally:
                total = time.perf_counter() - start
                inner = stack.pop()
                spent[stage] += total - inner
                if stack:
                    stack[-1] += total

        return wrapper

    for owner, name, stage in _targets():
        original = owner.__dict__[name]
        patched.append((owner, name, original))
        setattr(owner, name, timed(original, stage))
    try:
        yield spent
    finally:
        for owner, name, original in reversed(patched):
            setattr(owner, name, original)


def play(
    observation: str,
    half_seconds: float,
    seed: int,
    localization: str | None,
    particles: int | None = None,
    images: str = "default",
) -> tuple[Match, float, float]:
    """One default 5 v 5 match (``particles``: the particle filter's count instead of the
    default; ``images``: the image-effects preset on images); returns it with its wall and CPU
    seconds of ``run``."""
    cognition = None
    if localization is not None:
        params = LocalizationParams() if particles is None else LocalizationParams(particles=particles)
        cognition = CognitionConfig(localization=localization, localization_params=params)
    extra = {"images": images} if observation == "images" else {}
    config = MatchConfig(
        seed=seed,
        observation=observation,
        cognition=cognition,
        referee=RefereeParams(half_seconds=half_seconds),
        **extra,
    )
    match = Match(config)
    start, cpu = time.perf_counter(), time.process_time()
    match.run()
    return match, time.perf_counter() - start, time.process_time() - cpu


def _summarise(key: str, runs: list[tuple[Match, float, float]]) -> dict[str, float]:
    """Figures of one configuration's matches (one per seed), named ``<key>_...``; prints a line."""
    sim = sum(m.time for m, _, _ in runs)
    wall = sum(w for _, w, _ in runs)
    cpu = sum(c for _, _, c in runs)
    frames = sum(m.frames * len(m.world.robots) for m, _, _ in runs)
    rtfs = [m.time / w for m, w, _ in runs]  # per seed: this machine's run-to-run spread
    figures = {
        f"{key}_rtf": sim / wall, f"{key}_cpu_rtf": sim / cpu, f"{key}_rtf_min": min(rtfs), f"{key}_rtf_max": max(rtfs),
        f"{key}_us_per_robot_frame": 1e6 * wall / frames,
    }  # fmt: skip
    line = f"{key:8s} {sim / wall:6.2f}x real time (seeds {min(rtfs):.2f}..{max(rtfs):.2f}, CPU {sim / cpu:5.2f}x), "
    line += f"{1e6 * wall / frames:6.0f} us per robot-frame"
    summaries = [s for s in (m.localization_errors.summary() for m, _, _ in runs) if s is not None]
    if summaries:
        figures[f"{key}_position_error_m"] = sum(s.position_error_mean for s in summaries) / len(summaries)
        figures[f"{key}_heading_error_deg"] = sum(s.heading_error_mean for s in summaries) / len(summaries)
        line += f", mean position error {figures[f'{key}_position_error_m']:.3f} m"
        line += f", heading {figures[f'{key}_heading_error_deg']:.2f} deg"
    print(line, flush=True)
    return figures


def main(argv: list[str] | None = None) -> dict[str, float]:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--observation", nargs="+", default=["percepts", "images"], choices=["percepts", "images", "none"]
    )
    parser.add_argument("--localization", default="maturing", help="variant on percepts and images (default maturing)")
    parser.add_argument(
        "--particles", type=int, nargs="+", default=None,
        help="particle counts of the filter (default: the variant's, 300); several take turns seed by seed",
    )  # fmt: skip
    parser.add_argument(
        "--images", default="default", choices=["ideal", "default", "harsh"],
        help="image-effects preset of the match on images (default: default)",
    )  # fmt: skip
    parser.add_argument("--half-seconds", type=float, default=60.0, help="length of each half (s of game time)")
    parser.add_argument("--seeds", type=int, default=2)
    parser.add_argument("--core", type=int, default=0, help="the CPU core to run on (-1: leave the affinity)")
    parser.add_argument("--stages", action="store_true", help="also time every stage (a second, timed run)")
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args(argv)
    if args.core >= 0:
        os.sched_setaffinity(0, {args.core})
    play("none", 2.0, 0, None)  # load the compiled kernels of the world before any clock runs
    figures: dict[str, float] = {}
    counts: list[int | None] = list(args.particles) if args.particles else [None]
    for obs in args.observation:
        loc = None if obs == "none" else args.localization
        runs = counts if loc is not None else [None]
        for n in runs:
            play(obs, 1.0, 0, loc, n, args.images)  # load this mode's kernels (numba's cache) before timing
        played: dict[int | None, list[tuple[Match, float, float]]] = {n: [] for n in runs}
        for seed in range(args.seeds):  # the counts take turns, seed by seed: they share the machine's moods
            for n in runs:
                played[n].append(play(obs, args.half_seconds, seed, loc, n, args.images))
        for n in runs:
            key = obs if obs != "images" or args.images == "default" else f"images_{args.images}"
            key = key if len(runs) == 1 else f"{key}_p{n}"
            figures.update(_summarise(key, played[n]))
            if args.stages:
                with stage_timers() as spent:
                    match, w, _ = play(obs, args.half_seconds, 0, loc, n, args.images)
                frames = match.frames * len(match.world.robots)
                spent["other"] = w - sum(spent.values())
                print(f"  per robot-frame (seed 0, timed run: {1e6 * w / frames:.0f} us)")
                for stage in STAGES:
                    if spent.get(stage, 0.0) > 0.0:
                        figures[f"{key}_stage_{stage.replace(' ', '_')}_us"] = 1e6 * spent[stage] / frames
                        print(f"    {stage:16s} {1e6 * spent[stage] / frames:7.1f} us")
    write_figures(args.json, figures)
    return figures


if __name__ == "__main__":
    main()
