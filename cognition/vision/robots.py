"""Robot (obstacle) detection: where other robots stand, from non-green blobs and jerseys.

NimbRo (section 6.1) finds obstacles as dark or non-green blobs on the field and the team
from the colour of the markers on them; DNT's field boundary (section 3.4) already marks
where something stands in front of the carpet's edge. A robot stands on the carpet, so it is
found by its feet: the lowest row of a tall non-green region that meets green below it.

1. **Feet per column.** Every ``scan_step``-th column (read row by row, every second row,
   the ends to the pixel) gives at most one foot row, the lowest of

   a. the lower end of a run of non-green pixels below the field boundary at least as tall
      as ``min_height`` metres standing there (lines, the ball and penalty marks are flat or
      small);
   b. the field boundary itself where it dips: more than ``min_dip`` px (and a fifth of a
      robot's width) below the boundary within 1.3 robot widths on both sides. The carpet
      region of the image is convex (the projection of a convex polygon), so its edge alone
      never dips on both sides (a slanted edge rises on one side only, a green board in the
      hall only lifts the boundary); what pushes it down stands before the edge;
   c. the lower end of a run of non-green pixels (also from above the boundary: a robot
      before the hall) holding jersey pixels at the height of a standing robot's jersey
      above that end, with white (its body) below them down to about its ankles.

   A run that reaches the image's bottom has no visible feet: such robots are not reported.
2. **Segments.** Neighbouring columns whose feet lie within ``join`` x the expected image
   width of a robot there form one obstacle (one or two columns beside a nearer obstacle's
   feet are the side of its base, not an obstacle); its side edges are refined by a
   horizontal scan for the carpet a little above the feet. An obstacle narrower than
   ``min_width`` x the expected width (posts, lines) is dropped unless the image edge cuts
   it; one wider than ``split`` x the expected width (robots side by side) is divided.
3. **Evidence, position and team.** A robot's lower body (0.02-0.25 m) hides the carpet and
   is mostly white; across its jersey the colour does not change four times (a goal's net
   does); it shows ``min_jersey`` jersey samples unless the image's top cuts the jersey band
   (obstacles found only by a dip of the boundary always need them: the hall is not green
   either). The lowest foot pixel is the front of its base: its ground point plus
   ``robot_radius`` along the viewing direction is the centre, reported as ``x, y`` (robot
   frame) with ``u, v`` the centre's pixel on the ground (the annotations' "feet"). With
   ``min_jersey`` samples of one team's class and twice as many as of the other the robot is
   own (1) or opponent (2), else unknown (0).
4. **One robot, one report.** Two robots' bodies do not overlap, so detections whose centres
   lie within two radii of each other are one robot seen more than once (a near robot's wide
   base can be divided, or found by two rules): taken nearest first, each joins the first
   robot kept within two radii of it, and a kept robot's centre is the mean of its members'
   (its team guess the first one given). A detection farther away whose centre's pixel lies
   inside the image of a nearer robot kept (within its half width of its column, between its
   top at ``ROBOT_HEIGHT`` and its front on the ground) would have its feet hidden by it: it is
   a part of that robot, typically the lower edge of its jersey before the hall, and is
   dropped. At most ``max_robots`` are reported, nearest first.

One compiled call; covariance from the Darmstadt model at the ground (:mod:`.rows`). Pixel
sizes are for a 320 x 240 image and scale with the width.

=============  ============  ===========  ===========================================================
ObstacleParams default       range        meaning
=============  ============  ===========  ===========================================================
scan_step      4 px          [1, 32]      spacing of the scanned columns (at 320 px width)
min_height     0.12 m        (0, 1]       least height of an obstacle above its feet
min_dip        4 px          [0, 50]      a dip of the boundary deeper than this (and a fifth of a robot's
                                          width) is a robot's feet
join           0.25          (0, 2]       largest jump of the feet between columns, x expected width
min_width      0.5           [0, 2]       narrowest obstacle, x the expected image width of a robot
split          1.6           [1, 10]      wider obstacles are divided, x the expected width
jersey         (0.1, 0.45)   [0, 1]       heights (m) searched for the jersey (standing 0.26-0.45, fallen
                                          0.1-0.2)
min_jersey     3             [1, 100]     least jersey samples for a team guess
max_distance   8.0 m         (0, 100]     farthest obstacle reported (ground distance of its centre)
max_robots     10            [1, 32]      robots reported per image, nearest first
=============  ============  ===========  ===========================================================
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import ClassVar

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.params import Range, Ranges, check_ranges, positive
from cognition.percepts import N_COLS, Col
from cognition.vision.ball import camera_ok_nb, check_inputs
from cognition.vision.projection import ground_nb, horizon_row_nb, pixel_nb
from cognition.vision.rows import point_rows_nb

GREEN, WHITE = 1, 2
ROBOT_HEIGHT = 0.57
"""Height of a standing robot (m; a NAO V6 is 0.574 m tall): what a nearer robot hides."""


@dataclass(frozen=True)
class ObstacleParams:
    """Parameters of the robot detector (module table; pixels at 320 px width)."""

    scan_step: int = 4
    min_height: float = 0.12
    min_dip: float = 4.0
    join: float = 0.25
    min_width: float = 0.5
    split: float = 1.6
    jersey: tuple[float, float] = (0.1, 0.45)
    min_jersey: int = 3
    max_distance: float = 8.0
    max_robots: int = 10

    RANGES: ClassVar[Ranges] = {
        "scan_step": Range(1, 32),
        "min_height": positive(1.0),
        "min_dip": Range(0.0, 50.0),
        "join": positive(2.0),
        "min_width": Range(0.0, 2.0),
        "split": Range(1.0, 10.0),
        "jersey": Range(0.0, 1.0),
        "min_jersey": Range(1, 100),
        "max_distance": positive(100.0),
        "max_robots": Range(1, 32),
    }

    def __post_init__(self) -> None:
        check_ranges(self)
        if self.jersey[0] >= self.jersey[1]:
            raise ValueError(f"ObstacleParams.jersey must be (low, high) with low < high, got {self.jersey!r}")


@lru_cache(maxsize=64)
def _vector(p: ObstacleParams, width: int) -> NDArray[np.float64]:
    scale = width / 320.0
    v = np.array(
        [
            max(1, round(p.scan_step * scale)), p.min_height, p.min_dip * scale, p.join, p.min_width, p.split,
            p.jersey[0], p.jersey[1], p.min_jersey, p.max_distance, p.max_robots,
        ],
        dtype=np.float64,
    )  # fmt: skip
    v.setflags(write=False)
    return v


_STEP, _MIN_H, _DIP, _JOIN, _MIN_W, _SPLIT, _J_LO, _J_HI, _MIN_J, _MAX_D, _MAX_N = range(11)
_SUB = int(Col.SUBTYPE)


def detect_robots(
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    jersey_classes: tuple[int, int],
    team: int,
    robot_radius: float,
    params: ObstacleParams,
    sigma_alpha: float,
    sigma_beta: float,
) -> NDArray[np.float64]:
    """Percept rows of the robots seen, nearest first: ``x, y`` the robot-frame ground position
    of the robot's centre (m), ``u, v`` that point's pixel, ``subtype``
    :class:`cognition.percepts.RobotTeam` (0 unknown, 1 own, 2 opponent).

    ``classes`` (H x W uint8) are the colour classes, ``boundary`` (W, int32) the first field
    row per column, ``cam`` the camera row, ``jersey_classes`` the colour classes of team 0's and
    team 1's jerseys, ``team`` the own team's index (0 or 1), ``robot_radius`` (m) the robots'
    radius; ``sigma_alpha``, ``sigma_beta`` (rad) the frame's angular sigmas.
    """
    check_inputs(classes, boundary, cam, sigma_alpha, sigma_beta)
    if not isinstance(params, ObstacleParams):
        raise TypeError(f"params must be ObstacleParams, got {type(params).__name__}")
    if (
        not isinstance(jersey_classes, tuple)
        or len(jersey_classes) != 2
        or not all(
            isinstance(c, int | np.integer) and not isinstance(c, bool) and 0 <= c <= 255 for c in jersey_classes
        )
    ):
        raise ValueError(f"jersey_classes must be a pair of colour class codes (0..255), got {jersey_classes!r}")
    if team not in (0, 1) or isinstance(team, bool):
        raise ValueError(f"team must be 0 or 1 (the jersey index of the own team), got {team!r}")
    if isinstance(robot_radius, bool) or not isinstance(robot_radius, float | int) or not 0.0 < robot_radius <= 2.0:
        raise ValueError(f"robot_radius must be a number in (0, 2] m, got {robot_radius!r}")
    rows, code = _detect_robots_nb(
        classes, boundary, cam, int(jersey_classes[0]), int(jersey_classes[1]), int(team), float(robot_radius),
        _vector(params, classes.shape[1]), float(sigma_alpha), float(sigma_beta),
    )  # fmt: skip
    if code:
        raise ValueError("cam must be a finite camera row with positive focal lengths")
    return rows


# ----------------------------------------------------------------------------- compiled core


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _detect_robots_nb(
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    jersey0: int,
    jersey1: int,
    team: int,
    radius: float,
    prm: NDArray[np.float64],
    sa: float,
    sb: float,
) -> tuple[NDArray[np.float64], int]:  # pragma: no cover - compiled
    """(percept rows, 0), or (no rows, 1) for a bad camera row."""
    if not camera_ok_nb(cam):
        return np.empty((0, N_COLS)), 1
    found = _robots(classes, boundary, cam, jersey0, jersey1, team, radius, prm)
    rows = point_rows_nb(found[:, 0:2].copy(), found[:, 2:4].copy(), 0.0, cam, sa, sb)
    for k in range(rows.shape[0]):
        rows[k, _SUB] = found[k, 4]
    return rows, 0


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _dip(
    cam: NDArray[np.float64], boundary: NDArray[np.int32], c: int, i0: int, step: int, radius: float, dip: float
) -> bool:  # pragma: no cover - compiled
    """The boundary at scan column c lies more than ``dip`` px (at least a fifth of a robot's
    width) below the highest boundary within 1.3 robot widths on the left and on the right:
    something stands before the carpet's edge. The carpet is convex, so its edge alone never
    dips on both sides; a slanted edge rises on one side only."""
    w = boundary.shape[0]
    i = i0 + c * step
    b = float(boundary[i])
    wexp = _width_px(cam, i + 0.5, b, 2.0 * radius)
    if not (wexp > 0.0):
        return False
    need = max(dip, 0.2 * wexp)
    k = int(1.3 * wexp) + step
    # b - min(rows) > need holds exactly when one row is more than ``need`` above b (integer
    # rows: exact as floats), so each side stops at the first such row
    left = right = False
    for q in range(max(0, i - k), i, step):
        if b - float(boundary[q]) > need:
            left = True
            break
    if not left:
        return False
    for q in range(i + step, min(w, i + k + 1), step):
        if b - float(boundary[q]) > need:
            right = True
            break
    return right


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _jersey_fits(
    cam: NDArray[np.float64], u: float, v: float, top: int, bottom: int, white: int
) -> bool:  # pragma: no cover - compiled
    """Jersey pixels from row ``top`` to ``bottom`` and white down to row ``white`` fit a
    standing robot whose feet are at pixel (u, v): the jersey band (0.26-0.45 m above the
    ground) within a third of its image height of where it should be, the lowest white (the
    body above the ankle joints, 0.05 m) near that height."""
    x, y, ok = ground_nb(cam, u, v, 0.0)
    if not ok:
        return False
    _, v_lo, ok1 = pixel_nb(cam, x, y, 0.26)
    _, v_hi, ok2 = pixel_nb(cam, x, y, 0.45)
    if not (ok1 and ok2):
        return False
    _, v_ankle, ok3 = pixel_nb(cam, x, y, 0.05)
    band = v_lo - v_hi
    tol = max(2.0, 0.35 * band)
    return ok3 and abs(bottom - v_lo) <= tol and top >= v_hi - tol and abs(white - v_ankle) <= tol + 2.0


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _height_px(cam: NDArray[np.float64], u: float, v: float, z: float) -> float:  # pragma: no cover - compiled
    """Image height (px) of a vertical stick of height z (m) standing on the ground at pixel (u, v)."""
    x, y, ok = ground_nb(cam, u, v, 0.0)
    if not ok:
        return math.inf
    _, vt, ok2 = pixel_nb(cam, x, y, z)
    if not ok2:
        return math.inf
    return v - vt


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _width_px(cam: NDArray[np.float64], u: float, v: float, width: float) -> float:  # pragma: no cover - compiled
    """Image width (px) of an object ``width`` m wide whose front stands on the ground at (u, v)."""
    x, y, ok = ground_nb(cam, u, v, 0.0)
    if not ok:
        return math.nan
    dx, dy = x - cam[9], y - cam[10]
    d = math.hypot(dx, dy) + 0.5 * width
    return 0.5 * (cam[12] + cam[13]) * width / max(d, 1e-6)


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _robots(
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    jersey0: int,
    jersey1: int,
    team: int,
    radius: float,
    prm: NDArray[np.float64],
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """Robots found (K x 5: centre x, y, pixel u, v, team guess), nearest first."""
    h, w = classes.shape
    step = int(prm[_STEP])
    i0 = step // 2
    n_cols = (w - i0 + step - 1) // step
    feet = np.full(n_cols, math.nan)
    dipped = np.zeros(n_cols, dtype=np.bool_)  # the feet come from the boundary (robot before the hall)
    starts = np.full(n_cols, -1, dtype=np.int64)
    j_top = np.full(n_cols, -1, dtype=np.int64)  # first and last jersey rows of the current run
    j_bot = np.full(n_cols, -1, dtype=np.int64)
    white = np.full(n_cols, -1, dtype=np.int64)  # last WHITE row of the current run
    first = h
    for c in range(n_cols):
        i = i0 + c * step
        b = int(boundary[i])
        if b < h and _dip(cam, boundary, c, i0, step, radius, prm[_DIP]):
            feet[c] = b  # the boundary pushed down by something standing in front of the carpet's edge
            dipped[c] = True
        first = min(first, b, max(0, int(horizon_row_nb(cam, i + 0.5))))
    # runs of non-green read row by row (every second row, the ends to the pixel): (a) tall ones
    # below the boundary, (c) ones holding a jersey at a robot's jersey height above the feet
    for j in range(max(first, 0), h, 2):
        for c in range(n_cols):
            i = i0 + c * step
            cl = classes[j, i]
            if cl != GREEN:
                if starts[c] < 0:
                    starts[c] = j
                    j_top[c] = -1
                    white[c] = -1
                if cl in (jersey0, jersey1):
                    if j_top[c] < 0:
                        j_top[c] = j
                    j_bot[c] = j
                elif cl == WHITE:
                    white[c] = j
                continue
            s = starts[c]
            if s < 0:
                continue
            starts[c] = -1
            e = j - 1 if classes[j - 1, i] == GREEN else j  # the first carpet row below the run
            if e <= feet[c] or e - s < 3:
                continue
            if s >= boundary[i] - 1 and e - s >= _height_px(cam, i + 0.5, float(e), prm[_MIN_H]):
                feet[c] = e  # (a): lower than anything before in this column
                dipped[c] = False
            elif j_top[c] >= 0 and white[c] > j_bot[c] and _jersey_fits(cam, i + 0.5, e, j_top[c], j_bot[c], white[c]):
                feet[c] = e  # (c): a robot's jersey, its white body below and its feet on the carpet
                dipped[c] = False
    # (open runs at the image bottom: no visible feet)
    # segments of neighbouring columns with feet at about the same row
    segs = np.empty((n_cols, 3), dtype=np.int64)  # first, last and lowest-foot column
    n_seg = 0
    c = 0
    while c < n_cols:
        if not math.isfinite(feet[c]):
            c += 1
            continue
        a = c
        low_c = c
        while c + 1 < n_cols and math.isfinite(feet[c + 1]):
            tol = max(3.0, prm[_JOIN] * _width_px(cam, i0 + (c + 1) * step + 0.5, feet[c + 1], 2.0 * radius))
            if abs(feet[c + 1] - feet[c]) > tol:
                break
            c += 1
            if feet[c] > feet[low_c]:
                low_c = c
        segs[n_seg, 0], segs[n_seg, 1], segs[n_seg, 2] = a, c, low_c
        n_seg += 1
        c += 1
    out = np.empty((n_cols, 5))
    n_out = 0
    for k in range(n_seg):
        a, b, low_c = segs[k, 0], segs[k, 1], segs[k, 2]
        # one or two columns right beside a nearer obstacle's feet are its side (its base's
        # outline rises toward its sides), not an obstacle of their own
        side = False
        if b - a <= 1:
            for q in (k - 1, k + 1):
                if 0 <= q < n_seg and (segs[q, 0] == b + 1 or segs[q, 1] == a - 1):
                    wq = _width_px(cam, i0 + segs[q, 2] * step + 0.5, feet[segs[q, 2]], 2.0 * radius)
                    side |= 0.0 < feet[segs[q, 2]] - feet[low_c] <= wq
        if side:
            continue
        foot_v = feet[low_c]
        wexp = _width_px(cam, i0 + low_c * step + 0.5, foot_v, 2.0 * radius)
        if not math.isfinite(wexp) or wexp <= 0.0:
            continue
        # side edges: the carpet left and right, a little above the feet
        row = int(foot_v - max(2.0, 0.15 * wexp))
        row = min(max(row, 0), h - 1)
        left, cut_l = _edge_scan(classes, row, i0 + a * step, -1, int(wexp) + step)
        right, cut_r = _edge_scan(classes, row, i0 + b * step, 1, int(wexp) + step)
        width = right - left
        if width < prm[_MIN_W] * wexp and not ((cut_l or cut_r) and width >= 0.5 * prm[_MIN_W] * wexp):
            continue
        from_hall = True
        for cc in range(a, b + 1):
            from_hall &= dipped[cc]
        pieces = 1
        if width > prm[_SPLIT] * wexp:
            pieces = int(width / wexp + 0.5)
        for q in range(pieces):
            ul = left + width * q / pieces
            ur = left + width * (q + 1) / pieces
            um = 0.5 * (ul + ur)
            # the lowest foot inside this piece
            fv = -1.0
            for cc in range(a, b + 1):
                uc = i0 + cc * step + 0.5
                if ul - step <= uc <= ur + step and feet[cc] > fv:
                    fv = feet[cc]
            if fv < 0.0:
                fv = foot_v
            x, y, ok = ground_nb(cam, um, fv, 0.0)
            if not ok:
                continue
            d = math.hypot(x - cam[9], y - cam[10])
            if d <= 1e-6:
                continue
            # the front of the base seen at the lowest pixel; the centre lies a radius further on
            ex, ey = (x - cam[9]) / d, (y - cam[10]) / d
            cx, cy = x + radius * ex, y + radius * ey
            if math.hypot(cx, cy) > prm[_MAX_D] or n_out >= n_cols:
                continue
            pu, pv, _ = pixel_nb(cam, cx, cy, 0.0)
            guess, n_jersey, body, band_seen = _look(classes, cam, cx, cy, ul, ur, jersey0, jersey1, team, prm)
            if body < 0.8 or (n_jersey < prm[_MIN_J] and (band_seen or from_hall)):
                continue  # a robot shows its jersey (unless the image's top cuts it) on a non-green body
            out[n_out, 0], out[n_out, 1], out[n_out, 2], out[n_out, 3] = cx, cy, pu, pv
            out[n_out, 4] = guess
            n_out += 1
    # nearest first; two robots' bodies do not overlap, so centres within two radii of each
    # other are one robot seen more than once (the pieces of a near robot's wide base): they are
    # merged into their mean
    order = np.argsort(out[:n_out, 0] ** 2 + out[:n_out, 1] ** 2)
    keep = np.empty(n_out, dtype=np.int64)
    count = np.zeros(n_out)
    sx = np.zeros(n_out)
    sy = np.zeros(n_out)
    m = 0
    for k in range(n_out):
        r = order[k]
        home = -1
        hidden = False
        for q in range(m):
            if math.hypot(out[r, 0] - sx[q] / count[q], out[r, 1] - sy[q] / count[q]) < 2.0 * radius:
                home = q
                break
            hidden |= _behind(cam, out[keep[q], 0], out[keep[q], 1], radius, out[r, 2], out[r, 3])
        if home < 0 and hidden:
            continue  # its feet would be hidden by a nearer robot: a part of that robot (its jersey's edge)
        if home < 0:
            keep[m] = r
            home = m
            m += 1
        elif out[keep[home], 4] == 0.0:
            out[keep[home], 4] = out[r, 4]
        count[home] += 1.0
        sx[home] += out[r, 0]
        sy[home] += out[r, 1]
    m = min(m, int(prm[_MAX_N]))
    res = np.empty((m, 5))
    for k in range(m):
        res[k] = out[keep[k]]
        if count[k] > 1.0:
            res[k, 0], res[k, 1] = sx[k] / count[k], sy[k] / count[k]
            res[k, 2], res[k, 3], _ = pixel_nb(cam, res[k, 0], res[k, 1], 0.0)
    return res


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _behind(
    cam: NDArray[np.float64], x: float, y: float, radius: float, u: float, v: float
) -> bool:  # pragma: no cover - compiled
    """Pixel (u, v) lies inside the image of a standing robot centred at ground (x, y) (robot
    frame, m): within its half width of its centre's column, between its top and its front's
    ground row."""
    d = math.hypot(x - cam[9], y - cam[10])
    if d <= radius:
        return False
    uc, _, ok = pixel_nb(cam, x, y, 0.0)
    _, v_top, ok1 = pixel_nb(cam, x, y, ROBOT_HEIGHT)
    _, v_front, ok2 = pixel_nb(cam, x - radius * (x - cam[9]) / d, y - radius * (y - cam[10]) / d, 0.0)
    half = 0.5 * (cam[12] + cam[13]) * radius / (d - radius)
    return ok and ok1 and ok2 and abs(u - uc) <= half and v_top <= v <= v_front


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _edge_scan(
    classes: NDArray[np.uint8], j: int, i: int, di: int, reach: int
) -> tuple[float, bool]:  # pragma: no cover - compiled
    """The side edge (continuous column) of the non-green region at row j from column i toward
    di: where the carpet starts within ``reach`` px (else the reach's end), and whether the
    image edge cut the search."""
    w = classes.shape[1]
    for k in range(1, reach + 1):
        p = i + di * k
        if p < 0:
            return 0.0, True
        if p >= w:
            return float(w), True
        if classes[j, p] == GREEN:
            return (float(p) + 1.0) if di < 0 else float(p), False
    return float(i + di * reach) + (1.0 if di > 0 else 0.0), False


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _look(
    classes: NDArray[np.uint8],
    cam: NDArray[np.float64],
    x: float,
    y: float,
    ul: float,
    ur: float,
    jersey0: int,
    jersey1: int,
    team: int,
    prm: NDArray[np.float64],
) -> tuple[float, int, float, bool]:  # pragma: no cover - compiled
    """What a robot centred at ground (x, y) seen between columns ul and ur looks like: (team
    guess (RobotTeam) from the jersey band, body evidence: the smaller of the non-green share
    of its lower body (0.02-0.25 m) and twice its WHITE or jersey share, 0 where the colour
    changes four times or more across the middle of two rows of the jersey (a net), whether at least half
    of the band is in the image). Classes are read on a sparse grid (about 8 x 8 per band)."""
    h, w = classes.shape
    _, _v0, ok0 = pixel_nb(cam, x, y, 0.0)
    _, v_lo, ok1 = pixel_nb(cam, x, y, prm[_J_LO])
    _, v_hi, ok2 = pixel_nb(cam, x, y, prm[_J_HI])
    if not (ok0 and ok1 and ok2):
        return 0.0, 0, 0.0, False
    band_seen = 0.5 * (v_lo + v_hi) >= 0.0
    i0 = max(0, int(ul + 0.2 * (ur - ul)))
    i1 = min(w - 1, int(ur - 0.2 * (ur - ul)))
    if i1 < i0:
        return 0.0, 0, 0.0, band_seen
    si = max(1, (i1 - i0) // 8)
    n0 = n1 = 0
    j0 = max(0, int(v_hi))
    j1 = min(h - 1, int(v_lo))
    if j1 >= j0:
        sj = max(1, (j1 - j0) // 8)
        for j in range(j0, j1 + 1, sj):
            for i in range(i0, i1 + 1, si):
                c = classes[j, i]
                n0 += c == jersey0
                n1 += c == jersey1
    # the lower body (0.02-0.25 m): no carpet seen through it, mostly white (or the jersey of a
    # fallen robot)
    _, v_a, ok3 = pixel_nb(cam, x, y, 0.25)
    _, v_b, ok4 = pixel_nb(cam, x, y, 0.02)
    body = 0
    light = 0
    n_body = 0
    j0 = max(0, int(v_a))
    j1 = min(h - 1, int(v_b))
    if ok3 and ok4 and j1 >= j0:
        sj = max(1, (j1 - j0) // 8)
        for j in range(j0, j1 + 1, sj):
            for i in range(i0, i1 + 1, si):
                c = classes[j, i]
                n_body += 1
                body += c != GREEN
                light += c in (WHITE, jersey0, jersey1)
    share = min(body / n_body, 2.0 * light / n_body) if n_body > 0 else 1.0
    # a jersey is one solid colour across: a goal's net (strings every 0.1 m) is not
    changes = 0
    for z in (0.3, 0.4):
        _, vz, okz = pixel_nb(cam, x, y, z)
        j = int(vz)
        if okz and 0 <= j < h:
            for i in range(i0 + 1, i1 + 1):
                changes += classes[j, i] != classes[j, i - 1]
    if changes >= 4:
        share = 0.0
    if max(n0, n1) < prm[_MIN_J] or (n0 < 2 * n1 and n1 < 2 * n0):
        return 0.0, n0 + n1, share, band_seen
    seen = 0 if n0 > n1 else 1
    return (1.0 if seen == team else 2.0), n0 + n1, share, band_seen
