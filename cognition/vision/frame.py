"""One camera frame through the whole vision pipeline in one compiled call.

:meth:`cognition.vision.Vision.detect` checks its input in Python (a bad image or camera is
a :class:`~cognition.vision.VisionError` before any compiled code runs), calibrates the
colour classes, and then hands the frame to :func:`frame_nb`, which runs every stage of
:mod:`.vision`'s table in order: colour classes (:mod:`.colour`), field boundary
(:mod:`.boundary`), lines by either method (:mod:`.dnt` or :mod:`.hough`, with the
penalty-mark seeds of :mod:`.marks`), goal posts (:mod:`.posts`), ball (:mod:`.ball`),
robots (:mod:`.robots`), the geometric stages and the percept table (:mod:`.assemble`), and
the rules every percept row must satisfy (those :class:`cognition.percepts.Percepts` checks).
Calling the stages one by one from Python cost more in dispatch (every array argument and
every returned array crosses the interpreter boundary) than several of them cost to run.

All parameters of one image size are packed into one vector (:func:`frame_config`, entries
``C_*`` and the stages' own parameter vectors at the offsets ``O_*``), built once per size.

This driver compiles every stage into its own machine code; its on-disk cache is stamped
with the contents of every project module it imports (:mod:`cognition.kernel_cache`), so an
edit of any stage recompiles it.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.field import Field
from cognition.percept_checks import _SUBTYPE_MAX, _first_invalid_nb
from cognition.percepts import N_COLS
from cognition.vision import assemble as asm
from cognition.vision.ball import _detect_ball_nb
from cognition.vision.ball import _vector as ball_vector
from cognition.vision.boundary import _boundary
from cognition.vision.colour import _classify
from cognition.vision.dnt import dnt_lines_nb
from cognition.vision.hough import _FIELDS as HOUGH_FIELDS
from cognition.vision.hough import _config as hough_config
from cognition.vision.hough import _hough_nb
from cognition.vision.marks import loose_points_nb
from cognition.vision.params import VisionParams
from cognition.vision.posts import _posts_nb
from cognition.vision.posts_scan import _N_PARAMS as POST_PARAMS
from cognition.vision.robots import _detect_robots_nb
from cognition.vision.robots import _vector as robot_vector
from cognition.vision.scanlines import line_points_nb

# scalar entries of the frame configuration (pixel sizes already scaled to the image)
(C_HOUGH, C_STEP, C_GAP, C_PROBE, C_RUN, C_LINE_WIDTH, C_MAX_DISTANCE, C_MIN_LINE, C_INLIER, C_LOOSE, C_SCALE,
 C_POST_D, C_GOAL_H, C_BALL_R, C_MODERN, C_ROBOT_R, C_TEAM, C_JERSEY0, C_JERSEY1, C_GOAL_OWN, C_GOAL_OPP, C_NET,
 C_N) = range(23)  # fmt: skip
_N_CHAIN, _N_CIRCLE, _N_BALL, _N_ROBOTS = 5, 7, 17, 11
# offsets of the stages' parameter vectors in the frame configuration
O_CHAIN = C_N
O_CIRCLE = O_CHAIN + _N_CHAIN
O_ASSEMBLE = O_CIRCLE + _N_CIRCLE
O_POSTS = O_ASSEMBLE + asm.A_N
O_BALL = O_POSTS + POST_PARAMS
O_ROBOTS = O_BALL + _N_BALL
O_HOUGH = O_ROBOTS + _N_ROBOTS
N_CONFIG = O_HOUGH + len(HOUGH_FIELDS)

# status codes of frame_nb
OK, BAD_CAMERA = 0, 1


def frame_config(
    params: VisionParams,
    field: Field,
    classes: tuple[int, int, int, int, int],
    modern_ball: bool,
    team: int,
    width: int,
    height: int,
) -> NDArray[np.float64]:
    """The configuration vector of :func:`frame_nb` for images of ``width`` x ``height`` px.

    ``classes`` are the colour classes of the own goal, the opponent goal, the nets and the
    two teams' jerseys; ``modern_ball`` selects the white ball with black patches, ``team``
    is the own team's jersey index (0 or 1). Pixel sizes are scaled from 320 px width."""
    p = params
    dims = field.dims
    scale = width / 320.0
    goal_own, goal_opp, net, jersey0, jersey1 = classes
    out = np.zeros(N_CONFIG)
    out[: C_N] = [
        p.method == "hough", max(1, round(p.scan_step * scale)), max(1, round(p.edge_gap * scale)),
        max(4, round(12 * scale)), max(1, round(p.boundary_run * height / 240.0)), dims.line_width, p.max_distance,
        p.min_line_length, p.circle_inlier, 3.0 * width / 320.0, scale, dims.goal_post_diameter, dims.goal_height,
        dims.ball_diameter / 2, modern_ball, p.robot_radius, team, jersey0, jersey1, goal_own, goal_opp, net,
    ]  # fmt: skip
    out[O_CHAIN:O_CIRCLE] = [p.chain_gap * scale, p.chain_tolerance * scale, p.min_white, p.min_points, p.merge_angle]
    out[O_CIRCLE:O_ASSEMBLE] = [
        p.circle_cell, p.circle_directions, p.circle_inlier, p.circle_min_points, p.circle_min_span,
        p.circle_min_coverage, p.circle_vote_every,
    ]  # fmt: skip
    values = {
        asm.A_GOAL_WIDTH: dims.goal_inner_width + dims.goal_post_diameter, asm.A_GOAL_BEHIND: p.goal_behind,
        asm.A_MIN_LINE: p.min_line_length, asm.A_MARGIN: p.crossing_margin, asm.A_MARGIN_IN: p.crossing_margin_in,
        asm.A_BEYOND: p.crossing_beyond, asm.A_ANGLE: p.crossing_angle, asm.A_MIN_ARM: p.crossing_min_arm,
        asm.A_MERGE_ANGLE: p.merge_angle, asm.A_MERGE_OFFSET: p.merge_offset, asm.A_MERGE_GAP: p.merge_gap,
        asm.A_MAX_MPP: p.crossing_max_mpp, asm.A_CROSS_MAX: p.crossing_max_distance * math.sqrt(scale),
        asm.A_POST_CLEARANCE: p.post_clearance, asm.A_POST_RADIUS: dims.goal_post_diameter / 2,
        asm.A_GOAL_HEIGHT: dims.goal_height, asm.A_MAX_DISTANCE: p.max_distance,
        asm.A_CIRCLE_RADIUS: field.centre_circle.radius if field.centre_circle is not None else 0.0,
        asm.A_MARK_SIZE: dims.penalty_mark_size, asm.A_MARK_TOL: p.mark_tolerance,
        asm.A_MARK_GREEN: p.mark_min_green, asm.A_MARK_PX: max(1, round(p.mark_min_px * scale)),
        asm.A_MARK_MAX: p.mark_max_distance,
    }  # fmt: skip
    for k, value in values.items():
        out[O_ASSEMBLE + k] = value
    out[O_POSTS:O_BALL] = p.posts.packed
    out[O_BALL:O_ROBOTS] = ball_vector(p.ball, width)
    out[O_ROBOTS:O_HOUGH] = robot_vector(p.obstacles, width)
    out[O_HOUGH:] = hough_config(p.hough, width)
    return out


@nb.njit(cache=True, error_model="python", fastmath=False)
def frame_nb(
    rgb: NDArray[np.uint8],
    cam: NDArray[np.float64],
    table: NDArray[np.uint8],
    cfg: NDArray[np.float64],
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    own_goal: int,
    blur_u: float,
    blur_v: float,
    sa: float,
    sb: float,
) -> tuple:  # pragma: no cover - compiled
    """Percepts of one RGB image (H x W x 3) taken with the camera row ``cam``.

    ``table`` is the colour lookup table of the image's calibration
    (:meth:`~cognition.vision.colour.ColourClassifier.lut`), ``cfg`` the configuration of
    :func:`frame_config`; ``classes`` (H x W) and ``boundary`` (W) receive the class image
    and the field boundary. ``own_goal`` says which goal colour the robot defends (0 or 1),
    ``blur_u``, ``blur_v`` are the motion blur (px) along rows and columns and ``sa``,
    ``sb`` the angular sigmas (rad) of the frame.

    Returns ``(status, rows, offsets, points, seg_px, seg_ground, invalid)``: :data:`OK` or
    :data:`BAD_CAMERA` (a camera row the object detectors cannot use; nothing else is then
    valid), the percept table and its kind offsets (:class:`~cognition.percepts.Percepts`),
    the line points (K x 4), the segments in the image and on the ground (S x 4) and the
    first row that breaks the percept rules (-1: none).
    """
    _classify(rgb, table, classes)
    _boundary(classes, cam, int(cfg[C_RUN]), boundary)
    step, gap, probe = int(cfg[C_STEP]), int(cfg[C_GAP]), int(cfg[C_PROBE])
    line_width, max_distance, min_line = cfg[C_LINE_WIDTH], cfg[C_MAX_DISTANCE], cfg[C_MIN_LINE]
    prm = cfg[O_ASSEMBLE:O_POSTS]
    radius = prm[asm.A_CIRCLE_RADIUS]
    if cfg[C_HOUGH] == 0.0:
        points, seg_px, seg_ground, open_ends, cx, cy, loose = dnt_lines_nb(
            classes, boundary, cam, step, line_width, gap, max_distance, radius, cfg[O_CIRCLE:O_ASSEMBLE],
            cfg[O_CHAIN:O_CIRCLE], min_line, probe, blur_u, blur_v,
        )  # fmt: skip
    else:
        seg_px, seg_ground, open_ends, centre, _ = _hough_nb(
            classes, boundary, cam, line_width, radius, cfg[O_HOUGH:N_CONFIG]
        )
        cx, cy = centre
        # penalty-mark seeds: scanline points that lie on no line and not on the circle
        points = line_points_nb(classes, boundary, cam, step, line_width, gap, blur_u, blur_v)
        loose = loose_points_nb(points, seg_px, cam, cx, cy, radius, cfg[C_INLIER], cfg[C_LOOSE])
    own, opp = int(cfg[C_GOAL_OWN]), int(cfg[C_GOAL_OPP])
    goal_a, goal_b = (own, opp) if own_goal == 0 else (opp, own)
    posts = _posts_nb(
        classes, boundary, cam, goal_a, goal_b, cfg[C_POST_D], cfg[C_GOAL_H], cfg[O_POSTS:O_BALL], cfg[C_SCALE], sa,
        sb, np.zeros((0, 9)),
    )  # fmt: skip
    ball, bad_ball = _detect_ball_nb(
        rgb, classes, boundary, cam, cfg[C_BALL_R], cfg[C_MODERN] != 0.0, cfg[O_BALL:O_ROBOTS], sa, sb
    )
    robots, bad_robots = _detect_robots_nb(
        classes, boundary, cam, int(cfg[C_JERSEY0]), int(cfg[C_JERSEY1]), int(cfg[C_TEAM]), cfg[C_ROBOT_R],
        cfg[O_ROBOTS:O_HOUGH], sa, sb,
    )  # fmt: skip
    if bad_ball or bad_robots:
        empty = np.empty((0, 4))
        return BAD_CAMERA, np.empty((0, N_COLS)), np.zeros(1, dtype=np.int64), empty, empty, empty, -1
    rows, offsets, seg_px, seg_ground = asm.assemble_nb(
        classes, boundary, cam, points, loose, seg_px, seg_ground, open_ends, cx, cy, posts, ball, robots, goal_a,
        goal_b, int(cfg[C_NET]), prm, sa, sb,
    )  # fmt: skip
    return OK, rows, offsets, points, seg_px, seg_ground, _first_invalid_nb(rows, offsets, _SUBTYPE_MAX)[0]
