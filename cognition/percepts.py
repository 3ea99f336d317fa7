"""Percepts: what the vision of one robot reports for one camera image.

This is the output of vision (CMU paper, section II: vision features give robot-relative
coordinates of detected objects) and the input of localization and the world model. The
simulator synthesizes it directly (fast path); an image-based vision module produces the
same type.

Every percept is a row of a float table with the columns of :class:`Col`; a
:class:`Percepts` holds one table per :class:`Kind` and wraps them in typed views
(:class:`PerceptTable`) whose properties return numpy arrays, ready for vectorized filters.
:meth:`Percepts.records` gives the same content as small dataclasses for reading and
debugging.

Measurement model (Darmstadt paper, section IV.B, eqs. 3-15): each measured position
follows from two noisy viewing angles of the camera, ``alpha`` around the pitch axis
(depression below the horizontal) and ``beta`` around the yaw axis (bearing). Each row
carries the two angular sigmas and the 2 x 2 position covariance they imply (eq. 8 for the
distance, eq. 12 sideways, rotated by the bearing, eqs. 13-15).

Frames: positions ``x, y`` are in the **robot frame** (m, origin between the feet, +x
forward, +y left); orientations are robot-frame angles (rad); ``u, v`` are pixels of the
camera named in the camera matrix (see :mod:`cognition.camera`).

======  ============  =====================================================================
kind    subtype       geometry in the row
======  ============  =====================================================================
POST    PostSide      ``x, y`` base of the post; ``u, v`` base pixel; ``u2, v2`` top pixel;
                      ``goal`` 0 own / 1 opponent when goals have different colours, else -1
CROSS   0 L, 1 T, 2 X ``x, y`` junction; ``orientation`` as in :class:`cognition.field.LineCrossing`
LINE    0             end points ``(x, y)`` and ``(x2, y2)``; pixels ``(u, v)``, ``(u2, v2)``;
                      ``orientation`` direction in [0, pi); covariance at the point nearest
                      the robot
CIRCLE  0             ``x, y`` centre of the centre circle
MARK    0             ``x, y`` penalty mark
BALL    0             ``x, y`` ball on the ground (projection); ``radius_px`` image radius
ROBOT   RobotTeam     ``x, y`` robot centre on the ground
POLE    0             ``x, y`` corner pole base (KidSize field)
======  ============  =====================================================================

``truth`` is the ground-truth id of the landmark or object (index into the robot's own
field map: ``Field.goal_posts``, ``crossings``, ``lines``, ``penalty_marks``,
``corner_poles``; 0 for the circle and the ball; ``team * players + number - 1`` for
robots, team 0 being the observer's team), -1 for a false positive. It exists for
evaluation only: a brain must never read it.

**Validation.** Percepts come from the simulator, from vision, from logs and from users, so
:class:`Percepts` checks its input when it is built and raises :class:`PerceptError` (a
``ValueError``) naming the row, kind and column of the first bad entry. Every row needs a
finite ``x, y``, finite covariance entries with ``var_xx, var_yy >= 0``, finite angular
sigmas ``>= 0`` and an integer ``subtype`` in its kind's range (post side 0..2, crossing
kind 0..2, robot team 0..2, 0 for the other kinds); posts need ``goal`` in {-1, 0, 1},
crossings a finite ``orientation``, lines finite end points ``x2, y2``, balls a
``radius_px`` that is NaN (unknown) or finite and ``>= 0``. Pixels and ``truth`` are not
checked (pixels may be NaN when a log has none). The offsets must describe the kinds'
row ranges inside the table, in :class:`Kind` order.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.camera import CAMERA_ROW_SIZE, CameraMatrix, CameraSpec, CameraView, camera_view
from cognition.percept_checks import (
    _RULES,
    _SUBTYPE_MAX,
    _all_finite_nb,
    _first_invalid_many_nb,
    _first_invalid_nb,
    _offsets_ok_nb,
)
from cognition.percept_layout import N_COLS as N_COLS
from cognition.percept_layout import N_KINDS as N_KINDS
from cognition.percept_layout import Col as Col
from cognition.percept_layout import Kind as Kind
from cognition.percept_layout import PerceptTable as PerceptTable
from cognition.percept_layout import PostSide as PostSide
from cognition.percept_layout import RobotTeam as RobotTeam

_EMPTY = np.zeros((0, N_COLS))
_EMPTY.setflags(write=False)
_NO_OFFSETS = np.zeros(N_KINDS + 1, dtype=np.int64)
_NO_OFFSETS.setflags(write=False)


class PerceptError(ValueError):
    """Percepts that a consumer cannot use (non-finite values, unknown types, bad shapes)."""


def _row_error(rows: NDArray[np.float64], offsets: NDArray[np.int64], r: int, c: int, rule: int) -> str:
    """The message of an invalid entry ``rows[r, c]`` (rule: index into :data:`_RULES`)."""
    kind = Kind(int(np.searchsorted(offsets, r, side="right") - 1))
    text = _RULES[rule].format(top=int(_SUBTYPE_MAX[kind]))
    return (
        f"Percepts row {r - int(offsets[0])} ({kind.name} #{r - int(offsets[kind])}): "
        f"{Col(c).name.lower()} {text}, got {float(rows[r, c])!r}"
    )


def _check_table(time: float, rows: NDArray[np.float64]) -> None:
    """Raise :class:`PerceptError` unless ``time`` is a finite number and ``rows`` a row table."""
    if type(time) is not float and (
        isinstance(time, bool) or not isinstance(time, int | float | np.floating | np.integer)
    ):  # (the common case, a Python float, skips the slow isinstance on a union)
        raise PerceptError(f"Percepts.time must be a finite number (s), got {time!r}")
    if not math.isfinite(time):
        raise PerceptError(f"Percepts.time must be a finite number (s), got {time!r}")
    if not isinstance(rows, np.ndarray) or rows.dtype != np.float64 or rows.ndim != 2 or rows.shape[1] != N_COLS:
        got = f"{rows.dtype} array of shape {rows.shape}" if isinstance(rows, np.ndarray) else type(rows).__name__
        raise PerceptError(f"Percepts rows must be a float64 array of shape (n, {N_COLS}), got {got}")


def _check(
    time: float,
    rows: NDArray[np.float64],
    offsets: NDArray[np.int64],
    camera_row: NDArray[np.float64] | None,
    spec: CameraSpec | None,
) -> None:
    """Raise :class:`PerceptError` unless the arguments of :class:`Percepts` are usable."""
    _check_table(time, rows)
    if (
        not isinstance(offsets, np.ndarray)
        or offsets.dtype.kind not in "iu"
        or offsets.shape != (N_KINDS + 1,)
        or not _offsets_ok_nb(offsets.astype(np.int64, copy=False), rows.shape[0])
    ):
        raise PerceptError(
            f"Percepts offsets must be {N_KINDS + 1} non-decreasing integers within the {rows.shape[0]} rows "
            f"(kind k is rows[offsets[k]:offsets[k + 1]]), got {offsets!r}"
        )
    if (camera_row is None) != (spec is None):
        raise PerceptError("Percepts need both a camera row and a camera spec, or neither")
    if camera_row is not None:
        cam = camera_row if type(camera_row) is np.ndarray else np.asarray(camera_row)
        if cam.shape != (CAMERA_ROW_SIZE,) or cam.dtype.kind != "f" or not _all_finite_nb(cam.astype(np.float64)):
            raise PerceptError(f"Percepts camera row must hold {CAMERA_ROW_SIZE} finite numbers, got {camera_row!r}")
        if not isinstance(spec, CameraSpec):
            raise PerceptError(f"Percepts camera spec must be a CameraSpec, got {type(spec).__name__}")
    r, c, rule = _first_invalid_nb(rows, offsets.astype(np.int64, copy=False), _SUBTYPE_MAX)
    if r >= 0:
        raise PerceptError(_row_error(rows, offsets, r, c, rule))


class Percepts:
    """Everything vision reported for one image of one robot.

    ``time`` is when the image was taken (s since match start); with latency it lies before
    the sensor frame that delivers it. ``camera`` is the camera matrix of that image.
    """

    __slots__ = ("_bounds", "_camera", "_camera_row", "_offsets", "_rows", "_spec", "_view", "time")

    def __init__(
        self,
        time: float,
        rows: NDArray[np.float64],
        offsets: NDArray[np.int64],
        camera_row: NDArray[np.float64] | None,
        spec: CameraSpec | None,
    ):
        _check(time, rows, offsets, camera_row, spec)
        self.time = time
        self._rows = rows
        self._offsets = offsets
        self._camera_row = camera_row
        self._spec = spec
        self._camera: CameraMatrix | None = None
        self._view: CameraView | None = None
        self._bounds: list[int] | None = None

    @classmethod
    def empty(cls, time: float = 0.0) -> Percepts:
        """No percepts (camera not usable: fallen, picked up, off the field)."""
        return cls(time, _EMPTY, _NO_OFFSETS, None, None)

    @classmethod
    def of_checked_rows(
        cls,
        time: float,
        rows: NDArray[np.float64],
        offsets: NDArray[np.int64],
        camera_row: NDArray[np.float64],
        spec: CameraSpec,
    ) -> Percepts:
        """The constructor for a producer that guarantees what its checks verify of ``rows``,
        ``offsets`` and ``camera_row`` (vision's compiled pipeline runs them, ``_first_invalid_nb``
        included); a ``time`` that is not a finite float or a ``spec`` that is not a CameraSpec
        goes through the full checks."""
        if type(time) is not float or not math.isfinite(time) or type(spec) is not CameraSpec:
            return cls(time, rows, offsets, camera_row, spec)
        self = cls.__new__(cls)
        self.time, self._rows, self._offsets, self._camera_row, self._spec = time, rows, offsets, camera_row, spec
        self._camera = self._view = self._bounds = None
        return self

    @classmethod
    def many(
        cls,
        time: float,
        rows: NDArray[np.float64],
        offsets: NDArray[np.int64],
        camera_rows: NDArray[np.float64],
        specs: Sequence[CameraSpec | None],
    ) -> list[Percepts]:
        """The percepts of many images whose rows share one table: image ``i`` has the kinds of
        ``offsets[i]`` (``offsets``: one row of N_KINDS + 1 per image), the camera row
        ``camera_rows[i]`` and the camera ``specs[i]``; a spec of ``None`` gives
        :meth:`empty` percepts (no image). The constructor's checks run once for all images, in
        one compiled pass (a percept synthesizer's frame of every robot), and a failure is a
        :class:`PerceptError` that names the image."""
        n = len(specs)
        if not isinstance(offsets, np.ndarray) or offsets.dtype != np.int64 or offsets.shape != (n, N_KINDS + 1):
            raise PerceptError(f"Percepts.many offsets must be an int64 array of shape ({n}, {N_KINDS + 1})")
        if (
            not isinstance(camera_rows, np.ndarray)
            or camera_rows.dtype != np.float64
            or camera_rows.shape != (n, CAMERA_ROW_SIZE)
        ):
            raise PerceptError(f"Percepts.many camera rows must be a float64 array of shape ({n}, {CAMERA_ROW_SIZE})")
        has = np.array([spec is not None for spec in specs], dtype=np.bool_)
        for i, spec in enumerate(specs):
            if spec is not None and type(spec) is not CameraSpec:
                raise PerceptError(f"Percepts.many image {i}: camera spec must be a CameraSpec, got {spec!r}")
        _check_table(time, rows)
        i, what, r, c, rule = _first_invalid_many_nb(rows, offsets, camera_rows, has, _SUBTYPE_MAX)
        if i >= 0:
            if what == 0:
                problem = f"offsets {offsets[i]!r} are not {N_KINDS + 1} non-decreasing integers within the rows"
            elif what == 1:
                problem = f"camera row must hold {CAMERA_ROW_SIZE} finite numbers, got {camera_rows[i]!r}"
            else:
                problem = _row_error(rows, offsets[i], r, c, rule)
            raise PerceptError(f"Percepts.many image {i}: {problem}")
        return [
            cls.empty(time) if spec is None else cls.of_checked_rows(time, rows, offsets[i], camera_rows[i], spec)
            for i, spec in enumerate(specs)
        ]

    @property
    def camera(self) -> CameraMatrix | None:
        """The camera matrix of the image (``None`` when no image was taken)."""
        if self._camera is None:
            r = self._checked_camera_row()
            if r is not None:
                self._camera = CameraMatrix(r[:9].reshape(3, 3).copy(), r[9:12].copy(), self._spec)  # type: ignore[arg-type]
        return self._camera

    @property
    def camera_view(self) -> CameraView | None:
        """The camera matrix of the image as Python floats (:func:`~cognition.camera.camera_view`,
        the same numbers as :attr:`camera`'s arrays; ``None`` when no image was taken), without
        building the matrix: the world model's single-point questions (where the camera's foot is,
        whether a point is in view: :func:`~cognition.camera.view_sees`) ask for it every frame."""
        view = self._view
        if view is None:
            r = self._checked_camera_row()
            if r is not None:
                row = r.tolist()
                view = self._view = camera_view(row[:9], row[9:12], self._spec)  # type: ignore[arg-type]
        return view

    def _checked_camera_row(self) -> NDArray[np.float64] | None:
        """The camera row of the image (``None`` when no image was taken), for :attr:`camera` and
        :attr:`camera_view`."""
        r = self._camera_row
        if r is None or self._spec is None:
            return None
        if r.shape[0] != CAMERA_ROW_SIZE:
            raise ValueError(f"camera row must have {CAMERA_ROW_SIZE} entries, got {r.shape[0]}")
        return r

    @property
    def rows(self) -> NDArray[np.float64]:
        """All rows of this robot's image, grouped by kind in :class:`Kind` order."""
        o = self._offsets
        return self._rows[o[0] : o[-1]]

    @property
    def table_and_offsets(self) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
        """The underlying row table (possibly shared with other robots' percepts) and the
        offsets of this image's kinds in it: kind k is ``table[offsets[k]:offsets[k + 1]]``.
        For compiled consumers that avoid per-kind views."""
        return self._rows, self._offsets

    def span(self, kind: int) -> tuple[int, int]:
        """Where the rows of one :class:`Kind` lie in the table of :attr:`table_and_offsets`:
        ``table[lo:hi]``, as Python ints (the offsets are read into a list once per image, for
        the world model's modules that each ask for one kind every frame)."""
        bounds = self._bounds
        if bounds is None:
            bounds = self._bounds = self._offsets.tolist()
        return bounds[kind], bounds[kind + 1]

    @property
    def kinds(self) -> NDArray[np.int64]:
        """The :class:`Kind` of every row of :attr:`rows`."""
        return np.repeat(np.arange(N_KINDS), np.diff(self._offsets))

    def table(self, kind: Kind) -> PerceptTable:
        """The rows of one kind."""
        o = self._offsets
        return PerceptTable(kind, self._rows[o[kind] : o[kind + 1]])

    def count(self, kind: Kind) -> int:
        """Number of percepts of one kind."""
        return int(self._offsets[kind + 1] - self._offsets[kind])

    def __len__(self) -> int:
        return int(self._offsets[-1] - self._offsets[0])

    @property
    def posts(self) -> PerceptTable:
        return self.table(Kind.POST)

    @property
    def crossings(self) -> PerceptTable:
        return self.table(Kind.CROSS)

    @property
    def lines(self) -> PerceptTable:
        return self.table(Kind.LINE)

    @property
    def circle(self) -> PerceptTable:
        return self.table(Kind.CIRCLE)

    @property
    def penalty_marks(self) -> PerceptTable:
        return self.table(Kind.MARK)

    @property
    def ball(self) -> PerceptTable:
        """Ball percepts (usually 0 or 1; false positives can add more)."""
        return self.table(Kind.BALL)

    @property
    def robots(self) -> PerceptTable:
        return self.table(Kind.ROBOT)

    @property
    def poles(self) -> PerceptTable:
        return self.table(Kind.POLE)

    def ball_distance_from_size(self, ball_radius: float) -> NDArray[np.float64]:
        """Distances (m, from the optical centre) implied by the ball percepts' image radii.

        Uses the pinhole relation ``radius_px = f * r / sqrt(D^2 - r^2)`` with the mean focal
        length; ``ball_radius`` is the true ball radius (m, from the field map).
        """
        cam = self.camera
        rad = self.ball.radius_px
        if cam is None or len(rad) == 0:
            return np.zeros(0)
        f = 0.5 * (cam.spec.fx + cam.spec.fy)
        with np.errstate(divide="ignore"):
            return ball_radius * np.sqrt(1.0 + (f / rad) ** 2)

    def records(self) -> list[Any]:
        """All percepts as dataclass records (slow; for reading, tests and debugging)."""
        out: list[Any] = []
        for kind in Kind:
            for r in self.table(kind).rows:
                out.append(_record(kind, r))
        return out

    def __repr__(self) -> str:
        counts = ", ".join(f"{k.name.lower()}={self.count(k)}" for k in Kind if self.count(k))
        return f"Percepts(t={self.time:.3f}, {counts or 'none'})"


@dataclass(frozen=True)
class PerceptRecord:
    """One percept as a record (robot frame, metres, radians, pixels)."""

    kind: Kind
    x: float
    y: float
    u: float
    v: float
    subtype: int
    orientation: float
    x2: float
    y2: float
    u2: float
    v2: float
    cov: tuple[float, float, float]
    """(var_xx, var_xy, var_yy) in m^2."""
    sigma_alpha: float
    sigma_beta: float
    radius_px: float
    goal: int
    truth: int
    """Ground-truth id (evaluation only)."""

    @property
    def distance(self) -> float:
        return math.hypot(self.x, self.y)

    @property
    def bearing(self) -> float:
        return math.atan2(self.y, self.x)


def _record(kind: Kind, r: NDArray[np.float64]) -> PerceptRecord:
    return PerceptRecord(
        kind=kind,
        x=float(r[Col.X]),
        y=float(r[Col.Y]),
        u=float(r[Col.U]),
        v=float(r[Col.V]),
        subtype=int(r[Col.SUBTYPE]),
        orientation=float(r[Col.ORIENTATION]),
        x2=float(r[Col.X2]),
        y2=float(r[Col.Y2]),
        u2=float(r[Col.U2]),
        v2=float(r[Col.V2]),
        cov=(float(r[Col.VAR_XX]), float(r[Col.VAR_XY]), float(r[Col.VAR_YY])),
        sigma_alpha=float(r[Col.SIGMA_ALPHA]),
        sigma_beta=float(r[Col.SIGMA_BETA]),
        radius_px=float(r[Col.RADIUS_PX]),
        goal=int(r[Col.GOAL]),
        truth=int(r[Col.TRUTH]),
    )


def measurement_covariance(
    x: float, y: float, camera_x: float, camera_y: float, height: float, sigma_alpha: float, sigma_beta: float
) -> tuple[float, float, float]:
    """Covariance (var_xx, var_xy, var_yy; m^2, robot frame) of a point measured via angles.

    Darmstadt eqs. 8 and 12-15: distance sigma from the pitch-angle sigma, sideways sigma from
    the yaw-angle sigma, rotated by the bearing. ``(x, y)`` is the measured point and
    ``(camera_x, camera_y)`` the optical centre's ground position; ``height`` is the camera's
    height above the point (m).
    """
    return covariance_nb(x, y, camera_x, camera_y, height, sigma_alpha, sigma_beta)


@nb.njit(cache=True, error_model="python", fastmath=False)
def covariance_nb(
    x: float, y: float, cx: float, cy: float, h: float, sa: float, sb: float
) -> tuple[float, float, float]:  # pragma: no cover - compiled
    """Compiled body of :func:`measurement_covariance`."""
    dx, dy = x - cx, y - cy
    d = math.hypot(dx, dy)
    alpha = math.atan2(h, d)
    # eq. 8 (the nearer side: tan(alpha + sigma) stays finite for points near the horizon)
    sd = abs(h / math.tan(alpha) - h / math.tan(min(alpha + sa, 0.5 * math.pi - 1e-9)))
    sy = math.tan(sb) * d  # eq. 12
    b = math.atan2(dy, dx)
    c, s = math.cos(b), math.sin(b)
    a, e = sd * sd, sy * sy  # R_base = diag(a, e), eq. 13; rotated, eqs. 14-15
    return (c * c * a + s * s * e, c * s * (a - e), s * s * a + c * c * e)
