"""``benchmarks.bench_match``: its ``--particles`` option and the figures it reports."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from benchmarks import bench_match
from cognition.representations import RobotPose
from teamsim.image_params import ImageParams


@pytest.mark.slow(seconds=7)
def test_particles_option_reaches_every_filter() -> None:
    match, wall, cpu = bench_match.play("percepts", 1.0, 0, "maturing", particles=120)
    counts = [b.pose.n_particles for b in match.brains if isinstance(getattr(b, "pose", None), RobotPose)]
    assert len(counts) == 10
    assert all(0 < n <= 120 for n in counts)  # the default would be 300
    assert wall > 0.0 and cpu > 0.0


def _fake_match(n: int | None, seed: int) -> SimpleNamespace:
    """What ``main`` reads of a played match: 60 s in 1,800 frames of 10 robots, errors by count."""
    err = 0.1 if n is None else 30.0 / n
    summary = SimpleNamespace(position_error_mean=err, heading_error_mean=10 * err)
    return SimpleNamespace(
        time=60.0, frames=1800, world=SimpleNamespace(robots=[None] * 10),
        localization_errors=SimpleNamespace(summary=lambda: summary),
    )  # fmt: skip


def test_several_counts_take_turns_seed_by_seed(tmp_path, monkeypatch) -> None:
    calls: list[tuple[str, float, int, int | None]] = []

    def fake_play(obs, half, seed, loc, particles=None, images="default"):  # type: ignore[no-untyped-def]
        calls.append((obs, half, seed, particles))
        return _fake_match(particles, seed), 4.0 if particles == 300 else 2.0, 3.0

    monkeypatch.setattr(bench_match, "play", fake_play)
    out = tmp_path / "bench.json"
    figures = bench_match.main(
        ["--observation", "percepts", "--half-seconds", "30", "--seeds", "3", "--core", "-1",
         "--particles", "300", "150", "--json", str(out)]
    )  # fmt: skip
    timed = [(seed, n) for obs, half, seed, n in calls if half == 30.0]
    assert timed == [(0, 300), (0, 150), (1, 300), (1, 150), (2, 300), (2, 150)]  # turns, seed by seed
    assert out.exists() and "percepts_rtf" not in figures
    assert figures["percepts_p300_rtf"] == pytest.approx(15.0) and figures["percepts_p150_rtf"] == pytest.approx(30.0)
    assert figures["percepts_p300_us_per_robot_frame"] == pytest.approx(1e6 * 12.0 / 54_000)
    assert figures["percepts_p300_cpu_rtf"] == pytest.approx(20.0)
    assert figures["percepts_p150_position_error_m"] == pytest.approx(0.2)
    assert figures["percepts_p150_heading_error_deg"] == pytest.approx(2.0)


def test_images_option_reaches_the_match_and_names_the_figures(monkeypatch) -> None:
    presets: list[str] = []

    def fake_play(obs, half, seed, loc, particles=None, images="default"):  # type: ignore[no-untyped-def]
        if obs == "images":  # the world's warm-up plays on no observation
            presets.append(images)
        return _fake_match(particles, seed), 2.0, 3.0

    monkeypatch.setattr(bench_match, "play", fake_play)
    args = ["--observation", "images", "--seeds", "2", "--core", "-1", "--half-seconds", "5"]
    figures = bench_match.main([*args, "--images", "ideal"])
    assert presets == ["ideal"] * 3  # the warm-up run and both seeds
    assert figures["images_ideal_rtf"] == pytest.approx(30.0) and "images_rtf" not in figures
    presets.clear()
    assert "images_rtf" in bench_match.main(args) and set(presets) == {"default"}


def test_play_builds_the_match_with_the_preset(monkeypatch) -> None:
    configs: list = []

    class FakeMatch:
        def __init__(self, config) -> None:  # type: ignore[no-untyped-def]
            configs.append(config)

        def run(self) -> None:
            pass

    monkeypatch.setattr(bench_match, "Match", FakeMatch)
    bench_match.play("images", 1.0, 0, "maturing", images="harsh")
    bench_match.play("percepts", 1.0, 0, "maturing", images="harsh")  # no images: the preset is not used
    assert configs[0].images == ImageParams.preset("harsh") != ImageParams.preset("default")
    assert configs[1].images == ImageParams.preset("default")
