"""The memory soak benchmark (benchmarks/soak.py): its figures, its printed lines and its verdict, not its timing."""

from __future__ import annotations

import itertools
import json
from pathlib import Path

import pytest

import benchmarks.soak as soak

SHORT = ["--episodes", "4", "--warmup", "2", "--every", "2", "--steps", "2", "--players", "1"]


def test_short_soak_prints_rss_and_writes_consistent_figures(tmp_path: Path, capsys) -> None:
    path = tmp_path / "soak.json"
    assert soak.main([*SHORT, "--json", str(path)]) == 0  # a few MiB at most in two episodes
    fig = json.loads(path.read_text())["figures"]
    assert (fig["episodes"], fig["warmup"], fig["steps"], fig["max_growth_mb"]) == (4, 2, 2, 20.0)
    assert fig["rss_warm_mb"] == fig["rss_mb_2"] and fig["rss_end_mb"] == fig["rss_mb_4"]
    assert fig["rss_mb_2"] > 50.0  # a Python process with numpy, numba and a match is never this small
    assert fig["growth_mb"] == pytest.approx(fig["rss_mb_4"] - fig["rss_mb_2"])
    assert fig["growth_per_1000_mb"] == pytest.approx(fig["growth_mb"] * 500.0)
    assert fig["passed"] == 1.0 and fig["growth_mb"] <= 20.0
    out = capsys.readouterr().out
    assert "episode     2: RSS" in out and "episode     4: RSS" in out
    assert "RSS growth from episode 2 to 4" in out and out.rstrip().endswith("passed")


def test_growth_over_the_limit_fails_the_run(tmp_path: Path, capsys, monkeypatch) -> None:
    readings = itertools.count(300.0, 30.0)  # 30 MiB more at every reading: a leak
    monkeypatch.setattr(soak, "rss_mb", lambda: next(readings))
    path = tmp_path / "soak.json"
    assert soak.main([*SHORT, "--json", str(path)]) == 1
    fig = json.loads(path.read_text())["figures"]
    assert fig["growth_mb"] == 30.0 and fig["passed"] == 0.0
    assert capsys.readouterr().out.rstrip().endswith("limit 20.0 MiB: FAILED")
    assert soak.main([*SHORT, "--max-growth-mb", "45"]) == 0  # the same growth under a higher limit


@pytest.mark.parametrize(
    ("argv", "named"),
    [
        (["--episodes", "5", "--warmup", "5"], "--warmup"),
        (["--episodes", "5", "--warmup", "0"], "--warmup"),
        (["--episodes", "5", "--warmup", "2", "--every", "0"], "--every"),
        (["--episodes", "5", "--warmup", "2", "--max-growth-mb", "0"], "--max-growth-mb"),
    ],
)
def test_bad_arguments_are_refused_naming_the_option(argv: list[str], named: str, capsys) -> None:
    with pytest.raises(SystemExit) as stopped:
        soak.main(argv)
    assert stopped.value.code == 2 and named in capsys.readouterr().err
