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
image width.

==================  =============  =============  ==================================================
PostParams          default        range          meaning
==================  =============  =============  ==================================================
line_gap            3 px           [0, 20]        non-carpet pixels in a row skipped between the
                                                  field boundary and a foot (thin lines, noise)
foot_reach          16 px          [1, 200]       rows above the field boundary searched for a foot
foot_gap            1 px           [0, 20]        pixels allowed between a post and the carpet
min_fill            0.75           [0, 1]         goal-coloured share of the visible part of a post
max_gap             2 px           [0, 20]        misses in a row that end a post's run
min_length          8 px           [1, 1000]      shortest visible post (foot to the run's top)
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
from dataclasses import dataclass, field
from typing import ClassVar

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.camera import CAMERA_ROW_SIZE
from cognition.params import Range, Ranges, check_ranges, non_negative, positive
from cognition.percepts import Col
from cognition.vision.colour import Colour
from cognition.vision.image import VisionError
from cognition.vision.projection import ground_nb, pixel_nb
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
    packed: NDArray[np.float64] = field(init=False, repr=False, compare=False)
    """The parameters as the flat vector the compiled detector reads (pixels at 320 x 240)."""

    RANGES: ClassVar[Ranges] = {
        "line_gap": Range(0, 20),
        "foot_reach": Range(1, 200),
        "foot_gap": Range(0, 20),
        "min_fill": Range(0.0, 1.0),
        "max_gap": Range(0, 20),
        "min_length": Range(1.0, 1000.0),
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
        values = {
            _P_GAP: self.max_gap, _P_LINE: self.line_gap, _P_FILL: self.min_fill, _P_LEN: self.min_length,
            _P_WLO: self.width_range[0], _P_WHI: self.width_range[1], _P_SLACK: self.width_slack,
            _P_BAR: self.crossbar_length, _P_THICK: self.crossbar_thickness, _P_DLO: self.pair_distance[0],
            _P_DHI: self.pair_distance[1], _P_DMAX: self.max_distance, _P_BAND: self.band_fill,
            _P_REACH: self.foot_reach, _P_WMIN: self.min_width, _P_FOOT: self.foot_gap,
            _P_ROBOT: self.robot_height, _P_HEIGHT: self.min_height, _P_NMS: self.separation,
            _P_HRANGE: self.min_height_range, _P_COL: self.column_fill, _P_POLE: self.pole_band,
        }  # fmt: skip
        packed = np.zeros(_N_PARAMS)
        for k, value in values.items():
            packed[k] = value
        packed.flags.writeable = False
        object.__setattr__(self, "packed", packed)


# entries of PostParams.packed
_P_GAP, _P_LINE, _P_FILL, _P_LEN, _P_WLO, _P_WHI, _P_SLACK = 0, 1, 2, 3, 4, 5, 6
_P_BAR, _P_THICK, _P_DLO, _P_DHI, _P_DMAX, _P_BAND, _P_REACH = 7, 8, 9, 10, 11, 12, 13
_P_WMIN, _P_FOOT, _P_ROBOT, _P_HEIGHT, _P_NMS, _P_HRANGE, _P_COL, _P_POLE = 14, 15, 16, 17, 18, 19, 20, 21
_N_PARAMS = 22
_MAX_CAND = 64
_SAMPLES = 24
"""Samples along the axis of a post in the column histogram (a post checked as a candidate is
walked pixel by pixel)."""
_Check = tuple[int, float, float, float, float, float, float, float, int, int, float, float]
"""What :func:`_check_axis` returns."""
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


# -- compiled detector ------------------------------------------------------------------------


@nb.njit(cache=True)
def _is_goal(c: int, g0: int, g1: int) -> bool:  # pragma: no cover - compiled
    return c in (g0, g1)


@nb.njit(cache=True)
def _post_at(
    cam: NDArray[np.float64], u: float, v: float, r: float, goal_h: float
) -> tuple[bool, float, float, float, float, float]:  # pragma: no cover - compiled
    """A post whose front foot is seen at pixel (u, v): (ok, centre x, y, top pixel u, v,
    projected diameter in pixels)."""
    xf, yf, ok = ground_nb(cam, u, v, 0.0)
    if not ok:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0
    dx, dy = xf - cam[9], yf - cam[10]
    d = math.hypot(dx, dy)
    if d < 1e-6:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0
    ex, ey = dx / d, dy / d
    xc, yc = xf + r * ex, yf + r * ey
    ut, vt, okt = pixel_nb(cam, xc, yc, goal_h)
    if not okt:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0
    ua, _, oka = pixel_nb(cam, xc - r * ey, yc + r * ex, 0.0)
    ub, _, okb = pixel_nb(cam, xc + r * ey, yc - r * ex, 0.0)
    if not (oka and okb):
        return False, 0.0, 0.0, 0.0, 0.0, 0.0
    return True, xc, yc, ut, vt, abs(ub - ua)


@nb.njit(cache=True)
def _axis_run(
    classes: NDArray[np.uint8],
    g0: int,
    g1: int,
    ub: float,
    vb: float,
    ut: float,
    vt: float,
    start: int,
    fill: float,
    gap: int,
    step: int,
) -> tuple[bool, int, int, int, int]:  # pragma: no cover - compiled
    """Walk up the axis from the foot (ub, vb) toward the top (ut, vt), from row ``start`` to
    the top or where the axis leaves the image, every ``step`` rows: (at least ``fill`` of it
    goal-coloured, last goal row, goal samples of class g0, of class g1, class of the pixel
    that ended the run or -1). The run ends where too many samples missed for ``fill``, more
    than ``gap`` pixels in a row or two green or coloured samples in a row (carpet, a jersey);
    single noisy pixels do not end it (a miss with a goal-coloured pixel above it counts)."""
    width = classes.shape[1]
    slope = (ut - ub) / (vb - vt) if vb - vt > 1e-9 else 0.0
    stop = max(math.floor(_visible_top(ub, vb, ut, vt, width)), 0)
    total = (start - stop) // step + 1 if start >= stop else 0
    budget = (1.0 - fill) * total
    gap_samples = max(1, gap // step) if step > 1 else gap
    last = start + 1
    ended = -1
    miss = 0
    hard = 0
    gap_run = 0
    n0 = 0
    n1 = 0
    for j in range(start, stop - 1, -step):
        i = int(ub + slope * (vb - (j + 0.5)))
        if i < 0 or i >= width:
            break
        c = classes[j, i]
        if not _is_goal(c, g0, g1) and j > 0 and _is_goal(classes[j - 1, i], g0, g1):
            c = classes[j - 1, i]
        if c == g0:
            n0 += 1
            last = j
        elif c == g1:
            n1 += 1
            last = j
        else:
            miss += 1
            gap_run += 1
            # carpet or a colour (a jersey) inside the run: not a post (noise is grey or black)
            hard = hard + 1 if c == 1 or c >= 4 else 0
            if miss > budget or hard > 1 or gap_run > gap_samples:
                ended = c
                break
            continue
        hard = 0
        gap_run = 0
    return n0 + n1 >= fill * total - 1.0, last, n0, n1, ended


@nb.njit(cache=True)
def _foot(
    classes: NDArray[np.uint8],
    u: int,
    start: int,
    stop: int,
    g0: int,
    g1: int,
    line_gap: int,
    foot_gap: int,
) -> tuple[int, int]:  # pragma: no cover - compiled
    """The foot of a goal-coloured run in column u, searched upward from row ``start`` to row
    ``stop``: (lowest goal row, first carpet row below it), or (-1, -1). The run must end on
    green within ``foot_gap`` pixels. Green and up to ``line_gap`` other pixels in a row are
    skipped on the way up (thin lines or noise in the carpet push the field boundary below a
    post's foot). Where white is not a goal colour, white (lines) counts as carpet: a post may
    stand on a line."""
    height = classes.shape[0]
    lines = g0 != 2 and g1 != 2
    other = 0
    for j in range(start, stop - 1, -1):
        c = classes[j, u]
        if _is_goal(c, g0, g1):
            for k in range(j + 1, min(j + 2 + foot_gap, height)):
                ck = classes[k, u]
                if ck == 1 or (lines and ck == 2):
                    return j, k
            return -1, -1
        if c == 1 or (lines and c == 2):
            other = 0
        else:
            other += 1
            if other > line_gap:  # the hall above the carpet
                return -1, -1
    return -1, -1


@nb.njit(cache=True)
def _row_run(
    classes: NDArray[np.uint8], g0: int, g1: int, u: float, j: int, cap: int
) -> tuple[int, int]:  # pragma: no cover - compiled
    """The goal-coloured run of row j through (or next to) column u: (first, last) column, or (-1, -2)."""
    width = classes.shape[1]
    i = int(u)
    if i < 0 or i >= width:
        return -1, -2
    if not _is_goal(classes[j, i], g0, g1):
        if i + 1 < width and _is_goal(classes[j, i + 1], g0, g1):
            i += 1
        elif i - 1 >= 0 and _is_goal(classes[j, i - 1], g0, g1):
            i -= 1
        else:
            return -1, -2
    a = i
    while a - 1 >= 0 and i - a < cap and _is_goal(classes[j, a - 1], g0, g1):
        a -= 1
    e = i
    while e + 1 < width and e - i < cap and _is_goal(classes[j, e + 1], g0, g1):
        e += 1
    return a, e


@nb.njit(cache=True)
def _row_widths(
    classes: NDArray[np.uint8], g0: int, g1: int, ub: float, vb: float, ut: float, vt: float, last: float, cap: int
) -> float:  # pragma: no cover - compiled
    """Median width of the goal-coloured row runs through the axis (foot (ub, vb), top (ut,
    vt)) at eight heights between the foot and row ``last`` (px)."""
    slope = (ut - ub) / (vb - vt) if vb - vt > 1e-9 else 0.0
    widths = np.empty(8)
    k = 0
    for q in range(8):
        j = int(vb - 1.0 - (q + 0.5) * (vb - 1.0 - last) / 8.0)
        first, end = _row_run(classes, g0, g1, ub + slope * (vb - (j + 0.5)), j, cap)
        widths[k] = end - first + 1.0
        k += 1
    return float(np.median(widths[:k]))


@nb.njit(cache=True)
def _median_feet(feet: NDArray[np.float64], lo: int, hi: int) -> float:  # pragma: no cover - compiled
    """The foot row of a post over the candidate columns lo..hi: the 30th percentile of their
    feet (-1 if none). Not the median: columns over a line seen along its length under the
    post (white goals) have their foot where the line ends, lower in the image."""
    vals = np.empty(max(hi - lo + 1, 1))
    k = 0
    for i in range(lo, hi + 1):
        if feet[i] >= 0.0:
            vals[k] = feet[i]
            k += 1
    if k == 0:
        return -1.0
    return float(np.sort(vals[:k])[int(0.3 * (k - 1) + 0.5)])


@nb.njit(cache=True)
def _band_fill(
    classes: NDArray[np.uint8], g0: int, g1: int, ub: float, vb: float, ut: float, vt: float, last: int, band: float
) -> tuple[float, float]:  # pragma: no cover - compiled
    """Share of goal-coloured pixels in a band ``band`` px wide around the axis from the foot
    (ub, vb) up to row ``last``, and the smallest share of one column of the band (noise
    spreads over all columns, a thin string in front of a background leaves whole columns)."""
    height, width = classes.shape
    slope = (ut - ub) / (vb - vt) if vb - vt > 1e-9 else 0.0
    n = min(max(int(band + 0.5), 1), 16)
    hits = np.zeros(n)
    seen = np.zeros(n)
    for j in range(min(int(vb) - 1, height - 1), max(last, 0) - 1, -1):
        i0 = math.floor(ub + slope * (vb - (j + 0.5)) - 0.5 * n + 0.5)
        for k in range(n):
            i = i0 + k
            if 0 <= i < width:
                seen[k] += 1.0
                if _is_goal(classes[j, i], g0, g1):
                    hits[k] += 1.0
    total = seen.sum()
    if total <= 0.0:
        return 0.0, 0.0
    lo = 1.0
    for k in range(n):
        if seen[k] > 0.0:
            lo = min(lo, hits[k] / seen[k])
    return hits.sum() / total, lo


@nb.njit(cache=True)
def _crossbar(
    classes: NDArray[np.uint8], g0: int, g1: int, u: float, v: float, side: int, thick: float, steps: int
) -> tuple[int, bool, bool]:  # pragma: no cover - compiled
    """Follow a goal-coloured bar sideways from (u, v) (side -1 left, +1 right) for at most
    ``steps`` columns: (columns followed, reached the image edge, goal colour right below most
    of it: a wall of the hall in the goal's colour, not a bar)."""
    height, width = classes.shape
    half = 0.5 * thick + 2.0
    need = max(1, math.ceil(thick))
    vc = v
    below = 0
    for k in range(steps):
        i = int(u) + side * (k + 1)
        if i < 0 or i >= width:
            return k, True, k >= 3 and below > 0.6 * k
        lo = max(0, int(vc - half))
        hi = min(height - 1, int(vc + half))
        best = -1.0
        best_d = 1e9
        run = 0
        for j in range(lo, hi + 2):
            g = j <= hi and _is_goal(classes[j, i], g0, g1)
            if g:
                run += 1
            elif run > 0:
                if run >= need:
                    mid = j - 0.5 * run
                    dd = abs(mid - vc)
                    if dd < best_d:
                        best_d = dd
                        best = mid
                run = 0
        if best < 0.0:
            return k, False, k >= 3 and below > 0.6 * k
        vc = best
        j = int(vc + half + 1.0)
        if j < height and _is_goal(classes[j, i], g0, g1):
            below += 1
    return steps, False, below > 0.6 * steps


@nb.njit(cache=True)
def _visible_top(ub: float, vb: float, ut: float, vt: float, width: int) -> float:  # pragma: no cover - compiled
    """Row where the axis from the foot (ub, vb) to the top (ut, vt) ends or leaves the image."""
    top = max(vt, 0.0)
    if vb - vt > 1e-9:
        slope = (ut - ub) / (vb - vt)  # du per row upward
        if slope > 1e-9:
            top = max(top, vb - (width - ub) / slope)
        elif slope < -1e-9:
            top = max(top, vb + ub / slope)
    return top


@nb.njit(cache=True)
def _check_axis(
    classes: NDArray[np.uint8],
    cam: NDArray[np.float64],
    feet: NDArray[np.float64],
    g0: int,
    g1: int,
    uc: float,
    ua: float,
    i0: int,
    i1: int,
    r: float,
    goal_h: float,
    prm: NDArray[np.float64],
) -> _Check:  # pragma: no cover - compiled
    """Check a post centred at column ``uc`` whose foot is that of columns i0..i1 (see
    :func:`_median_feet`), along the axis through column ``ua`` (the middle of its visible
    part): (outcome, band fill, run share, foot row, centre x, y, top u, v, goal pixels of g0,
    of g1, last row of the run, smallest column fill). Outcomes as in :func:`_posts_nb`. When
    the run fails right above that foot (it is a line's, in front of the post), the next foot
    up is tried."""
    vb = _median_feet(feet, i0, i1)
    if vb < 0.0:
        return 2, 0.0, 0.0, vb, 0.0, 0.0, 0.0, 0.0, 0, 0, 0.0, 0.0
    res = _check_at(classes, cam, g0, g1, uc, ua, vb, i0, i1, r, goal_h, prm)
    if res[0] == 2 and res[2] < 0.3:
        top = -1.0
        for i in range(i0, i1 + 1):
            if top < feet[i] < vb - 0.5:
                top = feet[i]
        if top >= 0.0:
            other = _check_at(classes, cam, g0, g1, uc, ua, top, i0, i1, r, goal_h, prm)
            if other[0] == 0:
                return other
    return res


@nb.njit(cache=True)
def _check_at(
    classes: NDArray[np.uint8],
    cam: NDArray[np.float64],
    g0: int,
    g1: int,
    uc: float,
    ua: float,
    vb: float,
    i0: int,
    i1: int,
    r: float,
    goal_h: float,
    prm: NDArray[np.float64],
) -> _Check:  # pragma: no cover - compiled
    """:func:`_check_axis` for the foot row ``vb``."""
    width = classes.shape[1]
    ok, xc, yc, ut, vt, w_exp = _post_at(cam, uc, vb, r, goal_h)
    oka, _, _, uta, vta, _ = _post_at(cam, ua, vb, r, goal_h)
    if not (ok and oka):
        return 5, 0.0, 0.0, vb, 0.0, 0.0, 0.0, 0.0, 0, 0, 0.0, 0.0
    visible = vb - _visible_top(ua, vb, uta, vta, width)
    # one colour per post (a KidSize corner pole has bands of both goal colours)
    gs = g0
    fill, gap = prm[_P_FILL], int(prm[_P_GAP])
    filled, last, n0, _, ended = _axis_run(classes, g0, g0, ua, vb, uta, vta, int(vb) - 1, fill, gap, 1)
    n1 = 0
    if g1 != g0:
        filled1, last1, m1, _, ended1 = _axis_run(classes, g1, g1, ua, vb, uta, vta, int(vb) - 1, fill, gap, 1)
        if m1 > n0:
            gs, filled, last, n0, n1, ended = g1, filled1, last1, 0, m1, ended1
    share = (n0 + n1) / max(visible, 1e-9)
    band = max(1.0, 0.6 * min(w_exp, (i1 - i0 + 1.0) if ua != uc else w_exp))
    bf, col_min = _band_fill(classes, gs, gs, ua, vb, uta, vta, last, band)
    code = 0
    vtop = vb - visible
    # the visible part must reach min_height up the post (less, as 1 / distance, beyond
    # min_height_range): near the camera a line seen along the axis looks like a post's foot
    dist = math.hypot(xc - cam[9], yc - cam[10])
    _, vh, okh = pixel_nb(cam, xc, yc, prm[_P_HEIGHT] * min(1.0, prm[_P_HRANGE] / max(dist, 1e-9)))
    if g1 != g0:  # two goal colours: a corner pole has bands of both, its lowest one pole_band high
        _, vp, okp = pixel_nb(cam, xc, yc, prm[_P_POLE])
        if ended == g0 + g1 - gs or not okp or vp < vtop + 3.0:  # 3 px: room to see the next band
            okh = False
    if not filled or vb - last < prm[_P_LEN] or not okh or vh < vtop - 0.5:
        code = 2  # too little of the post in view (a line seen along the axis looks the same)
    elif bf < prm[_P_BAND] or col_min < prm[_P_COL]:
        code = 3
    elif math.hypot(xc, yc) > prm[_P_DMAX]:
        code = 4
    else:
        # only the part below a robot's height in view: a robot's legs would pass as well,
        # unless the goal-coloured rows of the lower half are no wider than a post
        _, vr, okr = pixel_nb(cam, xc, yc, prm[_P_ROBOT])
        if not okr or vr < vtop - 0.5:
            w_med = _row_widths(classes, gs, gs, ua, vb, uta, vta, 0.5 * (vb + last), int(4.0 * w_exp + 8.0))
            if w_med > prm[_P_WHI] * w_exp + prm[_P_SLACK]:
                code = 6
    return code, bf, share, vb, xc, yc, ut, vt, n0, n1, float(last), col_min


@nb.njit(cache=True)
def _search(
    classes: NDArray[np.uint8],
    cam: NDArray[np.float64],
    feet: NDArray[np.float64],
    g0: int,
    g1: int,
    a: int,
    e: int,
    lo: float,
    hi: float,
    w_exp: float,
    r: float,
    goal_h: float,
    prm: NDArray[np.float64],
) -> tuple[_Check, float]:  # pragma: no cover - compiled
    """The post centred between columns ``lo`` and ``hi`` (1 px steps) over the candidate
    columns a..e: of the centres that pass :func:`_check_axis`, the middle of those whose foot
    is lowest (a post stands in front of its net). Returns the check and the centre."""
    best_v = -1.0
    first_u = 0.0
    last_u = 0.0
    for q in range(int(hi - lo) + 1):
        uq = lo + q
        i0 = min(e, max(a, int(uq - 0.5 * w_exp)))
        i1 = max(i0, min(e, int(uq + 0.5 * w_exp)))
        rq = _check_axis(classes, cam, feet, g0, g1, uq, uq, i0, i1, r, goal_h, prm)
        if rq[0] != 0:
            continue
        if rq[3] > best_v + 0.5:
            best_v = rq[3]
            first_u = uq
            last_u = uq
        elif rq[3] >= best_v - 0.5:
            last_u = uq
    if best_v < 0.0:
        return (3, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0, 0, 0.0, 0.0), lo
    uc = 0.5 * (first_u + last_u)
    i0 = min(e, max(a, int(uc - 0.5 * w_exp)))
    i1 = max(i0, min(e, int(uc + 0.5 * w_exp)))
    return _check_axis(classes, cam, feet, g0, g1, uc, uc, i0, i1, r, goal_h, prm), uc


@nb.njit(cache=True)
def _columns(
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    g0: int,
    g1: int,
    r: float,
    goal_h: float,
    prm: NDArray[np.float64],
) -> tuple[NDArray[np.bool_], NDArray[np.float64]]:  # pragma: no cover - compiled
    """The column histogram: whether a post standing at the foot found above the field
    boundary of each column would be goal-coloured up its axis (``min_fill`` of its visible
    length), and that foot row (-1 where not)."""
    height, width = classes.shape
    gap, line_gap, reach = int(prm[_P_GAP]), int(prm[_P_LINE]), int(prm[_P_REACH])
    fill, min_len = prm[_P_FILL], prm[_P_LEN]
    cand = np.zeros(width, dtype=np.bool_)
    feet = np.full(width, -1.0)
    foot_gap = int(prm[_P_FOOT])
    for u in range(width):
        b = boundary[u]
        if b <= 0 or b >= height:
            continue
        start = b - 1
        stop = max(b - reach, 0)
        tries = 0
        while start >= stop:  # a line between a post's foot and the boundary ends a run early
            j0, vf = _foot(classes, u, start, stop, g0, g1, line_gap, foot_gap)
            if j0 < 0:
                break
            vb = float(vf)
            ok, _, _, ut, vt, _ = _post_at(cam, u + 0.5, vb, r, goal_h)
            if not ok:
                break
            visible = vb - _visible_top(u + 0.5, vb, ut, vt, width)
            if visible < min_len:
                break
            c0 = int(classes[j0, u])  # one colour per post
            step = max(1, int(visible / _SAMPLES))  # a candidate test: enough samples
            filled, last, _, _, _ = _axis_run(classes, c0, c0, u + 0.5, vb, ut, vt, j0 - 1, fill, gap, step)
            if filled:
                cand[u] = True
                feet[u] = vb
                break
            tries += 1
            if tries >= 2:
                break
            start = last - 1
    return cand, feet


@nb.njit(cache=True)
def _intervals(
    classes: NDArray[np.uint8],
    cam: NDArray[np.float64],
    cand: NDArray[np.bool_],
    feet: NDArray[np.float64],
    g0: int,
    g1: int,
    r: float,
    goal_h: float,
    prm: NDArray[np.float64],
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:  # pragma: no cover - compiled
    """The candidates: runs of candidate columns (one-column gaps bridged), first and last
    column. Two runs are one post standing on a line seen along its length (white goals: the
    line's columns have no foot) when the gap between them is goal-coloured just above their
    feet and narrower than the post."""
    width = classes.shape[1]
    starts = np.empty(width, dtype=np.int64)
    ends = np.empty(width, dtype=np.int64)
    n = 0
    u = 0
    while u < width:
        if not cand[u]:
            u += 1
            continue
        a = u
        e = u
        while e + 1 < width and (cand[e + 1] or (e + 2 < width and cand[e + 2])):
            e += 1 if cand[e + 1] else 2
        u = e + 1
        if n > 0:
            pa, pe = starts[n - 1], ends[n - 1]
            row = int(min(feet[pe], feet[a])) - 2
            ok, _, _, _, _, w_exp = _post_at(cam, 0.5 * (pa + e + 1), max(feet[pe], feet[a]), r, goal_h)
            if ok and row >= 0 and a - pe - 1 <= 0.75 * w_exp and e - pa + 1 <= prm[_P_WHI] * w_exp + prm[_P_SLACK]:
                filled = 0
                for i in range(pe + 1, a):
                    if _is_goal(classes[row, i], g0, g1):
                        filled += 1
                if filled >= 0.8 * (a - pe - 1):
                    ends[n - 1] = e
                    continue
        starts[n] = a
        ends[n] = e
        n += 1
    return starts[:n], ends[:n]


@nb.njit(cache=True)
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
    width = classes.shape[1]
    prm = packed.copy()
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
    slack = prm[_P_SLACK]
    starts, ends = _intervals(classes, cam, cand, feet, g0, g1, r, goal_h, prm)
    for q in range(starts.shape[0]):
        if n >= _MAX_CAND:
            break
        a = starts[q]
        e = ends[q]
        um = 0.5 * (a + e + 1)
        ok, _, _, _, _, w_exp = _post_at(cam, um, _median_feet(feet, a, e), r, goal_h)
        measured = e - a + 1.0
        left_edge = a <= 1
        right_edge = e >= width - 2
        w_lo = max(prm[_P_WMIN], prm[_P_WLO] * w_exp - slack)
        w_hi = prm[_P_WHI] * w_exp + slack
        code = 1
        res = (5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0, 0, 0.0, 0.0)
        uc = um
        if not ok:
            code = 5
        elif (left_edge or right_edge) and measured < w_exp:
            # cut by the image edge: the centre is half a diameter from the visible edge and
            # must be in the image (a post whose base centre is outside is not reported)
            uc = e + 1.0 - 0.5 * w_exp if left_edge else a + 0.5 * w_exp
            if measured >= max(prm[_P_WMIN], 0.25 * w_exp) and 0.0 <= uc < width:
                res = _check_axis(classes, cam, feet, g0, g1, uc, um, a, e, r, goal_h, prm)
                code = res[0]
        elif w_lo <= measured <= 4.0 * w_exp + slack:
            res = _check_axis(classes, cam, feet, g0, g1, um, um, a, e, r, goal_h, prm)
            code = res[0] if measured <= w_hi else 1
            if code != 0 and abs(measured - w_exp) > 1.0:
                # part of a post (the rest stands on a line) or a post in front of a white net,
                # robot or wall: the windows of one diameter that pass and stand lowest
                if measured < w_exp:
                    lo, hi = e + 1.0 - 0.5 * w_exp, a + 0.5 * w_exp
                else:
                    lo, hi = a + 0.5 * w_exp, e + 1.0 - 0.5 * w_exp
                res, uc = _search(classes, cam, feet, g0, g1, a, e, lo, hi, w_exp, r, goal_h, prm)
                code = res[0]
        if nd < dbg.shape[0]:
            dbg[nd, 0], dbg[nd, 1], dbg[nd, 2], dbg[nd, 3] = a, e, w_exp, res[3]
            dbg[nd, 4], dbg[nd, 5], dbg[nd, 6], dbg[nd, 7], dbg[nd, 8] = res[1], res[2], code, uc, res[11]
            nd += 1
        if code != 0:
            continue
        _, _, _, vb, xc, yc, ut, vt, n0, n1, last, _ = res
        ok, _, _, _, _, w_exp = _post_at(cam, uc, vb, r, goal_h)
        ub, vbc, _ = pixel_nb(cam, xc, yc, 0.0)
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
