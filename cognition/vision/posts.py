"""Goal posts: runs of the goal colour that stand on the carpet (DNT section 3.8).

DNT finds goal posts from a histogram of goal-coloured pixels per image column, takes its
local maxima as post candidates, follows each one down to its bottom (the transition from
the goal colour to green), checks its width, and tells the left post from the right one by
the crossbar attached at the top. This module does the same on the class image, with the
camera matrix predicting every post it checks, so that it also works where the goal colour
is not unique: ``modern`` goals are the white of the lines, the robots, the ball and the net.

1. **Column histogram.** Each column is searched upward from its field boundary for a foot:
   the lowest goal-coloured pixel with carpet right below it (within ``foot_gap``; carpet is
   green and, where white is not a goal colour, lines). A post standing there would have its
   front foot at that pixel; the camera matrix gives its axis in the image (foot to the top
   at ``goal_height``, vertical in the world, so slanted by roll and perspective). The
   column's histogram value is the goal-coloured run up that axis (sampled, at most 24
   samples); the column is a candidate when the run covers ``min_fill`` of the post's
   visible part. The run forgives single noisy pixels but ends at ``max_gap`` misses in a
   row and at two pixels of carpet or of another colour in a row (a robot's jersey). Lines
   and the ball never pass: they lie on the ground, a post is 0.8 m tall and crosses the
   horizon.
2. **Candidates** are the runs of neighbouring candidate columns (the histogram's peaks);
   two runs with goal colour between them are one post standing on a line seen along its
   length (white goals). Their width must match the post's projected diameter at their
   distance (``width_range``, ``width_slack``, at least ``min_width``); a run that is too
   narrow or too wide (part of a post, or a post in front of a white net, robot or wall) is
   searched for the windows of one diameter that pass, and the one standing lowest is kept
   (a post stands in front of its net). Along the axis, walked pixel by pixel, the run must
   cover ``min_fill`` of the visible part, and ``band_fill`` of a band 0.6 diameters wide and
   ``column_fill`` of each of its columns must be goal-coloured (a net string is thinner than
   a post). The foot of a candidate is the 30th percentile of its columns' feet (a line under
   a white post, seen along its length, puts some feet lower); when the run fails right above
   it (a line in front of the post), the next foot up is tried.
3. **Too little in view.** Near the camera a line seen along the axis looks like a post's
   foot, so the visible part must reach ``min_height`` up the post (less, as 1 / distance,
   beyond ``min_height_range``); when only the part below ``robot_height`` is in view, the
   rows of the lower half must also be no wider than a post (robots' legs are white too).
   With two goal colours a KidSize corner pole, banded in both, is told from a post by the
   second colour on top of the first; the part up to ``pole_band`` must be in view to see it.
4. **Position.** The bottom pixel sees the front of the post: its ground point is pushed back
   by the post's radius along the viewing direction to the centre. ``u, v`` is the pixel of
   that base centre (as in the synthesized percepts), ``u2, v2`` the top of the goal-coloured
   run along the axis (at most the projected top of the post). Of two posts closer than
   ``separation`` on the ground the nearer one is kept (the net stands behind the posts).
5. **Side.** Two posts of the same colour whose bases are ``pair_distance`` apart are one
   goal: the one further left in the image is the left post (as seen from the field facing
   the goal), and anything else of their colour between them is their net and dropped. A
   single post with its top in view gets its side from the crossbar, traced sideways from the
   top column by column along its slope: if it runs ``crossbar_length`` post widths (at least
   4 px) to one side only, at least ``crossbar_thickness`` diameters thick (net strings are
   thinner), the post is the left one when the bar goes right. Otherwise the side is unknown.

The goal of a post is read from its colour when the goals differ (``goal`` 0 for the colour
class ``goal_classes[0]`` of the own goal, 1 for the opponent's, -1 when both goals share a
colour). Posts whose foot is outside the image or hidden (by a robot, the ball) have no
carpet below their run and are not reported; a post cut by the left or right image edge is
reported when its centre is in view, placed from its visible edge and its projected diameter.

All pixel work is one compiled call; pixel sizes are for a 320 x 240 image and scale with the
image width. The compiled steps live in :mod:`.posts_scan` (the column histogram and the
candidate runs, steps 1-2) and :mod:`.posts_check` (a candidate checked along its axis, steps
2-3, and the crossbar of step 5); this module holds the parameters, the entry point and the
compiled driver that runs them and places, thins out and pairs the posts (steps 4-5).

==================  =============  =============  ==================================================
PostParams          default        range          meaning
==================  =============  =============  ==================================================
line_gap            3 px           [0, 20]        non-carpet pixels in a row skipped between the
                                                  field boundary and a foot (thin lines, noise)
foot_reach          16 px          [1, 200]       rows above the field boundary searched for a foot
foot_gap            1 px           [0, 20]        pixels allowed between a post and the carpet
min_fill            0.75           [0, 1]         goal-coloured share of the visible part of a post
max_gap             2 px           [0, 20]        misses in a row that end a post's run
min_length          8 px           [1, 1000]      shortest visible post (foot to the run's top) ...
min_length_unique   4 px           [1, 1000]      ... where no line is goal-coloured (yellow goals)
min_height          0.25 m         [0, 10]        height of the post that must be in view ...
min_height_range    2.0 m          (0, 100]       ... within this distance (as 1 / distance beyond)
robot_height        0.6 m          [0, 10]        below this height only, rows must be post-wide
pole_band           0.3 m          [0, 10]        with two goal colours: height of a corner pole's
                                                  lowest band, must be in view (0: not needed)
width_range         (0.4, 1.6)     [0, 10]        accepted run width / projected diameter
width_slack         0.75 px        [0, 20]        extra width tolerance (blur, anti-aliasing)
min_width           2 px           [0, 100]       narrowest post (net strings are one pixel)
band_fill           0.8            [0, 1]         goal-coloured share of the band along the axis
column_fill         0.5            [0, 1]         goal-coloured share of each column of the band
crossbar_length     2.0            [0, 50]        diameters the crossbar must be followed
crossbar_thickness  0.5            [0, 1]         thinnest crossbar run, share of the diameter
pair_distance       (1.0, 2.4) m   [0, 20]        distance of the two post bases of one goal
separation          0.9 m          [0, 10]        closer posts are one (the nearer is kept)
max_distance        12.0 m         (0, 100]       posts farther away (on the ground) are dropped
==================  =============  =============  ==================================================
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import ClassVar

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.camera import CAMERA_ROW_SIZE
from cognition.params import Range, Ranges, check_ranges, non_negative, positive
from cognition.percepts import Col
from cognition.vision.colour import Colour
from cognition.vision.image import VisionError
from cognition.vision.posts_check import _candidate, _crossbar, _split
from cognition.vision.posts_scan import (
    _N_PARAMS,
    _P_BAND,
    _P_BAR,
    _P_COL,
    _P_DHI,
    _P_DLO,
    _P_DMAX,
    _P_FILL,
    _P_FOOT,
    _P_GAP,
    _P_HEIGHT,
    _P_HRANGE,
    _P_LEN,
    _P_LEN_U,
    _P_LINE,
    _P_NMS,
    _P_POLE,
    _P_REACH,
    _P_ROBOT,
    _P_SLACK,
    _P_THICK,
    _P_WHI,
    _P_WLO,
    _P_WMIN,
    _columns,
    _intervals,
    _post_at,
)
from cognition.vision.projection import pixel_nb
from cognition.vision.rows import point_rows_nb


@dataclass(frozen=True)
class PostParams:
    """Parameters of the goal-post detector (module table; pixels at 320 x 240)."""

    line_gap: int = 3
    foot_reach: int = 16
    foot_gap: int = 1
    min_fill: float = 0.75
    max_gap: int = 2
    min_length: float = 8.0
    min_length_unique: float = 4.0
    min_height: float = 0.25
    min_height_range: float = 2.0
    robot_height: float = 0.6
    pole_band: float = 0.3
    width_range: tuple[float, float] = (0.4, 1.6)
    width_slack: float = 0.75
    min_width: float = 2.0
    band_fill: float = 0.8
    column_fill: float = 0.5
    crossbar_length: float = 2.0
    crossbar_thickness: float = 0.5
    pair_distance: tuple[float, float] = (1.0, 2.4)
    separation: float = 0.9
    max_distance: float = 12.0
    RANGES: ClassVar[Ranges] = {
        "line_gap": Range(0, 20),
        "foot_reach": Range(1, 200),
        "foot_gap": Range(0, 20),
        "min_fill": Range(0.0, 1.0),
        "max_gap": Range(0, 20),
        "min_length": Range(1.0, 1000.0),
        "min_length_unique": Range(1.0, 1000.0),
        "min_height": non_negative(10.0),
        "min_height_range": positive(100.0),
        "robot_height": non_negative(10.0),
        "pole_band": non_negative(10.0),
        "width_range": non_negative(10.0),
        "width_slack": non_negative(20.0),
        "min_width": non_negative(100.0),
        "band_fill": Range(0.0, 1.0),
        "column_fill": Range(0.0, 1.0),
        "crossbar_length": non_negative(50.0),
        "crossbar_thickness": Range(0.0, 1.0),
        "pair_distance": non_negative(20.0),
        "separation": non_negative(10.0),
        "max_distance": positive(100.0),
    }

    def __post_init__(self) -> None:
        check_ranges(self)
        for name in ("width_range", "pair_distance"):
            lo, hi = getattr(self, name)
            if lo > hi:
                raise ValueError(f"PostParams.{name} must be (low, high) with low <= high, got {(lo, hi)!r}")

    @cached_property
    def packed(self) -> NDArray[np.float64]:
        """The parameters as the flat vector the compiled detector reads (pixels at 320 x 240);
        read-only, and not a field, so configurations stay plain data."""
        values = {
            _P_GAP: self.max_gap, _P_LINE: self.line_gap, _P_FILL: self.min_fill, _P_LEN: self.min_length,
            _P_WLO: self.width_range[0], _P_WHI: self.width_range[1], _P_SLACK: self.width_slack,
            _P_BAR: self.crossbar_length, _P_THICK: self.crossbar_thickness, _P_DLO: self.pair_distance[0],
            _P_DHI: self.pair_distance[1], _P_DMAX: self.max_distance, _P_BAND: self.band_fill,
            _P_REACH: self.foot_reach, _P_WMIN: self.min_width, _P_FOOT: self.foot_gap,
            _P_ROBOT: self.robot_height, _P_HEIGHT: self.min_height, _P_NMS: self.separation,
            _P_HRANGE: self.min_height_range, _P_COL: self.column_fill, _P_POLE: self.pole_band,
            _P_LEN_U: self.min_length_unique,
        }  # fmt: skip
        packed = np.zeros(_N_PARAMS)
        for k, value in values.items():
            packed[k] = value
        packed.flags.writeable = False
        return packed


_MAX_CAND = 64
_NO_DEBUG = np.zeros((0, 9))
_GREEN = int(Colour.GREEN)
_U2, _V2, _SUB, _GOAL = int(Col.U2), int(Col.V2), int(Col.SUBTYPE), int(Col.GOAL)


def detect_posts(
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    goal_classes: tuple[int, int],
    post_diameter: float,
    goal_height: float,
    params: PostParams,
    sigma_alpha: float,
    sigma_beta: float,
) -> NDArray[np.float64]:
    """Percept rows (cognition.percepts columns, N x N_COLS) of the posts in one class image.

    ``classes`` is the class image (H x W uint8, :class:`~cognition.vision.colour.Colour`
    codes), ``boundary`` the first field row of each column (W integers,
    :func:`~cognition.vision.boundary.field_boundary`), ``cam`` the camera row
    (:meth:`CameraMatrix.as_row`, 18 floats), ``goal_classes`` the colour classes of the own
    and the opponent goal, ``post_diameter`` and ``goal_height`` the goal's sizes (m) and the
    sigmas (rad) those of the frame's measurement model. Rows: ``x, y`` base centre (m, robot
    frame), ``u, v`` its pixel, ``u2, v2`` the top of the visible post, ``subtype``
    :class:`~cognition.percepts.PostSide`, ``goal`` 0 / 1 / -1 (module docstring), Darmstadt
    covariance. Raises :class:`~cognition.vision.VisionError` (a ``ValueError``) naming the
    problem for bad input.
    """
    if not isinstance(params, PostParams):
        raise VisionError(f"params must be PostParams, got {type(params).__name__}")
    if not isinstance(classes, np.ndarray) or classes.ndim != 2 or classes.dtype != np.uint8:
        raise VisionError(f"classes must be an H x W uint8 class image, got {_describe(classes)}")
    height, width = classes.shape
    if height < 8 or width < 8:
        raise VisionError(f"classes must be at least 8 x 8 pixels, got {width} x {height}")
    if not isinstance(boundary, np.ndarray) or boundary.shape != (width,) or boundary.dtype.kind not in "iu":
        raise VisionError(f"boundary must be {width} integers (one per column of classes), got {_describe(boundary)}")
    if not isinstance(cam, np.ndarray) or cam.shape != (CAMERA_ROW_SIZE,) or cam.dtype.kind not in "fiu":
        raise VisionError(f"cam must be the camera row of {CAMERA_ROW_SIZE} numbers (CameraMatrix.as_row()), "
                          f"got {_describe(cam)}")  # fmt: skip
    if not math.isfinite(sum(cam.tolist())):
        raise VisionError(f"cam has non-finite entries: {cam.tolist()}")
    if cam[16] != width or cam[17] != height:
        raise VisionError(f"the camera is for {cam[16]:g} x {cam[17]:g} pixels but classes is {width} x {height}")
    g0, g1 = _goal_pair(goal_classes)
    return _posts_nb(
        classes if classes.flags.c_contiguous else np.ascontiguousarray(classes),
        boundary if boundary.dtype == np.int32 else boundary.astype(np.int32),
        cam if cam.dtype == np.float64 else cam.astype(np.float64),
        g0,
        g1,
        _number("post_diameter", post_diameter, True),
        _number("goal_height", goal_height, True),
        params.packed,
        width / 320.0,
        _number("sigma_alpha", sigma_alpha, False),
        _number("sigma_beta", sigma_beta, False),
        _NO_DEBUG,
    )


def _goal_pair(goal_classes: object) -> tuple[int, int]:
    """The two goal colour classes as ints, or a VisionError."""
    if isinstance(goal_classes, tuple | list) and len(goal_classes) == 2:
        g0, g1 = goal_classes
        if _is_class(g0) and _is_class(g1):
            return int(g0), int(g1)
    raise VisionError(
        f"goal_classes must be the colour classes (Colour codes other than GREEN) of the own and the opponent "
        f"goal, got {goal_classes!r}"
    )


def _is_class(g: object) -> bool:
    """Whether ``g`` is a colour class code other than GREEN (int, Colour or numpy integer)."""
    t = type(g)
    if t is int or t is Colour or (isinstance(g, int | np.integer) and t is not bool):
        return 0 <= g <= 255 and g != _GREEN  # type: ignore[operator]
    return False


def _number(name: str, value: object, positive: bool) -> float:
    """``value`` as a float if it is a finite real number (> 0 or >= 0), else a VisionError."""
    if value.__class__ is float or (
        isinstance(value, int | float | np.integer | np.floating) and not isinstance(value, bool)
    ):
        x = float(value)  # type: ignore[arg-type]
        if math.isfinite(x) and (x > 0.0 if positive else x >= 0.0):
            return x
    rule = "> 0" if positive else ">= 0"
    raise VisionError(f"{name} must be a finite number {rule}, got {value!r}")


def _describe(a: object) -> str:
    if isinstance(a, np.ndarray):
        return f"array of shape {a.shape} and dtype {a.dtype}"
    return type(a).__name__


# -- compiled driver --------------------------------------------------------------------------


@nb.njit(cache=True, error_model="python", fastmath=False)
def _posts_nb(
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    g0: int,
    g1: int,
    diameter: float,
    goal_h: float,
    packed: NDArray[np.float64],
    scale: float,
    sa: float,
    sb: float,
    dbg: NDArray[np.float64],
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """The detector (module docstring) with the parameters ``packed`` and pixel sizes scaled
    by ``scale`` (image width / 320). ``dbg`` (K x 9, or empty) receives one row per
    candidate: first and last column, projected diameter, foot row, band fill, run share,
    outcome (0 kept, 1 width, 2 too little in view, 3 band, 4 distance, 5 projection, 6 wider
    than a post), centre column, smallest column fill."""
    prm = packed.copy()
    if g0 != 2 and g1 != 2:  # no line is goal-coloured: a shorter piece of a post will do
        prm[_P_LEN] = prm[_P_LEN_U]
    for k in (_P_LEN, _P_SLACK, _P_WMIN):
        prm[k] *= scale
    for k in (_P_GAP, _P_LINE, _P_REACH, _P_FOOT):
        prm[k] = max(0.0 if k != _P_REACH else 1.0, math.floor(prm[k] * scale + 0.5))
    r = 0.5 * diameter
    # 1. the column histogram: run up the predicted axis of a post standing at the boundary
    cand, feet = _columns(classes, boundary, cam, g0, g1, r, goal_h, prm)
    # 2. candidates: runs of neighbouring candidate columns, checked along their axis
    out_xy = np.empty((_MAX_CAND, 2))
    out_uv = np.empty((_MAX_CAND, 2))
    out_top = np.empty((_MAX_CAND, 2))
    out_goal = np.empty(_MAX_CAND)
    out_side = np.zeros(_MAX_CAND)
    out_colour = np.empty(_MAX_CAND, dtype=np.int64)
    n = 0
    nd = 0
    starts, ends = _intervals(classes, cam, cand, feet, g0, g1, r, goal_h, prm)
    # a work list: the candidates, then the pieces of those that fail (split where their feet
    # jump) and the rest of a wide run beside the post found in it (a second post behind)
    cap = starts.shape[0] + 64
    work = np.empty((cap, 2), dtype=np.int64)
    nw = starts.shape[0]
    work[:nw, 0], work[:nw, 1] = starts, ends
    jump = max(1.0, 3.0 * scale)
    q = -1
    while q + 1 < nw and n < _MAX_CAND:
        q += 1
        a, e = work[q, 0], work[q, 1]
        res, uc, w_exp, searched = _candidate(classes, cam, feet, g0, g1, a, e, r, goal_h, prm)
        code = res[0]
        if code != 0:
            pieces = _split(cam, feet, a, e, r, goal_h, jump)
            if pieces.shape[0] > 1:
                for k in range(pieces.shape[0]):
                    if nw < cap:
                        work[nw, 0], work[nw, 1] = pieces[k, 0], pieces[k, 1]
                        nw += 1
        if nd < dbg.shape[0]:
            dbg[nd, 0], dbg[nd, 1], dbg[nd, 2], dbg[nd, 3] = a, e, w_exp, res[3]
            dbg[nd, 4], dbg[nd, 5], dbg[nd, 6], dbg[nd, 7], dbg[nd, 8] = res[1], res[2], code, uc, res[11]
            nd += 1
        if code != 0:
            continue
        _, _, _, vb, xc, yc, ut, vt, n0, n1, last, _ = res
        _, _, _, _, _, w_exp = _post_at(cam, uc, vb, r, goal_h)
        if searched:  # the rest of the run beside the post
            for lo, hi in ((a, int(uc - 0.5 * w_exp) - 1), (int(uc + 0.5 * w_exp) + 1, e)):
                if hi - lo + 1.0 >= max(prm[_P_WMIN], prm[_P_WLO] * w_exp) and nw < cap:
                    work[nw, 0], work[nw, 1] = lo, hi
                    nw += 1
        ub, vbc, _ = pixel_nb(cam, xc, yc, 0.0)
        if not (0.0 <= ub < classes.shape[1] and 0.0 <= vbc < classes.shape[0]):
            continue  # the centre of its base is outside the image: not reported
        out_xy[n, 0], out_xy[n, 1] = xc, yc
        out_uv[n, 0], out_uv[n, 1] = ub, vbc
        vtop = max(last, vt)
        out_top[n, 0] = uc + (ut - uc) * (vb - vtop) / max(vb - vt, 1e-9)
        out_top[n, 1] = vtop
        out_colour[n] = g0 if n0 >= n1 else g1
        out_goal[n] = -1.0 if g0 == g1 else (0.0 if n0 >= n1 else 1.0)
        # 3. the crossbar, when the top is in view
        if vt >= 1.0 and last <= vt + max(2.0, 0.5 * w_exp):
            thick = max(1.0, prm[_P_THICK] * w_exp)
            steps = max(4, int(prm[_P_BAR] * w_exp + 0.5))
            vbar = vt + 0.5 * w_exp
            gc = out_colour[n]
            nl, el, wl = _crossbar(classes, gc, gc, ut - 0.5 * w_exp - 1.0, vbar, -1, thick, steps)
            nr, er, wr = _crossbar(classes, gc, gc, ut + 0.5 * w_exp + 1.0, vbar, 1, thick, steps)
            long_l = nl >= steps or (el and nl >= 3)
            long_r = nr >= steps or (er and nr >= 3)
            # the other side must be seen without a bar (not cut off by the image edge), and no
            # wall of the goal's colour behind the top may pass for a bar
            if wl or wr:
                pass
            elif long_r and not long_l and nl < steps // 2 and not el:
                out_side[n] = 1.0
            elif long_l and not long_r and nr < steps // 2 and not er:
                out_side[n] = 2.0
        n += 1
    # 4. one post per place: of two candidates closer than ``separation`` on the ground keep
    # the nearer one (the posts stand in front of the net)
    keep = np.ones(n, dtype=np.bool_)
    for i in range(n):
        for k in range(n):
            if i != k and keep[i] and keep[k]:
                d = math.hypot(out_xy[k, 0] - out_xy[i, 0], out_xy[k, 1] - out_xy[i, 1])
                if d < prm[_P_NMS]:
                    far = k if math.hypot(out_xy[k, 0], out_xy[k, 1]) > math.hypot(out_xy[i, 0], out_xy[i, 1]) else i
                    keep[far] = False
    m = 0
    for i in range(n):
        if keep[i]:
            out_xy[m], out_uv[m], out_top[m] = out_xy[i], out_uv[i], out_top[i]
            out_goal[m], out_side[m], out_colour[m] = out_goal[i], out_side[i], out_colour[i]
            m += 1
    n = m
    # 5. pairs of one goal: the left one in the image is the left post
    paired = np.zeros(n, dtype=np.bool_)
    partner = np.full(n, -1, dtype=np.int64)
    for i in range(n):
        if paired[i]:
            continue
        best = -1
        best_err = 1e9
        for k in range(n):
            if k == i or paired[k] or out_colour[k] != out_colour[i]:
                continue
            d = math.hypot(out_xy[k, 0] - out_xy[i, 0], out_xy[k, 1] - out_xy[i, 1])
            if prm[_P_DLO] <= d <= prm[_P_DHI]:
                err = abs(d - 0.5 * (prm[_P_DLO] + prm[_P_DHI]))
                if err < best_err:
                    best_err = err
                    best = k
        if best >= 0:
            paired[i] = True
            paired[best] = True
            left, right = (i, best) if out_uv[i, 0] < out_uv[best, 0] else (best, i)
            out_side[left] = 1.0
            out_side[right] = 2.0
            partner[left] = right
    # 6. nothing of the goal's colour stands between the two posts of a goal but its net
    m = 0
    for i in range(n):
        inside = False
        if not paired[i]:
            for k in range(n):
                if partner[k] >= 0 and out_colour[k] == out_colour[i]:
                    inside = inside or out_uv[k, 0] < out_uv[i, 0] < out_uv[partner[k], 0]
        if not inside:
            out_xy[m], out_uv[m], out_top[m] = out_xy[i], out_uv[i], out_top[i]
            out_goal[m], out_side[m] = out_goal[i], out_side[i]
            m += 1
    rows = point_rows_nb(out_xy[:m], out_uv[:m], 0.0, cam, sa, sb)
    for i in range(m):
        rows[i, _U2] = out_top[i, 0]
        rows[i, _V2] = out_top[i, 1]
        rows[i, _SUB] = out_side[i]
        rows[i, _GOAL] = out_goal[i]
    return rows
