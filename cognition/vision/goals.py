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


@nb.njit(cache=True, error_model="python", fastmath=False)
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


@nb.njit(cache=True, error_model="python", fastmath=False)
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


@nb.njit(cache=True, error_model="python", fastmath=False)
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


@nb.njit(cache=True, error_model="python", fastmath=False)
def not_under_posts_nb(
    cross: NDArray[np.float64],
    classes: NDArray[np.uint8],
    cam: NDArray[np.float64],
    goal_a: int,
    goal_b: int,
    net: int,
    radius: float,
    height: float,
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """The crossings (C x >=2, robot frame, metres) on which no goal post or net stands in the image.

    Where a post's base is cut by the image edge or hidden, the post is not detected, but its
    foot still meets the goal line and the net's frame in junctions no field map has. For each
    crossing the vertical axes through it and ``radius`` to its left and right (seen from the
    camera) are sampled from 0.1 m up to ``height`` (the post's height). An axis is blocked
    when at least 80 % of its samples inside the image are of a goal colour (class ``goal_a``
    or ``goal_b``) or of the net's (``net``) and one of them is above the camera, where nothing
    on the carpet is seen; a crossing is dropped when one of its axes is blocked (requiring two
    kept 1.5 % more true crossings but half of the net's false ones). Below the camera a field
    line's crossing shows the carpet beyond it, except along a receding white line.
    """
    h, w = classes.shape
    keep = np.ones(cross.shape[0], dtype=np.bool_)
    cam_h = cam[11]
    if height <= cam_h + 0.05:
        return cross
    for k in range(cross.shape[0]):
        x, y = cross[k, 0], cross[k, 1]
        d = math.hypot(x - cam[9], y - cam[10])
        if d < 1e-6:
            continue
        ox, oy = -(y - cam[10]) / d * radius, (x - cam[9]) / d * radius
        blocked = 0
        for side in (-1.0, 0.0, 1.0):
            px, py = x + side * ox, y + side * oy
            seen = 0
            goal = 0
            high = 0
            for q in range(12):
                z = 0.1 + (height - 0.1) * q / 11.0
                u, v, ok = pixel_nb(cam, px, py, z)
                if not ok or u < 0.0 or v < 0.0 or u >= w or v >= h:
                    continue
                seen += 1
                c = classes[int(v), int(u)]
                if c in (goal_a, goal_b, net):
                    goal += 1
                    if z > cam_h + 0.05:
                        high += 1
            if seen >= 4 and high >= 1 and goal >= 0.8 * seen:
                blocked += 1
        keep[k] = blocked == 0
    return cross[keep]
