"""Study sweeps on a small scenario: event timing in the trace, paired seeds, resume after an
interruption (in process and after ``kill -9``), failing runs recorded without stopping the
sweep, the Ray backend, and the report rebuilt from the stored rows alone."""

from __future__ import annotations

import math
import os
import shutil
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import scenarios.runner as runner
from scenarios.spec import parse
from scenarios.store import TIMING_COLUMNS, read_rows
from scenarios.sweep import Task, plan, sweep
from scenarios.trace import TRACE_COLUMNS, Trace, trace_path
from teamsim.cli import main

TINY = """
description = "a small kidnapping"
duration = 9.0
seeds = 2
variants = ["reset", "mcl"]
metrics = ["localization", "recovery"]
[match]
players_per_team = 1
referee = { initial_seconds = 0.5, ready_seconds = 1.0, set_seconds = 0.5 }
[home]
brain = "observer"
[away]
brain = "observer"
[[timeline]]
kind = "kidnap"
time = 4.0
team = "home"
number = 1
region = "field"
"""


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    path = tmp_path_factory.mktemp("scenario") / "tiny.toml"
    path.write_text(TINY)
    return path


@pytest.fixture(scope="module")
def scenario(tiny):
    return parse(tiny.read_bytes(), str(tiny), "tiny")


@pytest.fixture(scope="module")
def reference(scenario, tmp_path_factory):
    """An uninterrupted sweep (2 variants x 2 seeds) and its rows."""
    folder = tmp_path_factory.mktemp("reference")
    sweep(plan([scenario], None, None), folder, workers=2, progress=False)
    return folder, read_rows(folder)


def _deterministic(rows: list[dict]) -> list[dict]:
    """Rows sorted by key with the timing columns left out."""
    out = [{k: v for k, v in r.items() if k not in TIMING_COLUMNS} for r in rows]
    return sorted(out, key=lambda r: (r["scenario"], r["variant"], r["seed"], r.get("event", 0)))


def _same(a: list[dict], b: list[dict]) -> bool:
    if len(a) != len(b):
        return False
    for x, y in zip(_deterministic(a), _deterministic(b), strict=True):
        for k in x:
            vx, vy = x[k], y[k]
            if not (vx == vy or (isinstance(vx, float) and math.isnan(vx) and math.isnan(vy))):
                return False
    return True


def test_the_kidnap_happens_at_its_time_in_the_trace_and_variants_see_the_same_world(scenario, reference):
    folder, rows = reference
    assert len(rows.runs) == 4 and all(r["status"] == "ok" for r in rows.runs)
    assert len(rows.events) == 4
    reset, mcl = (Trace.read(trace_path(folder, "tiny", v, 1)) for v in ("reset", "mcl"))
    (kidnap,) = scenario.events(1)
    t = reset.column("time")
    k = int(np.argmax(t >= kidnap.time - 1e-9))
    assert t[k] == pytest.approx(4.0)  # a cognition frame at the event time, right after the teleport
    true = np.column_stack([reset.column(c) for c in ("true_x", "true_y", "true_theta")])
    assert np.allclose(true[k], kidnap.pose, atol=1e-9)  # team frame = world frame for the home team
    assert np.hypot(*(true[k - 1, :2] - true[k, :2])) > 0.3  # the frame before: still at its old pose
    # paired seeds: identical truth, different estimates
    for c in ("time", "true_x", "true_y", "true_theta", "ball_true_x", "penalized"):
        assert np.array_equal(reset.column(c), mcl.column(c)), c
    assert not np.array_equal(reset.column("est_x"), mcl.column("est_x"))
    other = Trace.read(trace_path(folder, "tiny", "reset", 0))
    assert not np.allclose(other.column("true_x")[-1], reset.column("true_x")[-1])  # another seed, another kidnap
    kid = [e for e in rows.events if e["seed"] == 1]
    assert {e["detail"] for e in kid} == {" ".join(f"{v:.3f}" for v in kidnap.pose)}


def test_an_interrupted_sweep_resumes_without_redoing_runs(scenario, reference, tmp_path):
    folder = tmp_path / "study"
    tasks = plan([scenario], None, None)

    class StopSweepError(Exception):
        pass

    def stop_after_two(task, out):
        if len(read_rows(folder).runs) >= 2:
            raise StopSweepError

    with pytest.raises(StopSweepError):
        sweep(tasks, folder, workers=1, progress=False, on_result=stop_after_two)
    first = read_rows(folder)
    assert len(first.runs) == 2
    # a torn last line (a kill while writing) and orphaned event rows are repaired on resume
    with (folder / "runs.csv").open("a") as fh:
        fh.write("tiny,mcl,1,ok,,9.0,2")
    with (folder / "events.csv").open("a") as fh:
        fh.write("tiny,mcl,1,0,kidnap,0,1,4.0,x,4.0,5.0,5.0,0,5.0,0,0.1,2.0,nan,nan,0\n")
    ran: list[tuple] = []
    result = sweep(tasks, folder, workers=1, progress=False, on_result=lambda t, o: ran.append(t.key))
    assert result.ran == 2 and result.skipped == 2 and len(ran) == 2
    assert not {r[:3] for r in ran} & {(r["scenario"], r["variant"], r["seed"]) for r in first.runs}
    assert any("torn" in x for x in result.repairs) and any("unfinished" in x for x in result.repairs)
    again = read_rows(folder)
    assert _same(again.runs, reference[1].runs) and _same(again.events, reference[1].events)
    assert sweep(tasks, folder, workers=1, progress=False).ran == 0  # nothing left to do


@pytest.mark.slow(seconds=12)
def test_kill_9_midway_then_the_same_command_gives_the_same_report(tiny, reference, tmp_path):
    folder = tmp_path / "killed"
    argv = [sys.executable, "-m", "teamsim", "compare", "--scenario", str(tiny), "--out", str(folder),
            "--workers", "1", "--no-progress"]  # fmt: skip
    proc = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and proc.poll() is None:
        runs = folder / "runs.csv"
        if runs.exists() and len(runs.read_text().splitlines()) >= 2:  # header and one finished run
            break
        time.sleep(0.1)
    assert proc.poll() is None, "the sweep ended before it could be killed"
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    assert 1 <= len(read_rows(folder).runs) < 4
    assert main(["compare", "--scenario", str(tiny), "--out", str(folder), "--workers", "1", "--no-progress"]) == 0
    rows = read_rows(folder)
    assert _same(rows.runs, reference[1].runs) and _same(rows.events, reference[1].events)
    ref_folder = reference[0]
    main(["compare", "--report-only", str(ref_folder)])
    timing = "## Timing"
    ours = (folder / "report.md").read_text().split(timing)[0]
    theirs = (ref_folder / "report.md").read_text().split(timing)[0]
    assert ours == theirs
    # the report comes from the stored rows alone: without the traces it is the same, byte for byte
    rows_only = tmp_path / "rows-only"
    rows_only.mkdir()
    for name in ("runs.csv", "events.csv", "study.json"):
        shutil.copy(folder / name, rows_only / name)
    assert main(["compare", "--report-only", str(rows_only)]) == 0
    assert (rows_only / "report.md").read_bytes() == (folder / "report.md").read_bytes()
    for png in folder.glob("*.png"):
        assert (rows_only / png.name).read_bytes() == png.read_bytes()


def test_a_failing_run_is_recorded_and_the_sweep_goes_on(scenario, tmp_path, monkeypatch):
    real = runner.simulate

    def flaky(s, variant, seed):
        if seed == 1 and variant == "mcl":
            raise FloatingPointError("a brain blew up")
        if seed == 0 and variant == "mcl":
            os._exit(3)  # the worker process dies, as in a crash of native code
        return real(s, variant, seed)

    monkeypatch.setattr(runner, "simulate", flaky)  # the pool's forked workers inherit it
    folder = tmp_path / "flaky"
    result = sweep(plan([scenario], None, None), folder, workers=2, progress=False)
    rows = read_rows(folder)
    assert result.failed == 2 and len(rows.runs) == 4
    failed = {(r["variant"], r["seed"]): r["error"] for r in rows.runs if r["status"] == "failed"}
    assert failed[("mcl", 1)] == "FloatingPointError: a brain blew up"
    assert "worker process died" in failed[("mcl", 0)]
    assert all(r["status"] == "ok" for r in rows.runs if r["variant"] == "reset")
    assert {e["variant"] for e in rows.events} == {"reset"}  # failed runs have no event rows
    report = (folder / "report.md").read_text() if (folder / "report.md").exists() else ""
    assert report == ""  # sweep() writes rows only; the command writes the report
    assert main(["compare", "--report-only", str(folder)]) == 0
    text = (folder / "report.md").read_text()
    assert "FloatingPointError: a brain blew up" in text and "worker process died" in text
    monkeypatch.setattr(runner, "simulate", real)
    again = sweep(plan([scenario], None, None), folder, workers=2, progress=False)
    assert again.ran == 0  # failed runs are finished runs ...
    retry = sweep(plan([scenario], None, None), folder, workers=2, progress=False, retry_failed=True)
    assert retry.ran == 2 and retry.failed == 0  # ... until asked to retry them
    assert all(r["status"] == "ok" for r in read_rows(folder).runs)


@pytest.mark.slow(seconds=17)
def test_the_ray_backend_gives_the_same_rows(scenario, reference, tmp_path):
    pytest.importorskip("ray", reason="the studies extra (pip install -e '.[studies]') is not installed")
    folder = tmp_path / "ray"
    tasks = [t for t in plan([scenario], None, None) if t.seed == 1]
    result = sweep(tasks, folder, workers=2, backend="ray", progress=False)
    assert result.ran == 2 and result.failed == 0
    ref = [r for r in reference[1].runs if r["seed"] == 1]
    ref_events = [e for e in reference[1].events if e["seed"] == 1]
    rows = read_rows(folder)
    assert _same(rows.runs, ref) and _same(rows.events, ref_events)
    a = Trace.read(trace_path(folder, "tiny", "reset", 1)).table
    b = Trace.read(trace_path(reference[0], "tiny", "reset", 1)).table
    cpu = list(range(a.shape[1]))
    cpu.remove(TRACE_COLUMNS.index("loc_cpu_us"))  # timing
    assert np.array_equal(a[:, cpu], b[:, cpu], equal_nan=True)


def test_a_changed_scenario_does_not_mix_with_old_rows(scenario, reference, tmp_path):
    changed = parse(TINY.replace("time = 4.0", "time = 5.0").encode(), "tiny2.toml", "tiny")
    with pytest.raises(ValueError, match=r"another version of scenario 'tiny'"):
        sweep([Task(changed, "reset", 0)], reference[0], workers=1, progress=False)


@pytest.mark.slow(seconds=9)
def test_the_ball_noise_scenarios_measure_the_kalman_ball_like_the_darmstadt_table(tmp_path):
    """The study that replaced ``scenarios.ball_rmse``: three observation models on the same
    worlds (one seed). The robot's pose is the same for all three (same lowvar localization on
    the same frames), the ball RMSE is in the range of the paper's Table I (cm to tens of cm),
    and the models differ."""
    from scenarios.spec import load

    folder = tmp_path / "ball"
    sweep(plan([load("ball-noise"), load("ball-noise-rolling")], None, 1), folder, workers=2, progress=False)
    rows = read_rows(folder)
    assert len(rows.runs) == 6 and all(r["status"] == "ok" for r in rows.runs)
    for name, (low, high) in (("ball-noise", (0.05, 0.6)), ("ball-noise-rolling", (0.02, 0.3))):
        runs = {r["variant"]: r for r in rows.runs if r["scenario"] == name}
        assert set(runs) == {"fixed-5deg", "fixed-15deg", "adaptive"}
        assert len({r["pos_rmse_m"] for r in runs.values()}) == 1  # the ball model does not touch the pose
        rmse = [r["ball_rmse_m"] for r in runs.values()]
        assert all(low < v < high for v in rmse), (name, rmse)
        assert len(set(rmse)) == 3 and all(r["ball_frames"] > 600 for r in runs.values())


def test_compare_without_out_writes_under_out_compare(tiny, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["compare", "--scenario", str(tiny), "--variant", "reset", "--seeds", "1", "--no-progress"]) == 0
    rows = read_rows(tmp_path / "out" / "compare" / "tiny")
    assert [(r["variant"], r["seed"], r["status"]) for r in rows.runs] == [("reset", 0, "ok")]
    assert "out/compare/tiny/report.md" in capsys.readouterr().out
