"""Vision quality on seeded rendered frames: a smaller version of ``teamsim vision-eval``.

The evaluation of the vision issue runs 500 frames per colour scheme (see the README's
vision section for the full tables); here 150 random frames per scheme and line method, with
the ``default`` image effects (noise, blur, uneven light), must reach bounds a little below
what the full evaluation measures, so that a change that breaks a detector fails the suite
but the statistics of 150 frames do not. Counting rules: :mod:`scenarios.vision_match`, figures:
:mod:`scenarios.vision_report`.
"""

from __future__ import annotations

from typing import Any

import pytest

from cognition.field import FIELD_PRESETS, Field
from scenarios.vision_eval import evaluate as run_evaluation
from scenarios.vision_eval import frame_generators, make_frames
from scenarios.vision_report import summarize

FIELD = Field(FIELD_PRESETS["spl2025"], "spl2025")
FRAMES = 150

# (kind, figure, lower bound). On these 150 frames (seed 7) the three configurations measured
# at least: crossings 0.937 / 0.872, posts 0.968 / 0.935, ball 0.984 / 0.983, circle 1.0 / 0.867,
# lines 0.855 / 0.663, robots 0.898 / 0.824 (precision / recall; robots 0.810 / 0.838 before
# robots seen twice became one); the 500-frame evaluation on seeds 0-2: crossings
# >= 0.950 / 0.885, posts >= 0.980 / 0.990, ball >= 0.984 / 0.978.
BOUNDS = (
    ("crossing", "precision", 0.88),
    ("crossing", "recall", 0.80),
    ("post", "precision", 0.95),
    ("post", "recall", 0.90),
    ("post", "label_accuracy", 0.97),
    ("ball", "precision", 0.95),
    ("ball", "recall", 0.93),
    ("circle", "precision", 0.90),
    ("circle", "recall", 0.75),
    ("line", "precision", 0.80),
    ("line", "recall", 0.60),
    ("robot", "precision", 0.87),
    ("robot", "recall", 0.78),
)


def _figures(colours: str, method: str, images: str = "default") -> dict[str, dict[str, Any]]:
    scenes, effects = frame_generators(7)
    frames = make_frames(FRAMES, scenes, FIELD)
    (run,), _ = run_evaluation(frames, [method], colours, images, effects_rng=effects, field_map=FIELD)
    assert run.error is None
    return {kind: summarize(tally) for kind, tally in run.totals.items()}


# seconds: on a fresh clone this file is the first to compile the renderer and the vision (minutes)
@pytest.mark.slow(seconds=60)
@pytest.mark.parametrize(("colours", "method"), [("classic", "dnt"), ("modern", "dnt"), ("modern", "hough")])
def test_seeded_frames_reach_the_quality_bounds(colours: str, method: str) -> None:
    f = _figures(colours, method)
    for kind, figure, bound in BOUNDS:
        value = f[kind][figure]
        assert value is not None and value >= bound, f"{colours} {method}: {kind} {figure} {value} < {bound}"
    assert f["crossing"]["annotations"] >= 25 and f["post"]["annotations"] >= 20 and f["ball"]["annotations"] >= 40
    for kind in ("post", "crossing", "ball", "circle"):
        assert f[kind]["relative_distance_error_median"] < 0.05, kind


@pytest.mark.slow(seconds=1)
def test_harsh_images_do_not_collapse() -> None:
    f = _figures("classic", "dnt", "harsh")
    for kind in ("crossing", "post", "ball"):
        assert f[kind]["precision"] >= 0.8, kind
        assert f[kind]["recall"] >= 0.5, kind
    # robots: 0.831 / 0.471 (0.663 / 0.478 before robots seen twice became one)
    assert f["robot"]["precision"] >= 0.75 and f["robot"]["recall"] >= 0.4
