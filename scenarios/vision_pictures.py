"""Pictures of ``teamsim vision-eval``: detections and annotations drawn on a frame, montages of
the worst frames, and the detection gallery on the README's gallery scenes. Pixels of the
image, annotations scaled with it.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from pathlib import Path
from typing import TextIO

import cv2
import numpy as np
from numpy.typing import NDArray

from cognition.camera import CameraRig
from cognition.field import FIELD_PRESETS, Field
from cognition.percepts import Kind, Percepts
from cognition.vision import Vision, VisionParams
from cognition.vision.draw import draw_percepts
from teamsim.image_params import ImageParams
from teamsim.images import ImageAnnotations, ImageRenderer, draw_annotations, save_png


def scaled_annotations(ann: ImageAnnotations, factor: float) -> ImageAnnotations:
    """The annotations with every pixel (and the ball radius) multiplied by ``factor``."""

    def s(a: NDArray[np.float64], cols: int) -> NDArray[np.float64]:
        b = a.copy()
        b[:, :cols] *= factor
        return b

    return dataclasses.replace(
        ann, posts=s(ann.posts, 6), crossings=s(ann.crossings, 2), lines=s(ann.lines, 4), circle=s(ann.circle, 2),
        marks=s(ann.marks, 2), ball=s(ann.ball, 3), robots=s(ann.robots, 6), poles=s(ann.poles, 6),
    )  # fmt: skip


def overlay(
    image: NDArray[np.uint8], ann: ImageAnnotations | None, percepts: Percepts, factor: int = 2, caption: str = ""
) -> NDArray[np.uint8]:
    """The image enlarged by ``factor`` with annotations (thin) and detections (thick) drawn."""
    h, w = image.shape[:2]
    big = cv2.resize(image, (w * factor, h * factor), interpolation=cv2.INTER_NEAREST)
    if ann is not None:
        big = draw_annotations(big, scaled_annotations(ann, factor))
    big = draw_percepts(big, percepts, scale=factor)
    texts = caption.splitlines()
    if texts:  # a dark band under the caption, readable on any background
        band = big[: 8 + 16 * len(texts)]
        band[:] = (band * 0.35).astype(np.uint8)
    for i, text in enumerate(texts):
        for colour, width in (((0, 0, 0), 3), ((255, 255, 255), 1)):
            cv2.putText(big, text, (6, 16 + 16 * i), cv2.FONT_HERSHEY_SIMPLEX, 0.45, colour, width, cv2.LINE_AA)
    return big


_LEGEND = (
    "thin: truth (annotations: lines magenta, crossings blue +, posts yellow box, ball red, robots orange box)   "
    "thick: detections (lines yellow, crossings orange diamond, posts pink, ball cyan, circle pink star, "
    "marks red square, robots own blue / opp red)"
)


def montage(panels: Sequence[NDArray[np.uint8]], columns: int = 3) -> NDArray[np.uint8]:
    """The panels (same size) in a grid, with a legend line below."""
    h, w = panels[0].shape[:2]
    rows = max(1, math.ceil(len(panels) / columns))
    out = np.zeros((rows * h + 28, columns * w, 3), dtype=np.uint8)
    for i, p in enumerate(panels):
        r, c = divmod(i, columns)
        out[r * h : (r + 1) * h, c * w : (c + 1) * w] = p
    cv2.putText(out, _LEGEND, (6, rows * h + 18), cv2.FONT_HERSHEY_SIMPLEX, 0.42, (255, 255, 255), 1, cv2.LINE_AA)
    return out


def write_gallery(out_dir: Path, methods: Sequence[str], stream: TextIO | None = None) -> list[Path]:
    """Detections and annotations on the README gallery scenes, ``<stem>_<method>.png`` in ``out_dir``."""
    from teamsim.camera_views import gallery_scenes

    written = []
    for stem, field_name, scheme, preset, scene, r in gallery_scenes():
        fld = Field(FIELD_PRESETS[field_name], field_name)
        ren = ImageRenderer(fld, scheme, CameraRig(), ImageParams.preset(preset), np.random.default_rng(1))
        image = ren.render(scene, r)
        ann = ren.annotate(scene)[r]
        o = scene.observers[r]
        for m in methods:
            try:
                vision = Vision(VisionParams(method=m), field=fld, scheme=scheme, team=int(o[11]))  # type: ignore[arg-type]
            except (ValueError, TypeError, NotImplementedError) as exc:
                print(f"{stem}: method {m} unavailable ({exc})", file=stream)
                continue
            percepts = vision.detect(
                image, ren.camera_matrix(scene, r), 0.0, float(o[5]), float(o[6]), bool(o[8] > 0.5)
            )
            written.append(save_png(out_dir / f"{stem}_{m}.png", overlay(image, ann, percepts, 2, f"{stem} ({m})")))
            if stream is not None:
                counts = ", ".join(f"{k.name.lower()} {percepts.count(k)}" for k in Kind if percepts.count(k))
                print(f"{stem} ({m}): {counts or 'nothing detected'}", file=stream)
    return written
