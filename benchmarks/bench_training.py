"""Training throughput with the environments in 1 or more worker processes (``teamsim train --envs N``).

Each run trains PPO (the default hyperparameters of :mod:`envs.training`, one torch thread) for
``--timesteps`` decisions and divides by the wall time of the whole :func:`envs.training.train`
call, start-up of the worker processes included, as a user of ``teamsim train`` sees it. The
policy update runs in the training process; the workers step the environments, so the gain of
a second process is bounded by the share of the time spent stepping.

=======================================  =================================================================
figure                                   meaning
=======================================  =================================================================
striker_{obs}_p{P}_decisions_per_s       ``teamsim/Striker-v0`` (discrete actions, observation ``obs``),
                                         2 copies in P processes: decisions per wall second
striker_{obs}_speedup                    decisions per second with 2 processes over 1
soccer_{obs}_p{P}_agent_steps_per_s      ``soccer_v0`` 5 v 5 (home team controlled, discrete), 2 matches in
                                         P processes: agent decisions per wall second
soccer_{obs}_speedup                     the same ratio
=======================================  =================================================================

Usage: ``python -m benchmarks.bench_training [--timesteps 6144] [--observation percepts truth]
[--json out/bench_training.json]`` (the script must run as a module or under a ``__main__``
guard: the worker processes start a fresh interpreter).
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from benchmarks.common import write_figures


def rate(env_id: str, env_kwargs: dict[str, object], processes: int, timesteps: int) -> float:
    """Decisions per wall second of one :func:`envs.training.train` run (2 environment copies)."""
    from envs.training import train

    with tempfile.TemporaryDirectory() as tmp:
        start = time.perf_counter()
        train(
            env_id, timesteps=timesteps, out_dir=Path(tmp) / "run", seed=0, env_kwargs=env_kwargs, n_envs=2,
            processes=processes, progress_bar=False, checkpoint_every=10**9,
        )  # fmt: skip
        return timesteps / (time.perf_counter() - start)


def main(argv: list[str] | None = None) -> dict[str, float]:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--timesteps", type=int, default=6144, help="decisions per run")
    parser.add_argument("--observation", nargs="+", default=["percepts", "truth"], choices=["percepts", "truth"])
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args(argv)
    figures: dict[str, float] = {}
    for obs in args.observation:
        tasks = {
            "striker": ("teamsim/Striker-v0", {"action_type": "discrete", "observation": obs}, "decisions_per_s"),
            "soccer": ("soccer_v0", {"action_type": "discrete", "observation": obs}, "agent_steps_per_s"),
        }
        for name, (env_id, kwargs, unit) in tasks.items():
            for processes in (1, 2):
                r = rate(env_id, kwargs, processes, args.timesteps)
                figures[f"{name}_{obs}_p{processes}_{unit}"] = r
                print(f"{name:8s} {obs:9s} {processes} process{'es' if processes > 1 else '  '} {r:8.0f} {unit}")
            speedup = figures[f"{name}_{obs}_p2_{unit}"] / figures[f"{name}_{obs}_p1_{unit}"]
            figures[f"{name}_{obs}_speedup"] = speedup
            print(f"{name:8s} {obs:9s} speedup with 2 processes: {speedup:.2f}x")
    write_figures(args.json, figures)
    return figures


if __name__ == "__main__":
    main()
