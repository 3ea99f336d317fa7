"""Paired comparison of two checkouts: the same job run by both at the same time.

On a shared virtual machine the speed of a core can change by a third from one minute to the
next, so two benchmarks run one after the other compare the machine's moods as much as the
code. Here a job is run by the checkout ``--base`` and by this one *at the same time*, and the
ratio of their times is what the code changed. Two modes (``--mode``):

==========  ========================================================================================
mode        how
==========  ========================================================================================
same-core   (default) both processes on one core (``--core``), each timing its own CPU time
            (``time.process_time``): the scheduler interleaves them every few milliseconds, so
            they share every slow phase of that core. On 2026-11-27 the per-round ratios of a
            change stayed within 0.90 to 0.94 where cross-core rounds of the same change ranged
            from 0.57 to 1.48 (the VM's two cores slowed down at different times).
cross-core  one process per core, the cores swapped every round, each timing its wall time
==========  ========================================================================================

The jobs (``--job``):

===============  =====================================================================================
job              what is timed, per unit
===============  =====================================================================================
match            the default 5 v 5 match (``maturing``, percepts; ``--half-seconds``), per robot and
                 cognition frame; a 1 s-half match first loads numba's cache
match-images     the same match on rendered images (``default`` effects, each robot's vision)
soccer-percepts  ``soccer_v0`` 5 v 5, all robots controlled, random continuous actions, percepts,
                 cognition at 30 Hz, ``--steps`` parallel steps after 20 untimed ones, per agent step
soccer-truth     the same in ``truth`` mode, cognition at 10 Hz, per agent step
striker          ``teamsim/Striker-v0``, random discrete actions, 5 ``--steps`` steps after 100
                 untimed ones (resets included), per step
===============  =====================================================================================

==================  ==========================================================================
figure              meaning
==================  ==========================================================================
base_us, this_us    time per unit of each round (us; CPU time in ``same-core`` mode), per checkout
ratio_median        median over rounds of this / base (below 1: this checkout is faster)
ratio_min, max      the range of the per-round ratios
==================  ==========================================================================

Usage: ``python -m benchmarks.paired --base ../teamsim-old [--job match|match-images|...] [--mode same-core]
[--core 0] [--rounds 8] [--half-seconds 60] [--steps 300] [--seed 0] [--json out.json]``;
``--base`` is a checkout of another commit (``git worktree add ../teamsim-old <commit>``).
``cross-core`` needs two cores.
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
    return MatchConfig(seed=seed, observation={observation!r}, cognition=CognitionConfig(),
                       referee=RefereeParams(half_seconds=half))
Match(config({seed} + 1, 1.0)).run()
m = Match(config({seed}, {half}))
t = {clock}()
m.run()
print(({clock}() - t) / (m.frames * len(m.world.robots)) * 1e6)
"""


_ENV = """
import time
import gymnasium
import envs
from envs import soccer_v0
job, steps = {job!r}, {steps}
if job == "striker":
    env = gymnasium.make("teamsim/Striker-v0", observation="truth", action_type="discrete")
    env.action_space.seed(0)
    env.reset(seed=0)
    actions = [env.action_space.sample() for _ in range(100 + 5 * steps)]
    def play(batch):
        for a in batch:
            _, _, term, trunc, _ = env.step(a)
            if term or trunc:
                env.reset()
    play(actions[:100])
    t = {clock}()
    play(actions[100:])
    print(({clock}() - t) / (5 * steps) * 1e6)
else:
    mode, hz = ("percepts", 30.0) if job == "soccer-percepts" else ("truth", 10.0)
    env = soccer_v0.parallel_env(players_per_team=5, control="both", observation=mode, cognition_hz=hz,
                                 start="playing", max_cycles=10**9, obstacle_model="sectors")
    space = env.action_space("home_1")
    space.seed(0)
    env.reset(seed=0)
    actions = [{{a: space.sample() for a in env.possible_agents}} for _ in range(20 + steps)]
    for act in actions[:20]:
        env.step(act)
    t = {clock}()
    for act in actions[20:]:
        env.step(act)
    print(({clock}() - t) / (10 * steps) * 1e6)
"""
JOBS = ("match", "match-images", "soccer-percepts", "soccer-truth", "striker")
_UNIT = {"match": "robot-frame", "match-images": "robot-frame", "striker": "step"}


def _start(tree: Path, core: int, args: argparse.Namespace) -> subprocess.Popen[str]:
    env = {**os.environ, "PYTHONPATH": str(tree)}
    clock = "time.process_time" if args.mode == "same-core" else "time.perf_counter"
    if args.job in ("match", "match-images"):
        observation = "images" if args.job == "match-images" else "percepts"
        code = _PLAY.format(seed=args.seed, half=args.half_seconds, clock=clock, observation=observation)
    else:
        code = _ENV.format(job=args.job, steps=args.steps, clock=clock)
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
    parser.add_argument("--mode", choices=("same-core", "cross-core"), default="same-core")
    parser.add_argument("--core", type=int, default=0, help="the core of the same-core mode")
    parser.add_argument("--rounds", type=int, default=8)
    parser.add_argument("--half-seconds", type=float, default=60.0, help="match halves (s of game time)")
    parser.add_argument(
        "--steps", type=int, default=300, help="timed parallel steps of soccer_v0 (striker: five times as many steps)"
    )
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args(argv)
    base, this = args.base.resolve(), Path(__file__).resolve().parent.parent
    if not (base / "teamsim" / "match.py").is_file():
        raise SystemExit(f"--base {args.base}: not a teamsim checkout (no teamsim/match.py)")
    if args.mode == "cross-core" and len(os.sched_getaffinity(0)) < 2:
        raise SystemExit("paired --mode cross-core needs two cores (one per checkout)")
    if args.mode == "same-core" and args.core not in os.sched_getaffinity(0):
        raise SystemExit(f"--core {args.core} is not a core this process may run on: {sorted(os.sched_getaffinity(0))}")
    if args.rounds < 1 or args.half_seconds <= 0 or args.steps < 10:
        raise SystemExit("--rounds must be >= 1, --half-seconds > 0 and --steps >= 10")
    unit = _UNIT.get(args.job, "agent step")
    base_us: list[float] = []
    this_us: list[float] = []
    for r in range(args.rounds):
        if args.mode == "same-core":
            cores = (args.core, args.core)
        else:
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
