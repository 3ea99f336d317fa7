"""Images per second of the camera-image renderer for every robot of a 5 v 5 match.

Scenes are recorded from a real match (scripted players on truth beliefs, ``--seconds`` of
play), then every robot's image of every recorded scene is rendered on one core. The budget
of the image issue at 320 x 240: at least 5,000 images/s with the effects off (``ideal``)
and at least 1,500 images/s with the ``default`` effects on.

Figures printed (and written as JSON with ``--json PATH``), per resolution ``WxH``:

=================================  ======================================================
figure                             meaning
=================================  ======================================================
<WxH>_ideal_images_per_s           ImageRenderer.render, effects off, median over repeats
<WxH>_default_images_per_s         the same with the ``default`` effects
<WxH>_harsh_images_per_s           the same with the ``harsh`` effects
<WxH>_annotate_us_per_frame        ImageRenderer.annotate for all robots of one frame
match_rtf_images                   real-time factor of a match with ``observation="images"``
=================================  ======================================================

Usage: ``python -m benchmarks.bench_images [--seconds 30] [--repeats 3] [--json out.json]``
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import numpy as np

from benchmarks.bench_percepts import record_scenes
from benchmarks.common import write_figures
from cognition.camera import CameraRig
from teamsim.images import ImageRenderer
from teamsim.match import Match, MatchConfig
from teamsim.percepts import Scene

BUDGET_IDEAL = 5000.0
BUDGET_EFFECTS = 1500.0
RESOLUTIONS = ((320, 240), (640, 480))


def bench_render(scenes: list[Scene], size: tuple[int, int], preset: str, repeats: int) -> float:
    """Median images per second over all robots of all scenes."""
    match = Match(MatchConfig(players_per_team=scenes[0].players_per_team, observation="none"))
    rig = CameraRig().with_resolution(*size)
    ren = ImageRenderer(match.field, match.config.colours, rig, preset, np.random.default_rng(0))
    out = np.empty((size[1], size[0], 3), dtype=np.uint8)
    robots = range(scenes[0].observers.shape[0])
    ren.render(scenes[0], 0, out)  # compile / load the cache
    rates = []
    for _ in range(repeats):
        count = 0
        start = time.perf_counter()
        for s in scenes:
            for r in robots:
                if s.observers[r, 9] > 0.5:
                    ren.render(s, r, out)
                    count += 1
        rates.append(count / (time.perf_counter() - start))
    return statistics.median(rates)


def bench_annotate(scenes: list[Scene], size: tuple[int, int]) -> float:
    """Microseconds to annotate all robots' images of one frame."""
    match = Match(MatchConfig(players_per_team=scenes[0].players_per_team, observation="none"))
    ren = ImageRenderer(match.field, match.config.colours, CameraRig().with_resolution(*size), "ideal")
    ren.annotate(scenes[0])
    start = time.perf_counter()
    for s in scenes:
        ren.annotate(s)
    return (time.perf_counter() - start) / len(scenes) * 1e6


def match_rtf(seconds: float, players: int) -> float:
    """Real-time factor of a match whose robots receive images (default effects)."""
    match = Match(MatchConfig(players_per_team=players, observation="images"))
    start = time.perf_counter()
    match.run(until=seconds)
    return seconds / (time.perf_counter() - start)


def main(argv: list[str] | None = None) -> dict[str, float]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=30.0, help="match time to record scenes from (s)")
    ap.add_argument("--players", type=int, default=5, help="players per team")
    ap.add_argument("--repeats", type=int, default=3, help="timed passes over the scenes (median)")
    ap.add_argument("--json", type=Path, default=None, help="also write the figures to this JSON file")
    args = ap.parse_args(argv)
    scenes = record_scenes(args.seconds, args.players, every=3)
    figures: dict[str, float] = {"scenes": float(len(scenes)), "players_per_team": float(args.players)}
    for size in RESOLUTIONS:
        tag = f"{size[0]}x{size[1]}"
        for preset in ("ideal", "default", "harsh"):
            rate = bench_render(scenes, size, preset, args.repeats)
            figures[f"{tag}_{preset}_images_per_s"] = rate
            print(f"{tag} {preset:8s} {rate:9.0f} images/s  ({1e6 / rate:7.1f} us/image)", flush=True)
        ann = bench_annotate(scenes, size)
        figures[f"{tag}_annotate_us_per_frame"] = ann
        print(f"{tag} annotate {ann:9.1f} us per frame (all robots)", flush=True)
    rtf = match_rtf(min(args.seconds, 20.0), args.players)
    figures["match_rtf_images"] = rtf
    print(f"match with images: real-time factor {rtf:.1f}")
    ideal, effects = figures["320x240_ideal_images_per_s"], figures["320x240_default_images_per_s"]
    print(
        f"budget 320x240: ideal {ideal:.0f} >= {BUDGET_IDEAL:.0f} {'OK' if ideal >= BUDGET_IDEAL else 'MISSED'}; "
        f"default {effects:.0f} >= {BUDGET_EFFECTS:.0f} {'OK' if effects >= BUDGET_EFFECTS else 'MISSED'}"
    )
    write_figures(args.json, figures)
    return figures


if __name__ == "__main__":
    main()
