"""Low-variance resampling (DNT section 4.6; Thrun's systematic resampling).

One uniform offset r in [0, 1/m) and m evenly spaced pointers r + k/m walk once along the
cumulative weights: a particle of weight w is drawn floor(m w) or ceil(m w) times, never
more or fewer, so resampling a filter whose weights are all equal keeps every particle, and
the draw loses less diversity than m independent draws (:mod:`.multinomial`). The compiled
resampling step (:func:`cognition.localization.resample.resample_nb`) merges the pointers
with the cumulative weights. Random numbers come from the filter's xorshift64* state.
"""

from __future__ import annotations

import numba as nb

from cognition.localization.kernels import rand_u
from cognition.localization.strategy import Resampling

LOW_VARIANCE = Resampling("low variance", low_variance=True)
"""The low-variance draw (variants ``lowvar`` and ``maturing``)."""


@nb.njit(cache=True, error_model="python", fastmath=False)
def low_variance_draws_nb(u, m, state):  # pragma: no cover - compiled
    """Fill ``u[:m]`` with the m pointers r + k / m, r uniform in [0, 1 / m)."""
    r = rand_u(state) / m
    for k in range(m):
        u[k] = r + k / m
