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
rerun skips the (seed, pairing, mode) already there, so a stopped run resumes. A run killed
while writing leaves a torn last line: the resume cuts it off the log, says so in one line and
plays that match again; a damaged line before the last one is corruption, and the script stops
naming that line (:class:`LogError`) instead of guessing. Matches run in worker processes
(``--jobs``) that end with the script however it ends, ``kill -9`` included
(:func:`die_with_parent`). At the end the script prints, per pairing and mode, the mean goals
for and against, the mean goal difference with a 95% confidence interval (Student's t over
seeds, ``scipy.stats``), the share of matches in which both teams scored, and the
percepts-minus-truth margin of the goal difference.
"""

from __future__ import annotations

import argparse
import ctypes
import ctypes.util
import json
import math
import multiprocessing
import os
import signal
import sys
import threading
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np
from scipy import stats

from cognition.brain import Brain
from cognition.pipeline import CognitionConfig
from teamsim.brains import random_brains, scripted_brains
from teamsim.match import Match, MatchConfig
from teamsim.referee import RefereeParams

MODES = ("truth", "percepts")
PAIRINGS = ("scripted-random", "scripted-scripted")
RECORD_KEYS = ("seed", "pairing", "mode", "minutes", "goals_for", "goals_against")
"""Keys every line of ``matches.jsonl`` must have."""
_PR_SET_PDEATHSIG = 1
"""``prctl`` option of Linux: the signal this process gets when its parent dies (``<linux/prctl.h>``)."""


class LogError(ValueError):
    """A results log that cannot be resumed from: a damaged line other than the last."""


def _kernel_kills_orphan() -> bool:
    """Ask Linux to SIGKILL this process when its parent dies; False where that is not available."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
        return int(libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)) == 0
    except (OSError, AttributeError):
        return False


def _watch_parent() -> None:
    """Start a daemon thread that ends this process as soon as its multiprocessing parent is gone.

    It blocks on the parent's sentinel (a pipe whose other end only the parent holds open, or a
    process handle on Windows), so it costs nothing while the parent lives and works on every
    platform.
    """
    parent = multiprocessing.parent_process()
    if parent is None:
        return

    def wait_then_exit() -> None:
        parent.join()
        os._exit(1)

    threading.Thread(target=wait_then_exit, name="parent-watchdog", daemon=True).start()


def die_with_parent(parent_pid: int, kernel: bool = True) -> None:
    """Pool initializer: the worker ends when the script that started it ends, even by ``kill -9``.

    On Linux (``kernel``) the kernel sends the worker SIGKILL when its parent dies
    (``prctl(PR_SET_PDEATHSIG)``); everywhere a watchdog thread waits for the parent and exits
    (:func:`_watch_parent`), which also covers other platforms. A parent that died before this
    ran (the worker was already re-parented) ends the worker at once.
    """
    if kernel:
        _kernel_kills_orphan()
    _watch_parent()
    if os.getppid() != parent_pid:
        os._exit(1)


def play(seed: int, pairing: str, mode: str, minutes: float) -> dict[str, Any]:
    """One match; returns its record (goals for the home team first)."""
    if pairing not in PAIRINGS or mode not in MODES:
        raise ValueError(f"unknown pairing {pairing!r} or mode {mode!r}; valid: {PAIRINGS}, {MODES}")
    cognition = None if mode == "truth" else CognitionConfig()  # the full stack: maturing localization
    cfg = MatchConfig(
        seed=seed,
        observation="none" if mode == "truth" else "percepts",
        cognition=cognition,
        referee=RefereeParams(half_seconds=30.0 * minutes),
    )
    home = scripted_brains(cognition, cfg.referee.rules)
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
    """Two-sided 95% quantile of Student's t with ``n - 1`` degrees of freedom (``n`` >= 2 samples)."""
    return float(stats.t.ppf(0.975, n - 1))


def read_log(log: Path) -> list[dict[str, Any]]:
    """The match records of ``log`` (none if it does not exist), ready for appending.

    A last line that is not valid JSON was torn by a run killed while writing it: it is cut off
    the file and reported in one printed line, so that match runs again. A damaged line before
    the last, or a line that is JSON but not a match record, raises :class:`LogError` naming
    the line; the file is then left as it is.
    """
    if not log.exists():
        return []
    data = log.read_bytes()
    lines = data.splitlines(keepends=True)
    last = max((i for i, line in enumerate(lines) if line.strip()), default=-1)
    records: list[dict[str, Any]] = []
    offset = 0
    for i, line in enumerate(lines):
        number = i + 1
        if line.strip():
            try:
                rec = json.loads(line.decode("utf-8"))
            except (UnicodeDecodeError, json.JSONDecodeError) as e:
                if i != last:
                    raise LogError(
                        f"{log} line {number} is not valid JSON ({e}) but lines follow it: the log is corrupt, "
                        f"not torn by a stopped run; repair or remove line {number} and run again"
                    ) from e
                with log.open("r+b") as f:
                    f.truncate(offset)
                print(f"{log}: line {number} was torn by a stopped run; dropped it, that match runs again")
                return records
            missing = [k for k in RECORD_KEYS if not isinstance(rec, dict) or k not in rec]
            if missing:
                raise LogError(f"{log} line {number} is not a match record: it lacks {missing}; got {line[:80]!r}")
            records.append(rec)
        offset += len(line)
    if data and not data.endswith(b"\n"):  # a whole record whose newline was not written yet
        with log.open("ab") as f:
            f.write(b"\n")
    return records


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
    records = read_log(log)
    done = {(r["seed"], r["pairing"], r["mode"], r["minutes"]) for r in records}
    todo = [
        (s, p, m, args.minutes)
        for m in modes
        for p in pairings
        for s in range(args.seeds)
        if (s, p, m, args.minutes) not in done
    ]
    pool = ProcessPoolExecutor(max_workers=max(1, args.jobs), initializer=die_with_parent, initargs=(os.getpid(),))
    with log.open("a") as out, pool:
        for rec in pool.map(play, *zip(*todo, strict=True)) if todo else ():
            out.write(json.dumps(rec) + "\n")
            out.flush()
            records.append(rec)
            print(f"seed {rec['seed']} {rec['pairing']} {rec['mode']}: {rec['goals_for']}:{rec['goals_against']}")
    chosen = [r for r in records if r["minutes"] == args.minutes and r["mode"] in modes and r["pairing"] in pairings]
    print("\n".join(summarize(chosen)))
    return chosen


if __name__ == "__main__":
    try:
        main()
    except LogError as error:
        sys.exit(f"team_play: {error}")
