"""Paired comparison of two checkouts: the same job run by both at the same time.

On a shared virtual machine the speed of a core can change by a third from one minute to the
next, so two benchmarks run one after the other compare the machine's moods as much as the
code. Here a job is run by the checkout ``--base`` and by this one *at the same time*, one
process per core, and the cores are swapped every round; both suffer the same slow phases, and
the ratio of their times is what the code changed. The jobs (``--job``):

===============  =====================================================================================
job              what is timed, per unit
===============  =====================================================================================
match            the default 5 v 5 match (``maturing``, percepts; ``--half-seconds``), per robot and
                 cognition frame; a 1 s-half match first loads numba's cache
soccer-percepts  ``soccer_v0`` 5 v 5, all robots controlled, percepts, cognition at 30 Hz
                 (:func:`benchmarks.bench_envs.bench_soccer`, ``--steps`` parallel steps, best of 3
                 passes), per agent step
soccer-truth     the same in ``truth`` mode, cognition at 10 Hz, per agent step
striker          ``teamsim/Striker-v0`` (:func:`benchmarks.bench_envs.bench_striker`, 2 ``--steps``
                 steps, best of 3 passes), per step
===============  =====================================================================================

==================  ==========================================================================
figure              meaning
==================  ==========================================================================
base_us, this_us    wall time per unit of each round (us), per checkout
ratio_median        median over rounds of this / base (below 1: this checkout is faster)
ratio_min, max      the range of the per-round ratios
==================  ==========================================================================

Usage: ``python -m benchmarks.paired --base ../teamsim-old [--job match] [--rounds 8]
[--half-seconds 60] [--steps 300] [--seed 0] [--json out.json]``; ``--base`` is a checkout of
another commit (``git worktree add ../teamsim-old <commit>``). Needs two cores.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
from pathlib import Path

from benchmarks.common import write_figures

_PLAY = """
import time
from cognition.pipeline import CognitionConfig
from teamsim.match import Match, MatchConfig
from teamsim.referee import RefereeParams
def config(seed, half):
    return MatchConfig(seed=seed, observation="percepts", cognition=CognitionConfig(),
                       referee=RefereeParams(half_seconds=half))
Match(config({seed} + 1, 1.0)).run()
m = Match(config({seed}, {half}))
t = time.perf_counter()
m.run()
print((time.perf_counter() - t) / (m.frames * len(m.world.robots)) * 1e6)
"""


_ENV = """
from benchmarks.bench_envs import bench_soccer, bench_striker
job, steps = {job!r}, {steps}
if job == "striker":
    print(1e6 / bench_striker(2 * steps, 3))
else:
    mode, hz = ("percepts", 30.0) if job == "soccer-percepts" else ("truth", 10.0)
    print(1e6 / (10.0 * bench_soccer(mode, hz, steps, 3)))
"""
JOBS = ("match", "soccer-percepts", "soccer-truth", "striker")
_UNIT = {"match": "robot-frame", "striker": "step"}


def _start(tree: Path, core: int, args: argparse.Namespace) -> subprocess.Popen[str]:
    env = {**os.environ, "PYTHONPATH": str(tree)}
    if args.job == "match":
        code = _PLAY.format(seed=args.seed, half=args.half_seconds)
    else:
        code = _ENV.format(job=args.job, steps=args.steps)
    return subprocess.Popen(
        ["taskset", "-c", str(core), sys.executable, "-c", code], cwd=tree, env=env, stdout=subprocess.PIPE, text=True
    )


def _read(p: subprocess.Popen[str], tree: Path) -> float:
    out, _ = p.communicate()
    if p.returncode != 0:
        raise RuntimeError(f"the job in {tree} failed (exit status {p.returncode})")
    return float(out.strip().splitlines()[-1])


def main(argv: list[str] | None = None) -> dict[str, float]:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--base", type=Path, required=True, help="checkout of the code to compare against")
    parser.add_argument("--job", choices=JOBS, default="match")
    parser.add_argument("--rounds", type=int, default=8)
    parser.add_argument("--half-seconds", type=float, default=60.0, help="match halves (s of game time)")
    parser.add_argument("--steps", type=int, default=300, help="parallel steps of soccer_v0 (striker: twice as many)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args(argv)
    base, this = args.base.resolve(), Path(__file__).resolve().parent.parent
    if not (base / "teamsim" / "match.py").is_file():
        raise SystemExit(f"--base {args.base}: not a teamsim checkout (no teamsim/match.py)")
    if len(os.sched_getaffinity(0)) < 2:
        raise SystemExit("paired needs two cores (one per checkout)")
    if args.rounds < 1 or args.half_seconds <= 0 or args.steps < 10:
        raise SystemExit("--rounds must be >= 1, --half-seconds > 0 and --steps >= 10")
    unit = _UNIT.get(args.job, "agent step")
    base_us: list[float] = []
    this_us: list[float] = []
    for r in range(args.rounds):
        cores = (0, 1) if r % 2 == 0 else (1, 0)
        procs = [
            _start(base, cores[0], args),
            _start(this, cores[1], args),
        ]
        base_us.append(_read(procs[0], base))
        this_us.append(_read(procs[1], this))
        print(f"round {r}: base {base_us[-1]:.1f} us, this {this_us[-1]:.1f} us per {unit}", flush=True)
    ratios = [t / b for b, t in zip(base_us, this_us, strict=True)]
    figures = {"ratio_median": statistics.median(ratios), "ratio_min": min(ratios), "ratio_max": max(ratios)}
    figures.update({f"base_us_{i}": v for i, v in enumerate(base_us)})
    figures.update({f"this_us_{i}": v for i, v in enumerate(this_us)})
    print(
        f"this / base: median {figures['ratio_median']:.3f} (range {figures['ratio_min']:.3f} to "
        f"{figures['ratio_max']:.3f}); base {min(base_us):.0f} to {max(base_us):.0f} us, this "
        f"{min(this_us):.0f} to {max(this_us):.0f} us per {unit} ({args.job})"
    )
    write_figures(args.json, figures)
    return figures


if __name__ == "__main__":
    main()
