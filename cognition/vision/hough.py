"""Field lines by oriented line points and an oriented Hough transform (NimbRo sections 5.1-5.2).

The second line method of the vision pipeline (``VisionParams.method == "hough"``). It turns
the class image into the same products the DNT chaining gives (segments in the image and on
the ground, which ends are open, the centre circle), so crossings, percept rows and
everything after them work unchanged. Five steps, one compiled call:

1. **Oriented line points** (NimbRo 5.1). NimbRo convolves the class image with elongated
   kernels in four orientations and two sizes: white along the kernel, green on both sides.
   Here the kernels are evaluated only where a line can be: at the centres of white runs on
   every ``scan_step``-th row and column below the field boundary that have carpet within
   ``edge_gap`` of both ends and are at most about three line widths long (a longer run is
   a robot, or a line along the scan, which the other scan direction crosses). A kernel
   samples five Gaussian-weighted positions along its direction on the white and as many
   on both sides on the green; its response is the smallest of the three weighted shares
   (white centre, green left, green right), counted over the samples inside the image (an
   image edge says nothing about a line). Its cross-section follows the width a painted
   line has at that pixel (ground width through the Jacobian of the ground projection),
   its length is one of two sizes, ``kernel_small`` for thin (far) lines and
   ``kernel_large`` for wide (near) ones, switched at ``size_switch`` px of line width. A
   point whose best response reaches ``min_response``, and whose white run is at least
   ``min_width`` of the line's width (a goal net's strands are thinner), keeps the best
   orientation and the better neighbour orientation.
2. **Ground projection and merging** (5.1). Points and both orientations are projected to
   the ground (robot frame); the direction is the response-weighted mean of the two.
   Points close in the image (``merge_radius``) with similar image directions are merged
   into short segments: ground centroid, weight (summed responses) and direction. Where
   the points spread along a line, their principal axis in the image, projected to the
   ground, replaces the kernels' estimate (also for the points). Far away and seen at a
   slant, a few degrees in the image are tens on the ground: a direction's uncertainty on
   the ground is taken from the kernels' (10 deg) or the points' (``position_error`` px
   over their spread) uncertainty in the image.
3. **Centre circle** (5.2, after de Jong et al.). Every short segment votes at
   ``circle_radius`` from its centroid, orthogonal to its direction, on both sides, into a
   grid of ``circle_cell``; the best cell (with its neighbours) gives a first centre, which
   a fixed-radius fit on the segments near the ring and tangent to it refines. It is
   accepted when those segments hold ``circle_min_points`` line points spanning
   ``circle_min_span`` of the circle, and when the circle, projected back into the image,
   shows a quarter of it with ``circle_min_coverage`` of that on white
   (:func:`~cognition.vision.circle.verify_circle_nb`, as the DNT path checks it). Its
   segments and points are then removed.
4. **Oriented Hough transform** (5.2). Each short segment adds its weight to the bins
   ``(theta +- vote_spread, rho)`` around its own normal only (bins of ``theta_bin`` x
   ``rho_bin``, NimbRo: 2.5 deg x 6 cm; rho split linearly between the two nearest bins).
   The main orientation ``alpha_max`` maximizes the sum of the rows ``alpha`` and
   ``alpha + pi/2`` (eq. 3). A segment whose direction is less certain than
   ``vote_spread`` then votes over its uncertainty (up to ``max_uncertainty``; beyond, it
   does not vote). Lines are taken from the rows within ``orientation_tolerance`` of the
   two main orientations, strongest 3 x 3 sum first. NimbRo keeps two lines per
   orientation; an SPL image can show more (goal line, goal area, penalty area), so up to
   ``max_lines`` per orientation are taken, and the votes of the short segments a line
   explains are removed before the next peak is sought (non-maximum suppression by
   explanation, which keeps a parallel line 0.6 m away).
5. **Segments.** A peak's line is refined by a weighted total least-squares fit to the
   free line points near it (within ``support_distance`` or ``support_pixels`` of a
   pixel's ground size, image direction within ``support_angle`` of the line's image
   direction there), the points are ordered along it and split where consecutive points
   are more than ``gap`` px apart over a stretch that is not white (a robot on the line);
   each piece with ``min_points`` points is a segment. Its ends are then followed along
   the white and classed open or real exactly as the DNT segments'
   (:func:`~cognition.vision.ends.segments_on_ground_nb`: an image edge, the field
   boundary or an object next to an end leaves it open); a segment the white leads beyond
   ``max_distance`` is cut there (that end open) instead of dropped, and segments shorter
   than ``min_line_length`` are dropped.

The compiled steps live in :mod:`.hough_points` (steps 1-2, NimbRo 5.1) and
:mod:`.hough_votes` (the pieces of steps 3-5, NimbRo 5.2); this module holds the parameters,
the entry point and the compiled driver that runs the five steps in one call.

Pixel sizes are for a 320 x 240 image and scale with the image width; ground sizes in
metres, angles in radians; robot frame (+x forward, +y left), pixels ``u`` right, ``v`` down.

=====================  ========  ==============  ===========================================================
parameter              default   range           meaning
=====================  ========  ==============  ===========================================================
scan_step              3 px      [1, 32]         rows and columns searched for line point candidates
orientations           4         [2, 16]         kernel orientations (NimbRo: 4)
kernel_small           3 px      [1, 20]         half-length of the kernel for thin (far) lines
kernel_large           6 px      [1, 40]         half-length of the kernel for wide (near) lines
size_switch            4 px      [0, 100]        line width (px) from which the large kernel is used
min_response           0.6       [0, 1]          response a line point needs (share of white / green)
min_width              0.5       [0, 2]          the white run is at least this x the line's width (px) - 1
edge_gap               3 px      [1, 20]         a candidate run has carpet this close to both ends
merge_radius           7 px      [1, 50]         points closer than this (image) may form a short segment
merge_angle            0.4 rad   (0, pi/2]       their image orientations differ by at most this
theta_bin              2.5 deg   (0, pi/4]       Hough angle bin (NimbRo: 2.5 deg)
rho_bin                0.06 m    (0, 1]          Hough distance bin (NimbRo: 6 cm)
position_error         0 px      [0, 10]         image position error that widens a direction's votes (0: trusted)
vote_spread            5 deg     [0, pi/4]       a segment votes for normals within this of its own
max_uncertainty        30 deg    [0, pi/2]       ... or within its direction's uncertainty, up to this
orientation_tolerance  2.5 deg   [0, pi/4]       lines are sought within this of the two main orientations
min_votes              3.0       (0, 1000]       summed responses of a peak (3 x 3 bins) to be a line
max_lines              4         [1, 20]         lines per main orientation
support_distance       0.06 m    (0, 1]          a point within this of a line supports it ...
support_pixels         1.5 px    [0, 20]         ... or within this many of its pixel's ground size
support_angle          15 deg    (0, pi/2]       ... and its direction within this of the line's
gap                    12 px     [1, 200]        a larger gap between points that is not white splits a line
min_white              0.7       [0, 1]          white share that bridges a gap (DNT's white ratio)
min_points             4         [2, 1000]       line points of a segment
min_line_length        0.10 m    [0, 100]        shorter segments (on the ground) are dropped
max_distance           6.0 m     (0, 100]        farther points are dropped, segments cut there
end_probe              12 px     [1, 100]        pixels looked at beyond an end to class it open
circle_cell            0.06 m    (0, 1]          vote grid of the centre circle
circle_inlier          0.08 m    (0, 1]          distance from the circle of its segments
circle_tangent         30 deg    (0, pi/2]       their direction within this of the tangent
circle_min_points      10        [3, 10000]      line points of an accepted circle
circle_min_span        90 deg    [0, 2pi]        arc of the circle its segments cover
circle_min_coverage    0.85      [0, 1]          share of the projected circle's visible points on white
=====================  ========  ==============  ===========================================================
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass
from typing import ClassVar

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.params import Range, Ranges, check_ranges, non_negative, positive
from cognition.vision.circle import verify_circle_nb
from cognition.vision.ends import segments_on_ground_nb
from cognition.vision.hough_points import (
    _DEG,
    _PHI,
    _SN,
    _SPHI,
    _SUNC,
    _SW,
    _SX,
    _SY,
    _U,
    _V,
    _X,
    _Y,
    _line_points,
    _merge,
)
from cognition.vision.hough_votes import _circle, _clip, _fit, _on_ring, _peak, _strip, _support, _vote, _wrapped
from cognition.vision.projection import pixel_nb
from cognition.vision.segments import white_ratio_nb


@dataclass(frozen=True)
class HoughParams:
    """Parameters of :func:`hough_lines` (module table)."""

    scan_step: int = 3
    orientations: int = 4
    kernel_small: float = 3.0
    kernel_large: float = 6.0
    size_switch: float = 4.0
    min_response: float = 0.6
    min_width: float = 0.5
    edge_gap: int = 3
    merge_radius: float = 7.0
    merge_angle: float = 0.4
    theta_bin: float = 2.5 * _DEG
    rho_bin: float = 0.06
    position_error: float = 0.0
    vote_spread: float = 5.0 * _DEG
    max_uncertainty: float = 30.0 * _DEG
    orientation_tolerance: float = 2.5 * _DEG
    min_votes: float = 3.0
    max_lines: int = 4
    support_distance: float = 0.06
    support_pixels: float = 1.5
    support_angle: float = 15.0 * _DEG
    gap: float = 12.0
    min_white: float = 0.7
    min_points: int = 4
    min_line_length: float = 0.10
    max_distance: float = 6.0
    end_probe: int = 12
    circle_cell: float = 0.06
    circle_inlier: float = 0.08
    circle_tangent: float = 30.0 * _DEG
    circle_min_points: int = 10
    circle_min_span: float = 90.0 * _DEG
    circle_min_coverage: float = 0.85

    RANGES: ClassVar[Ranges] = {
        "scan_step": Range(1, 32),
        "orientations": Range(2, 16),
        "kernel_small": Range(1.0, 20.0),
        "kernel_large": Range(1.0, 40.0),
        "size_switch": non_negative(100.0),
        "min_response": Range(0.0, 1.0),
        "min_width": Range(0.0, 2.0),
        "edge_gap": Range(1, 20),
        "merge_radius": Range(1.0, 50.0),
        "merge_angle": positive(math.pi / 2),
        "theta_bin": positive(math.pi / 4),
        "rho_bin": positive(1.0),
        "position_error": non_negative(10.0),
        "vote_spread": non_negative(math.pi / 4),
        "max_uncertainty": non_negative(math.pi / 2),
        "orientation_tolerance": non_negative(math.pi / 4),
        "min_votes": positive(1000.0),
        "max_lines": Range(1, 20),
        "support_distance": positive(1.0),
        "support_pixels": non_negative(20.0),
        "support_angle": positive(math.pi / 2),
        "gap": Range(1.0, 200.0),
        "min_white": Range(0.0, 1.0),
        "min_points": Range(2, 1000),
        "min_line_length": non_negative(100.0),
        "max_distance": positive(100.0),
        "end_probe": Range(1, 100),
        "circle_cell": positive(1.0),
        "circle_inlier": positive(1.0),
        "circle_tangent": positive(math.pi / 2),
        "circle_min_points": Range(3, 10000),
        "circle_min_span": Range(0.0, 2 * math.pi),
        "circle_min_coverage": Range(0.0, 1.0),
    }

    def __post_init__(self) -> None:
        check_ranges(self)


@dataclass(frozen=True, eq=False)
class HoughLines:
    """The lines of one image found by :func:`hough_lines` (module docstring)."""

    seg_px: NDArray[np.float64]
    """S x 4 image end points (u1, v1, u2, v2) of the segments."""
    seg_ground: NDArray[np.float64]
    """S x 4 robot-frame ground end points (x1, y1, x2, y2), m."""
    open_ends: NDArray[np.bool_]
    """S x 2: the end is not a real line end (image edge, field boundary or an object next to it)."""
    circle: tuple[float, float]
    """Robot-frame centre (m) of the centre circle, NaN when it was not found."""
    points: NDArray[np.float64]
    """K x 5 oriented line points: u, v (px), x, y (m, robot frame), direction on the ground
    (rad in [0, pi), robot frame), for debugging."""


def hough_lines(
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    line_width: float,
    circle_radius: float,
    params: HoughParams,
) -> HoughLines:
    """The field lines and the centre circle of one class image (module docstring).

    ``classes``: H x W class image (:class:`~cognition.vision.colour.Colour` codes);
    ``boundary``: first field row per column (W, from :mod:`.boundary`); ``cam``: the camera
    row (:meth:`~cognition.camera.CameraMatrix.as_row`) of the same image size;
    ``line_width``: painted line width (m); ``circle_radius``: centre circle radius (m, 0 when
    the field has none). Raises ``ValueError`` on input of the wrong shape, type or size.
    """
    classes, boundary, cam = _check(classes, boundary, cam, line_width, circle_radius, params)
    seg, ground, open_ends, circle, pts = _hough_nb(
        classes, boundary, cam, float(line_width), float(circle_radius), _config(params, classes.shape[1])
    )
    return HoughLines(seg, ground, open_ends, (float(circle[0]), float(circle[1])), pts)


def _check(
    classes: object, boundary: object, cam: object, line_width: float, circle_radius: float, params: object
) -> tuple[NDArray[np.uint8], NDArray[np.int32], NDArray[np.float64]]:
    """The inputs as the compiled code takes them, or a ``ValueError`` (``TypeError`` for params)."""
    if not isinstance(params, HoughParams):
        raise TypeError(f"params must be HoughParams, got {type(params).__name__}")
    if not isinstance(classes, np.ndarray) or classes.dtype != np.uint8 or classes.ndim != 2:
        what = f"{classes.dtype} array of shape {classes.shape}" if isinstance(classes, np.ndarray) else type(classes)
        raise ValueError(f"classes must be an H x W uint8 class image, got {what}")
    height, width = classes.shape
    if height < 8 or width < 8:
        raise ValueError(f"classes must be at least 8 x 8 pixels, got {height} x {width}")
    b = boundary if isinstance(boundary, np.ndarray) else np.asarray(boundary)
    if b.shape != (width,) or b.dtype.kind not in "iu":
        raise ValueError(f"boundary must hold one integer row per image column ({width}), got {b.dtype} {b.shape}")
    c = cam if isinstance(cam, np.ndarray) and cam.dtype == np.float64 else np.asarray(cam, dtype=np.float64)
    if c.shape != (18,) or not math.isfinite(float(c.sum())):
        raise ValueError(f"cam must be a finite camera row of 18 numbers (CameraMatrix.as_row()), got shape {c.shape}")
    if int(c[16]) != width or int(c[17]) != height:
        raise ValueError(f"the camera is {int(c[16])} x {int(c[17])} pixels, the class image {width} x {height}")
    if not (math.isfinite(line_width) and 0.0 < line_width <= 1.0):
        raise ValueError(f"line_width must be in (0, 1] m, got {line_width!r}")
    if not (math.isfinite(circle_radius) and 0.0 <= circle_radius <= 10.0):
        raise ValueError(f"circle_radius must be in [0, 10] m (0: no circle), got {circle_radius!r}")
    if not classes.flags.c_contiguous:
        classes = np.ascontiguousarray(classes)
    if b.dtype != np.int32 or not b.flags.c_contiguous:
        b = np.ascontiguousarray(b, dtype=np.int32)
    if not c.flags.c_contiguous:
        c = np.ascontiguousarray(c)
    return classes, b, c


_FIELDS = tuple(f.name for f in dataclasses.fields(HoughParams))
"""The parameters in the order of the compiled configuration row (the dataclass order)."""
_PIXELS = ("scan_step", "kernel_small", "kernel_large", "size_switch", "edge_gap", "merge_radius", "gap", "end_probe")
"""Pixel sizes (given at 320 px width, scaled with the image)."""
_ROUNDED = ("scan_step", "edge_gap", "end_probe")


@functools.lru_cache(maxsize=64)
def _config(params: HoughParams, width: int) -> NDArray[np.float64]:
    """The compiled functions' configuration row for ``params`` at an image ``width`` (px)."""
    scale = width / 320.0
    row = []
    for name in _FIELDS:
        value = float(getattr(params, name))
        if name in _PIXELS:
            value *= scale
        if name in _ROUNDED:
            value = float(max(1, round(value)))
        row.append(value)
    out = np.array(row)
    out.flags.writeable = False
    return out


@nb.njit(cache=True, error_model="python", fastmath=False)
def _hough_nb(
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    line_width: float,
    circle_radius: float,
    cfg: NDArray[np.float64],
) -> tuple:  # pragma: no cover - compiled
    """All five steps (module docstring) with the parameters ``cfg`` (:data:`_FIELDS` order);
    returns seg_px, seg_ground, open_ends, circle centre, points."""
    height, width = classes.shape
    (
        step, n_orient, k_small, k_large, switch, min_response, min_width, edge, merge_radius, merge_angle,
        theta_bin, rho_bin, position_error, vote_spread, max_uncertainty, orientation_tolerance, min_votes, max_lines,
        support_distance, support_pixels, support_angle, gap, min_white, min_points, min_line_length, max_distance,
        probe, circle_cell, circle_inlier, circle_tangent, circle_min_points, circle_min_span, circle_min_coverage,
    ) = cfg  # the HoughParams fields in their order (_FIELDS)  # fmt: skip
    step, n_orient, edge, max_lines = int(step), int(n_orient), int(edge), int(max_lines)
    min_points, probe, circle_min_points = int(min_points), int(probe), int(circle_min_points)
    pts = _line_points(
        classes, boundary, cam, line_width, step, n_orient, k_small, k_large, switch, min_response, max_distance, edge,
        min_width,
    )  # fmt: skip
    n = pts.shape[0]
    labels = np.full(n, -1, dtype=np.int64)
    segs = _merge(pts, cam, width, height, merge_radius, merge_angle, position_error, labels)
    ns = segs.shape[0]
    # 3. the centre circle, and its segments and points out of the way
    cx, cy = math.nan, math.nan
    if circle_radius > 0.0 and ns >= 3:
        cx, cy = _circle(segs, circle_radius, circle_cell, circle_inlier, circle_tangent, circle_min_points,
                         circle_min_span)  # fmt: skip
        if math.isfinite(cx):
            seen, share = verify_circle_nb(classes, boundary, cam, cx, cy, circle_radius, 64)
            if seen < 16 or share < circle_min_coverage:  # a quarter of it in view, mostly on white (as DNT)
                cx, cy = math.nan, math.nan
    seg_free = np.ones(ns, dtype=np.bool_)
    free = np.ones(n, dtype=np.bool_)
    if math.isfinite(cx):
        for k in range(ns):
            if _on_ring(segs[k, _SX], segs[k, _SY], segs[k, _SPHI], cx, cy, circle_radius, circle_inlier,
                        circle_tangent):  # fmt: skip
                seg_free[k] = False
        for p in range(n):
            if not seg_free[labels[p]] or _on_ring(
                pts[p, _X], pts[p, _Y], pts[p, _PHI], cx, cy, circle_radius, circle_inlier, circle_tangent
            ):
                free[p] = False
    # 4. oriented votes, main orientation (eq. 3)
    n_theta = 2 * max(1, round(0.5 * math.pi / theta_bin))
    tb = math.pi / n_theta
    half_rho = math.ceil(max_distance / rho_bin) + 1
    acc = np.zeros((n_theta, 2 * half_rho + 1))
    # NimbRo's epsilon; a direction less certain than that votes over its uncertainty (and only
    # after the main orientation is found), one too uncertain does not vote
    spread = np.full(ns, -1, dtype=np.int64)
    for k in range(ns):
        if segs[k, _SUNC] <= vote_spread:
            spread[k] = round(vote_spread / tb)
        elif segs[k, _SUNC] <= max_uncertainty:
            spread[k] = math.ceil(segs[k, _SUNC] / tb)
    for k in range(ns):
        if seg_free[k] and segs[k, _SUNC] <= vote_spread:
            _vote(acc, segs[k, _SX], segs[k, _SY], segs[k, _SPHI], segs[k, _SW], tb, rho_bin, spread[k])
    quarter = n_theta // 2
    best_alpha = 0
    best_sum = -1.0
    for i in range(quarter):
        s = np.sum(acc[i]) + np.sum(acc[i + quarter])
        if s > best_sum:
            best_sum, best_alpha = s, i
    for k in range(ns):
        if seg_free[k] and vote_spread < segs[k, _SUNC] <= max_uncertainty:
            _vote(acc, segs[k, _SX], segs[k, _SY], segs[k, _SPHI], segs[k, _SW], tb, rho_bin, spread[k])
    tol_bins = round(orientation_tolerance / tb)
    # 5. peaks -> lines -> segments
    max_seg = 2 * max_lines * 8
    seg = np.zeros((max_seg, 4))
    n_seg = 0
    idx = np.empty(n, dtype=np.int64)
    along = np.empty(n)
    still = np.zeros(ns, dtype=np.int64)  # free points per short segment
    for p in range(n):
        if free[p]:
            still[labels[p]] += 1
    strip = np.empty((2 * tol_bins + 3, acc.shape[1]))
    for o in range(2):
        centre = best_alpha + o * quarter
        found = 0
        for _ in range(6 * max_lines):
            if found >= max_lines:
                break
            _strip(acc, centre - tol_bins - 1, strip)
            best, bi, bj = _peak(strip)
            if bj < 0 or best < min_votes:
                break
            bi += centre - tol_bins - 1  # the angle index
            theta = bi * tb
            rho = (bj - half_rho) * rho_bin
            nx, ny = math.cos(theta), math.sin(theta)
            m = _support(pts, free, nx, ny, rho, support_distance, support_pixels, support_angle, idx)
            for _ in range(2):
                if m < 2:
                    break
                nx, ny, rho = _fit(pts, idx, m, support_pixels, support_distance)
                m = _support(pts, free, nx, ny, rho, support_distance, support_pixels, support_angle, idx)
            # the votes of these points' short segments are explained: take them away
            taken = 0
            for k in range(m):
                p = idx[k]
                free[p] = False
                g = labels[p]
                still[g] -= 1
                if seg_free[g] and 2 * still[g] < segs[g, _SN]:
                    seg_free[g] = False
                    if spread[g] < 0:
                        continue
                    taken += 1
                    _vote(acc, segs[g, _SX], segs[g, _SY], segs[g, _SPHI], -segs[g, _SW], tb, rho_bin, spread[g])
            if taken == 0:  # nothing explained: clear the peak so that the search moves on
                for di in range(-1, 2):
                    for dj in range(-1, 2):
                        r, c = _wrapped(acc, bi + di, bj + dj)
                        if 0 <= c < acc.shape[1]:
                            acc[r, c] = 0.0
            if m < min_points:
                continue
            # order along the line, split at gaps that are not white
            tx, ty = -ny, nx
            for k in range(m):
                along[k] = pts[idx[k], _X] * tx + pts[idx[k], _Y] * ty
            order = np.argsort(along[:m])
            start = 0
            made = False
            for k in range(1, m + 1):
                split = k == m
                if not split:
                    a, b = idx[order[k - 1]], idx[order[k]]
                    du, dv = pts[b, _U] - pts[a, _U], pts[b, _V] - pts[a, _V]
                    if du * du + dv * dv > gap * gap:
                        split = white_ratio_nb(classes, pts[a, _U], pts[a, _V], pts[b, _U], pts[b, _V]) < min_white
                if not split:
                    continue
                if k - start >= min_points and n_seg < max_seg:
                    t0, t1 = along[order[start]], along[order[k - 1]]
                    u1, v1, ok1 = pixel_nb(cam, rho * nx + t0 * tx, rho * ny + t0 * ty, 0.0)
                    u2, v2, ok2 = pixel_nb(cam, rho * nx + t1 * tx, rho * ny + t1 * ty, 0.0)
                    if ok1 and ok2:
                        seg[n_seg, 0], seg[n_seg, 1], seg[n_seg, 2], seg[n_seg, 3] = u1, v1, u2, v2
                        n_seg += 1
                        made = True
                start = k
            if made:
                found += 1
    # ends: followed along the white and classed (the DNT rules); a segment that the white leads
    # beyond max_distance is cut there (that end open) rather than dropped
    seg_px, seg_ground, open_ends, _ = segments_on_ground_nb(
        cam, seg[:n_seg], classes, boundary, min_line_length, 1e6, probe
    )
    seg_px, seg_ground, open_ends = _clip(seg_px, seg_ground, open_ends, cam, max_distance, min_line_length)
    out_pts = np.empty((n, 5))
    for p in range(n):
        out_pts[p, 0] = pts[p, _U]
        out_pts[p, 1] = pts[p, _V]
        out_pts[p, 2] = pts[p, _X]
        out_pts[p, 3] = pts[p, _Y]
        out_pts[p, 4] = pts[p, _PHI]
    return seg_px, seg_ground, open_ends, (cx, cy), out_pts
