"""The geometric stages after lines and posts, and the percept table, in one compiled function.

Once the lines (either method), the goal posts, the ball and the robots are found, the rest
of a frame (:mod:`.frame`) is geometry on small arrays: the net behind a seen
goal line is cut away (:mod:`.goals`), crossings are built from the segments (DNT 3.7) and
filtered (distance, post bases, posts and nets standing on them, the centre circle's X
crossings), penalty marks are found among the loose line points, every percept gets its row
with the Darmstadt covariance (:mod:`.rows`), and the rows are stacked in the order of
:class:`cognition.percepts.Kind`. Each of these steps is its own compiled function, and this
module chains them. Units and frames as in the modules it calls (robot frame, metres,
pixels of this image).
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.percepts import N_COLS, N_KINDS
from cognition.vision.crossings import crossings_nb, look_nb
from cognition.vision.dnt import ground_points_nb
from cognition.vision.goals import clear_of_posts_nb, cut_behind_nb, goal_lines_nb, not_under_posts_nb
from cognition.vision.marks import marks_nb
from cognition.vision.rows import crossing_rows_nb, line_rows_nb, point_rows_nb

# entries of the parameter vector ``prm`` of assemble_nb
(A_GOAL_WIDTH, A_GOAL_BEHIND, A_MIN_LINE, A_MARGIN, A_MARGIN_IN, A_BEYOND, A_ANGLE, A_MIN_ARM, A_MERGE_ANGLE,
 A_MERGE_OFFSET, A_MERGE_GAP, A_MAX_MPP, A_CROSS_MAX, A_POST_CLEARANCE, A_POST_RADIUS, A_GOAL_HEIGHT,
 A_CIRCLE_RADIUS, A_MAX_DISTANCE, A_MARK_SIZE, A_MARK_TOL, A_MARK_GREEN, A_MARK_PX, A_MARK_MAX,
 A_N) = range(24)  # fmt: skip


@nb.njit(cache=True, error_model="python", fastmath=False)
def assemble_nb(
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    points: NDArray[np.float64],
    loose: NDArray[np.bool_],
    seg_px: NDArray[np.float64],
    seg_ground: NDArray[np.float64],
    open_ends: NDArray[np.float64],
    cx: float,
    cy: float,
    posts: NDArray[np.float64],
    ball: NDArray[np.float64],
    robots: NDArray[np.float64],
    goal_a: int,
    goal_b: int,
    net: int,
    prm: NDArray[np.float64],
    sa: float,
    sb: float,
) -> tuple:  # pragma: no cover - compiled
    """``(rows, offsets, seg_px, seg_ground)``: the percept table of one image (rows N x
    N_COLS, offsets N_KINDS + 1, kinds in :class:`~cognition.percepts.Kind` order) and the line
    segments left after the goal cut (image and ground, S x 4).

    ``points`` are the line points (K x >=2 pixels) and ``loose`` which of them are on no line
    and not on the circle, ``seg_px``, ``seg_ground``, ``open_ends`` the line method's segments,
    ``cx, cy`` the circle's centre (NaN: none), ``posts``, ``ball``, ``robots`` the rows of
    those detectors, ``goal_a``, ``goal_b`` the goal colour classes and ``net`` the net's,
    ``prm`` the parameters (``A_*`` entries, pixel sizes already scaled to this image), ``sa``,
    ``sb`` the frame's angular sigmas (rad).
    """
    if posts.shape[0] > 0:  # nothing behind a seen goal line is a field line
        goal_lines = goal_lines_nb(posts, seg_ground, prm[A_GOAL_WIDTH])
        seg_px, seg_ground, open_ends = cut_behind_nb(
            seg_px, seg_ground, open_ends, goal_lines, cam, prm[A_GOAL_BEHIND], prm[A_MIN_LINE]
        )
    cross = crossings_nb(
        seg_ground, open_ends, classes, boundary, cam, prm[A_MARGIN], prm[A_MARGIN_IN], prm[A_BEYOND],
        prm[A_ANGLE], prm[A_MIN_ARM], 0.3, prm[A_MERGE_ANGLE], prm[A_MERGE_OFFSET], prm[A_MERGE_GAP],
        prm[A_MAX_MPP],
    )  # fmt: skip
    near = np.ones(cross.shape[0], dtype=np.bool_)
    for k in range(cross.shape[0]):
        near[k] = math.hypot(cross[k, 0], cross[k, 1]) <= prm[A_CROSS_MAX]
    cross = cross[near]
    if posts.shape[0] > 0:
        cross = clear_of_posts_nb(cross, posts, prm[A_POST_CLEARANCE])
    if cross.shape[0] > 0:  # and where a post or net is seen standing on it, though its base is not
        cross = not_under_posts_nb(cross, classes, cam, goal_a, goal_b, net, prm[A_POST_RADIUS], prm[A_GOAL_HEIGHT])
    radius = prm[A_CIRCLE_RADIUS]
    if math.isfinite(cx):
        cross = circle_crossings_nb(cross, cx, cy, radius, seg_ground, cam, prm[A_MAX_DISTANCE], classes, boundary)
    marks = marks_nb(
        classes, points, loose, cam, prm[A_MARK_SIZE], prm[A_MARK_TOL], prm[A_MARK_GREEN], int(prm[A_MARK_PX])
    )
    cross_rows = crossing_rows_nb(cross, cam, sa, sb)
    line_rows = line_rows_nb(seg_px, seg_ground, cam, sa, sb)
    circle_rows = np.empty((0, N_COLS))
    if math.isfinite(cx):
        centre = np.empty((1, 2))
        centre[0, 0], centre[0, 1] = cx, cy
        circle_rows = point_rows_nb(centre, np.full((1, 2), np.nan), 0.0, cam, sa, sb)
    mark_rows = np.empty((0, N_COLS))
    if marks.shape[0] > 0:
        xy, ok = ground_points_nb(cam, marks, prm[A_MARK_MAX])
        uv = np.ascontiguousarray(marks[ok, :2])
        mark_rows = point_rows_nb(np.ascontiguousarray(xy[ok]), uv, 0.0, cam, sa, sb)
    # Kind order: POST, CROSS, LINE, CIRCLE, MARK, BALL, ROBOT, POLE (none from vision)
    tables = (posts, cross_rows, line_rows, circle_rows, mark_rows, ball, robots)
    offsets = np.zeros(N_KINDS + 1, dtype=np.int64)
    for k in range(len(tables)):
        offsets[k + 1] = offsets[k] + tables[k].shape[0]
    for k in range(len(tables), N_KINDS):
        offsets[k + 1] = offsets[k]
    rows = np.empty((offsets[N_KINDS], N_COLS))
    k = 0
    for t in tables:
        rows[k : k + t.shape[0]] = t
        k += t.shape[0]
    return rows, offsets, seg_px, seg_ground


@nb.njit(cache=True, error_model="python", fastmath=False)
def circle_crossings_nb(
    cross: NDArray[np.float64],
    cx: float,
    cy: float,
    radius: float,
    seg_ground: NDArray[np.float64],
    cam: NDArray[np.float64],
    max_distance: float,
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """``cross`` (C x 6) plus the X crossings where a line through the circle's centre (the
    halfway line) meets the circle; the circle's X replaces whatever the segments made there."""
    extra = np.empty((2, 6))
    n_extra = 0
    for k in range(seg_ground.shape[0]):
        x1, y1, x2, y2 = seg_ground[k, 0], seg_ground[k, 1], seg_ground[k, 2], seg_ground[k, 3]
        length = math.hypot(x2 - x1, y2 - y1)
        if length < 0.3:
            continue
        dx, dy = (x2 - x1) / length, (y2 - y1) / length
        if abs((cx - x1) * dy - (cy - y1) * dx) > 0.15:
            continue
        for s in (-1.0, 1.0):
            px, py = cx + s * radius * dx, cy + s * radius * dy
            # it must be in view and on white (a robot may stand on it)
            if look_nb(classes, boundary, cam, px, py) == 1 and math.hypot(px, py) <= max_distance:
                extra[n_extra, 0] = px
                extra[n_extra, 1] = py
                extra[n_extra, 2] = 2.0
                extra[n_extra, 3] = math.atan2(dy, dx) % (0.5 * math.pi)
                extra[n_extra, 4] = 1.0
                extra[n_extra, 5] = 0.0
                n_extra += 1
        break
    if n_extra == 0:
        return cross
    keep = np.ones(cross.shape[0], dtype=np.bool_)
    for k in range(cross.shape[0]):
        for e in range(n_extra):
            if math.hypot(cross[k, 0] - extra[e, 0], cross[k, 1] - extra[e, 1]) <= 0.3:
                keep[k] = False
    return np.concatenate((cross[keep], extra[:n_extra]))
