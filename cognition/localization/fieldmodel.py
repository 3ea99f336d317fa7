"""The field map as flat arrays and lookup grids for the compiled sensor models.

The CMU paper (Sec. III.C.2-3) finds the map landmark an observation belongs to with a
decision tree that partitions the field: for a crossing the nearest map crossing of the
same type, for a line the nearest map line of the matching orientation. Here the partition
is a precomputed grid (:data:`CELL` metres per cell over the field plus a margin) that
stores, per cell centre, the index of the nearest landmark of each type; a lookup is one
array read per particle and observation.

Arrays (team frame, metres, radians):

=============  ===============  ==============================================================
name           shape            content
=============  ===============  ==============================================================
posts          4 x 4            x, y, side (1 left, 2 right, seen from the field), goal
                                (0 own, 1 opponent), in ``Field.goal_posts`` order
crossings      C x 4            x, y, orientation, kind (0 L, 1 T, 2 X)
lines          M x 7            x1, y1, x2, y2, direction in [0, pi), orientation class
                                (0: closer to the x axis, 1: closer to the y axis),
                                1 / squared length
marks          P x 2            penalty marks
poles          Q x 2            corner poles (KidSize)
cross_grid     3 x GY x GX      nearest crossing index per kind (-1: no crossing of the kind)
partial_grid   3 x GY x GX      per seen kind, the nearest crossing that can look like it when
                                seen in part (L: any crossing, T: T or X, X: X; -1: none), for
                                ``LocalizationParams.partial_crossings``
line_grid      2 x GY x GX      nearest line index per orientation class (-1: none)
geo            12               grid x0, y0, cell, GX, GY, circle radius, half length, half width,
                                the carpet's (the field plus its border strip) half length and half
                                width, a goal's half width to the posts' outer sides and its depth
=============  ===============  ==============================================================
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from cognition.field import CROSSING_KINDS, Field

CELL = 0.05
"""Grid cell size (m)."""
MARGIN = 2.0
"""The grid extends this far beyond the field lines (m); lookups outside are clamped."""


def _segment_distance(
    px: NDArray[np.float64], py: NDArray[np.float64], seg: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Distance (m) from points (px, py) to the segment (x1, y1, x2, y2)."""
    x1, y1, x2, y2 = seg[:4]
    dx, dy = x2 - x1, y2 - y1
    ll = dx * dx + dy * dy
    t = np.clip(((px - x1) * dx + (py - y1) * dy) / ll, 0.0, 1.0) if ll > 0 else np.zeros_like(px)
    return np.hypot(px - (x1 + t * dx), py - (y1 + t * dy))


class FieldModel:
    """Flat arrays and nearest-landmark grids of one field (see the module docstring)."""

    def __init__(self, field: Field):
        self.field = field
        self.posts = np.array(
            [(p.x, p.y, 1.0 if p.side == "left" else 2.0, 0.0 if p.goal == "own" else 1.0) for p in field.goal_posts]
        ).reshape(-1, 4)
        self.crossings = np.array(
            [(c.x, c.y, c.orientation, float(CROSSING_KINDS.index(c.kind))) for c in field.crossings]
        ).reshape(-1, 4)
        rows = []
        for s in field.lines:
            d = s.direction
            cls = 0.0 if min(d, math.pi - d) <= math.pi / 4 else 1.0
            rows.append((s.x1, s.y1, s.x2, s.y2, d, cls, 1.0 / max(s.length**2, 1e-12)))
        self.lines = np.array(rows).reshape(-1, 7)
        self.marks = np.array([(m.x, m.y) for m in field.penalty_marks]).reshape(-1, 2)
        self.poles = np.array([(p.x, p.y) for p in field.corner_poles]).reshape(-1, 2)
        hl, hw = field.half_length, field.half_width
        x0, y0 = -hl - MARGIN, -hw - MARGIN
        gx = math.ceil((2 * hl + 2 * MARGIN) / CELL)
        gy = math.ceil((2 * hw + 2 * MARGIN) / CELL)
        d = field.dims
        carpet = (hl + d.border_strip, hw + d.border_strip)
        goal = (0.5 * d.goal_inner_width + d.goal_post_diameter, d.goal_depth)
        self.geo = np.array([x0, y0, CELL, gx, gy, field.centre_circle.radius, hl, hw, *carpet, *goal])
        cx = x0 + (np.arange(gx) + 0.5) * CELL
        cy = y0 + (np.arange(gy) + 0.5) * CELL
        px, py = np.meshgrid(cx, cy)
        self.cross_grid = np.full((3, gy, gx), -1, dtype=np.int32)
        self.partial_grid = np.full((3, gy, gx), -1, dtype=np.int32)
        for k in range(3):  # seen in part, a crossing looks like a lesser kind: an X as a T, a T as an L
            for grid, idx in (
                (self.cross_grid, np.flatnonzero(self.crossings[:, 3] == k)),
                (self.partial_grid, np.flatnonzero(self.crossings[:, 3] >= k)),
            ):
                if idx.size:
                    d = np.stack([np.hypot(px - self.crossings[i, 0], py - self.crossings[i, 1]) for i in idx])
                    grid[k] = idx[np.argmin(d, axis=0)]
        self.line_grid = np.full((2, gy, gx), -1, dtype=np.int32)
        for k in range(2):
            idx = np.flatnonzero(self.lines[:, 5] == k)
            if idx.size:
                d = np.stack([_segment_distance(px, py, self.lines[i]) for i in idx])
                self.line_grid[k] = idx[np.argmin(d, axis=0)]
        for a in (
            self.posts, self.crossings, self.lines, self.marks, self.poles, self.cross_grid, self.partial_grid,
            self.line_grid,
        ):  # fmt: skip
            a.setflags(write=False)
