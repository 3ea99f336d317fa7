"""The team-play scenario script: resuming from a damaged log, confidence intervals, worker processes
that end with a killed script."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import psutil
import pytest
from scipy import stats

import scenarios.team_play as tp

ROOT = Path(__file__).resolve().parents[1]
SMALL = ["--seeds", "1", "--minutes", "0.05", "--modes", "truth"]
posix_only = pytest.mark.skipif(os.name != "posix", reason="SIGKILL of a parent process is a POSIX test")


def _records(log: Path) -> list[dict]:
    return [json.loads(line) for line in log.read_text().splitlines()]


def _without_wall_time(rec: dict) -> dict:
    return {k: v for k, v in rec.items() if k != "wall_seconds"}


def test_resume_drops_a_torn_last_line_and_plays_that_match_again(tmp_path: Path, capsys) -> None:
    out = tmp_path / "run"
    first = tp.main([*SMALL, "--out", str(out)])
    log = out / "matches.jsonl"
    whole = _records(log)
    assert len(first) == len(whole) == 2 and whole[1]["pairing"] == "scripted-scripted"
    # a run killed while writing the second record: half of its line, no newline
    lines = log.read_text().splitlines(keepends=True)
    log.write_text(lines[0] + lines[1][: len(lines[1]) // 2])
    capsys.readouterr()
    resumed = tp.main([*SMALL, "--out", str(out)])
    printed = capsys.readouterr().out.splitlines()
    torn = [line for line in printed if "torn" in line]
    assert len(torn) == 1 and "line 2" in torn[0] and str(log) in torn[0]
    assert any(line.startswith("seed 0 scripted-scripted truth") for line in printed)  # played again
    again = _records(log)  # every line parses: the torn bytes were cut, not left before the new record
    assert len(again) == 2 and again[0] == whole[0]
    assert _without_wall_time(again[1]) == _without_wall_time(whole[1])  # same seed, same match
    assert [_without_wall_time(r) for r in resumed] == [_without_wall_time(r) for r in whole]


def test_resume_completes_a_whole_last_record_whose_newline_is_missing(tmp_path: Path, capsys) -> None:
    log = tmp_path / "matches.jsonl"
    rec = {"seed": 0, "pairing": "scripted-random", "mode": "truth", "minutes": 0.05, "goals_for": 1}
    rec["goals_against"] = 0
    log.write_text(json.dumps(rec))
    assert tp.read_log(log) == [rec]
    assert log.read_text().endswith("\n") and "torn" not in capsys.readouterr().out


def test_a_damaged_line_before_the_last_is_corruption_named_by_its_line(tmp_path: Path) -> None:
    out = tmp_path / "run"
    out.mkdir()
    log = out / "matches.jsonl"
    good = {"seed": 0, "pairing": "scripted-random", "mode": "truth", "minutes": 0.05, "goals_for": 2}
    good["goals_against"] = 0
    text = json.dumps(good) + "\n" + '{"seed": 1, "pairing": "scr\n' + json.dumps(good) + "\n"
    log.write_text(text)
    with pytest.raises(tp.LogError, match=r"line 2 is not valid JSON.*corrupt"):
        tp.main([*SMALL, "--out", str(out)])
    assert log.read_text() == text  # nothing was cut or appended
    log.write_text(json.dumps(good) + "\n" + json.dumps({"seed": 1, "pairing": "scripted-random"}) + "\n")
    with pytest.raises(tp.LogError, match=r"line 2 is not a match record.*'mode'"):
        tp.read_log(log)
    # the script itself stops with the message, not a traceback
    log.write_text(text)
    run = subprocess.run(
        [sys.executable, "-m", "scenarios.team_play", *SMALL, "--out", str(out)],
        cwd=ROOT, capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert run.returncode == 1 and "line 2 is not valid JSON" in run.stderr and "Traceback" not in run.stderr


@pytest.mark.parametrize("n", [2, 3, 11, 16, 25, 200])
def test_confidence_interval_uses_students_t(n: int) -> None:
    assert tp._t95(n) == pytest.approx(stats.t.ppf(0.975, n - 1), rel=1e-12)
    records = [
        {
            "seed": s,
            "pairing": "scripted-random",
            "mode": "truth",
            "minutes": 1.0,
            "goals_for": s % 4,
            "goals_against": 0,
        }
        for s in range(n)
    ]
    row = tp.summarize(records)[1]
    d = [s % 4 for s in range(n)]
    mean = sum(d) / n
    sd = (sum((x - mean) ** 2 for x in d) / (n - 1)) ** 0.5
    assert f"± {stats.t.ppf(0.975, n - 1) * sd / n**0.5:5.2f}" in row


def _wait_for_children(parent: psutil.Process, timeout: float) -> list[psutil.Process]:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        kids = parent.children()
        if kids:
            return kids
        time.sleep(0.05)
    raise AssertionError(f"process {parent.pid} started no worker within {timeout} s")


def _gone(proc: psutil.Process) -> bool:
    try:
        return proc.status() == psutil.STATUS_ZOMBIE  # dead, waiting to be reaped by whoever adopted it
    except psutil.NoSuchProcess:
        return True


def _assert_all_gone(procs: list[psutil.Process], within: float) -> None:
    deadline = time.monotonic() + within
    while time.monotonic() < deadline and not all(_gone(p) for p in procs):
        time.sleep(0.05)
    alive = [p.pid for p in procs if not _gone(p)]
    for pid in alive:  # do not leave them behind when the test fails
        os.kill(pid, signal.SIGKILL)
    assert not alive, f"worker processes {alive} outlived their killed parent by {within} s"


@posix_only
def test_match_worker_dies_with_the_script_killed_by_sigkill(tmp_path: Path) -> None:
    script = subprocess.Popen(
        [sys.executable, "-m", "scenarios.team_play", "--seeds", "1", "--minutes", "5", "--modes", "truth",
         "--pairings", "scripted-random", "--out", str(tmp_path / "run")],
        cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
    )  # fmt: skip
    try:
        workers = _wait_for_children(psutil.Process(script.pid), timeout=60.0)
        deadline = time.monotonic() + 30.0
        while sum(w.cpu_times().user for w in workers) < 0.5:  # the worker is playing its match
            assert time.monotonic() < deadline, "the worker never started playing"
            time.sleep(0.05)
        script.send_signal(signal.SIGKILL)
        script.wait(timeout=10)
        _assert_all_gone(workers, within=5.0)
    finally:
        if script.poll() is None:
            script.kill()
            script.wait()


@posix_only
def test_watchdog_alone_ends_an_orphaned_worker(tmp_path: Path) -> None:
    # without the Linux prctl (the fallback of other platforms): the watchdog thread must notice
    code = textwrap.dedent(
        """
        import os, time
        from concurrent.futures import ProcessPoolExecutor
        from scenarios.team_play import die_with_parent

        pool = ProcessPoolExecutor(1, initializer=die_with_parent, initargs=(os.getpid(), False))
        pool.submit(os.getpid).result()  # the initializer has run
        pool.submit(time.sleep, 120)
        print("ready", flush=True)
        time.sleep(120)
        """
    )
    parent = subprocess.Popen([sys.executable, "-c", code], cwd=ROOT, stdout=subprocess.PIPE, text=True)
    try:
        assert parent.stdout is not None and parent.stdout.readline().strip() == "ready"
        workers = _wait_for_children(psutil.Process(parent.pid), timeout=10.0)
        parent.send_signal(signal.SIGKILL)
        parent.wait(timeout=10)
        _assert_all_gone(workers, within=5.0)
    finally:
        if parent.poll() is None:
            parent.kill()
            parent.wait()
