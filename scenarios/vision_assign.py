"""One-to-one assignment of a frame's detections to its ground-truth annotations, for
``teamsim vision-eval`` (:mod:`scenarios.vision_match` holds the counting rules): greedy by
increasing cost (points by pixel distance, robots by their feet inside a box, lines by their
carrier line), and whether the labels of the pairs agree. Pixels of the image.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

LINE_SAMPLES = 32
"""Points along a segment where line coverage is measured."""


def greedy_match(cost: NDArray[np.float64]) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """One-to-one pairs of detections (rows) and annotations (columns) by increasing ``cost``;
    an infinite or NaN cost forbids the pair. Returns (annotation of each detection, detection
    of each annotation), -1 where unmatched."""
    c = np.asarray(cost, dtype=np.float64)
    n, m = c.shape
    det = np.full(n, -1, dtype=np.int64)
    ann = np.full(m, -1, dtype=np.int64)
    if n == 0 or m == 0:
        return det, ann
    flat = np.where(np.isfinite(c), c, np.inf).ravel()
    order = np.argsort(flat, kind="stable")
    for f in order[: int(np.isfinite(flat).sum())]:
        i, j = divmod(int(f), m)
        if det[i] < 0 and ann[j] < 0:
            det[i], ann[j] = j, i
    return det, ann


def _distances(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """Pixel distances (n x m) between points a (n x 2) and b (m x 2); NaN where undefined."""
    return np.hypot(a[:, None, 0] - b[None, :, 0], a[:, None, 1] - b[None, :, 1])


def match_points(
    det_uv: NDArray[np.float64], ann_uv: NDArray[np.float64], tolerance: float | NDArray[np.float64]
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Greedy matching of pixels within ``tolerance`` (px; a scalar or one per annotation)."""
    d = _distances(np.asarray(det_uv, float).reshape(-1, 2), np.asarray(ann_uv, float).reshape(-1, 2))
    tol = np.broadcast_to(np.asarray(tolerance, dtype=float), d.shape[1:])
    with np.errstate(invalid="ignore"):
        return greedy_match(np.where(d <= tol[None, :], d, np.inf))


def match_boxes(
    det_uv: NDArray[np.float64], ann_uv: NDArray[np.float64], boxes: NDArray[np.float64], tolerance: float, widen: float
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Greedy matching by pixel distance to ``ann_uv``, allowed within ``tolerance`` of it or inside
    the annotation's box (u0, v0, u1, v1) widened by ``widen`` px on every side."""
    p = np.asarray(det_uv, float).reshape(-1, 2)
    b = np.asarray(boxes, float).reshape(-1, 4)
    d = _distances(p, np.asarray(ann_uv, float).reshape(-1, 2))
    with np.errstate(invalid="ignore"):
        inside = (
            (p[:, None, 0] >= b[None, :, 0] - widen) & (p[:, None, 0] <= b[None, :, 2] + widen)
            & (p[:, None, 1] >= b[None, :, 1] - widen) & (p[:, None, 1] <= b[None, :, 3] + widen)
        )  # fmt: skip
        return greedy_match(np.where((d <= tolerance) | inside, np.nan_to_num(d, nan=1e9), np.inf))


def labels_agree(
    det_label: NDArray[np.int64], ann_label: NDArray[np.int64], det_to_ann: NDArray[np.int64], unknown: int | None
) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """(agree, checked) per detection: ``checked`` where the detection is matched and both labels
    are known (not ``unknown``); ``agree`` is True unless checked and different."""
    matched = det_to_ann >= 0
    a = np.where(matched, np.asarray(ann_label)[np.maximum(det_to_ann, 0)] if len(ann_label) else -1, -1)
    d = np.asarray(det_label)
    checked = matched & ((d != unknown) & (a != unknown) if unknown is not None else matched)
    return ~checked | (d == a), checked


def _segment_distance(p: NDArray[np.float64], seg: NDArray[np.float64]) -> NDArray[np.float64]:
    """Distances (n x m) from points p (n x 2) to segments seg (m x 4: u1, v1, u2, v2)."""
    a, ab = seg[None, :, :2], seg[None, :, 2:] - seg[None, :, :2]
    rel = p[:, None, :] - a
    t = np.clip((rel * ab).sum(-1) / np.maximum((ab * ab).sum(-1), 1e-12), 0.0, 1.0)
    return np.linalg.norm(rel - t[..., None] * ab, axis=-1)


def _carrier_distance(p: NDArray[np.float64], seg: NDArray[np.float64], tolerance: float) -> NDArray[np.float64]:
    """Distances (n x m) from points p (n x 2) to the carrier lines of segments seg (m x 4),
    infinite where a point lies farther than max(3 tolerance, 20 % of the segment) beyond its
    ends along it."""
    a, ab = seg[None, :, :2], seg[None, :, 2:] - seg[None, :, :2]
    length = np.maximum(np.linalg.norm(ab, axis=-1), 1e-9)
    rel = p[:, None, :] - a
    along = (rel * ab).sum(-1) / length
    across = np.abs(rel[..., 0] * ab[..., 1] - rel[..., 1] * ab[..., 0]) / length
    slack = np.maximum(3.0 * tolerance, 0.2 * length)
    return np.where((along >= -slack) & (along <= length + slack), across, np.inf)


def match_lines(
    det_seg: NDArray[np.float64],
    ann_seg: NDArray[np.float64],
    tolerance: float,
    ann_ids: NDArray[np.int64] | None = None,
    samples: int = LINE_SAMPLES,
) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
    """(line id of each detected segment, or -1; covered samples per annotated piece).

    Pieces with the same id (``ann_ids``, default: each piece its own id) are pieces of one
    straight line (split where robots hide it). A detected segment (u1, v1, u2, v2) lies on
    the line whose pieces are nearest to both its ends when both are within ``tolerance`` px of
    their carrier lines, no farther than max(3 ``tolerance``, 20 % of the piece) beyond the
    piece (a segment bridging a robot in front of a line is on that line; one running into the
    width of a line it meets at a crossing too). Each annotated
    piece is sampled at ``samples`` points; a sample is covered when it is within
    ``tolerance`` of a detected segment.
    """
    det = np.asarray(det_seg, float).reshape(-1, 4)
    ann = np.asarray(ann_seg, float).reshape(-1, 4)
    ids = np.arange(len(ann)) if ann_ids is None else np.asarray(ann_ids, dtype=np.int64)
    line = np.full(len(det), -1, dtype=np.int64)
    covered = np.zeros((len(ann), samples), dtype=np.bool_)
    if len(det) == 0 or len(ann) == 0:
        return line, covered
    names = np.unique(ids)
    same = ids[None, :] == names[:, None]  # (lines x pieces)
    ends = []
    for end in (det[:, :2], det[:, 2:]):
        d = np.nan_to_num(_carrier_distance(end, ann, tolerance), nan=np.inf)
        ends.append(np.where(same[None], d[:, None, :], np.inf).min(axis=2))  # (det x lines)
    worst = np.maximum(*ends)
    best = np.argmin(worst, axis=1)
    ok = worst[np.arange(len(det)), best] <= tolerance
    line[ok] = names[best[ok]]
    pts = line_samples(ann, samples).reshape(-1, 2)
    with np.errstate(invalid="ignore"):
        covered = (_segment_distance(pts, det) <= tolerance).any(axis=1).reshape(len(ann), samples)
    return line, covered


def line_samples(seg: NDArray[np.float64], samples: int) -> NDArray[np.float64]:
    """``samples`` points (m x samples x 2) evenly inside each segment (cell centres)."""
    t = (np.arange(samples) + 0.5) / samples
    return seg[:, None, :2] + t[None, :, None] * (seg[:, None, 2:] - seg[:, None, :2])
