"""The percept table's layout: its kinds (:class:`Kind`), its columns (:class:`Col`) and the typed
view of one kind's rows (:class:`PerceptTable`). :mod:`cognition.percepts` documents the table and
re-exports all of these; import them from there.
"""

from __future__ import annotations

from enum import IntEnum

import numpy as np
from numpy.typing import NDArray


class Kind(IntEnum):
    """Percept kinds (table index)."""

    POST = 0
    CROSS = 1
    LINE = 2
    CIRCLE = 3
    MARK = 4
    BALL = 5
    ROBOT = 6
    POLE = 7


N_KINDS = len(Kind)


class PostSide(IntEnum):
    """Which post of its goal a post percept is, as seen from the field facing that goal."""

    UNKNOWN = 0
    LEFT = 1
    RIGHT = 2


class RobotTeam(IntEnum):
    """The jersey colour vision assigned to a robot percept."""

    UNKNOWN = 0
    OWN = 1
    OPPONENT = 2


class Col(IntEnum):
    """Columns of a percept row (units in the module docstring)."""

    X = 0
    """Robot-frame x (m)."""
    Y = 1
    """Robot-frame y (m)."""
    U = 2
    """Image column (px)."""
    V = 3
    """Image row (px)."""
    X2 = 4
    """Second point x (m): line end; NaN otherwise."""
    Y2 = 5
    """Second point y (m)."""
    U2 = 6
    """Second pixel: line end or post top (px)."""
    V2 = 7
    ORIENTATION = 8
    """Robot-frame orientation (rad) of crossings and lines; NaN otherwise."""
    SUBTYPE = 9
    """Post side, crossing kind (0 L, 1 T, 2 X) or robot team guess."""
    VAR_XX = 10
    """Position covariance (m^2), robot frame."""
    VAR_XY = 11
    VAR_YY = 12
    SIGMA_ALPHA = 13
    """Angular sigma around the pitch axis reported with the percept (rad)."""
    SIGMA_BETA = 14
    """Angular sigma around the yaw axis reported with the percept (rad)."""
    RADIUS_PX = 15
    """Ball image radius (px); NaN otherwise."""
    TRUTH = 16
    """Ground-truth id (evaluation only), -1 for false positives."""
    GOAL = 17
    """Post goal by colour: 0 own, 1 opponent, -1 unknown (same colours)."""


N_COLS = len(Col)


class PerceptTable:
    """A typed, read-only view of the rows of one percept kind."""

    __slots__ = ("kind", "rows")

    def __init__(self, kind: Kind, rows: NDArray[np.float64]):
        self.kind = kind
        self.rows = rows
        """The rows (n x :data:`N_COLS`)."""

    def __len__(self) -> int:
        return self.rows.shape[0]

    def __bool__(self) -> bool:
        return self.rows.shape[0] > 0

    def __repr__(self) -> str:
        return f"PerceptTable({self.kind.name}, n={len(self)})"

    def column(self, col: Col) -> NDArray[np.float64]:
        """One column as an array."""
        return self.rows[:, col]

    @property
    def x(self) -> NDArray[np.float64]:
        return self.rows[:, Col.X]

    @property
    def y(self) -> NDArray[np.float64]:
        return self.rows[:, Col.Y]

    @property
    def xy(self) -> NDArray[np.float64]:
        """Positions (n x 2, m, robot frame)."""
        return self.rows[:, Col.X : Col.Y + 1]

    @property
    def xy2(self) -> NDArray[np.float64]:
        """Second points (n x 2): line ends."""
        return self.rows[:, Col.X2 : Col.Y2 + 1]

    @property
    def uv(self) -> NDArray[np.float64]:
        """Pixels (n x 2)."""
        return self.rows[:, Col.U : Col.V + 1]

    @property
    def uv2(self) -> NDArray[np.float64]:
        """Second pixels (n x 2): line ends, post tops."""
        return self.rows[:, Col.U2 : Col.V2 + 1]

    @property
    def orientation(self) -> NDArray[np.float64]:
        return self.rows[:, Col.ORIENTATION]

    @property
    def subtype(self) -> NDArray[np.int64]:
        return self.rows[:, Col.SUBTYPE].astype(np.int64)

    @property
    def distance(self) -> NDArray[np.float64]:
        """Distance of the (first) point from the robot origin (m)."""
        return np.hypot(self.rows[:, Col.X], self.rows[:, Col.Y])

    @property
    def bearing(self) -> NDArray[np.float64]:
        """Direction of the (first) point from the robot origin (rad)."""
        return np.arctan2(self.rows[:, Col.Y], self.rows[:, Col.X])

    @property
    def cov(self) -> NDArray[np.float64]:
        """Position covariances (n x 2 x 2, m^2, robot frame)."""
        r = self.rows
        out = np.empty((len(r), 2, 2))
        out[:, 0, 0] = r[:, Col.VAR_XX]
        out[:, 0, 1] = out[:, 1, 0] = r[:, Col.VAR_XY]
        out[:, 1, 1] = r[:, Col.VAR_YY]
        return out

    @property
    def sigma_alpha(self) -> NDArray[np.float64]:
        return self.rows[:, Col.SIGMA_ALPHA]

    @property
    def sigma_beta(self) -> NDArray[np.float64]:
        return self.rows[:, Col.SIGMA_BETA]

    @property
    def radius_px(self) -> NDArray[np.float64]:
        return self.rows[:, Col.RADIUS_PX]

    @property
    def goal(self) -> NDArray[np.int64]:
        return self.rows[:, Col.GOAL].astype(np.int64)

    @property
    def truth(self) -> NDArray[np.int64]:
        """Ground-truth ids; for evaluation only, never for a brain."""
        return self.rows[:, Col.TRUTH].astype(np.int64)
