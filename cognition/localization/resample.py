"""The compiled resampling step of the particle filter: one call draws, jitters and picks slots.

The draw itself is the filter's :class:`~cognition.localization.strategy.Resampling`:
:mod:`.multinomial` (DNT 4.1) or :mod:`.low_variance` (DNT 4.6). Around it this step builds
the cumulative weights, merges the sorted draws with them in one pass, adds the Gaussian
jitter of CMU III.D to every drawn particle, makes the new weights uniform and, when
particles are to be injected, chooses their slots (:func:`cognition.localization.kernels.choose_nb`
semantics), all from the filter's xorshift64* state. Poses are (x m, y m, theta rad), team frame.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from cognition.localization.kernels import _choose_into, rand_n, wrap
from cognition.localization.low_variance import low_variance_draws_nb
from cognition.localization.multinomial import multinomial_draws_nb


@nb.njit(cache=True, error_model="python", fastmath=False)
def resample_nb(
    parts, n, w, logw, out, m, low_variance, jit_xy, jit_th, m_inj, slots, state
):  # pragma: no cover - compiled
    """Draw ``m`` particles from particles [0, n) with normalised weights ``w`` into ``out``
    (low-variance draw if ``low_variance``, else multinomial), then make the weights of
    [0, m) uniform (``logw`` 0, ``w`` 1 / m) and, with ``m_inj`` > 0, choose the slots of the
    poses to inject: ``slots[:m_inj]`` (as :func:`~cognition.localization.kernels.choose_nb`
    over m; ``slots`` holds at least m entries and is work space beyond ``m_inj``). Each drawn
    particle gets Gaussian jitter (sd ``jit_xy`` m, ``jit_th`` rad)."""
    cdf = np.empty(n)
    acc = 0.0
    for i in range(n):
        acc += w[i]
        cdf[i] = acc
    cdf[n - 1] = 1.0 + 1e-12
    u = np.empty(m)
    if low_variance:
        low_variance_draws_nb(u, m, state)
    else:
        multinomial_draws_nb(u, m, state)
    j = 0
    for k in range(m):
        while j < n - 1 and cdf[j] < u[k]:
            j += 1
        out[k, 0] = parts[j, 0] + jit_xy * rand_n(state)
        out[k, 1] = parts[j, 1] + jit_xy * rand_n(state)
        out[k, 2] = wrap(parts[j, 2] + jit_th * rand_n(state))
    for k in range(m):
        logw[k] = 0.0
        w[k] = 1.0 / m
    if m_inj > 0:
        _choose_into(slots, m, m_inj, state)
