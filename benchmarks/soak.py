"""Memory soak: the resident set size (RSS) of the process over many resets of a ``percepts`` environment.

A training loop resets one environment thousands of times; anything a reset leaves behind (a
cache that grows with every match, a reference cycle holding a match) shows up here as RSS that
keeps growing. Each *episode* resets one ``soccer_v0`` environment (``observation="percepts"``:
every robot runs localization and the world model; ``start="playing"``; 5 v 5, the home team
controlled) with seed ``k`` and then runs ``--steps`` decision steps of random continuous
actions (from a seeded action space). RSS is read with ``psutil`` after a full garbage
collection, so reference cycles that are merely waiting for the collector do not count.

The first ``--warmup`` episodes compile the numba kernels and fill the bounded caches, so the
growth that counts runs from the end of episode ``--warmup`` to the end of the last episode. The
script prints RSS every ``--every`` episodes and the growth, and exits with status 1 when the
growth exceeds ``--max-growth-mb`` (0 otherwise).

========================  ======================================================================
figure                    meaning
========================  ======================================================================
rss_mb_{k}                RSS (MiB) after episode ``k`` (every ``--every`` episodes and the last)
rss_warm_mb               RSS after episode ``--warmup``
rss_end_mb                RSS after the last episode
growth_mb                 ``rss_end_mb - rss_warm_mb``
growth_per_1000_mb        the growth scaled to 1,000 episodes after the warm-up
max_growth_mb             the limit (``--max-growth-mb``)
passed                    1 if ``growth_mb <= max_growth_mb``, else 0
episodes, warmup, steps   the run's settings
========================  ======================================================================

Usage: ``python -m benchmarks.soak [--episodes 1000] [--warmup 100] [--every 100] [--steps 5]
[--players 5] [--max-growth-mb 20] [--json out/soak.json]``
"""

from __future__ import annotations

import argparse
import gc
import time
from pathlib import Path

import psutil

from benchmarks.common import write_figures
from envs import soccer_v0

MIB = 2.0**20
"""Bytes per MiB (the unit of every RSS figure)."""


def rss_mb() -> float:
    """RSS of this process (MiB) after a full garbage collection."""
    gc.collect()
    return psutil.Process().memory_info().rss / MIB


def soak(episodes: int, warmup: int, every: int, steps: int, players: int) -> dict[str, float]:
    """Run the episodes (module docstring), print RSS as it goes; returns the figures without the verdict."""
    env = soccer_v0.parallel_env(players_per_team=players, observation="percepts", start="playing")
    space = env.action_space(env.possible_agents[0])
    space.seed(0)
    figures: dict[str, float] = {"episodes": episodes, "warmup": warmup, "steps": steps}
    start = time.perf_counter()
    print(f"RSS before the first episode: {rss_mb():.1f} MiB")
    for k in range(1, episodes + 1):
        env.reset(seed=k)
        for _ in range(steps):
            if not env.agents:
                break
            env.step({a: space.sample() for a in env.agents})
        if k % every == 0 or k in (warmup, episodes):
            rss = rss_mb()
            figures[f"rss_mb_{k}"] = rss
            if k % every == 0 or k == episodes:
                print(f"episode {k:5d}: RSS {rss:8.1f} MiB  ({time.perf_counter() - start:6.0f} s)", flush=True)
    env.close()
    figures["rss_warm_mb"] = figures[f"rss_mb_{warmup}"]
    figures["rss_end_mb"] = figures[f"rss_mb_{episodes}"]
    figures["growth_mb"] = figures["rss_end_mb"] - figures["rss_warm_mb"]
    figures["growth_per_1000_mb"] = figures["growth_mb"] * 1000.0 / (episodes - warmup)
    return figures


def main(argv: list[str] | None = None) -> int:
    """Run the soak, print the figures, write JSON if asked; returns the exit status (module docstring)."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--episodes", type=int, default=1000, help="resets of the environment")
    ap.add_argument("--warmup", type=int, default=100, help="episodes before the growth is measured")
    ap.add_argument("--every", type=int, default=100, help="print RSS every this many episodes")
    ap.add_argument("--steps", type=int, default=5, help="decision steps after each reset")
    ap.add_argument("--players", type=int, default=5, help="robots per team (1..7)")
    ap.add_argument("--max-growth-mb", type=float, default=20.0, help="largest RSS growth (MiB) that passes")
    ap.add_argument("--json", type=Path, default=None)
    args = ap.parse_args(argv)
    if args.warmup < 1 or args.episodes <= args.warmup:
        ap.error(f"need 1 <= --warmup < --episodes, got --warmup {args.warmup} and --episodes {args.episodes}")
    if args.every < 1 or args.steps < 0:
        ap.error(f"need --every >= 1 and --steps >= 0, got --every {args.every} and --steps {args.steps}")
    if not args.max_growth_mb > 0:
        ap.error(f"--max-growth-mb must be > 0, got {args.max_growth_mb}")
    figures = soak(args.episodes, args.warmup, args.every, args.steps, args.players)
    figures["max_growth_mb"] = args.max_growth_mb
    passed = figures["growth_mb"] <= args.max_growth_mb
    figures["passed"] = float(passed)
    print(
        f"RSS growth from episode {args.warmup} to {args.episodes}: {figures['growth_mb']:+.1f} MiB "
        f"({figures['growth_per_1000_mb']:+.1f} MiB per 1,000 episodes); limit {args.max_growth_mb:.1f} MiB: "
        + ("passed" if passed else "FAILED")
    )
    write_figures(args.json, figures)
    return 0 if passed else 1


if __name__ == "__main__":
    raise SystemExit(main())
