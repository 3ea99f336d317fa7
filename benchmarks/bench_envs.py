"""Environment throughput: decision steps per second of ``soccer_v0`` and the Gymnasium drills.

Setting of the issues' bars: 5 v 5, all 10 robots controlled (``control="both"``), physics at
100 Hz, random continuous actions, one core; at least 8,000 agent steps/s in ``truth`` mode with
decisions and cognition at 10 Hz, 2,000 in ``percepts`` mode (cognition at 30 Hz), and 2,500
steps/s of ``teamsim/Striker-v0``. Each line prints its bar, if it has one. One *parallel step* is one
decision of all agents (0.1 simulated s); one *agent step* is one agent's decision, which is
what PettingZoo's AEC ``env.step`` and Stable-Baselines3 (one vectorised env per agent under
parameter sharing) count as an environment step. Each figure is the best of ``--passes`` runs
of ``--steps`` parallel steps (the development machine is a shared VM).

==================================  ==========================================================
figure                              meaning
==================================  ==========================================================
{mode}_c{hz}_parallel_steps_per_s   parallel steps per wall second, cognition at ``hz``
{mode}_c{hz}_agent_steps_per_s      the same times the 10 agents
{mode}_c{hz}_real_time_factor       simulated seconds per wall second
striker_truth_steps_per_s           ``teamsim/Striker-v0`` steps per second (truth, discrete)
==================================  ==========================================================

``mode`` is ``truth``, ``percepts`` (the default cognition frame) or ``percepts_lean``: the
same with the env's ``cognition`` argument leaving out the optional modules (:data:`LEAN`:
ball hypotheses, team ball, obstacles, goal model), the speed a policy that needs none of them
can train at. ``images`` is not timed here (``bench_vision`` times the pixel path).

Usage: ``python -m benchmarks.bench_envs [--steps 300] [--passes 3] [--json out/bench_envs.json]``
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import gymnasium

import envs  # noqa: F401  (registers the Gymnasium ids)
from benchmarks.common import write_figures
from envs import soccer_v0

LEAN = {"hypotheses": "none", "team_ball": "none", "goal": "none"}
"""With ``obstacle_model="none"``, the ``percepts_lean`` cognition frame: localization, the
Kalman ball, the teammates' messages and the beliefs only."""


def bench_soccer(
    observation: str, cognition_hz: float, steps: int, passes: int, cognition: dict[str, str] | None = None
) -> float:
    """Best parallel steps per second over ``passes`` runs (5 v 5, both teams controlled)."""
    env = soccer_v0.parallel_env(
        players_per_team=5, control="both", observation=observation, cognition_hz=cognition_hz,
        start="playing", max_cycles=10**9, cognition=cognition,
        obstacle_model="sectors" if cognition is None else "none",
    )  # fmt: skip
    space = env.action_space("home_1")
    space.seed(0)
    best = 0.0
    for k in range(passes):
        env.reset(seed=k)
        actions = [{a: space.sample() for a in env.possible_agents} for _ in range(steps)]
        t = time.perf_counter()
        for act in actions:
            env.step(act)
        best = max(best, steps / (time.perf_counter() - t))
    return best


BARS = {"truth_c10": " (bar 8,000 agent steps/s)", "percepts_c30": " (bar 2,000)", "striker": " (bar 2,500)"}
"""The bars of the issues, printed after their lines (by figure key)."""


def bench_striker(steps: int, passes: int) -> float:
    """Best ``teamsim/Striker-v0`` steps per second (truth, discrete, random actions, resets included)."""
    env = gymnasium.make("teamsim/Striker-v0", observation="truth", action_type="discrete")
    env.action_space.seed(0)
    best = 0.0
    for k in range(passes):
        env.reset(seed=k)
        t = time.perf_counter()
        for _ in range(steps):
            _, _, term, trunc, _ = env.step(env.action_space.sample())
            if term or trunc:
                env.reset()
        best = max(best, steps / (time.perf_counter() - t))
    return best


def main(argv: list[str] | None = None) -> dict[str, float]:
    """Run the benchmark, print the figures, write JSON if asked."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--steps", type=int, default=300, help="parallel steps per pass")
    ap.add_argument("--passes", type=int, default=3)
    ap.add_argument("--json", type=Path, default=None)
    args = ap.parse_args(argv)
    figures: dict[str, float] = {}
    for mode, hz, steps in (
        ("truth", 30.0, args.steps),
        ("truth", 10.0, args.steps),
        ("percepts", 30.0, args.steps // 3),
        ("percepts_lean", 30.0, args.steps // 3),
    ):
        lean = mode == "percepts_lean"
        per_s = bench_soccer("percepts" if lean else mode, hz, max(10, steps), args.passes, LEAN if lean else None)
        key = f"{mode}_c{int(hz)}"
        figures[f"{key}_parallel_steps_per_s"] = per_s
        figures[f"{key}_agent_steps_per_s"] = 10.0 * per_s
        figures[f"{key}_real_time_factor"] = per_s / 10.0
        print(
            f"soccer_v0 5v5 {mode:13s} cognition {int(hz):2d} Hz: {per_s:7.0f} parallel steps/s, "
            f"{10 * per_s:7.0f} agent steps/s, {per_s / 10:5.1f}x real time{BARS.get(key, '')}"
        )
    figures["striker_truth_steps_per_s"] = bench_striker(args.steps * 2, args.passes)
    print(f"teamsim/Striker-v0 truth discrete: {figures['striker_truth_steps_per_s']:.0f} steps/s{BARS['striker']}")
    write_figures(args.json, figures)
    return figures


if __name__ == "__main__":
    main()
