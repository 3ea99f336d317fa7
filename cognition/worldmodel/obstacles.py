"""Obstacle models (Darmstadt paper, Sec. VII): a robot-centric occupancy grid and 72 sectors.

**Grid** (:class:`ObstacleGrid`, the paper's model in development): log-odds occupancy on a
square grid centred on the robot (robot frame, ``cell`` m per cell). Each frame with an
image:

* cells inside the camera's view (on the ground, within ``view_range``) get the log-odds
  of free space, unless an obstacle percept is near them;
* around each robot percept, cells get occupancy weighted by a Gaussian whose width
  across the line of sight comes from the percept's bearing sigma (sigma_beta d, Darmstadt
  eqs. 3-4, 12) and along it from its distance sigma (eq. 8's projection with
  sigma_alpha), like an ultrasonic sensor model;
* log-odds are clamped to +-``clamp`` and decay toward 0 (unknown) with time.

Odometry moves the grid: the map is resampled into the new robot frame (nearest cell), so
a map survives turning and walking, with the smear of the discretisation.

**Sectors** (:class:`ObstacleSectors`, the model the Darmstadt robots used in 2009-2010):
the distance to the nearest obstacle in each of 72 five-degree sectors around the robot,
set by robot percepts, moved approximately with odometry, forgotten after ``memory`` s; no
free space, no uncertainty.

Both output :class:`ObstacleModel`: obstacle positions (robot frame, m) and, for the grid,
the occupancy probability map.

====================  =======  =============  ===================================================
ObstacleGridParams    default  range          meaning
====================  =======  =============  ===================================================
extent                3.0      (0, 50]        half width of the square grid (m)
cell                  0.1      (0, 10]        cell size (m); 2 extent / cell is 1 to 500 cells
view_range            3.0      (0, 100]       free space is only claimed this far (m)
log_free              -0.4     [-100, 0)      log-odds added to a free cell in view
log_hit               1.2      (0, 100]       log-odds added at the centre of an obstacle percept
clamp                 4.0      (0, 100]       log-odds are clamped to +-clamp
decay_per_second      1.0      [0, 100]       log-odds lost per second toward unknown
robot_radius          0.15     (0, 10]        half width of an obstacle (m)
====================  =======  =============  ===================================================

The sector model's ``memory`` (s) lies in (0, 3600]. Every value is checked against its
range when the parameters are built (:func:`cognition.params.check_ranges`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.params import Range, Ranges, check_number, check_ranges, non_negative, positive
from cognition.percepts import N_KINDS, Col, Kind, Percepts
from cognition.records import fast_init
from cognition.representations import OdometryReading
from cognition.worldmodel.kalman_ball import camera_measurement

SECTORS = 72
MAX_GRID_CELLS = 500
"""Largest number of grid cells per side (250,000 cells, 2 MB of log-odds per robot)."""


@fast_init
@dataclass(frozen=True)
class ObstacleModel:
    """Obstacles around the robot (robot frame, m)."""

    obstacles: NDArray[np.float64]
    """K x 2 positions of obstacles (grid: centroids of occupied cells above 0.7)."""
    occupancy: NDArray[np.float64] | None
    """Grid only: P(occupied) per cell, rows along y (first row y = -extent), columns along x."""
    cell: float
    """Cell size (m); 0 for the sector model."""


@dataclass(frozen=True)
class ObstacleGridParams:
    """Tuning of the occupancy grid (m, s)."""

    extent: float = 3.0
    """Half width of the square grid (m)."""
    cell: float = 0.1
    view_range: float = 3.0
    """Free space is only claimed this far (m)."""
    log_free: float = -0.4
    log_hit: float = 1.2
    clamp: float = 4.0
    decay_per_second: float = 1.0
    """Log-odds lost per second toward unknown (a saturated cell is forgotten in 4 s: robots
    move)."""
    robot_radius: float = 0.15
    """Half width of an obstacle (m), added to the percept's spread."""

    RANGES: ClassVar[Ranges] = {
        "extent": positive(50.0),
        "cell": positive(10.0),
        "view_range": positive(100.0),
        "log_free": Range(-100.0, 0.0, high_open=True),
        "log_hit": positive(100.0),
        "clamp": positive(100.0),
        "decay_per_second": non_negative(100.0),
        "robot_radius": positive(10.0),
    }

    def __post_init__(self) -> None:
        check_ranges(self)
        n = round(2 * self.extent / self.cell)
        if not 1 <= n <= MAX_GRID_CELLS:
            raise ValueError(
                f"ObstacleGridParams.extent and cell give a grid of {n} x {n} cells (2 extent / cell); "
                f"it must have 1 to {MAX_GRID_CELLS} cells per side, got extent {self.extent!r} m, cell {self.cell!r} m"
            )

    @property
    def cells_per_side(self) -> int:
        """Cells along each side of the square grid: ``round(2 extent / cell)``."""
        return round(2 * self.extent / self.cell)


class ObstacleGrid:
    """Robot-centric log-odds occupancy grid (module docstring)."""

    def __init__(self, params: ObstacleGridParams | None = None):
        self.params = params or ObstacleGridParams()
        p = self.params
        self.n = p.cells_per_side
        c = (np.arange(self.n) + 0.5) * p.cell - p.extent
        self.cx, self.cy = np.meshgrid(c, c)  # cell centres, robot frame
        self.logodds = np.zeros((self.n, self.n))
        self.time: float | None = None

    def update(self, time: float, odometry: OdometryReading, percepts: Percepts | None) -> ObstacleModel:
        """Decay, move with the odometry, then add the image's free space and obstacles."""
        p = self.params
        dt = 0.0 if self.time is None else max(0.0, time - self.time)
        self.time = time
        self._move(odometry)
        self.logodds -= np.sign(self.logodds) * np.minimum(np.abs(self.logodds), p.decay_per_second * dt)
        if percepts is not None and percepts.camera is not None:
            self._observe(percepts)
        return self.model()

    def _move(self, o: OdometryReading) -> None:
        if o.dx == 0.0 and o.dy == 0.0 and o.dtheta == 0.0:
            return
        p = self.params
        c, s = math.cos(o.dtheta), math.sin(o.dtheta)
        # a new cell's centre in the old robot frame, then the old cell it falls into
        ox = c * self.cx - s * self.cy + o.dx
        oy = s * self.cx + c * self.cy + o.dy
        ix = np.floor((ox + p.extent) / p.cell).astype(int)
        iy = np.floor((oy + p.extent) / p.cell).astype(int)
        inside = (ix >= 0) & (ix < self.n) & (iy >= 0) & (iy < self.n)
        moved = np.zeros_like(self.logodds)
        moved[inside] = self.logodds[iy[inside], ix[inside]]
        self.logodds = moved

    def _observe(self, percepts: Percepts) -> None:
        p = self.params
        cam = percepts.camera
        assert cam is not None
        pts = np.column_stack([self.cx.ravel(), self.cy.ravel(), np.zeros(self.cx.size)])
        uv, front = cam.project(pts)
        seen = (front & cam.in_image(uv)).reshape(self.cx.shape)
        seen &= np.hypot(self.cx, self.cy) <= p.view_range
        hit = np.zeros_like(self.logodds)
        rows = percepts.table(Kind.ROBOT).rows
        for r in rows:
            x, y = float(r[Col.X]), float(r[Col.Y])
            d = max(math.hypot(x, y), 0.05)
            ux, uy = x / d, y / d
            sa, sb = max(float(r[Col.SIGMA_ALPHA]), 1e-3), max(float(r[Col.SIGMA_BETA]), 1e-3)
            _, cov = camera_measurement(x, y, max(cam.height, 0.1), sa, sb)  # eqs. 8, 12-15
            sd_r = math.sqrt(ux * ux * cov[0, 0] + 2 * ux * uy * cov[0, 1] + uy * uy * cov[1, 1]) + p.robot_radius
            sd_t = math.sqrt(uy * uy * cov[0, 0] - 2 * ux * uy * cov[0, 1] + ux * ux * cov[1, 1]) + p.robot_radius
            ex, ey = self.cx - x, self.cy - y
            along = ex * ux + ey * uy
            across = -ex * uy + ey * ux
            hit = np.maximum(hit, np.exp(-0.5 * ((along / sd_r) ** 2 + (across / sd_t) ** 2)))
        self.logodds += np.where(seen & (hit < 0.1), p.log_free, 0.0) + p.log_hit * hit
        np.clip(self.logodds, -p.clamp, p.clamp, out=self.logodds)

    def model(self) -> ObstacleModel:
        """The current map: occupancy probabilities and occupied-cell centroids."""
        prob = 1.0 / (1.0 + np.exp(-self.logodds))
        occ = prob > 0.7
        pts = np.column_stack([self.cx[occ], self.cy[occ]]) if occ.any() else np.zeros((0, 2))
        return ObstacleModel(pts, prob, self.params.cell)


class ObstacleSectors:
    """The 72-sector model: nearest obstacle distance per 5 degrees (module docstring)."""

    def __init__(self, memory: float = 3.0):
        check_number("ObstacleSectors", "memory", memory, positive(3600.0))
        self.memory = memory
        self.distance = np.full(SECTORS, np.inf)
        self.stamp = np.full(SECTORS, -np.inf)
        self.time = 0.0

    def update(self, time: float, odometry: OdometryReading, percepts: Percepts | None) -> ObstacleModel:
        """Move with the odometry (per sector's obstacle point), forget old ones, add percepts."""
        self.time = time
        table, offsets = (_NO_ROBOTS, _NO_OFFSETS) if percepts is None else percepts.table_and_offsets
        o = odometry
        points = _sectors_frame_nb(self.distance, self.stamp, time, self.memory, o.dx, o.dy, o.dtheta, table, offsets)
        return ObstacleModel(points, None, 0.0)

    def model(self) -> ObstacleModel:
        """The sectors' obstacle points (robot frame, m; one per sector that holds one)."""
        return ObstacleModel(_sector_points_nb(self.distance), None, 0.0)


_NO_ROBOTS = np.zeros((0, len(Col)))
_NO_OFFSETS = np.zeros(N_KINDS + 1, dtype=np.int64)
"""The percept table and offsets of no percepts (:meth:`ObstacleSectors.update`)."""
_CX, _CY = int(Col.X), int(Col.Y)
_ROBOT = int(Kind.ROBOT)


@nb.njit(cache=True, error_model="python", fastmath=False)
def _sector_set(distance, stamp, x, y, t):  # pragma: no cover - compiled
    """Put the obstacle point (x, y) (robot frame, m) seen at ``t`` into its sector: the nearer
    or the newer of it and the sector's point wins."""
    k = int((math.atan2(y, x) + math.pi) / (2 * math.pi) * SECTORS) % SECTORS
    d = math.hypot(x, y)
    if d < distance[k] or t > stamp[k]:
        distance[k], stamp[k] = d, t


@nb.njit(cache=True, error_model="python", fastmath=False)
def _sectors_update_nb(distance, stamp, time, memory, dx, dy, dth, robots, cx, cy):  # pragma: no cover - compiled
    """One frame of :class:`ObstacleSectors` in place: move the remembered points by the
    odometry (dx, dy m, dth rad: the robot's motion in its old frame), drop those older than
    ``memory`` s, then add the robot percepts (rows of ``robots``, point at columns cx, cy)."""
    step = 2 * math.pi / SECTORS
    px = np.empty(SECTORS)
    py = np.empty(SECTORS)
    ts = np.empty(SECTORS)
    n = 0
    for k in range(SECTORS):
        if np.isfinite(distance[k]) and time - stamp[k] <= memory:
            a = (k + 0.5) * step - math.pi
            px[n], py[n], ts[n] = distance[k] * np.cos(a), distance[k] * np.sin(a), stamp[k]
            n += 1
    c, s = math.cos(dth), math.sin(dth)
    distance[:] = np.inf
    stamp[:] = -np.inf
    for k in range(n):
        x, y = px[k] - dx, py[k] - dy
        _sector_set(distance, stamp, c * x + s * y, -s * x + c * y, ts[k])
    for r in range(robots.shape[0]):
        _sector_set(distance, stamp, robots[r, cx], robots[r, cy], time)


@nb.njit(cache=True, error_model="python", fastmath=False)
def _sector_points_nb(distance):  # pragma: no cover - compiled
    """Obstacle points (K x 2, robot frame, m) of the sectors that hold one."""
    step = 2 * math.pi / SECTORS
    n = 0
    for k in range(SECTORS):
        if np.isfinite(distance[k]):
            n += 1
    out = np.empty((n, 2))
    n = 0
    for k in range(SECTORS):
        if np.isfinite(distance[k]):
            a = (k + 0.5) * step - math.pi
            out[n, 0], out[n, 1] = distance[k] * np.cos(a), distance[k] * np.sin(a)
            n += 1
    return out


@nb.njit(cache=True, error_model="python", fastmath=False)
def _sectors_frame_nb(distance, stamp, time, memory, dx, dy, dth, table, offsets):  # pragma: no cover - compiled
    """:func:`_sectors_update_nb` with the robot percepts of ``table`` (kind ``Kind.ROBOT`` of
    the percept ``offsets``; the point at columns ``Col.X``, ``Col.Y``), then
    :func:`_sector_points_nb`: one frame of :class:`ObstacleSectors` in one call."""
    robots = table[offsets[_ROBOT] : offsets[_ROBOT + 1]]
    _sectors_update_nb(distance, stamp, time, memory, dx, dy, dth, robots, _CX, _CY)
    return _sector_points_nb(distance)
