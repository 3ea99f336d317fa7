"""The compiled checks of percept tables (the rules are in :mod:`cognition.percepts`).

:class:`cognition.percepts.Percepts` refuses rows that break its rules: positions and
variances that are not finite, negative variances, subtypes out of their kind's range, a goal
index other than -1, 0 or 1, a ball radius that is neither unknown (NaN) nor >= 0, and offsets
that do not delimit the kinds within the table. These kernels find the first offending entry
in one pass; :func:`_first_invalid_many_nb` checks many images sharing one table (a percept
synthesizer's frame of every robot). Columns are given by index (:class:`cognition.percepts.Col`:
x 0, y 1, x2 4, y2 5, orientation 8, subtype 9, var_xx 10, var_xy 11, var_yy 12, sigma_alpha 13,
sigma_beta 14, radius_px 15, goal 17), kinds by their :class:`cognition.percepts.Kind` index.
All of them live in this one file: numba caches per file and would not notice an edit of a
callee in another.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

_SUBTYPE_MAX = np.array([2, 2, 0, 0, 0, 0, 2, 0], dtype=np.int64)
"""Largest ``subtype`` per :class:`cognition.percepts.Kind` (post side, crossing kind, robot team; 0 elsewhere)."""
_RULES = (
    "must be finite",
    "must be finite and >= 0",
    "must be an integer in 0..{top}",
    "must be -1, 0 or 1",
    "must be NaN (unknown) or finite and >= 0",
)


@nb.njit(cache=True, error_model="python", fastmath=False)
def _offsets_ok_nb(offsets: NDArray[np.int64], n_rows: int) -> bool:  # pragma: no cover - compiled
    """Offsets start at >= 0, never decrease and end within ``n_rows``."""
    if offsets[0] < 0 or offsets[-1] > n_rows:
        return False
    for k in range(offsets.shape[0] - 1):  # noqa: SIM110 - compiled, no generators
        if offsets[k + 1] < offsets[k]:
            return False
    return True


@nb.njit(cache=True, error_model="python", fastmath=False)
def _all_finite_nb(values: NDArray[np.float64]) -> bool:  # pragma: no cover - compiled
    """No NaN or infinity in ``values``."""
    for x in values:  # noqa: SIM110 - compiled, no generators
        if not math.isfinite(x):
            return False
    return True


@nb.njit(cache=True, error_model="python", fastmath=False)
def _first_invalid_nb(rows, offsets, subtype_max):  # pragma: no cover - compiled
    """(row, column, rule) of the first entry that breaks the rules of the module docstring
    (rule: index into ``_RULES``), or (-1, -1, -1) when every row of the offsets' range is valid."""
    kind = 0
    for r in range(offsets[0], offsets[-1]):
        while r >= offsets[kind + 1]:
            kind += 1
        row = rows[r]
        for c in (0, 1, 11):  # x, y, var_xy
            if not math.isfinite(row[c]):
                return r, c, 0
        for c in (10, 12, 13, 14):  # var_xx, var_yy, sigma_alpha, sigma_beta
            if not (math.isfinite(row[c]) and row[c] >= 0.0):
                return r, c, 1
        sub = row[9]
        if not (sub >= 0.0 and sub <= subtype_max[kind] and sub == math.floor(sub)):
            return r, 9, 2
        if kind == 0 and not (row[17] == -1.0 or row[17] == 0.0 or row[17] == 1.0):
            return r, 17, 3
        if kind == 1 and not math.isfinite(row[8]):
            return r, 8, 0
        if kind == 2:
            for c in (4, 5):
                if not math.isfinite(row[c]):
                    return r, c, 0
        if kind == 5 and not (math.isnan(row[15]) or (math.isfinite(row[15]) and row[15] >= 0.0)):
            return r, 15, 4
    return -1, -1, -1


@nb.njit(cache=True, error_model="python", fastmath=False)
def _first_invalid_many_nb(rows, offsets, camera_rows, has_camera, subtype_max):  # pragma: no cover - compiled
    """The checks of :func:`_check` on the rows, offsets and camera rows of many images that
    share one row table (``offsets``: one row per image), for the images that were taken
    (``has_camera``; the others are empty percepts, their rows unused). Returns (image, what,
    row, column, rule): what 0 = bad offsets, 1 = a non-finite camera row, 2 = an invalid row
    (``row``, ``column``, ``rule`` as in :func:`_first_invalid_nb`); image -1 when all is valid."""
    for i in range(offsets.shape[0]):
        if not has_camera[i]:
            continue
        if not _offsets_ok_nb(offsets[i], rows.shape[0]):
            return i, 0, -1, -1, -1
        if not _all_finite_nb(camera_rows[i]):
            return i, 1, -1, -1, -1
        r, c, rule = _first_invalid_nb(rows, offsets[i], subtype_max)
        if r >= 0:
            return i, 2, r, c, rule
    return -1, -1, -1, -1, -1
