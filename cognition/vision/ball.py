"""Ball detection: the classic orange ball and the modern white ball with black patches.

NimbRo (section 6.1) finds the orange ball as a colour blob checked for its size; the modern
SPL ball is white with black patches and shares its white with lines, penalty marks, goal
posts and robots, so a colour blob is not enough. Both balls are found here by the same
geometric hypothesis test, with the colour rules of the scheme. *Ball pixels* are ORANGE
(classic) or anything not GREEN (modern: the lit side is WHITE, the shaded side grey
(OTHER), the patches BLACK). The camera model gives the image radius ``R(u, v)`` a ball
centred at any pixel must have (the pixel projected onto the plane at the ball's radius,
pinhole size, times the stretch of a sphere's outline off the optical axis: its semi-axes
are 1 / cos and 1 / cos^2 of the off-axis angle times the on-axis radius), so no radius is
searched for.

1. **Seeds.** Every ``scan_step``-th column is read (every ``scan_rows``-th pixel, row by
   row, as the class image is stored) from a little above the field boundary down, for runs
   of ball pixels; from the row where every ball is at least 4.5 column steps in radius only
   every third column. Runs shorter than ``min_run`` x R (or one sample) are dropped (a line
   seen at a slant is thin vertically, a ball is not). A run up to about a diameter long
   seeds a centre at its middle (a vertical chord of a circle is halved by the horizontal
   diameter); a longer one (the ball merged with a robot, post or line) seeds centres one
   radius above its lower end (the ball sits on the carpet) and below its upper end. The
   end of a run open at the top (the hall above the boundary) seeds only where the field
   boundary dips on both sides or, modern, where black lies near the run's end (a ball's
   patches before a robot that hides the carpet's edge).
2. **Refinement.** A horizontal and a vertical chord through the seed move it toward the
   centre; a chord through the centre, or a diagonal one, with carpet at both ends and
   shorter than R is a line (rejected), and a loose colour check (below) must pass. Then 16
   rays from the centre find the ball's outline: each ray walks over ball pixels to the
   first pixel that is not (modern: to the carpet, as every non-green colour may be part of
   the ball), the edge placed to a sub-pixel by that pixel's coverage from the red channel
   (the carpet has almost no red, both balls much). Rays that leave the image or run on
   beyond the ball (into a robot, post or line) are dropped. The circle of radius R with
   most edge points near it (the seed's, or one through a pair of neighbouring edge points:
   robust to a seed far off and to points on a robot's foot or beyond a line) is refined by
   least squares; when its points span more than half the circle its radius is fitted too.
   Two rounds.
3. **Verification.** The ball must (a) have a ball's size there: a fitted radius within
   ``radius_tolerance`` of R (the distance implied by the image radius agrees with the
   projected distance), rms residual of the outline below ``max_residual`` x R + 0.5 px;
   (b) be filled with ball pixels (share ``min_fill`` of 31 samples inside 0.8 R; classic:
   ORANGE, or YELLOW where orange blends with the carpet, at least half ORANGE); modern:
   with black patches, pixels darker than ``dark_value`` x the carpet beside the ball (share
   in [``min_black``, ``max_black``]; relative to the local carpet, so shadows and exposure
   do not matter; a robot's dark grey joints are not that dark) and white or grey; (c) lie
   on the carpet: on a ring just outside its lower part at least ``min_ring_green`` of the
   samples GREEN and at most ``max_ring_other`` neither GREEN nor WHITE (a line under the
   ball is WHITE; a robot's foot or a post's base continue sideways in their own colours;
   where the image edge cuts the lower ring the whole ring counts); classic: at most
   ``max_ring_orange`` of the whole ring ORANGE. Penalty marks, line crossings and white
   goal posts have no black patches; the orange fringe of a red jersey is a pixel wide.

The candidates are ranked by a score (fill x ring green x size fit) and the best
``max_candidates`` are reported, each a percept row (:mod:`.rows`): ``x, y`` the robot-frame
ground point under the ball's centre (the centre pixel projected onto the plane at the
ball's radius), ``u, v`` the centre pixel, ``radius_px`` the fitted image radius converted
to the on-axis radius (what :meth:`~cognition.percepts.Percepts.ball_distance_from_size`
expects; R where the radius was fixed), covariance from the Darmstadt model at height
``ball_radius``. All of it is one compiled call.

Pixel sizes are for a 320 x 240 image and scale with the width.

==================  =======  ==========  ================================================================
BallParams          default  range       meaning
==================  =======  ==========  ================================================================
scan_step           4 px     [1, 32]     spacing of the scanned columns (at 320 px width)
scan_rows           2 px     [1, 8]      spacing of the pixels read in a scanned column
min_run             0.7      [0, 2]      shortest run of ball pixels that seeds a centre, x R
min_radius          1.5 px   [0.5, 50]   smallest image radius searched (farther balls are ignored)
max_distance        7.0 m    (0, 100]    farthest ball reported (ground distance)
radius_tolerance    0.3      (0, 2]      allowed relative error of the fitted image radius against R
max_residual        0.2      (0, 2]      largest rms residual of the silhouette fit, x R (plus 0.5 px)
min_fill            0.8      [0, 1]      share of ball pixels among the samples inside 0.8 R (classic:
                                         ORANGE, or YELLOW where orange blends with the carpet, at
                                         least half ORANGE)
min_black           0.08     [0, 1]      modern: least share of black samples inside (the patches)
max_black           0.7      [0, 1]      modern: largest share of black samples inside
dark_value          0.25     [0, 1]      modern: black is darker than this x the carpet beside the ball
min_white           0.2      [0, 1]      modern: least share of WHITE or grey samples inside
min_ring_green      0.3      [0, 1]      least share of GREEN on the ring below the ball
max_ring_other      0.35     [0, 1]      largest share of the ring below neither GREEN nor WHITE
max_ring_orange     0.25     [0, 1]      classic: largest share of ORANGE on the whole ring
max_tests           40       [1, 1000]   most centres fitted and verified per image (bounds the time)
max_candidates      1        [1, 16]     balls reported per image, best first
==================  =======  ==========  ================================================================
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import ClassVar

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.params import PROBABILITY, Range, Ranges, check_ranges, positive
from cognition.percepts import N_COLS, Col
from cognition.vision.projection import ground_nb
from cognition.vision.rows import point_rows_nb

GREEN, WHITE, BLACK, ORANGE, YELLOW = 1, 2, 3, 4, 5


@dataclass(frozen=True)
class BallParams:
    """Parameters of the ball detector (module table; pixels at 320 px width)."""

    scan_step: int = 4
    scan_rows: int = 2
    min_run: float = 0.7
    min_radius: float = 1.5
    max_distance: float = 7.0
    radius_tolerance: float = 0.3
    max_residual: float = 0.2
    min_fill: float = 0.8
    min_black: float = 0.08
    dark_value: float = 0.25
    max_black: float = 0.7
    min_white: float = 0.2
    min_ring_green: float = 0.3
    max_ring_other: float = 0.35
    max_ring_orange: float = 0.25
    max_tests: int = 40
    max_candidates: int = 1

    RANGES: ClassVar[Ranges] = {
        "scan_step": Range(1, 32),
        "scan_rows": Range(1, 8),
        "min_run": Range(0.0, 2.0),
        "min_radius": Range(0.5, 50.0),
        "max_distance": positive(100.0),
        "radius_tolerance": positive(2.0),
        "max_residual": positive(2.0),
        "min_fill": PROBABILITY,
        "min_black": PROBABILITY,
        "dark_value": PROBABILITY,
        "max_black": PROBABILITY,
        "min_white": PROBABILITY,
        "min_ring_green": PROBABILITY,
        "max_ring_other": PROBABILITY,
        "max_ring_orange": PROBABILITY,
        "max_tests": Range(1, 1000),
        "max_candidates": Range(1, 16),
    }

    def __post_init__(self) -> None:
        check_ranges(self)


@lru_cache(maxsize=64)
def _vector(p: BallParams, width: int) -> NDArray[np.float64]:
    """The parameters as the compiled kernel reads them, pixel sizes scaled to ``width``."""
    scale = width / 320.0
    v = np.array(
        [
            max(1, round(p.scan_step * scale)), max(1, round(p.scan_rows * scale)), p.min_run, p.min_radius * scale,
            p.max_distance, p.radius_tolerance, p.max_residual, p.min_fill, p.min_black, p.max_black, p.min_white,
            p.min_ring_green, p.max_ring_other, p.max_ring_orange, p.max_tests, p.max_candidates, p.dark_value,
        ],
        dtype=np.float64,
    )  # fmt: skip
    v.setflags(write=False)
    return v


_STEP, _ROWS, _MIN_RUN, _MIN_R, _MAX_D, _TOL, _RESID, _FILL = 0, 1, 2, 3, 4, 5, 6, 7
_MIN_BLACK, _MAX_BLACK, _MIN_WHITE, _RING_GREEN, _RING_OTHER, _RING_ORANGE, _MAX_TESTS, _MAX_CAND = range(8, 16)
_DARK = 16


def _disc_pattern() -> NDArray[np.float64]:
    """Sample offsets inside a unit disc: the centre and rings at 0.3, 0.55 and 0.8."""
    pts = [(0.0, 0.0)]
    for ring, (rad, n) in enumerate(((0.3, 6), (0.55, 10), (0.8, 14))):
        for k in range(n):
            a = 2.0 * math.pi * (k + 0.5 * (ring + 1)) / n
            pts.append((rad * math.cos(a), rad * math.sin(a)))
    return np.array(pts)


_DISC = _disc_pattern()
_RING = np.array([(math.cos(a), math.sin(a)) for a in 2.0 * math.pi * (np.arange(24) + 0.5) / 24.0])
"""Unit directions of the ring samples outside the ball (v grows downward: sin > 0 is below)."""
_N_RAYS = 16
_RAYS = np.array([(math.cos(a), math.sin(a)) for a in 2.0 * math.pi * np.arange(_N_RAYS) / _N_RAYS])

# candidate columns: u, v, radius reported, x, y, score, expected radius
_CU, _CV, _CR, _CX, _CY, _CS, _CE = 0, 1, 2, 3, 4, 5, 6
_N_CAND = 7
_RADIUS = int(Col.RADIUS_PX)


def detect_ball(
    rgb: NDArray[np.uint8],
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    ball_radius: float,
    modern: bool,
    params: BallParams,
    sigma_alpha: float,
    sigma_beta: float,
) -> NDArray[np.float64]:
    """Percept rows (:mod:`cognition.percepts` columns) of the ball candidates, best first.

    ``rgb`` (H x W x 3 uint8) is the image, ``classes`` (H x W uint8) its colour classes
    (:class:`~cognition.vision.colour.Colour`), ``boundary`` (W, int32) the first field row per
    column, ``cam`` the camera row (:meth:`~cognition.camera.CameraMatrix.as_row`),
    ``ball_radius`` the ball's radius (m), ``modern`` selects the white ball with black patches
    (else the orange ball); ``sigma_alpha``, ``sigma_beta`` (rad) are the frame's angular
    sigmas for the covariance. Returns 0 to ``params.max_candidates`` rows.
    """
    check_inputs(classes, boundary, cam, sigma_alpha, sigma_beta, rgb)
    if not isinstance(params, BallParams):
        raise TypeError(f"params must be BallParams, got {type(params).__name__}")
    if isinstance(ball_radius, bool) or not isinstance(ball_radius, float | int) or not 0.0 < ball_radius <= 1.0:
        raise ValueError(f"ball_radius must be a number in (0, 1] m, got {ball_radius!r}")
    rows, code = _detect_ball_nb(
        rgb, classes, boundary, cam, float(ball_radius), bool(modern), _vector(params, classes.shape[1]),
        float(sigma_alpha), float(sigma_beta),
    )  # fmt: skip
    if code:
        raise ValueError("cam must be a finite camera row with positive focal lengths")
    return rows


def check_inputs(
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    sigma_alpha: float,
    sigma_beta: float,
    rgb: NDArray[np.uint8] | None = None,
) -> None:
    """Raise ``ValueError`` naming the problem unless the detector inputs fit together (the
    camera row's values are checked inside the compiled call)."""
    if not (isinstance(classes, np.ndarray) and classes.dtype == np.uint8 and classes.ndim == 2):
        raise ValueError(f"classes must be an H x W uint8 array, got {_describe(classes)}")
    h, w = classes.shape
    if h < 8 or w < 8 or not classes.flags.c_contiguous:
        raise ValueError(f"classes must be C-contiguous and at least 8 x 8, got shape {classes.shape}")
    if rgb is not None and not (
        isinstance(rgb, np.ndarray) and rgb.dtype == np.uint8 and rgb.shape == (h, w, 3) and rgb.flags.c_contiguous
    ):
        raise ValueError(f"rgb must be a C-contiguous {h} x {w} x 3 uint8 array, got {_describe(rgb)}")
    if not (isinstance(boundary, np.ndarray) and boundary.dtype == np.int32 and boundary.shape == (w,)):
        raise ValueError(f"boundary must be an int32 array of {w} rows (one per column), got {_describe(boundary)}")
    if not (isinstance(cam, np.ndarray) and cam.dtype == np.float64 and cam.shape == (18,)):
        raise ValueError(f"cam must be a float64 camera row of 18 entries (CameraMatrix.as_row), got {_describe(cam)}")
    if cam[16] != w or cam[17] != h:
        raise ValueError(f"cam is for {cam[16]:g} x {cam[17]:g} images, the classes are {w} x {h}")
    for name, s in (("sigma_alpha", sigma_alpha), ("sigma_beta", sigma_beta)):
        if isinstance(s, bool) or not isinstance(s, float | int) or not 0.0 <= s <= math.pi / 2:
            raise ValueError(f"{name} must be an angle in [0, pi/2] rad, got {s!r}")


def _describe(a: object) -> str:
    if isinstance(a, np.ndarray):
        return f"{a.dtype} array of shape {a.shape}"
    return type(a).__name__


# ----------------------------------------------------------------------------- compiled core


@nb.njit(cache=True, error_model="numpy")
def camera_ok_nb(cam: NDArray[np.float64]) -> bool:  # pragma: no cover - compiled
    """The camera row is finite with positive focal lengths."""
    for k in range(cam.shape[0]):
        if not math.isfinite(cam[k]):
            return False
    return cam[12] > 0.0 and cam[13] > 0.0


@nb.njit(cache=True, error_model="numpy")
def _detect_ball_nb(
    rgb: NDArray[np.uint8],
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    ball_r: float,
    modern: bool,
    prm: NDArray[np.float64],
    sa: float,
    sb: float,
) -> tuple[NDArray[np.float64], int]:  # pragma: no cover - compiled
    """(percept rows, 0), or (no rows, 1) for a bad camera row."""
    if not camera_ok_nb(cam):
        return np.empty((0, N_COLS)), 1
    cand = _candidates(rgb, classes, boundary, cam, ball_r, modern, prm)
    rows = point_rows_nb(cand[:, _CX : _CY + 1].copy(), cand[:, _CU : _CV + 1].copy(), ball_r, cam, sa, sb)
    for k in range(rows.shape[0]):
        rows[k, _RADIUS] = cand[k, _CR]
    return rows, 0


@nb.njit(cache=True, error_model="numpy", inline="always")
def _is_ball(c: int, modern: bool) -> bool:  # pragma: no cover - compiled
    return c != GREEN if modern else c == ORANGE


@nb.njit(cache=True, error_model="numpy")
def _stretch(cam: NDArray[np.float64], u: float, v: float) -> float:  # pragma: no cover - compiled
    """How much larger than on the optical axis a small sphere looks at pixel (u, v): its outline
    is an ellipse with semi-axes 1 / cos(t) and 1 / cos(t)^2 times the on-axis radius (t the
    angle off the axis); the mean of the two."""
    a = (cam[14] - u) / cam[12]
    b = (cam[15] - v) / cam[13]
    c2 = 1.0 / (1.0 + a * a + b * b)  # cos(t)^2
    c = math.sqrt(c2)
    return 0.5 * (1.0 / c + 1.0 / c2)


@nb.njit(cache=True, error_model="numpy")
def _radius(cam: NDArray[np.float64], u: float, v: float, r: float) -> float:  # pragma: no cover - compiled
    """The outline radius (px) of a ball of radius ``r`` centred at pixel (u, v) (see
    :func:`_expected`; NaN at or above the horizon), in one short computation: the ray's
    camera-frame direction (1, a, b) has squared length 1 / cos(t)^2."""
    a = (cam[14] - u) / cam[12]
    b = (cam[15] - v) / cam[13]
    dz = cam[6] + cam[7] * a + cam[8] * b
    if dz >= -1e-9 or cam[11] <= r:
        return math.nan
    t = (r - cam[11]) / dz
    n2 = 1.0 + a * a + b * b
    d2 = t * t * n2 - r * r
    if d2 <= 0.0:
        return math.nan
    return 0.5 * (cam[12] + cam[13]) * r / math.sqrt(d2) * 0.5 * (math.sqrt(n2) + n2)


@nb.njit(cache=True, error_model="numpy")
def _expected(cam: NDArray[np.float64], u: float, v: float, r: float) -> tuple[float, float, float]:  # pragma: no cover
    """(image radius px of the outline, ground x, ground y) of a ball of radius ``r`` centred at
    pixel (u, v): the pinhole radius on the optical axis times :func:`_stretch`."""
    x, y, ok = ground_nb(cam, u, v, r)
    if not ok:
        return math.nan, math.nan, math.nan
    dx, dy, dz = x - cam[9], y - cam[10], r - cam[11]
    d2 = dx * dx + dy * dy + dz * dz
    f = 0.5 * (cam[12] + cam[13])
    return f * r / math.sqrt(max(d2 - r * r, 1e-12)) * _stretch(cam, u, v), x, y


@nb.njit(cache=True, error_model="numpy")
def _coverage(
    rgb: NDArray[np.uint8], j0: int, i0: int, j1: int, i1: int, j2: int, i2: int
) -> float:  # pragma: no cover
    """Ball coverage of the carpet pixel (j1, i1) between the ball pixel (j0, i0) and the carpet
    pixel (j2, i2) further out, from the red channel (0.5 when the contrast is too low)."""
    h, w = rgb.shape[0], rgb.shape[1]
    inner = float(rgb[j0, i0, 0])
    outer = float(rgb[j1, i1, 0])
    bg = float(rgb[j2, i2, 0]) if 0 <= j2 < h and 0 <= i2 < w else outer
    bg = min(bg, outer)
    if inner - bg < 40.0:
        return 0.5
    return min(1.0, max(0.0, (outer - bg) / (inner - bg)))


@nb.njit(cache=True, error_model="numpy")
def _run_end(
    rgb: NDArray[np.uint8], classes: NDArray[np.uint8], i: int, j: int, di: int, dj: int, reach: int, modern: bool
) -> tuple[float, bool]:  # pragma: no cover - compiled
    """The end (continuous position along the axis of (di, dj)) of the run of ball pixels from
    pixel (i, j) in direction (di, dj), and whether it is a real edge (a non-ball pixel within
    ``reach``; not the image edge)."""
    h, w = classes.shape
    pos = i if di != 0 else j
    lim = w if di != 0 else h
    sg = di + dj
    for k in range(1, reach + 1):
        p = pos + sg * k
        if p < 0 or p >= lim:
            return (0.0 if sg < 0 else float(lim)), False
        ci, cj = i + di * k, j + dj * k
        c = classes[cj, ci]
        if not _is_ball(c, modern):
            a = _coverage(rgb, cj - dj, ci - di, cj, ci, cj + dj, ci + di) if c == GREEN else 0.5
            return ((float(p) + a) if sg > 0 else (float(p) + 1.0 - a)), True
    return float(pos + sg * reach) + (1.0 if sg > 0 else 0.0), False


@nb.njit(cache=True, error_model="numpy")
def _chord(
    rgb: NDArray[np.uint8], classes: NDArray[np.uint8], u: float, v: float, horizontal: bool, reach: int, modern: bool
) -> tuple[float, float, bool, bool]:  # pragma: no cover - compiled
    """Ends (px, continuous) of the horizontal or vertical run of ball pixels through (u, v) and
    whether each is a real edge (see :func:`_run_end`)."""
    h, w = classes.shape
    i, j = math.floor(u), math.floor(v)
    if not (0 <= i < w and 0 <= j < h):
        return math.nan, math.nan, False, False
    di, dj = (1, 0) if horizontal else (0, 1)
    a, ra = _run_end(rgb, classes, i, j, -di, -dj, reach, modern)
    b, rb = _run_end(rgb, classes, i, j, di, dj, reach, modern)
    return a, b, ra, rb


@nb.njit(cache=True, error_model="numpy")
def _thin(classes: NDArray[np.uint8], u: float, v: float, r: float, modern: bool) -> bool:  # pragma: no cover
    """A diagonal chord through (u, v) with carpet at both ends is shorter than r: a slanted line,
    not a ball (every chord through a point near a disc's centre is longer than its radius)."""
    h, w = classes.shape
    i, j = math.floor(u), math.floor(v)
    if not (0 <= i < w and 0 <= j < h):
        return False
    reach = int(r) + 1
    for dj in (-1, 1):
        n = 1
        ends = 0
        for s in (-1, 1):
            for k in range(1, reach + 1):
                ci, cj = i + s * k, j + s * dj * k
                if not (0 <= ci < w and 0 <= cj < h):
                    break
                if not _is_ball(classes[cj, ci], modern):
                    ends += 1
                    break
                n += 1
        if ends == 2 and 1.41421356 * n < r:
            return True
    return False


@nb.njit(cache=True, error_model="numpy")
def _dip(boundary: NDArray[np.int32], i: int, j: int, r: float) -> bool:  # pragma: no cover - compiled
    """The field boundary at column ``i`` (at row ``j``) lies at least r / 2 below the boundary
    2.5 r to both sides (or the image edge): something small stands in front of the hall there."""
    w = boundary.shape[0]
    k = int(2.5 * r) + 1
    lo = boundary[i - k] if i - k >= 0 else -1
    hi = boundary[i + k] if i + k < w else -1
    return max(lo, hi) < j - 0.5 * r


@nb.njit(cache=True, error_model="numpy")
def _silhouette(
    rgb: NDArray[np.uint8],
    classes: NDArray[np.uint8],
    u: float,
    v: float,
    r: float,
    modern: bool,
    pts: NDArray[np.float64],
    used: NDArray[np.bool_],
) -> int:  # pragma: no cover - compiled
    """Edge points of the ball's outline on 16 rays from (u, v) into ``pts``; ``used`` marks the
    rays that found one (an edge to a non-ball pixel within 1.8 r + 2 px inside the image).
    Returns their number."""
    h, w = classes.shape
    reach = 1.8 * r + 2.0
    coarse = max(1.0, math.floor(r / 5.0))  # big balls: walk in coarse steps, then pixel by pixel
    n = 0
    for k in range(_N_RAYS):
        used[k] = False
        cx, sy = _RAYS[k, 0], _RAYS[k, 1]
        inside = 0.0  # the farthest point along the ray known to be on the ball
        t = coarse
        while t <= reach:
            i = math.floor(u + t * cx)
            j = math.floor(v + t * sy)
            if not (0 <= i < w and 0 <= j < h) or not _is_ball(classes[j, i], modern):
                break
            inside = t
            t += coarse
        t = inside + 1.0
        pi_, pj = math.floor(u + inside * cx), math.floor(v + inside * sy)
        while t <= reach:
            i = math.floor(u + t * cx)
            j = math.floor(v + t * sy)
            if not (0 <= i < w and 0 <= j < h):
                break
            if i == pi_ and j == pj:
                t += 1.0
                continue
            c = classes[j, i]
            if not _is_ball(c, modern):
                a = 0.5
                if c == GREEN:
                    i2 = math.floor(u + (t + 1.0) * cx)
                    j2 = math.floor(v + (t + 1.0) * sy)
                    a = _coverage(rgb, pj, pi_, j, i, j2, i2)
                # the edge crosses the outer pixel's centre when it covers half of it
                tc = (i + 0.5 - u) * cx + (j + 0.5 - v) * sy
                te = tc - 0.5 + a
                pts[n, 0] = u + te * cx
                pts[n, 1] = v + te * sy
                used[k] = True
                n += 1
                break
            pi_, pj = i, j
            t += 1.0
    return n


@nb.njit(cache=True, error_model="numpy", inline="always")
def _det3(a: float, b: float, c: float, d: float, e: float, f: float, g: float, h: float, i: float) -> float:
    """Determinant of the 3 x 3 matrix with rows (a, b, c), (d, e, f), (g, h, i)."""  # pragma: no cover
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)


@nb.njit(cache=True, error_model="numpy")
def _fit_circle(
    pts: NDArray[np.float64], keep: NDArray[np.bool_], n: int, u0: float, v0: float, r: float, free: bool
) -> tuple[bool, float, float, float]:  # pragma: no cover - compiled
    """Circle through the kept points: (ok, centre u, v, radius). ``free``: algebraic fit of
    centre and radius; else the centre (Gauss-Newton from (u0, v0)) with the radius fixed to r."""
    if free:
        # x^2 + y^2 + D x + E y + F = 0 in coordinates relative to (u0, v0)
        s = np.zeros((3, 3))
        b = np.zeros(3)
        for k in range(n):
            if not keep[k]:
                continue
            x, y = pts[k, 0] - u0, pts[k, 1] - v0
            q = -(x * x + y * y)
            row = (x, y, 1.0)
            for a in range(3):
                b[a] += row[a] * q
                for c in range(3):
                    s[a, c] += row[a] * row[c]
        det = _det3(s[0, 0], s[0, 1], s[0, 2], s[1, 0], s[1, 1], s[1, 2], s[2, 0], s[2, 1], s[2, 2])
        if abs(det) < 1e-9:
            return False, u0, v0, r
        d = _det3(b[0], s[0, 1], s[0, 2], b[1], s[1, 1], s[1, 2], b[2], s[2, 1], s[2, 2]) / det
        e = _det3(s[0, 0], b[0], s[0, 2], s[1, 0], b[1], s[1, 2], s[2, 0], b[2], s[2, 2]) / det
        f = _det3(s[0, 0], s[0, 1], b[0], s[1, 0], s[1, 1], b[1], s[2, 0], s[2, 1], b[2]) / det
        cu, cv = -0.5 * d, -0.5 * e
        rr = cu * cu + cv * cv - f
        if rr <= 0.0:
            return False, u0, v0, r
        return True, u0 + cu, v0 + cv, math.sqrt(rr)
    cu, cv = u0, v0
    for _ in range(4):
        a11 = a12 = a22 = g1 = g2 = 0.0
        for k in range(n):
            if not keep[k]:
                continue
            dx, dy = pts[k, 0] - cu, pts[k, 1] - cv
            d = max(math.hypot(dx, dy), 1e-9)
            jx, jy = -dx / d, -dy / d
            e = d - r
            a11 += jx * jx
            a12 += jx * jy
            a22 += jy * jy
            g1 += jx * e
            g2 += jy * e
        det = a11 * a22 - a12 * a12
        if det < 1e-9:
            return False, u0, v0, r
        du = -(a22 * g1 - a12 * g2) / det
        dv = -(a11 * g2 - a12 * g1) / det
        cu += du
        cv += dv
        if abs(du) + abs(dv) < 0.03:
            break
    return True, cu, cv, r


@nb.njit(cache=True, error_model="numpy")
def _inliers(pts: NDArray[np.float64], n: int, u: float, v: float, lo2: float, hi2: float) -> int:  # pragma: no cover
    """Points whose squared distance from (u, v) lies in [lo2, hi2]."""
    m = 0
    for k in range(n):
        dx, dy = pts[k, 0] - u, pts[k, 1] - v
        d2 = dx * dx + dy * dy
        m += lo2 <= d2 <= hi2
    return m


@nb.njit(cache=True, error_model="numpy")
def _fit(
    rgb: NDArray[np.uint8],
    classes: NDArray[np.uint8],
    u: float,
    v: float,
    r: float,
    modern: bool,
    pts: NDArray[np.float64],
    used: NDArray[np.bool_],
    keep: NDArray[np.bool_],
) -> tuple[bool, float, float, float, float]:  # pragma: no cover - compiled
    """The ball's outline around (u, v) with expected radius r: (ok, centre u, v, fitted radius
    (NaN where it was fixed to r), rms residual px).

    First the centre with the radius fixed to r, robustly: of the seed and the centres of the
    circles of radius r through pairs of neighbouring edge points, the one with most points
    within the larger of 1.5 px and r / 4 of the circle (the outline; a seed far off the centre,
    edge points on a robot's foot or beyond a line do not mislead it), then least squares on
    those points. When they span more than half the circle, centre and radius are fitted to
    them freely.
    """
    n = _silhouette(rgb, classes, u, v, r, modern, pts, used)
    if n < 3:
        return False, u, v, math.nan, math.inf
    cut = max(1.5, 0.25 * r)
    lo2, hi2 = max(r - cut, 0.0) ** 2, (r + cut) ** 2
    # the centre with most outline points within the cut of radius r: the seed, or one of the two
    # centres of the circles of radius r through neighbouring outline points
    cu, cv = u, v
    best = _inliers(pts, n, u, v, lo2, hi2)
    for k in range(n if best < max(4, n - 2) else 0):  # search unless the seed fits well
        for d in (1, 2):
            if d >= n:
                continue
            k2 = (k + d) % n
            mx, my = 0.5 * (pts[k, 0] + pts[k2, 0]), 0.5 * (pts[k, 1] + pts[k2, 1])
            qx, qy = 0.5 * (pts[k2, 0] - pts[k, 0]), 0.5 * (pts[k2, 1] - pts[k, 1])
            q2 = qx * qx + qy * qy
            if q2 < 0.25 or q2 >= r * r:
                continue
            f = math.sqrt((r * r - q2) / q2)
            for sg in (-1.0, 1.0):
                hx, hy = mx - sg * f * qy, my + sg * f * qx
                m = _inliers(pts, n, hx, hy, lo2, hi2)
                if m > best:
                    best, cu, cv = m, hx, hy
    if best < 3:
        return False, u, v, math.nan, math.inf
    m = 0
    for _ in range(3):
        for k in range(n):
            dx, dy = pts[k, 0] - cu, pts[k, 1] - cv
            d2 = dx * dx + dy * dy
            keep[k] = lo2 <= d2 <= hi2
        ok, fu, fv, _r = _fit_circle(pts, keep, n, cu, cv, r, False)
        if not ok:
            return False, u, v, math.nan, math.inf
        moved = abs(fu - cu) + abs(fv - cv)
        cu, cv = fu, fv
        if moved < 0.05:
            break
    m = 0
    for k in range(n):
        keep[k] = abs(math.hypot(pts[k, 0] - cu, pts[k, 1] - cv) - r) <= cut
        m += keep[k]
    if m < 3:
        return False, u, v, math.nan, math.inf
    # the angular span of the outline: the largest gap between rays with a kept edge point
    gap = 0
    run = 0
    k = 0
    for q in range(2 * _N_RAYS):
        ray = q % _N_RAYS
        if used[ray]:
            kept = keep[k % n]
            k += 1
        else:
            kept = False
        if kept:
            run = 0
        else:
            run += 1
            gap = max(gap, run)
    if gap > _N_RAYS - 4:  # less than about 70 degrees of outline
        return False, u, v, math.nan, math.inf
    rad = math.nan
    if m >= 6 and gap <= _N_RAYS // 2 - 1:  # more than half the circle: fit the radius too
        ok, fu, fv, fr = _fit_circle(pts, keep, n, cu, cv, r, True)
        if ok:
            cu, cv, rad = fu, fv, fr
    rr = rad if math.isfinite(rad) else r
    ss = 0.0
    for k in range(n):
        if keep[k]:
            e = math.hypot(pts[k, 0] - cu, pts[k, 1] - cv) - rr
            ss += e * e
    return True, cu, cv, rad, math.sqrt(ss / m)


@nb.njit(cache=True, error_model="numpy")
def _refine(
    rgb: NDArray[np.uint8],
    classes: NDArray[np.uint8],
    cam: NDArray[np.float64],
    u: float,
    v: float,
    r: float,
    ball_r: float,
    modern: bool,
    pts: NDArray[np.float64],
    used: NDArray[np.bool_],
    keep: NDArray[np.bool_],
    prm: NDArray[np.float64],
) -> tuple[bool, float, float, float, float, float]:  # pragma: no cover - compiled
    """From a seed centre: (plausible, centre u, v, expected radius there, fitted radius (NaN:
    fixed), rms residual)."""
    reach = int(2.6 * r) + 2
    a, b, ra, rb = _chord(rgb, classes, u, v, True, reach, modern)
    if ra and rb and b - a < r:
        return False, u, v, r, math.nan, math.inf  # a chord through the centre is a diameter: too thin
    if ra and rb and b - a <= 3.2 * r:
        u = 0.5 * (a + b)
    elif ra and not rb:
        u = a + r
    elif rb and not ra:
        u = b - r
    a, b, ra, rb = _chord(rgb, classes, u, v, False, reach, modern)
    if ra and rb and b - a < r:
        return False, u, v, r, math.nan, math.inf
    if ra and rb and b - a <= 3.2 * r:
        v = 0.5 * (a + b)
    elif rb:  # the lower edge meets the carpet: the ball sits on it
        v = b - r
    elif ra:
        v = a + r
    if _thin(classes, u, v, r, modern) or not _plausible(rgb, classes, u, v, r, modern, prm):
        return False, u, v, r, math.nan, math.inf
    rad, rms = math.nan, math.inf
    for _ in range(2):
        e = _radius(cam, u, v, ball_r)
        if not math.isfinite(e):
            return False, u, v, r, math.nan, math.inf
        r = e
        ok, u, v, rad, rms = _fit(rgb, classes, u, v, r, modern, pts, used, keep)
        if not ok:
            return False, u, v, r, math.nan, math.inf
    e = _radius(cam, u, v, ball_r)
    if not math.isfinite(e):
        return False, u, v, r, math.nan, math.inf
    return True, u, v, e, rad, rms


@nb.njit(cache=True, error_model="numpy")
def _candidates(
    rgb: NDArray[np.uint8],
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    ball_r: float,
    modern: bool,
    prm: NDArray[np.float64],
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """Verified ball candidates (K x 7: u, v, radius px, x, y, score, expected radius), best first.

    The scanned columns are read row by row (the class image is row-major), each keeping the
    start of its current run of ball pixels. Where a ball is big enough (R at least 1.5 x three
    column steps, from the row where that holds at every column down) only every third column
    is read.
    """
    h, w = classes.shape
    step = int(prm[_STEP])
    rs = int(prm[_ROWS])
    max_tests = int(prm[_MAX_TESTS])
    st = _State(max_tests)
    n_cols = (w - step // 2 + step - 1) // step
    i0 = step // 2
    tops = np.empty(n_cols, dtype=np.int64)
    starts = np.full(n_cols, -1, dtype=np.int64)
    darks = np.full(n_cols, -1, dtype=np.int64)  # last BLACK row of the current run (modern)
    first = h
    for c in range(n_cols):
        i = i0 + c * step
        b0 = int(boundary[i])
        tops[c] = h
        if b0 >= h:
            continue
        rb = _radius(cam, i + 0.5, float(b0), ball_r)
        pad = int(2.2 * rb) + 1 if math.isfinite(rb) else 0
        tops[c] = max(0, b0 - pad)
        first = min(first, tops[c])
    split = _coarse_row(cam, w, h, ball_r, 4.5 * step)
    lut = np.zeros(256, dtype=np.bool_)  # ball pixel by class
    for c in range(256):
        lut[c] = _is_ball(c, modern)
    half = 0.5 * (rs - 1)  # a run's ends lie up to rs - 1 rows before the samples that show them
    j = first
    while j <= h and st.more():
        fine = 1 if j < split else 3  # big balls below the split: every third column
        if j >= split and j - rs < split:
            for c in range(n_cols):  # the other columns stop
                if c % 3 != 0:
                    starts[c] = -1
        for c in range(0, n_cols, fine):
            cl = classes[j, i0 + c * step] if j < h else GREEN  # below the image: every run ends
            if not lut[cl]:
                if starts[c] < 0:
                    continue  # the common case: carpet, no run open
            elif j < tops[c]:
                continue
            else:
                if starts[c] < 0:
                    starts[c] = j
                if cl == BLACK:
                    darks[c] = j
                continue
            # a run [start, j) of ball pixels ends in column i
            start = starts[c]
            starts[c] = -1
            if j - start < 2 * rs:
                continue  # a single sample: balls this small are beyond the range
            _run_end_seeds(
                rgb, classes, boundary, cam, ball_r, modern, prm, st, i0 + c * step, start - half, j - half,
                start - rs >= tops[c], j < h, darks[c],
            )  # fmt: skip
        if j == h:
            break
        j = min(j + rs, h)
    return st.best(int(prm[_MAX_CAND]))


@nb.experimental.jitclass(
    [
        ("tested", nb.float64[:, :]),
        ("n_tested", nb.int64),
        ("n_tests", nb.int64),
        ("n_seeds", nb.int64),
        ("max_tests", nb.int64),
        ("cand", nb.float64[:, :]),
        ("n_cand", nb.int64),
        ("pts", nb.float64[:, :]),
        ("used", nb.bool_[:]),
        ("keep", nb.bool_[:]),
    ]
)
class _State:  # pragma: no cover - compiled
    """Work of one image: the seeds and fitted centres tried (u, v, R, 1 if fitted), the counts,
    the candidates found and the silhouette buffers."""

    def __init__(self, max_tests: int) -> None:
        self.max_tests = max_tests
        self.tested = np.empty((5 * max_tests, 4))
        self.n_tested = 0
        self.n_tests = 0
        self.n_seeds = 0
        self.cand = np.empty((max_tests, _N_CAND))
        self.n_cand = 0
        self.pts = np.empty((_N_RAYS, 2))
        self.used = np.empty(_N_RAYS, dtype=np.bool_)
        self.keep = np.empty(_N_RAYS, dtype=np.bool_)

    def more(self) -> bool:
        return self.n_seeds < 4 * self.max_tests and self.n_tests < self.max_tests

    def near(self, u: float, v: float, r: float, fitted: bool) -> bool:
        """A seed (``fitted`` False) near an earlier seed, or a fitted centre near an earlier one."""
        for t in range(self.n_tested):
            if (self.tested[t, 3] > 0.5) != fitted:
                continue
            q = r if fitted else self.tested[t, 2]
            if abs(self.tested[t, 0] - u) < 0.6 * q and abs(self.tested[t, 1] - v) < 0.6 * q:
                return True
        return False

    def add(self, u: float, v: float, r: float, fitted: bool) -> None:
        if self.n_tested < self.tested.shape[0]:
            k = self.n_tested
            self.tested[k, 0], self.tested[k, 1], self.tested[k, 2] = u, v, r
            self.tested[k, 3] = 1.0 if fitted else 0.0
            self.n_tested += 1

    def best(self, n_max: int) -> NDArray[np.float64]:
        """The candidates by score, best first, without those overlapping a better one."""
        order = np.argsort(-self.cand[: self.n_cand, _CS])
        out = np.empty((min(self.n_cand, n_max), _N_CAND))
        n = 0
        for k in order:
            if n >= out.shape[0]:
                break
            ok = True
            for m in range(n):
                d = math.hypot(out[m, _CU] - self.cand[k, _CU], out[m, _CV] - self.cand[k, _CV])
                if d < out[m, _CE] + self.cand[k, _CE]:
                    ok = False
                    break
            if ok:
                out[n] = self.cand[k]
                n += 1
        return out[:n]


@nb.njit(cache=True, error_model="numpy")
def _coarse_row(cam: NDArray[np.float64], w: int, h: int, ball_r: float, r_min: float) -> int:  # pragma: no cover
    """The first row from which a ball's radius is at least ``r_min`` px in every column (at the
    image's left, middle and right; R grows downward), or ``h``."""
    lo, hi = 0, h
    if not _big(cam, w, float(h - 1), ball_r, r_min):
        return h
    while hi - lo > 1:
        m = (lo + hi) // 2
        if _big(cam, w, float(m), ball_r, r_min):
            hi = m
        else:
            lo = m
    return hi


@nb.njit(cache=True, error_model="numpy")
def _big(cam: NDArray[np.float64], w: int, v: float, ball_r: float, r_min: float) -> bool:  # pragma: no cover
    for u in (0.0, 0.5 * w, float(w)):
        r = _radius(cam, u, v, ball_r)
        if not (r >= r_min):
            return False
    return True


@nb.njit(cache=True, error_model="numpy")
def _run_end_seeds(
    rgb: NDArray[np.uint8],
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    ball_r: float,
    modern: bool,
    prm: NDArray[np.float64],
    st: _State,
    i: int,
    lo: float,
    hi: float,
    bounded: bool,
    closed: bool,
    dark: int,
) -> None:  # pragma: no cover - compiled
    """Seeds from a run of ball pixels [lo, hi) (rows) in column ``i`` and the candidates they
    lead to. ``bounded``: the run began below a non-ball pixel; ``closed``: it ended above one
    (not at the image's bottom); ``dark``: its last BLACK row.

    A run up to about a diameter long seeds its middle. A longer one, or one open at the top,
    seeds a centre one radius above its lower end and (if bounded) one below its upper end; the
    end of a run open at the top (the hall above a straight field boundary) seeds only where
    the boundary dips or, modern, where the run's lower end holds black (a ball's patches in
    front of a robot).
    """
    u = i + 0.5
    mid = 0.5 * (lo + hi)
    r = _radius(cam, u, mid, ball_r)
    if not (r >= prm[_MIN_R]) or hi - lo < prm[_MIN_RUN] * r:
        return
    if hi - lo <= 2.6 * r and bounded:
        _try_seed(rgb, classes, cam, ball_r, modern, prm, st, u, mid)
        return
    if closed and (bounded or _dip(boundary, i, int(hi + 0.5), r) or (modern and dark >= hi - 2.2 * r)):
        rr = _radius(cam, u, hi - r, ball_r)
        if rr >= 0.0:
            _try_seed(rgb, classes, cam, ball_r, modern, prm, st, u, hi - rr)
    if bounded:
        rr = _radius(cam, u, lo + r, ball_r)
        if rr >= 0.0:
            _try_seed(rgb, classes, cam, ball_r, modern, prm, st, u, lo + rr)


@nb.njit(cache=True, error_model="numpy")
def _try_seed(
    rgb: NDArray[np.uint8],
    classes: NDArray[np.uint8],
    cam: NDArray[np.float64],
    ball_r: float,
    modern: bool,
    prm: NDArray[np.float64],
    st: _State,
    su: float,
    sv: float,
) -> None:  # pragma: no cover - compiled
    """Refine, fit and verify the seed centre (su, sv) unless it (or its fitted centre) was
    tried before; a verified ball becomes a candidate."""
    if not st.more() or st.near(su, sv, 0.0, False):
        return
    r0 = _radius(cam, su, sv, ball_r)
    if not math.isfinite(r0):
        return
    st.n_seeds += 1
    st.add(su, sv, r0, False)
    ok, cu, cv, re, rad, rms = _refine(rgb, classes, cam, su, sv, r0, ball_r, modern, st.pts, st.used, st.keep, prm)
    if not ok or st.near(cu, cv, re, True):
        return
    st.n_tests += 1
    st.add(cu, cv, re, True)
    score = _verify(rgb, classes, cu, cv, re, rad, rms, modern, prm)
    if score <= 0.0:
        return
    re, x, y = _expected(cam, cu, cv, ball_r)
    if not math.isfinite(re) or math.hypot(x, y) > prm[_MAX_D] or st.n_cand >= st.cand.shape[0]:
        return
    k = st.n_cand
    st.cand[k, _CU], st.cand[k, _CV] = cu, cv
    # reported as the on-axis radius (what the pinhole relation of the percepts expects)
    st.cand[k, _CR] = (rad if math.isfinite(rad) else re) / _stretch(cam, cu, cv)
    st.cand[k, _CX], st.cand[k, _CY], st.cand[k, _CS], st.cand[k, _CE] = x, y, score, re
    st.n_cand += 1


@nb.njit(cache=True, error_model="numpy")
def _content(
    rgb: NDArray[np.uint8], classes: NDArray[np.uint8], u: float, v: float, r: float, modern: bool, dark_value: float
) -> tuple[int, float, float, float, int, float, float, float]:  # pragma: no cover - compiled
    """What lies inside and around a ball of radius r centred at (u, v): (samples inside, share
    of ball pixels (classic: ORANGE or blended YELLOW, NaN if less than half ORANGE), share of
    black (darker than ``dark_value`` x the carpet on the ring), share of WHITE or grey, ring
    samples below the ball, their GREEN share, their share neither GREEN nor WHITE, ORANGE share
    of the whole ring). Where the ring below is cut by the image edge the whole ring counts."""
    h, w = classes.shape
    rr = 1.3 * r + 1.5
    n_low = n_green = n_other = n_all = n_all_green = n_all_other = n_orange = 0
    carpet = 0.0
    for k in range(_RING.shape[0]):
        i = math.floor(u + rr * _RING[k, 0])
        j = math.floor(v + rr * _RING[k, 1])
        if not (0 <= i < w and 0 <= j < h):
            continue
        c = classes[j, i]
        n_all += 1
        n_orange += c == ORANGE
        if c == GREEN:
            n_all_green += 1
            carpet += max(rgb[j, i, 0], rgb[j, i, 1], rgb[j, i, 2])
        n_all_other += c != GREEN and c != WHITE
        if _RING[k, 1] > 0.25:  # below the ball (v grows downward)
            n_low += 1
            n_green += c == GREEN
            n_other += c != GREEN and c != WHITE
    if n_low < 6:
        n_low, n_green, n_other = n_all, n_all_green, n_all_other
    dark = dark_value * carpet / max(n_all_green, 1)
    n_in = n_ball = n_blend = n_black = n_white = 0
    for k in range(_DISC.shape[0]):
        i = math.floor(u + r * _DISC[k, 0])
        j = math.floor(v + r * _DISC[k, 1])
        if not (0 <= i < w and 0 <= j < h):
            continue
        c = classes[j, i]
        n_in += 1
        if _is_ball(c, modern):
            n_ball += 1
        elif c == YELLOW and not modern:
            n_blend += 1  # orange blurred or blended with the carpet looks yellow
        if max(rgb[j, i, 0], rgb[j, i, 1], rgb[j, i, 2]) < dark:
            n_black += 1
        elif c == WHITE or c == 0:
            n_white += 1
    m = max(n_in, 1)
    fill = (n_ball + n_blend) / m if n_ball >= 0.5 * n_in else math.nan
    ml = max(n_low, 1)
    return (
        n_in, fill, n_black / m, n_white / m, n_low, n_green / ml, n_other / ml, n_orange / max(n_all, 1)
    )  # fmt: skip


@nb.njit(cache=True, error_model="numpy")
def _plausible(
    rgb: NDArray[np.uint8],
    classes: NDArray[np.uint8],
    u: float,
    v: float,
    r: float,
    modern: bool,
    prm: NDArray[np.float64],
) -> bool:  # pragma: no cover - compiled
    """A loose form of :func:`_verify`'s colour tests for a rough centre (before the fit)."""
    n_in, fill, black, _, _, _, _, _ = _content(rgb, classes, u, v, r, modern, prm[_DARK])
    if n_in < 8 or not fill >= prm[_FILL] - 0.25:
        return False
    return not modern or black >= 0.5 * prm[_MIN_BLACK]


@nb.njit(cache=True, error_model="numpy")
def _verify(
    rgb: NDArray[np.uint8],
    classes: NDArray[np.uint8],
    u: float,
    v: float,
    r: float,
    rad: float,
    rms: float,
    modern: bool,
    prm: NDArray[np.float64],
) -> float:  # pragma: no cover - compiled
    """Score in (0, 1] of a ball centred at (u, v) with expected radius r, fitted radius ``rad``
    (NaN: fixed to r) and fit residual ``rms`` (px); 0: no ball."""
    if r < prm[_MIN_R]:
        return 0.0
    tol = prm[_TOL]
    fit = 1.0
    if math.isfinite(rad):
        err = abs(rad / r - 1.0)
        if err > tol:
            return 0.0
        fit = 1.0 - 0.5 * err / tol
    if rms > prm[_RESID] * r + 0.5:
        return 0.0
    n_in, fill, black, white, n_low, green, other, orange = _content(rgb, classes, u, v, r, modern, prm[_DARK])
    if n_in < 9 or n_low < 6 or not fill >= prm[_FILL]:
        return 0.0
    if green < prm[_RING_GREEN] or other > prm[_RING_OTHER]:
        return 0.0
    if modern and (black < prm[_MIN_BLACK] or black > prm[_MAX_BLACK] or white < prm[_MIN_WHITE]):
        return 0.0
    if not modern and orange > prm[_RING_ORANGE]:
        return 0.0
    return fill * (0.5 + 0.5 * green) * fit
