"""The ``teamsim scenario`` and ``teamsim compare`` commands (registered from above through the
``teamsim.commands`` entry point, so that ``teamsim`` never imports ``scenarios``).

=======================================  ==========================================================================
command                                  what it does
=======================================  ==========================================================================
``teamsim scenario list``                the built-in scenarios with their variants and a description
``teamsim scenario run NAME|FILE``       runs a scenario (``--seeds``, ``--variant``); writes the traces, the
                                         metrics tables, ``error.png`` (localization error over time, events
                                         marked) and ``report.md`` to ``--out`` and prints the main figures
``teamsim compare --scenario ... ``      the cross product of scenarios, variants and paired seeds on ``--workers``
                                         processes or ``--backend ray``; resumable; writes ``report.md``
``teamsim compare --report-only DIR``    the report again, from the stored rows alone
``teamsim vision-eval``                  precision, recall and errors of the vision per feature type on rendered
                                         frames (:mod:`scenarios.vision_eval`; no extra needed)
=======================================  ==========================================================================

``scenario`` and ``compare`` need the studies extra (``pip install -e '.[studies]'``: pandas, pyarrow, matplotlib, Ray).
Bad input (an unknown scenario, variant or key in a scenario file) ends with exit code 2 and one
line naming the file, the key and what is allowed.
"""

from __future__ import annotations

import argparse
import math
import os
import shutil
import time
from pathlib import Path
from typing import Any, TextIO

from scenarios.spec import builtin_names, describe, load

EXTRA = "pip install -e '.[studies]'"
MAX_WORKERS = 512
RESULT_FILES = ("runs.csv", "events.csv", "study.json", "report.md")


def _positive(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}") from None
    if not 1 <= value <= 10_000:
        raise argparse.ArgumentTypeError(f"must be in 1..10000, got {value}")
    return value


def _workers(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number of processes, got {text!r}") from None
    if not 1 <= value <= MAX_WORKERS:
        raise argparse.ArgumentTypeError(f"must be in 1..{MAX_WORKERS}, got {value}")
    return value


def register(sub: Any) -> None:
    """Add ``scenario``, ``compare`` and ``vision-eval`` to the ``teamsim`` subcommands (the entry point)."""
    p = sub.add_parser("scenario", help="list or run scenarios (kidnapping, penalties, ...; needs the studies extra)")
    actions = p.add_subparsers(dest="action", required=True, metavar="ACTION")
    actions.add_parser("list", help="the built-in scenarios").set_defaults(handler=run_list)
    r = actions.add_parser("run", help="run a scenario and write its traces, metrics and plots")
    r.add_argument("scenario", metavar="NAME|FILE", help="a built-in scenario name or a TOML file")
    r.add_argument("--seeds", type=_positive, default=1, help="seeds per variant (default 1)")
    r.add_argument("--variant", nargs="+", default=None, help="variants (default: the scenario's)")
    r.add_argument("--out", type=Path, default=None, help="output directory (default out/scenarios/NAME)")
    r.add_argument("--workers", type=_workers, default=None, help="processes (default: all cores)")
    r.add_argument("--overwrite", action="store_true", help="delete earlier results in --out first (else: resume)")
    r.set_defaults(handler=run_scenario)
    c = sub.add_parser(
        "compare",
        help="compare variants over paired seeds (resumable; local processes or Ray; needs the studies extra)",
        description="Run every (scenario, variant, seed) with paired seeds, write one row per run as it finishes, "
        "and write report.md with confidence intervals, paired tests and survival curves. Run the same command "
        "again to resume an interrupted sweep.",
    )
    c.add_argument("--scenario", nargs="+", default=None, metavar="NAME|FILE", help="scenarios (built-in or TOML)")
    c.add_argument("--variant", nargs="+", default=None, help="variants (default: each scenario's own)")
    c.add_argument("--seeds", type=_positive, default=None, help="paired seeds (default: each scenario's own)")
    c.add_argument("--workers", type=_workers, default=None, help="processes or Ray CPUs (default: all cores)")
    c.add_argument("--backend", choices=["local", "ray"], default="local", help="local processes or Ray tasks")
    c.add_argument("--address", default=None, help="Ray cluster address (default: start a local Ray instance)")
    c.add_argument(
        "--out", type=Path, default=None, help="output directory (default out/compare/SCENARIO[+SCENARIO...])"
    )
    c.add_argument("--retry-failed", action="store_true", help="run the failed runs in --out again")
    c.add_argument("--report-only", type=Path, default=None, metavar="DIR", help="rewrite DIR/report.md from its rows")
    c.add_argument("--no-progress", action="store_true", help="no progress bar")
    c.set_defaults(handler=run_compare)
    from scenarios.vision_eval import add_parser  # the module needs no studies extra

    add_parser(sub)


def _needs_extra() -> None:
    missing = []
    for module in ("pandas", "pyarrow", "matplotlib", "tqdm"):
        try:
            __import__(module)
        except ImportError:
            missing.append(module)
    if missing:
        raise ValueError(f"studies need {', '.join(missing)}: {EXTRA}")


def run_list(args: argparse.Namespace, out: TextIO) -> int:
    """``teamsim scenario list``."""
    for name in builtin_names():
        print(describe(load(name)), file=out)
    return 0


def run_scenario(args: argparse.Namespace, out: TextIO) -> int:
    """``teamsim scenario run``."""
    _needs_extra()
    from scenarios.plots import error_plot
    from scenarios.report import write_report
    from scenarios.sweep import plan, sweep

    scenario = load(args.scenario)
    folder = args.out if args.out is not None else Path("out/scenarios") / scenario.name
    tasks = plan([scenario], args.variant, args.seeds)
    _prepare(folder, args.overwrite)
    start = time.perf_counter()
    result = sweep(tasks, folder, args.workers or 0)
    png = error_plot(folder, scenario.name)
    report = write_report(folder)
    _print_summary(folder, out)
    print(f"{result.ran} run(s) in {time.perf_counter() - start:.1f} s, {result.failed} failed", file=out)
    print(f"results written to {folder} (runs.csv, events.csv, traces/, {png.name}, {report.name})", file=out)
    return 1 if result.failed else 0


def run_compare(args: argparse.Namespace, out: TextIO) -> int:
    """``teamsim compare``."""
    _needs_extra()
    from scenarios.report import write_report
    from scenarios.sweep import plan, sweep

    if args.report_only is not None:
        if not (args.report_only / "runs.csv").exists():
            raise ValueError(f"--report-only {args.report_only}: no runs.csv there (not a study directory)")
        path = write_report(args.report_only)
        print(f"report written to {path}", file=out)
        return 0
    if not args.scenario:
        raise ValueError("--scenario is required (or --report-only DIR)")
    scenarios = [load(s) for s in args.scenario]
    if args.out is None:
        args.out = Path("out/compare") / "+".join(s.name for s in scenarios)
    tasks = plan(scenarios, args.variant, args.seeds)
    _prepare(args.out, overwrite=False)
    start = time.perf_counter()
    result = sweep(
        tasks, args.out, args.workers or 0, args.backend, args.address, args.retry_failed,
        progress=False if args.no_progress else None,
    )  # fmt: skip
    for line in result.repairs:
        print(f"resume: {line}", file=out)
    path = write_report(args.out)
    wall = time.perf_counter() - start
    print(
        f"{len(tasks)} runs: {result.ran} ran now ({result.failed} failed), {result.skipped} already done; "
        f"{wall:.1f} s on {args.workers or os.cpu_count()} {args.backend} worker(s)",
        file=out,
    )
    print(f"report written to {path}", file=out)
    return 0


def _prepare(folder: Path, overwrite: bool) -> None:
    """Refuse a file as --out; with ``overwrite`` delete the results of an earlier run (without it,
    the command resumes the runs in ``folder``)."""
    if folder.exists() and not folder.is_dir():
        raise ValueError(f"--out {folder} exists and is not a directory")
    if overwrite:
        for name in RESULT_FILES:
            (folder / name).unlink(missing_ok=True)
        shutil.rmtree(folder / "traces", ignore_errors=True)


def _print_summary(folder: Path, out: TextIO) -> None:
    """The main figures per variant: position RMSE and, for events, relocalization times."""
    from scenarios.store import read_rows

    rows = read_rows(folder)
    variants = sorted({r["variant"] for r in rows.runs})
    print(f"{'variant':12s} {'runs':>4s} {'pos RMSE m':>10s} {'heading RMSE deg':>16s} {'relocalized':>12s}", file=out)
    for v in variants:
        rs = [r for r in rows.runs if r["variant"] == v and r["status"] == "ok"]
        es = [e for e in rows.events if e["variant"] == v and not math.isnan(e["relocalize_s"])]
        rmse = sum(r["pos_rmse_m"] for r in rs) / len(rs) if rs else math.nan
        head = sum(r["heading_rmse_deg"] for r in rs) / len(rs) if rs else math.nan
        rec = f"{sum(e['relocalized'] for e in es)}/{len(es)}" if es else "-"
        print(f"{v:12s} {len(rs):4d} {rmse:10.3f} {head:16.1f} {rec:>12s}", file=out)
