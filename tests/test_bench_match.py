"""``benchmarks.bench_match``: the figures it reports and its ``--particles`` option."""

from __future__ import annotations

import math

import pytest

from benchmarks import bench_match
from cognition.representations import RobotPose


@pytest.mark.slow(seconds=7)
def test_particles_option_reaches_every_filter() -> None:
    match, wall, cpu = bench_match.play("percepts", 1.0, 0, "maturing", particles=120)
    counts = [b.pose.n_particles for b in match.brains if isinstance(getattr(b, "pose", None), RobotPose)]
    assert len(counts) == 10
    assert all(0 < n <= 120 for n in counts)  # the default would be 300
    assert wall > 0.0 and cpu > 0.0


@pytest.mark.slow(seconds=15)
def test_figures_of_a_short_run(tmp_path) -> None:
    out = tmp_path / "bench.json"
    figures = bench_match.main(
        ["--observation", "percepts", "--half-seconds", "1", "--seeds", "1", "--core", "-1", "--particles", "150",
         "--json", str(out)]
    )  # fmt: skip
    assert out.exists()
    assert figures["percepts_rtf"] > 0.0 and figures["percepts_us_per_robot_frame"] > 0.0
    assert figures["percepts_rtf_min"] <= figures["percepts_rtf"] <= figures["percepts_rtf_max"]
    assert 0.0 <= figures["percepts_position_error_m"] < 5.0
    assert 0.0 <= figures["percepts_heading_error_deg"] < 180.0 and math.isfinite(figures["percepts_heading_error_deg"])
