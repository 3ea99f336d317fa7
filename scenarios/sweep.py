"""A study: the cross product of scenarios, variants and paired seeds, run on local processes or Ray.

**Paired seeds.** Run (scenario, variant, seed) plays the match of ``scenario.config(seed)``:
the same match seed, hence the same physics, percept noise, odometry noise and team-message
streams, and the same timeline draws, for every variant. Where the robots under study are
observers (:mod:`scenarios.observer`) their actions never depend on their beliefs, so every
variant sees identical true trajectories and identical sensor frames; only the localization
differs. Where they play (``brain = "scripted"``), a robot acts on its own estimate: once two
variants' estimates differ, the robots walk differently, see different percepts and draw
different amounts from the shared noise streams, so the worlds diverge from that frame on
(same start, same events, same seed). Paired tests remain valid (the pairing removes the
seed's share of the variance) but the pairs are less alike.

**Results, resume.** The driver (this process) writes every finished run at once
(:mod:`scenarios.store`: ``runs.csv`` and ``events.csv``, traces under ``traces/``), so an
interrupted sweep loses nothing it finished; run again with the same arguments it runs only the
missing runs. ``study.json`` records each scenario's digest: rows of a changed scenario file
never mix with old ones (the sweep refuses and names the scenario). A run that fails is
recorded with its error and not run again (``--retry-failed`` runs them again).

**Backends.** ``local``: a process pool of ``workers`` processes that die with the driver,
``kill -9`` included. ``ray``: the same function as Ray tasks (``ray.init(address)``: a local
instance, or an existing cluster whose nodes have teamsim installed); the driver still writes
every row and trace, so resume works the same.
"""

from __future__ import annotations

import json
import os
import sys
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from scenarios.runner import RunOutput, failed_row, run
from scenarios.spec import Scenario, ScenarioError
from scenarios.store import RowWriter, drop_runs, read_rows
from scenarios.team_play import die_with_parent
from scenarios.trace import trace_path, write_atomic

BACKENDS = ("local", "ray")


@dataclass(frozen=True)
class Task:
    """One run of a sweep."""

    scenario: Scenario
    variant: str
    seed: int

    @property
    def key(self) -> tuple[str, str, int]:
        return (self.scenario.name, self.variant, self.seed)


@dataclass
class SweepResult:
    """What a sweep did."""

    ran: int
    skipped: int
    failed: int
    repairs: list[str]


def plan(scenarios: Sequence[Scenario], variants: Sequence[str] | None, seeds: int | None) -> list[Task]:
    """The cross product (each scenario's own variants and seed count when not given); checks
    every variant name against its scenario before anything runs."""
    tasks = []
    names = [s.name for s in scenarios]
    if len(set(names)) != len(names):
        raise ScenarioError(f"two scenarios share a name: {names}; rename one file")
    for s in scenarios:
        chosen = list(variants) if variants else [v.name for v in s.variants]
        for v in chosen:
            s.variant(v)  # ScenarioError naming the scenario and the valid variants
        if len(set(chosen)) != len(chosen):
            raise ScenarioError(f"--variant names a variant twice: {chosen}")
        for seed in range(seeds if seeds is not None else s.seeds):
            tasks.extend(Task(s, v, seed) for v in chosen)
    return tasks


def _check_study(folder: Path, scenarios: Sequence[Scenario]) -> None:
    """Refuse to add rows of a scenario whose content changed since the folder's first sweep."""
    path = folder / "study.json"
    known: dict[str, Any] = json.loads(path.read_text()) if path.exists() else {}
    for s in scenarios:
        old = known.get(s.name)
        if old is not None and old["digest"] != s.digest:
            raise ScenarioError(
                f"{folder} holds results of another version of scenario {s.name!r} (from {old['source']}); "
                "use a new --out directory"
            )
        known[s.name] = {"source": s.source, "digest": s.digest}
    folder.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".json.tmp")
    tmp.write_text(json.dumps(known, indent=2, sort_keys=True) + "\n")
    os.replace(tmp, path)


def _run_task(task: Task) -> RunOutput:
    return run(task.scenario, task.variant, task.seed)


def _pool(workers: int) -> ProcessPoolExecutor:
    return ProcessPoolExecutor(max_workers=workers, initializer=die_with_parent, initargs=(os.getpid(),))


def _isolated(task: Task) -> RunOutput:
    """Run one task in a process of its own; a crash fails only this run."""
    pool = _pool(1)
    try:
        return pool.submit(_run_task, task).result()
    except BrokenProcessPool:
        return RunOutput(failed_row(*task.key, "the worker process died (a crash in native code)"), [], None)
    finally:
        pool.shutdown(wait=False, cancel_futures=True)


def _local(tasks: list[Task], workers: int) -> Iterator[tuple[Task, RunOutput]]:
    """Runs on a process pool, at most ``2 * workers`` submitted at a time. A worker that dies
    breaks the pool: the runs it held are then run again one per process (the one that crashes
    again is failed) and the rest goes on in a new pool."""
    pending = list(tasks)
    while pending:
        pool = _pool(workers)
        futures: dict[Future[RunOutput], Task] = {}
        queue = iter(list(pending))
        broken = False
        try:
            while True:
                for task in queue:
                    futures[pool.submit(_run_task, task)] = task
                    if len(futures) >= 2 * workers:
                        break
                if not futures:
                    break
                done, _ = wait(futures, return_when=FIRST_COMPLETED)
                for f in done:
                    try:
                        out = f.result()
                    except BrokenProcessPool:
                        broken = True
                        continue
                    task = futures.pop(f)
                    pending.remove(task)
                    yield task, out
                if broken:
                    break
        finally:
            pool.shutdown(wait=not broken, cancel_futures=True)
        if broken:
            for task in list(futures.values()):
                pending.remove(task)
                yield task, _isolated(task)


def _ray(tasks: list[Task], workers: int, address: str | None) -> Iterator[tuple[Task, RunOutput]]:
    try:
        import ray
    except ImportError as exc:
        raise ScenarioError(f"--backend ray needs Ray: pip install -e '.[studies]' ({exc})") from None
    started = False
    if not ray.is_initialized():
        kwargs: dict[str, Any] = {"include_dashboard": False, "log_to_driver": False, "configure_logging": False}
        if address:
            ray.init(address=address, **kwargs)
        else:
            ray.init(num_cpus=workers, **kwargs)
        started = True
    try:
        remote = ray.remote(num_cpus=1, max_retries=0)(_run_task)
        refs = {remote.remote(t): t for t in tasks}
        while refs:
            done, _ = ray.wait(list(refs), num_returns=1)
            for ref in done:
                task = refs.pop(ref)
                try:
                    out = ray.get(ref)
                except Exception as exc:  # the worker died; the run is failed, the sweep goes on
                    out = RunOutput(failed_row(*task.key, f"Ray task failed: {type(exc).__name__}: {exc}"), [], None)
                yield task, out
    finally:
        if started:
            ray.shutdown()


def sweep(
    tasks: list[Task],
    folder: Path,
    workers: int = 0,
    backend: str = "local",
    address: str | None = None,
    retry_failed: bool = False,
    progress: bool | None = None,
    on_result: Callable[[Task, RunOutput], None] | None = None,
) -> SweepResult:
    """Run the missing tasks and write each result as it arrives (module docstring).

    ``workers`` 0 means all cores; ``progress`` None shows a bar only on a terminal.
    """
    if backend not in BACKENDS:
        raise ScenarioError(f"unknown backend {backend!r}; valid: {list(BACKENDS)}")
    workers = workers or os.cpu_count() or 1
    scenarios = list({t.scenario.name: t.scenario for t in tasks}.values())
    _check_study(folder, scenarios)
    rows = read_rows(folder)
    done = {r["scenario"] + "\0" + r["variant"] + "\0" + str(r["seed"]): r["status"] for r in rows.runs}
    todo = []
    for t in tasks:
        status = done.get(f"{t.key[0]}\0{t.key[1]}\0{t.key[2]}")
        if status is None or (retry_failed and status == "failed"):
            todo.append(t)
    if retry_failed:
        drop_runs(folder, {t.key for t in todo})
    from tqdm import tqdm

    failed = 0
    bar = tqdm(total=len(tasks), initial=len(tasks) - len(todo), unit="run", dynamic_ncols=True, file=sys.stderr,
               disable=(not sys.stderr.isatty()) if progress is None else not progress)  # fmt: skip
    results = _local(todo, workers) if backend == "local" else _ray(todo, workers, address)
    with RowWriter(folder) as writer, bar:
        for task, out in results:
            if out.trace is not None:
                write_atomic(trace_path(folder, *task.key), out.trace)
            writer.add(out.run, out.events)
            failed += out.run["status"] == "failed"
            bar.set_postfix(failed=failed, refresh=False)
            bar.update(1)
            if on_result is not None:
                on_result(task, out)
    return SweepResult(len(todo), len(tasks) - len(todo), failed, rows.repairs)
