"""The ball-rmse experiment: sane figures, incremental results, resume without recomputing."""

from __future__ import annotations

import json
import math

import pytest

import scenarios.ball_rmse as exp


@pytest.mark.slow
def test_experiment_writes_incrementally_and_resumes(tmp_path, monkeypatch, capsys):
    out = tmp_path / "ball.jsonl"
    table = exp.main(["--seeds", "2", "--out", str(out)])
    lines = [json.loads(x) for x in out.read_text().splitlines()]
    assert len(lines) == 4 and {r["situation"] for r in lines} == {"static", "moving"}
    for s in exp.SITUATIONS:
        for name in exp.MODELS:
            assert len(table[s][name]) == 2 and all(0.0 < v < 1.0 for v in table[s][name])
    printed = capsys.readouterr().out
    assert "RMSE static ball" in printed and "adaptive" in printed

    def boom(*a, **k):
        raise AssertionError("a finished seed was simulated again")

    monkeypatch.setattr(exp, "record", boom)
    again = exp.main(["--seeds", "2", "--out", str(out)])
    assert again == table  # everything came from the file


def test_too_few_seeds_is_a_clear_error(tmp_path):
    with pytest.raises(SystemExit):
        exp.main(["--seeds", "1", "--out", str(tmp_path / "x.jsonl")])


def test_table_has_confidence_intervals():
    table = {s: {n: [0.1, 0.2, 0.3] for n in exp.MODELS} for s in exp.SITUATIONS}
    text = exp.format_table(table)
    assert "20.0 cm" in text and "n= 3" in text
    half = 4.303 * 10.0 / math.sqrt(3)  # t(0.975, 2) * sd / sqrt(n), in cm: 24.8
    assert f"+- {half:4.1f}" in text
