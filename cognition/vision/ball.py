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
``ball_radius``. All of it is one compiled call: the search (seeds, refinement, verification)
lives in :mod:`.ball_candidates`, the radius model, the outline and the circle fit in
:mod:`.ball_fit`; this module holds the parameters, the input checks and the entry point.

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
max_ring_orange     0.15     [0, 1]      classic: largest share of ORANGE on the whole ring
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
from cognition.vision.ball_candidates import _CR, _CU, _CV, _CX, _CY, _candidates
from cognition.vision.rows import point_rows_nb


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
    max_ring_orange: float = 0.15
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


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def camera_ok_nb(cam: NDArray[np.float64]) -> bool:  # pragma: no cover - compiled
    """The camera row is finite with positive focal lengths."""
    for k in range(cam.shape[0]):
        if not math.isfinite(cam[k]):
            return False
    return cam[12] > 0.0 and cam[13] > 0.0


@nb.njit(cache=True, error_model="numpy", fastmath=False)
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
