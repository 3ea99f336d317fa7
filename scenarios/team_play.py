"""How well the scripted team plays: against random walkers, against itself, on truth and on percepts.

Usage::

    python -m scenarios.team_play --seeds 10 --minutes 10 --out out/team_play \\
        [--modes truth,percepts] [--pairings scripted-random,scripted-scripted] [--jobs 2]

Each match lasts ``--minutes`` of game time (two halves) with 5 players a team. Modes:

========  =======================================================================================
mode      what the scripted players believe
========  =======================================================================================
truth     the oracle providers (no camera: ``observation="none"``)
percepts  the cognition stack on synthesized percepts (``maturing`` localization, Kalman ball,
          team ball, goal and obstacle models)
========  =======================================================================================

The home team is scripted; the away team is ``random`` (random walkers) or ``scripted`` (the
same players, same mode). Each finished match is appended to ``OUT/matches.jsonl`` at once; a
rerun skips the (seed, pairing, mode) already there, so a stopped run resumes. At the end the
script prints, per pairing and mode, the mean goals for and against, the mean goal difference
with a 95% confidence interval (t distribution over seeds), the share of matches in which both
teams scored, and the percepts-minus-truth margin of the goal difference.
"""

from __future__ import annotations

import argparse
import json
import math
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np

from cognition.brain import Brain
from teamsim.brains import random_brains, scripted_brains
from teamsim.match import Match, MatchConfig
from teamsim.referee import RefereeParams

MODES = ("truth", "percepts")
PAIRINGS = ("scripted-random", "scripted-scripted")
_T95 = {1: 12.71, 2: 4.30, 3: 3.18, 4: 2.78, 5: 2.57, 6: 2.45, 7: 2.36, 8: 2.31, 9: 2.26, 10: 2.23, 19: 2.09}


def play(seed: int, pairing: str, mode: str, minutes: float) -> dict[str, Any]:
    """One match; returns its record (goals for the home team first)."""
    if pairing not in PAIRINGS or mode not in MODES:
        raise ValueError(f"unknown pairing {pairing!r} or mode {mode!r}; valid: {PAIRINGS}, {MODES}")
    localization = None if mode == "truth" else "maturing"
    cfg = MatchConfig(
        seed=seed,
        observation="none" if mode == "truth" else "percepts",
        localization=localization,
        referee=RefereeParams(half_seconds=30.0 * minutes),
    )
    home = scripted_brains(localization, cfg.localization_params, cfg.referee.rules, cfg.obstacle_model)
    away = random_brains if pairing == "scripted-random" else home

    def brains(team: int, number: int) -> Brain:
        return home(team, number) if team == 0 else away(team, number)

    s = Match(cfg, brains=brains).run()
    return {
        "seed": seed, "pairing": pairing, "mode": mode, "minutes": minutes, "goals_for": s.score[0],
        "goals_against": s.score[1], "penalties": len(s.penalties), "wall_seconds": s.wall_seconds,
        "position_error": s.localization.position_error_mean if s.localization else None,
    }  # fmt: skip


def _t95(n: int) -> float:
    return _T95.get(n - 1, 2.0 if n > 20 else _T95[min(_T95, key=lambda k: abs(k - (n - 1)))])


def summarize(records: Sequence[dict[str, Any]]) -> list[str]:
    """The printed table (module docstring)."""
    lines = [
        f"{'pairing':18s} {'mode':9s} {'n':>3s} {'for':>6s} {'against':>8s} {'difference (95% CI)':>22s} {'both':>6s}"
    ]
    diffs: dict[tuple[str, str], float] = {}
    for pairing in PAIRINGS:
        for mode in MODES:
            rs = [r for r in records if r["pairing"] == pairing and r["mode"] == mode]
            if not rs:
                continue
            d = np.array([r["goals_for"] - r["goals_against"] for r in rs], dtype=float)
            half = _t95(len(d)) * d.std(ddof=1) / math.sqrt(len(d)) if len(d) > 1 else math.nan
            both = np.mean([r["goals_for"] > 0 and r["goals_against"] > 0 for r in rs])
            gf = np.mean([r["goals_for"] for r in rs])
            ga = np.mean([r["goals_against"] for r in rs])
            diffs[(pairing, mode)] = float(d.mean())
            lines.append(
                f"{pairing:18s} {mode:9s} {len(rs):3d} {gf:6.2f} {ga:8.2f} {d.mean():+10.2f} ± {half:5.2f}     "
                f"{100 * both:5.0f}%"
            )
    for pairing in PAIRINGS:
        if (pairing, "truth") in diffs and (pairing, "percepts") in diffs:
            margin = diffs[(pairing, "percepts")] - diffs[(pairing, "truth")]
            lines.append(f"{pairing}: percepts minus truth goal difference {margin:+.2f} goals per match")
    return lines


def main(argv: list[str] | None = None) -> list[dict[str, Any]]:
    """Run the missing matches, append them to the log, print the table."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--minutes", type=float, default=10.0, help="game time of a match (two halves)")
    ap.add_argument("--out", type=Path, default=Path("out/team_play"))
    ap.add_argument("--modes", default="truth,percepts")
    ap.add_argument("--pairings", default=",".join(PAIRINGS))
    ap.add_argument("--jobs", type=int, default=1)
    args = ap.parse_args(argv)
    modes = [m for m in args.modes.split(",") if m]
    pairings = [p for p in args.pairings.split(",") if p]
    for m in modes:
        if m not in MODES:
            ap.error(f"unknown mode {m!r}; valid: {list(MODES)}")
    for p in pairings:
        if p not in PAIRINGS:
            ap.error(f"unknown pairing {p!r}; valid: {list(PAIRINGS)}")
    if args.seeds < 1 or not args.minutes > 0:
        ap.error("--seeds must be >= 1 and --minutes > 0")
    args.out.mkdir(parents=True, exist_ok=True)
    log = args.out / "matches.jsonl"
    records: list[dict[str, Any]] = []
    if log.exists():
        for line in log.read_text().splitlines():
            if line.strip():
                records.append(json.loads(line))
    done = {(r["seed"], r["pairing"], r["mode"], r["minutes"]) for r in records}
    todo = [
        (s, p, m, args.minutes)
        for m in modes
        for p in pairings
        for s in range(args.seeds)
        if (s, p, m, args.minutes) not in done
    ]
    with log.open("a") as out, ProcessPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        for rec in pool.map(play, *zip(*todo, strict=True)) if todo else ():
            out.write(json.dumps(rec) + "\n")
            out.flush()
            records.append(rec)
            print(f"seed {rec['seed']} {rec['pairing']} {rec['mode']}: {rec['goals_for']}:{rec['goals_against']}")
    chosen = [r for r in records if r["minutes"] == args.minutes and r["mode"] in modes and r["pairing"] in pairings]
    print("\n".join(summarize(chosen)))
    return chosen


if __name__ == "__main__":
    main()
