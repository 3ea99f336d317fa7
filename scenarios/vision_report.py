"""The figures of ``teamsim vision-eval``: per-kind summaries of the tallies, recall by distance,
the issue's bars and the text tables (matching rules and tallies: :mod:`scenarios.vision_match`).

**Bars** (the vision issue, stated for ``default`` images and >= 500 frames per colour
scheme): crossings precision >= 0.95, recall >= 0.80; posts precision, recall and side accuracy
>= 0.97; ball precision and recall >= 0.95 (within 4 m); circle recall >= 0.7 (half in view);
median relative distance error < 5 % (posts, crossings, circle, marks, ball). Distances in
metres, bearings in degrees.
"""

from __future__ import annotations

import itertools
from typing import Any

import numpy as np
from numpy.typing import NDArray

from scenarios.vision_match import KINDS, LABELS, Tally


def summarize(tally: Tally) -> dict[str, float | int | None]:
    """The figures of one kind: counts, precision, recall, error medians and 90th percentiles
    (None where there is nothing to compute them from)."""
    e = np.asarray(tally.errors, dtype=float).reshape(-1, 3)
    dist = np.abs(e[:, 1] - e[:, 0])
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = dist / e[:, 0]
    rel = rel[np.isfinite(rel)]

    def q(a: NDArray[np.float64], level: float) -> float | None:
        return float(np.quantile(a, level)) if len(a) else None

    return {
        "annotations": tally.annotations,
        "detections": tally.detections,
        "tp": tally.tp,
        "fp": tally.fp,
        "fn": tally.fn,
        "precision": tally.tp_det / tally.detections if tally.detections else None,
        "recall": tally.tp / tally.annotations if tally.annotations else None,
        "matched": len(e),
        "distance_error_median_m": q(dist, 0.5),
        "distance_error_p90_m": q(dist, 0.9),
        "relative_distance_error_median": q(rel, 0.5),
        "relative_distance_error_p90": q(rel, 0.9),
        "bearing_error_median_deg": q(e[:, 2], 0.5),
        "bearing_error_p90_deg": q(e[:, 2], 0.9),
        "label_accuracy": tally.label_correct / tally.label_checked if tally.label_checked else None,
        "label_checked": tally.label_checked,
        "recall_by_distance": _recall_bins(tally.found),
    }


DISTANCE_BINS = (0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0)
"""Bin edges (m) of ``recall_by_distance`` in metrics.json."""


def _recall_bins(found: list[tuple[float, bool]]) -> list[dict[str, Any]]:
    """Recall per true-distance bin of :data:`DISTANCE_BINS` (point kinds; empty for lines)."""
    f = np.asarray(found, dtype=float).reshape(-1, 2)
    out = []
    for lo, hi in itertools.pairwise(DISTANCE_BINS):
        sel = (f[:, 0] >= lo) & (f[:, 0] < hi)
        n = int(sel.sum())
        out.append({"from_m": lo, "to_m": hi, "annotations": n, "recall": float(f[sel, 1].mean()) if n else None})
    return out if len(f) else []


BARS: tuple[tuple[str, str, str, float], ...] = (
    ("crossing", "precision", ">=", 0.95),
    ("crossing", "recall", ">=", 0.80),
    ("post", "precision", ">=", 0.97),
    ("post", "recall", ">=", 0.97),
    ("post", "label_accuracy", ">=", 0.97),
    ("ball", "precision", ">=", 0.95),
    ("ball", "recall", ">=", 0.95),
    ("circle", "recall", ">=", 0.70),
    *((k, "relative_distance_error_median", "<", 0.05) for k in ("post", "crossing", "circle", "mark", "ball")),
)
"""(kind, figure, comparison, bound) of the vision issue (module docstring)."""


def check_bars(kinds: dict[str, dict[str, Any]]) -> list[dict[str, Any]]:
    """Each bar with the measured value and whether it holds (a missing value does not)."""
    out = []
    for kind, name, op, bound in BARS:
        value = kinds[kind][name]
        ok = value is not None and (value >= bound if op == ">=" else value < bound)
        out.append({"kind": kind, "figure": name, "op": op, "bound": bound, "value": value, "ok": bool(ok)})
    return out


def format_table(kinds: dict[str, dict[str, Any]]) -> str:
    """The table of one method (one row per kind of :data:`KINDS`)."""

    def f(v: Any, spec: str, scale: float = 1.0) -> str:
        return format(v * scale, spec) if v is not None else "-".rjust(int(spec.split(".")[0]))

    head = (
        f"{'kind':13s}{'ann':>6s}{'det':>6s}{'TP':>6s}{'FP':>5s}{'FN':>5s}{'prec':>7s}{'recall':>7s}"
        f"{'dist med':>9s}{'p90':>6s}{'rel med':>8s}{'p90':>6s}{'brg med':>8s}{'p90':>6s}  label"
    )
    lines = [head, "-" * len(head)]
    for name in KINDS:
        s = kinds[name]
        label = "-"
        if s["label_accuracy"] is not None:
            label = f"{LABELS.get(name, 'label')} {s['label_accuracy']:.3f} ({s['label_checked']})"
        lines.append(
            f"{name:13s}{s['annotations']:6d}{s['detections']:6d}{s['tp']:6d}{s['fp']:5d}{s['fn']:5d}"
            f"{f(s['precision'], '7.3f')}{f(s['recall'], '7.3f')}"
            f"{f(s['distance_error_median_m'], '9.3f')}{f(s['distance_error_p90_m'], '6.2f')}"
            f"{f(s['relative_distance_error_median'], '8.3f')}{f(s['relative_distance_error_p90'], '6.3f')}"
            f"{f(s['bearing_error_median_deg'], '8.2f')}{f(s['bearing_error_p90_deg'], '6.2f')}  {label}"
        )
    lines.append(
        "dist: |measured - true distance| (m), rel: the same / true distance, brg: bearing error (deg), median and "
        "90th percentile; lines: distance to the line and direction error"
    )
    return "\n".join(lines)


def format_recall_by_distance(kinds: dict[str, dict[str, Any]]) -> str:
    """Recall per true-distance bin (:data:`DISTANCE_BINS`) of the kinds with annotations."""
    edges = DISTANCE_BINS
    head = "recall by true distance (m): " + " ".join(f"{a:g}-{b:g}".rjust(7) for a, b in itertools.pairwise(edges))
    lines = [head]
    for name in KINDS:
        bins = kinds[name]["recall_by_distance"]
        if name == "crossing_any" or not bins:
            continue
        cells = [("-" if b["recall"] is None else f"{b['recall']:.2f}").rjust(7) for b in bins]
        lines.append(f"  {name:27s}" + " ".join(cells))
    return "\n".join(lines)
