"""Python function calls per unit of work: a speed figure that the machine's mood cannot move.

The time of a cognition frame is mostly Python between compiled kernels (README, "where the
time of a cognition frame goes"), and on a shared virtual machine wall times of the same code
wander by a quarter from minute to minute. The number of calls does not: one seed and one
configuration make the same calls, so it shows what a change did to the Python glue exactly,
where a timed benchmark needs paired runs (:mod:`benchmarks.paired`) and still sees noise.

Each job runs once without counting (numba's caches load, lazy tables fill), then once under
:mod:`cProfile`, whose call counts are exact: the same command gives the same counts. A job's
counts depend a little on the jobs run before it in the process (caches they filled), so compare
counts of the same command line. A call is counted as

======================  ======================================================================
kind                    what
======================  ======================================================================
python                  a function or method written in Python (teamsim, cognition, envs,
                        the libraries they call: pymunk's wrappers, gymnasium's wrappers, ...)
kernel                  a call of a compiled numba function from Python (its dispatch costs
                        1 to 3 us: typing of every argument)
builtin                 a function of C (builtins such as ``min``, numpy functions and
                        methods, ``math``, pymunk's C calls)
======================  ======================================================================

======================================  =========================================================
figure                                  meaning
======================================  =========================================================
<job>_python_calls_per_<unit>           Python calls per unit (see ``--job``)
<job>_kernel_calls_per_<unit>           compiled-kernel calls per unit
<job>_builtin_calls_per_<unit>          C calls per unit
<job>_profiled_us_per_<unit>            wall time per unit under the profiler (not a speed figure:
                                        the profiler slows Python calls far more than C)
======================================  =========================================================

Jobs and units: ``match`` (the default 5 v 5 match, ``maturing``, percepts, seed 0,
``--half-seconds`` halves) per robot-frame (one robot's cognition frame and its share of the
physics between frames); ``soccer-percepts`` (``soccer_v0`` 5 v 5, all robots controlled,
random continuous actions, cognition at 30 Hz, ``--steps`` parallel steps) and
``soccer-truth`` (the same on the truth at 10 Hz) per agent step; ``striker``
(``teamsim/Striker-v0``, discrete random actions, 10 ``--steps`` steps) per step. ``--top``
lists the Python functions and kernels called most per unit.

Usage: ``python -m benchmarks.bench_calls [--job match soccer-percepts soccer-truth striker]
[--half-seconds 10] [--steps 100] [--top 15] [--json out/bench_calls.json]``
"""

from __future__ import annotations

import argparse
import cProfile
import pstats
import sys
import time
from collections.abc import Callable
from pathlib import Path

import gymnasium
import numba

import envs  # noqa: F401  (registers the Gymnasium ids)
from benchmarks.common import write_figures
from cognition.pipeline import CognitionConfig
from envs import soccer_v0
from teamsim.match import Match, MatchConfig
from teamsim.referee import RefereeParams

JOBS = ("match", "soccer-percepts", "soccer-truth", "striker")
UNITS = {"match": "robot_frame", "soccer-percepts": "agent_step", "soccer-truth": "agent_step", "striker": "step"}

Key = tuple[str, int, str]
"""A profiled function: (file, first line, name), as :mod:`pstats` keys them."""


def _match_job(half_seconds: float) -> tuple[Callable[[], None], Callable[[], float]]:
    def config(seed: int, half: float) -> MatchConfig:
        return MatchConfig(
            seed=seed, observation="percepts", cognition=CognitionConfig(), referee=RefereeParams(half_seconds=half)
        )

    Match(config(1, 1.0)).run()  # caches
    match = Match(config(0, half_seconds))
    return match.run, lambda: float(match.frames * len(match.world.robots))


def _soccer_job(observation: str, hz: float, steps: int) -> tuple[Callable[[], None], Callable[[], float]]:
    env = soccer_v0.parallel_env(
        players_per_team=5, control="both", observation=observation, cognition_hz=hz, start="playing",
        max_cycles=10**9, obstacle_model="sectors",
    )  # fmt: skip
    space = env.action_space("home_1")
    space.seed(0)
    env.reset(seed=0)
    actions = [{a: space.sample() for a in env.possible_agents} for _ in range(steps + 10)]
    for act in actions[:10]:  # caches
        env.step(act)

    def run() -> None:
        for act in actions[10:]:
            env.step(act)

    return run, lambda: float(steps * len(env.possible_agents))


def _striker_job(steps: int) -> tuple[Callable[[], None], Callable[[], float]]:
    env = gymnasium.make("teamsim/Striker-v0", observation="truth", action_type="discrete")
    env.action_space.seed(0)
    env.reset(seed=0)
    actions = [env.action_space.sample() for _ in range(steps + 50)]

    def play(batch: list[int]) -> None:
        for a in batch:
            _, _, term, trunc, _ = env.step(a)
            if term or trunc:
                env.reset()

    play(actions[:50])  # caches
    return lambda: play(actions[50:]), lambda: float(steps)


def _kernels() -> set[Key]:
    """The profile keys of every numba function loaded so far (compiled functions show up in a
    profile under their Python function's file, line and name)."""
    keys: set[Key] = set()
    for module in list(sys.modules.values()):
        for value in list(getattr(module, "__dict__", {}).values()):
            if isinstance(value, numba.core.registry.CPUDispatcher):
                code = value.py_func.__code__
                keys.add((code.co_filename, code.co_firstlineno, code.co_name))
    return keys


def count(job: str, half_seconds: float, steps: int, top: int) -> dict[str, float]:
    """Run ``job`` once under the profiler; its figures (module docstring), printed with the
    ``top`` Python functions and kernels called most per unit."""
    if job == "match":
        run, units = _match_job(half_seconds)
    elif job == "striker":
        run, units = _striker_job(10 * steps)
    else:
        run, units = _soccer_job(
            "percepts" if job == "soccer-percepts" else "truth", 30.0 if "percepts" in job else 10.0, steps
        )
    profile = cProfile.Profile()
    start = time.perf_counter()
    profile.runcall(run)
    wall = time.perf_counter() - start
    stats = pstats.Stats(profile).stats  # type: ignore[attr-defined]
    kernels = _kernels()
    n = units()
    calls = {"python": 0, "kernel": 0, "builtin": 0}
    rows: list[tuple[int, str, str]] = []
    for key, (_, ncalls, *_rest) in stats.items():
        file, line, name = key
        kind = "kernel" if key in kernels else ("builtin" if file == "~" else "python")
        calls[kind] += ncalls
        where = name if file == "~" else f"{file.split('/site-packages/')[-1].split('/work/main/')[-1]}:{line}({name})"
        rows.append((ncalls, kind, where))
    unit = UNITS[job]
    key = job.replace("-", "_")
    figures = {f"{key}_{kind}_calls_per_{unit}": c / n for kind, c in calls.items()}
    figures[f"{key}_profiled_us_per_{unit}"] = wall / n * 1e6
    print(
        f"{job}: {calls['python'] / n:.1f} Python, {calls['kernel'] / n:.2f} kernel and {calls['builtin'] / n:.1f} "
        f"C calls per {unit.replace('_', '-')} ({n:.0f} units; {wall / n * 1e6:.0f} us each under the profiler)"
    )
    for ncalls, kind, where in sorted((r for r in rows if r[1] != "builtin"), reverse=True)[:top]:
        print(f"  {ncalls / n:8.2f}  {kind:7s}  {where}")
    return figures


def main(argv: list[str] | None = None) -> dict[str, float]:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--job", nargs="+", choices=JOBS, default=list(JOBS))
    parser.add_argument("--half-seconds", type=float, default=10.0, help="match halves (s of game time)")
    parser.add_argument(
        "--steps", type=int, default=100, help="parallel steps of soccer_v0 (striker: ten times as many)"
    )
    parser.add_argument("--top", type=int, default=15, help="Python functions and kernels to list per job")
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args(argv)
    if args.half_seconds <= 0 or args.steps < 1 or args.top < 0:
        raise SystemExit("--half-seconds must be > 0, --steps >= 1 and --top >= 0")
    figures: dict[str, float] = {}
    for job in args.job:
        figures.update(count(job, args.half_seconds, args.steps, args.top))
    write_figures(args.json, figures)
    return figures


if __name__ == "__main__":
    main()
