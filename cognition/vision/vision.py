"""The vision pipeline: one camera image and its camera matrix in, :class:`Percepts` out.

The stages follow DNT's basic pipeline (section 3.2) with the detectors of both vision
papers, one module per stage:

==================  ===============================================  ==========================
stage               module                                           paper
==================  ===============================================  ==========================
image input         :mod:`.image` (RGB or YUV422, checks)            DNT 3.3
colour classes      :mod:`.colour` (HSV, calibrated, lookup table)   DNT 3.1, 3.5, Table 1
field boundary      :mod:`.boundary`                                 DNT 3.4
line points         :mod:`.scanlines` (method ``dnt``)               DNT 3.6.2
                    :mod:`.hough` (method ``hough``)                 NimbRo 5.1
centre circle       :mod:`.circle` (voting at the radius)            NimbRo 5.2, de Jong et al.
line segments       :mod:`.segments` (chaining, merging)             DNT 3.6.2, Algorithm 1
                    :mod:`.hough` (oriented Hough transform)         NimbRo 5.2
crossings L/T/X     :mod:`.crossings`                                DNT 3.7
goal posts          :mod:`.posts`                                    DNT 3.8
ball, robots        :mod:`.ball`, :mod:`.robots`                     NimbRo 6.1 (colour blobs)
penalty marks       :mod:`.marks`
ground projection   :mod:`.projection` (Darmstadt covariance)        DNT 3.10, Darmstadt IV.B
bird's-eye view     :mod:`.birdseye` (debug image)                   DNT 3.10
==================  ===============================================  ==========================

The result is the same :class:`~cognition.percepts.Percepts` the simulator synthesizes:
robot-frame positions (m), pixels, covariances from the Darmstadt noise model with the same
defaults, and ``truth`` -1 (vision does not know which landmark it saw). Everything after
the percepts (localization, world model, behaviors) runs unchanged on either source.

``Vision`` keeps state only for the colour calibration (a cache of lookup tables and the
latest carpet colour); one instance per camera stream.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.camera import CameraMatrix
from cognition.field import FIELD_PRESETS, ColourScheme, Field, make_colour_scheme
from cognition.percepts import N_COLS, N_KINDS, Col, Kind, Percepts
from cognition.vision.boundary import field_boundary
from cognition.vision.circle import find_circle_nb, verify_circle_nb
from cognition.vision.colour import ColourClassifier
from cognition.vision.crossings import crossings_nb
from cognition.vision.image import as_rgb, check_camera
from cognition.vision.marks import marks_nb
from cognition.vision.params import VisionParams
from cognition.vision.projection import ground_nb, pixel_nb, sigmas
from cognition.vision.rows import line_rows_nb, point_rows_nb
from cognition.vision.scanlines import line_points_nb
from cognition.vision.segments import segments_nb


@dataclass(frozen=True, eq=False)
class VisionDebug:
    """Intermediate results of the latest :meth:`Vision.detect` (for drawing and tests)."""

    classes: NDArray[np.uint8]
    """Class image (H x W, :class:`~cognition.vision.colour.Colour` codes)."""
    boundary: NDArray[np.int32]
    """First field row per column."""
    points: NDArray[np.float64]
    """Line points (K x 4: u, v, run, direction) of the ``dnt`` method."""
    segments_px: NDArray[np.float64]
    """Line segments in the image (S x 4: u1, v1, u2, v2)."""
    segments_ground: NDArray[np.float64]
    """The same on the ground (S x 4, robot frame, m)."""


class Vision:
    """Detects percepts in camera images (module docstring).

    ``field`` gives the sizes vision expects (line width, circle radius, mark, post and ball
    sizes; default: the 2025 SPL field) and ``scheme`` the colours of goals, ball and jerseys
    (a :class:`ColourScheme` or its name); ``team`` is the own team's jersey index in the
    scheme (0 or 1) for the robots' team guess.
    """

    def __init__(
        self,
        params: VisionParams | None = None,
        field: Field | None = None,
        scheme: ColourScheme | str = "modern",
        team: int = 0,
    ):
        self.params = params or VisionParams()
        if not isinstance(self.params, VisionParams):
            raise TypeError(f"params must be VisionParams, got {type(self.params).__name__}")
        self.field = field or Field(FIELD_PRESETS["spl2025"], "spl2025")
        self.scheme = make_colour_scheme(scheme) if isinstance(scheme, str) else scheme
        if team not in (0, 1):
            raise ValueError(f"team must be 0 or 1 (the jersey index in the colour scheme), got {team!r}")
        self.team = team
        self.classifier = ColourClassifier(self.params.colours)
        self.debug: VisionDebug | None = None
        """Intermediate results of the latest image."""

    def detect(
        self,
        image: NDArray[np.uint8],
        camera: CameraMatrix,
        time: float = 0.0,
        head_yaw_rate: float = 0.0,
        head_pitch_rate: float = 0.0,
        walking: bool = False,
    ) -> Percepts:
        """Percepts of one image (RGB H x W x 3 or YUV422 H x W x 2, uint8) taken with ``camera``.

        ``time`` is the exposure time (s); the head rates (rad/s) and ``walking`` set the
        reported sigmas (Darmstadt eqs. 3-6).
        """
        cam = check_camera(camera)
        rgb = as_rgb(image, camera)
        p = self.params
        height, width = rgb.shape[:2]
        scale = width / 320.0
        classes = self.classifier.classify(rgb, camera)
        boundary = field_boundary(classes, camera, max(1, round(p.boundary_run * height / 240.0)))
        dims = self.field.dims
        step = max(1, round(p.scan_step * scale))
        points = line_points_nb(classes, boundary, cam, step, dims.line_width, max(1, round(p.edge_gap * scale)))
        ground, valid = _ground_points(cam, points, p.max_distance)
        radius = self.field.centre_circle.radius if self.field.centre_circle is not None else 0.0
        circle = (math.nan, math.nan)
        on_circle = np.zeros(len(points), dtype=np.bool_)
        if radius > 0.0:
            cx, cy, _, _ = find_circle_nb(
                ground[valid], radius, p.circle_cell, p.circle_directions, p.circle_inlier,
                p.circle_min_points, p.circle_min_span,
            )  # fmt: skip
            if math.isfinite(cx):
                seen, share = verify_circle_nb(classes, boundary, cam, cx, cy, radius, 64)
                if seen < 8 or share < p.circle_min_coverage:
                    cx = math.nan
            if math.isfinite(cx):
                circle = (cx, cy)
                d = np.hypot(ground[:, 0] - cx, ground[:, 1] - cy)
                on_circle = valid & (np.abs(d - radius) <= 1.5 * p.circle_inlier)
        free = valid & ~on_circle
        idx = np.flatnonzero(free)
        seg_px, labels = segments_nb(
            points[idx], classes, p.chain_gap * scale, p.chain_tolerance * scale, p.min_white, p.min_points,
            p.merge_angle,
        )  # fmt: skip
        seg_px, seg_ground, open_ends = _segments_on_ground(
            cam, seg_px, classes, boundary, p.min_line_length, p.max_distance, max(4, round(12 * scale))
        )
        in_segment = np.zeros(len(points), dtype=np.bool_)
        in_segment[idx[labels >= 0]] = True
        cross = crossings_nb(seg_ground, open_ends, p.crossing_margin, p.crossing_angle, p.crossing_min_arm, 0.3)
        if math.isfinite(circle[0]):
            cross = _circle_crossings(cross, circle, radius, seg_ground, cam, width, height, p.max_distance)
        marks = marks_nb(
            classes, points, free & ~in_segment, cam, dims.penalty_mark_size, p.mark_tolerance, p.mark_min_green
        )
        self.debug = VisionDebug(classes, boundary, points, seg_px[:, :4], seg_ground)
        sa, sb = sigmas(
            p.sigma_alpha_base, p.sigma_beta_base, p.c_tilt, p.c_pan, p.sigma_alpha_moving, p.sigma_beta_moving,
            head_pitch_rate, head_yaw_rate, walking,
        )  # fmt: skip
        tables: list[NDArray[np.float64]] = [_EMPTY] * N_KINDS
        crossing_rows = point_rows_nb(np.ascontiguousarray(cross[:, :2]), _no_pixels(len(cross)), 0.0, cam, sa, sb)
        crossing_rows[:, Col.SUBTYPE] = cross[:, 2]
        crossing_rows[:, Col.ORIENTATION] = cross[:, 3]
        tables[Kind.CROSS] = crossing_rows
        tables[Kind.LINE] = line_rows_nb(seg_px, seg_ground, cam, sa, sb)
        if math.isfinite(circle[0]):
            tables[Kind.CIRCLE] = point_rows_nb(np.array([circle]), _no_pixels(1), 0.0, cam, sa, sb)
        if len(marks):
            xy, ok = _pixels_to_ground(cam, marks[:, :2], 0.0)
            tables[Kind.MARK] = point_rows_nb(xy[ok], np.ascontiguousarray(marks[ok, :2]), 0.0, cam, sa, sb)
        rows = np.concatenate(tables) if any(len(t) for t in tables) else _EMPTY
        offsets = np.zeros(N_KINDS + 1, dtype=np.int64)
        offsets[1:] = np.cumsum([len(t) for t in tables])
        return Percepts(time, rows, offsets, cam, camera.spec)


_EMPTY = np.zeros((0, N_COLS))


def _no_pixels(n: int) -> NDArray[np.float64]:
    """NaN pixels: the row builders project the ground points."""
    return np.full((n, 2), np.nan)


@nb.njit(cache=True)
def _ground_points_nb(
    cam: NDArray[np.float64],
    pts: NDArray[np.float64],
    z: float,
    out: NDArray[np.float64],
) -> None:  # pragma: no cover - compiled
    for k in range(pts.shape[0]):
        x, y, _ = ground_nb(cam, pts[k, 0], pts[k, 1], z)
        out[k, 0] = x
        out[k, 1] = y


def _pixels_to_ground(cam: NDArray[np.float64], uv: NDArray[np.float64], z: float) -> tuple:
    out = np.empty((len(uv), 2))
    _ground_points_nb(cam, np.ascontiguousarray(uv, dtype=np.float64), z, out)
    ok = np.isfinite(out[:, 0])
    return out, ok


def _ground_points(cam: NDArray[np.float64], points: NDArray[np.float64], max_distance: float) -> tuple:
    ground, ok = _pixels_to_ground(cam, points[:, :2] if len(points) else np.zeros((0, 2)), 0.0)
    with np.errstate(invalid="ignore"):
        ok &= np.hypot(ground[:, 0], ground[:, 1]) <= max_distance
    return ground, ok


@nb.njit(cache=True)
def _follow_white(
    classes: NDArray[np.uint8], u: float, v: float, du: float, dv: float, steps: int
) -> tuple[float, float]:  # pragma: no cover - compiled
    """The last point along (du, dv) from (u, v), at most ``steps`` px, that is still white (or
    has a white neighbour across the direction)."""
    height, width = classes.shape
    last_u, last_v = u, v
    for q in range(1, steps + 1):
        cu, cv = u + du * q, v + dv * q
        i, j = int(cu), int(cv)
        if i < 0 or j < 0 or i >= width or j >= height:
            break
        ni, nj = int(cu - dv), int(cv + du)
        mi, mj = int(cu + dv), int(cv - du)
        white = classes[j, i] == 2
        if not white and 0 <= ni < width and 0 <= nj < height:
            white = classes[nj, ni] == 2
        if not white and 0 <= mi < width and 0 <= mj < height:
            white = classes[mj, mi] == 2
        if not white:
            break
        last_u, last_v = cu, cv
    return last_u, last_v


@nb.njit(cache=True)
def _segments_on_ground_nb(
    cam: NDArray[np.float64],
    seg: NDArray[np.float64],
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    min_length: float,
    max_distance: float,
    probe: int,
    extend: int,
    keep: NDArray[np.bool_],
    ground: NDArray[np.float64],
    open_ends: NDArray[np.bool_],
) -> None:  # pragma: no cover - compiled
    height, width = classes.shape
    for k in range(seg.shape[0]):
        u1, v1, u2, v2 = seg[k, 0], seg[k, 1], seg[k, 2], seg[k, 3]
        # the scanlines leave up to a step of white beyond the last point: follow the white
        length = math.hypot(u2 - u1, v2 - v1)
        if length > 1e-9:
            du, dv = (u2 - u1) / length, (v2 - v1) / length
            u1, v1 = _follow_white(classes, u1, v1, -du, -dv, extend)
            u2, v2 = _follow_white(classes, u2, v2, du, dv, extend)
            seg[k, 0], seg[k, 1], seg[k, 2], seg[k, 3] = u1, v1, u2, v2
        x1, y1, ok1 = ground_nb(cam, u1, v1, 0.0)
        x2, y2, ok2 = ground_nb(cam, u2, v2, 0.0)
        keep[k] = (
            ok1 and ok2 and math.hypot(x2 - x1, y2 - y1) >= min_length
            and math.hypot(x1, y1) <= max_distance and math.hypot(x2, y2) <= max_distance
        )  # fmt: skip
        ground[k, 0], ground[k, 1], ground[k, 2], ground[k, 3] = x1, y1, x2, y2
        length = math.hypot(u2 - u1, v2 - v1)
        if length < 1e-9:
            open_ends[k, 0] = open_ends[k, 1] = True
            continue
        du, dv = (u2 - u1) / length, (v2 - v1) / length
        for e in range(2):
            eu, ev, s = (u1, v1, -1.0) if e == 0 else (u2, v2, 1.0)
            # the end is real when carpet follows it; an image edge, the field boundary or an
            # object right after it leaves the true end unknown
            is_open = False
            other = 0
            for q in range(1, probe + 1):
                i = int(eu + s * du * q)
                j = int(ev + s * dv * q)
                if i < 0 or j < 0 or i >= width or j >= height or j < boundary[i] + 2:
                    is_open = True
                    break
                c = classes[j, i]
                if c == 1:
                    break
                other = 0 if c == 2 else other + 1
                if other >= 3:  # three pixels of something else (blended edges give one or two)
                    is_open = True
                    break
            open_ends[k, e] = is_open


def _segments_on_ground(
    cam: NDArray[np.float64],
    seg: NDArray[np.float64],
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    min_length: float,
    max_distance: float,
    probe: int,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
    n = len(seg)
    keep = np.zeros(n, dtype=np.bool_)
    ground = np.zeros((n, 4))
    open_ends = np.zeros((n, 2), dtype=np.bool_)
    if n:
        extend = 2 * probe
        _segments_on_ground_nb(
            cam, seg, classes, boundary, min_length, max_distance, probe, extend, keep, ground, open_ends
        )
    return seg[keep], ground[keep], open_ends[keep]


def _circle_crossings(
    cross: NDArray[np.float64],
    circle: tuple[float, float],
    radius: float,
    seg_ground: NDArray[np.float64],
    cam: NDArray[np.float64],
    width: int,
    height: int,
    max_distance: float,
) -> NDArray[np.float64]:
    """Add the X crossings where a line through the circle's centre (the halfway line) meets it."""
    cx, cy = circle
    extra = []
    for x1, y1, x2, y2 in seg_ground:
        d = np.array([x2 - x1, y2 - y1])
        length = float(np.hypot(*d))
        if length < 0.3:
            continue
        d /= length
        off = abs((cx - x1) * d[1] - (cy - y1) * d[0])
        if off > 0.15:
            continue
        for s in (-1.0, 1.0):
            px, py = cx + s * radius * d[0], cy + s * radius * d[1]
            u, v, ok = pixel_nb(cam, px, py, 0.0)
            if ok and 0 <= u < width and 0 <= v < height and math.hypot(px, py) <= max_distance:
                extra.append((px, py, 2.0, math.atan2(d[1], d[0]) % (0.5 * math.pi), 1.0, 0.0))
        break
    if not extra:
        return cross
    add = np.array(extra)
    keep = np.ones(len(cross), dtype=np.bool_)
    for x, y, *_ in add:  # the circle's X replaces whatever the segments made there
        keep &= np.hypot(cross[:, 0] - x, cross[:, 1] - y) > 0.3
    return np.concatenate([cross[keep], add])
