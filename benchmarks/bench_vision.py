"""Frames per second of the vision pipeline, and a match whose robots see through it.

Camera images are rendered (``default`` effects) for every robot of scenes recorded from a
5 v 5 match, then :meth:`cognition.vision.Vision.detect` runs on each of them on one core,
per line method and resolution. The budget of the vision issue: at least 2,000 frames/s at
320 x 240 with the ``dnt`` method; the cost at 640 x 480 is reported. Rendering is not
timed, only vision.

The match figures run the default 5 v 5 match with ``localization="maturing"`` twice on the
same seeds: once on synthesized percepts, once on rendered images through vision
(``observation="images"``), and report each one's real-time factor (one core) and mean
localization error. The issue's bar: images within 1.5x of the percepts' error, at >= 5x
real time. The default 60 s matches are a quick look, not the bar's test: rare resets to the
mirrored pose make the ratio grow with the match (on 2026-11-26 it was 0.80 over two 60 s
matches but 2.3 and 4.4 on two default-length matches, ``--match-seconds 1200``).

=====================================  =====================================================
figure                                 meaning
=====================================  =====================================================
<WxH>_<method>_frames_per_s            Vision.detect, median over repeats, all robots' images
<WxH>_<method>_us_per_frame            the same as microseconds per image
<WxH>_<method>_percepts_per_frame      mean percepts reported per image (a sanity check)
match_<obs>_rtf                        real-time factor of the match (simulated / wall time)
match_<obs>_position_error_m           mean position error of the localizing robots (m)
match_images_error_ratio               images error / percepts error
=====================================  =====================================================

Usage: ``python -m benchmarks.bench_vision [--seconds 20] [--repeats 3] [--match-seconds 60]
[--seeds 2] [--json out.json]`` (``--match-seconds 0`` skips the matches).
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import numpy as np

from benchmarks.bench_percepts import record_scenes
from benchmarks.common import write_figures
from cognition.camera import CameraMatrix, CameraRig
from cognition.pipeline import CognitionConfig
from cognition.vision import METHODS, Vision, VisionParams
from teamsim.images import ImageRenderer
from teamsim.match import Match, MatchConfig
from teamsim.referee import RefereeParams

BUDGET_FPS = 2000.0
RESOLUTIONS = ((320, 240), (640, 480))


def render_frames(seconds: float, size: tuple[int, int], colours: str) -> list[tuple[np.ndarray, CameraMatrix]]:
    """Every seeing robot's image (default effects) of the scenes of ``seconds`` of a match."""
    scenes = record_scenes(seconds, 5, every=3)
    match = Match(MatchConfig(players_per_team=5, observation="none"))
    ren = ImageRenderer(match.field, colours, CameraRig().with_resolution(*size), "default", np.random.default_rng(0))
    frames = []
    for s in scenes:
        for r in range(s.observers.shape[0]):
            if s.observers[r, 9] > 0.5:
                frames.append((ren.render(s, r), ren.camera_matrix(s, r)))
    return frames


def bench_detect(
    frames: list[tuple[np.ndarray, CameraMatrix]], method: str, colours: str, repeats: int
) -> tuple[float, float]:
    """(median frames per second, mean percepts per frame) of Vision.detect over ``frames``."""
    vision = Vision(VisionParams(method=method), scheme=colours)  # type: ignore[arg-type]
    vision.detect(*frames[0])  # compile / load the cache
    rates = []
    count = 0
    for _ in range(repeats):
        count = 0
        start = time.perf_counter()
        for image, camera in frames:
            count += len(vision.detect(image, camera))
        rates.append(len(frames) / (time.perf_counter() - start))
    return statistics.median(rates), count / len(frames)


def bench_match(observation: str, seconds: float, seeds: int) -> tuple[float, float]:
    """(real-time factor, mean position error in m) of maturing 5 v 5 matches over ``seeds`` seeds."""
    sim = wall = 0.0
    errors = []
    for seed in range(seeds):
        config = MatchConfig(
            seed=seed, observation=observation, cognition=CognitionConfig(),  # maturing
            referee=RefereeParams(half_seconds=seconds / 2),
        )  # fmt: skip
        match = Match(config)
        start = time.perf_counter()
        match.run()
        wall += time.perf_counter() - start
        sim += match.time
        errors.append(match.localization_errors.summary().position_error_mean)
    return sim / wall, float(np.mean(errors))


def main(argv: list[str] | None = None) -> dict[str, float]:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=20.0, help="simulated seconds of recorded scenes")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--colours", default="classic", choices=["classic", "modern"])
    parser.add_argument("--match-seconds", type=float, default=60.0, help="match length (0: skip the matches)")
    parser.add_argument("--seeds", type=int, default=2, help="match seeds")
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args(argv)
    figures: dict[str, float] = {}
    for size in RESOLUTIONS:
        frames = render_frames(args.seconds, size, args.colours)
        for method in METHODS:
            fps, per_frame = bench_detect(frames, method, args.colours, args.repeats)
            key = f"{size[0]}x{size[1]}_{method}"
            figures[f"{key}_frames_per_s"] = fps
            figures[f"{key}_us_per_frame"] = 1e6 / fps
            figures[f"{key}_percepts_per_frame"] = per_frame
            budget = f" (budget {BUDGET_FPS:,.0f})" if size == (320, 240) and method == "dnt" else ""
            print(f"{key:18s} {fps:8.0f} frames/s{budget}  {1e6 / fps:7.0f} us/frame  {per_frame:.1f} percepts/frame")
    if args.match_seconds > 0:
        for obs in ("percepts", "images"):
            rtf, err = bench_match(obs, args.match_seconds, args.seeds)
            figures[f"match_{obs}_rtf"] = rtf
            figures[f"match_{obs}_position_error_m"] = err
            print(f"match on {obs:8s}: {rtf:5.1f}x real time, mean position error {err:.3f} m")
        ratio = figures["match_images_position_error_m"] / figures["match_percepts_position_error_m"]
        figures["match_images_error_ratio"] = ratio
        print(f"images / percepts position error: {ratio:.2f} (bar: <= 1.5)")
    write_figures(args.json, figures)
    return figures


if __name__ == "__main__":
    main()
