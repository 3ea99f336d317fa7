"""Nothing behind a seen goal line is a field line: the goal's net and frame are cut away.

A goal's net hangs from the crossbar to the ground and its frame lies on the carpet behind
the goal line; seen through the net, its white strands and bars look like field lines and
their junctions like crossings (the DNT paper's goal detection, section 3.8, has no use for
them, and its line detection, 3.6, is fooled by them just the same). Once the goal posts are
found, the goal line is known: it runs through the bases of two posts of one goal (at the
goal's width apart), or, with one post, along the longest detected line that passes through
the post's base and goes on to both sides of it (the net's side bar ends at the post). No
field line lies behind a goal line, so every line segment is cut at ``behind`` metres beyond
it (the side away from the robot) and dropped when nothing long enough is left; the goal
line itself and the lines that end on it stay. Crossings within ``clearance`` of a post's
base are dropped too: the post's foot and the net's frame meet the goal line there (the
nearest field junction, the goal area's corner, is 0.3 m away).

Ground points: robot frame, metres (the robot stands on the field side of the goal line).
Segments: image end points S x 4 (u1, v1, u2, v2) and ground end points S x 4 (x1, y1, x2,
y2) with their open ends S x 2, as the line methods produce them.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.vision.projection import pixel_nb


@nb.njit(cache=True)
def goal_lines_nb(
    posts: NDArray[np.float64], seg_ground: NDArray[np.float64], goal_width: float
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """Goal lines G x 4 (a point on the line x, y and the unit normal nx, ny pointing away from
    the robot) from the post positions (P x >=2, robot frame) and the ground segments."""
    n = posts.shape[0]
    out = np.empty((n, 4))
    g = 0
    used = np.zeros(n, dtype=np.bool_)
    for a in range(n):  # two posts of one goal
        for b in range(a + 1, n):
            if used[a] or used[b]:
                continue
            dx, dy = posts[b, 0] - posts[a, 0], posts[b, 1] - posts[a, 1]
            d = math.hypot(dx, dy)
            if not 0.7 * goal_width <= d <= 1.3 * goal_width:
                continue
            nx, ny = -dy / d, dx / d
            if nx * posts[a, 0] + ny * posts[a, 1] < 0.0:
                nx, ny = -nx, -ny
            out[g, 0], out[g, 1], out[g, 2], out[g, 3] = posts[a, 0], posts[a, 1], nx, ny
            g += 1
            used[a] = used[b] = True
    for a in range(n):  # a single post: the longest detected line through its base
        if used[a]:
            continue
        px, py = posts[a, 0], posts[a, 1]
        best = 0.0
        bx = by = 0.0
        for k in range(seg_ground.shape[0]):
            x1, y1, x2, y2 = seg_ground[k, 0], seg_ground[k, 1], seg_ground[k, 2], seg_ground[k, 3]
            length = math.hypot(x2 - x1, y2 - y1)
            if length < 0.3 or length <= best:
                continue
            ux, uy = (x2 - x1) / length, (y2 - y1) / length
            t = (px - x1) * ux + (py - y1) * uy
            # it must go on to both sides of the post (the net's side bar on the ground ends there)
            if abs((px - x1) * uy - (py - y1) * ux) <= 0.15 and 0.2 <= t <= length - 0.2:
                best, bx, by = length, ux, uy
        if best > 0.0:
            nx, ny = -by, bx
            if nx * px + ny * py < 0.0:
                nx, ny = -nx, -ny
            if nx * px + ny * py < 0.3:  # the robot stands (almost) on the line: no side to cut
                continue
            out[g, 0], out[g, 1], out[g, 2], out[g, 3] = px, py, nx, ny
            g += 1
    return out[:g]


@nb.njit(cache=True)
def cut_behind_nb(
    seg_px: NDArray[np.float64],
    seg_ground: NDArray[np.float64],
    open_ends: NDArray[np.bool_],
    lines: NDArray[np.float64],
    cam: NDArray[np.float64],
    behind: float,
    min_length: float,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:  # pragma: no cover - compiled
    """The segments cut at ``behind`` metres beyond every goal line (G x 4 from
    :func:`goal_lines_nb`); pieces shorter than ``min_length`` are dropped."""
    s = seg_ground.shape[0]
    px = seg_px[:, :4].copy()
    gr = seg_ground.copy()
    op = open_ends.copy()
    keep = np.ones(s, dtype=np.bool_)
    for k in range(s):
        for g in range(lines.shape[0]):
            ox, oy, nx, ny = lines[g, 0], lines[g, 1], lines[g, 2], lines[g, 3]
            d1 = (gr[k, 0] - ox) * nx + (gr[k, 1] - oy) * ny - behind
            d2 = (gr[k, 2] - ox) * nx + (gr[k, 3] - oy) * ny - behind
            if d1 > 0.0 and d2 > 0.0:
                keep[k] = False
                break
            if d1 <= 0.0 and d2 <= 0.0:
                continue
            t = d1 / (d1 - d2)  # where the segment crosses the cut
            x, y = gr[k, 0] + t * (gr[k, 2] - gr[k, 0]), gr[k, 1] + t * (gr[k, 3] - gr[k, 1])
            u, v, ok = pixel_nb(cam, x, y, 0.0)
            e = 0 if d1 > 0.0 else 1
            gr[k, 2 * e], gr[k, 2 * e + 1] = x, y
            if ok:
                px[k, 2 * e], px[k, 2 * e + 1] = u, v
            op[k, e] = True
        if keep[k] and math.hypot(gr[k, 2] - gr[k, 0], gr[k, 3] - gr[k, 1]) < min_length:
            keep[k] = False
    return px[keep], gr[keep], op[keep]


@nb.njit(cache=True)
def clear_of_posts_nb(
    cross: NDArray[np.float64], posts: NDArray[np.float64], clearance: float
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """The crossings (C x >=2, robot frame) farther than ``clearance`` metres from every post
    base (P x >=2): where a post stands on the goal line, its foot and the net's frame meet the
    line in junctions no field map has."""
    keep = np.ones(cross.shape[0], dtype=np.bool_)
    for k in range(cross.shape[0]):
        for q in range(posts.shape[0]):
            if math.hypot(cross[k, 0] - posts[q, 0], cross[k, 1] - posts[q, 1]) <= clearance:
                keep[k] = False
    return cross[keep]
