"""Multinomial resampling (DNT section 4.1, the draw of the sampling-importance-resampling filter).

Each of the m new particles is an independent draw from the normalised weights. The m
uniforms are generated already sorted, as the normalised cumulative sums of m + 1 exponential
variates (the spacings of sorted uniforms are a normalised exponential vector), so that the
compiled resampling step (:func:`cognition.localization.resample.resample_nb`) merges them
with the cumulative weights in one pass: the same distribution as a binary search per draw,
in linear time. Random numbers come from the filter's xorshift64* state
(:func:`cognition.localization.kernels.rand_u`).
"""

from __future__ import annotations

import math

import numba as nb

from cognition.localization.kernels import rand_u
from cognition.localization.strategy import Resampling

MULTINOMIAL = Resampling("multinomial", low_variance=False)
"""The multinomial draw (variants ``mcl``, ``amcl`` and ``reset``)."""


@nb.njit(cache=True, error_model="python", fastmath=False)
def multinomial_draws_nb(u, m, state):  # pragma: no cover - compiled
    """Fill ``u[:m]`` with m sorted independent uniforms in [0, 1)."""
    total = 0.0
    for k in range(m):
        total -= math.log(1.0 - rand_u(state))
        u[k] = total
    total -= math.log(1.0 - rand_u(state))
    for k in range(m):
        u[k] /= total
