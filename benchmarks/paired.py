"""Paired comparison of two checkouts: the default match played by both at the same time.

On a shared virtual machine the speed of a core can change by a third from one minute to the
next, so two benchmarks run one after the other compare the machine's moods as much as the
code. Here the default 5 v 5 match (``maturing``, percepts) is played by the checkout
``--base`` and by this one *at the same time*, one process per core, and the cores are swapped
every round; both suffer the same slow phases, and the ratio of their times per robot-frame is
what the code changed. Each process first plays a 1 s-half match to load numba's cache.

==================  ==========================================================================
figure              meaning
==================  ==========================================================================
base_us, this_us    wall time per robot and cognition frame of each round (us), per checkout
ratio_median        median over rounds of this / base (below 1: this checkout is faster)
ratio_min, max      the range of the per-round ratios
==================  ==========================================================================

Usage: ``python -m benchmarks.paired --base ../teamsim-old [--rounds 8] [--half-seconds 60]
[--seed 0] [--json out.json]``; ``--base`` is a checkout of another commit (``git worktree
add ../teamsim-old <commit>``). Needs two cores.
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


def _start(tree: Path, core: int, seed: int, half: float) -> subprocess.Popen[str]:
    env = {**os.environ, "PYTHONPATH": str(tree)}
    code = _PLAY.format(seed=seed, half=half)
    return subprocess.Popen(
        ["taskset", "-c", str(core), sys.executable, "-c", code], cwd=tree, env=env, stdout=subprocess.PIPE, text=True
    )


def _read(p: subprocess.Popen[str], tree: Path) -> float:
    out, _ = p.communicate()
    if p.returncode != 0:
        raise RuntimeError(f"the match in {tree} failed (exit status {p.returncode})")
    return float(out.strip().splitlines()[-1])


def main(argv: list[str] | None = None) -> dict[str, float]:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--base", type=Path, required=True, help="checkout of the code to compare against")
    parser.add_argument("--rounds", type=int, default=8)
    parser.add_argument("--half-seconds", type=float, default=60.0)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args(argv)
    base, this = args.base.resolve(), Path(__file__).resolve().parent.parent
    if not (base / "teamsim" / "match.py").is_file():
        raise SystemExit(f"--base {args.base}: not a teamsim checkout (no teamsim/match.py)")
    if len(os.sched_getaffinity(0)) < 2:
        raise SystemExit("paired needs two cores (one per checkout)")
    if args.rounds < 1 or args.half_seconds <= 0:
        raise SystemExit("--rounds must be >= 1 and --half-seconds > 0")
    base_us: list[float] = []
    this_us: list[float] = []
    for r in range(args.rounds):
        cores = (0, 1) if r % 2 == 0 else (1, 0)
        procs = [
            _start(base, cores[0], args.seed, args.half_seconds),
            _start(this, cores[1], args.seed, args.half_seconds),
        ]
        base_us.append(_read(procs[0], base))
        this_us.append(_read(procs[1], this))
        print(f"round {r}: base {base_us[-1]:.1f} us, this {this_us[-1]:.1f} us per robot-frame", flush=True)
    ratios = [t / b for b, t in zip(base_us, this_us, strict=True)]
    figures = {"ratio_median": statistics.median(ratios), "ratio_min": min(ratios), "ratio_max": max(ratios)}
    figures.update({f"base_us_{i}": v for i, v in enumerate(base_us)})
    figures.update({f"this_us_{i}": v for i, v in enumerate(this_us)})
    print(
        f"this / base: median {figures['ratio_median']:.3f} (range {figures['ratio_min']:.3f} to "
        f"{figures['ratio_max']:.3f}); base {min(base_us):.0f} to {max(base_us):.0f} us, this "
        f"{min(this_us):.0f} to {max(this_us):.0f} us per robot-frame"
    )
    write_figures(args.json, figures)
    return figures


if __name__ == "__main__":
    main()
