"""Augmented MCL (DNT section 4.4, after Thrun et al.): random poses when the evidence drops.

The filter keeps two running averages of the evidence per observation, ``w_slow`` and
``w_fast`` (rates ``alpha_slow`` < ``alpha_fast``), updated at every resampling. When the fast
one falls below the slow one, the particles explain the recent observations worse than they
used to: a share ``max(0, 1 - w_fast / w_slow)`` of the resampled particles (at most
``injection_max``) is replaced by random poses over the field, in mirrored pairs, or in the
own half while the game state is INITIAL, READY or SET. Both averages restart from 0 after an
injection. The averages follow the evidence without the likelihood floors (see
:mod:`cognition.localization.particle_filter`). Sensor resetting (:mod:`.resetting`) and
particle maturing (:mod:`.maturing`) size their injections by the same rule.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from cognition.localization.strategy import FilterView, Injection
from cognition.representations import RobotPose


def augmented_share(w_slow: float, w_fast: float, injection_max: float) -> float:
    """Share of particles to replace, ``max(0, 1 - w_fast / w_slow)`` capped at ``injection_max``
    (0 while ``w_slow`` is not positive)."""
    if w_slow <= 0.0:
        return 0.0
    return min(injection_max, max(0.0, 1.0 - w_fast / w_slow))


class AMCLInjection(Injection):
    """Random poses in a share of the particles as the evidence averages say (module docstring)."""

    name = "amcl"

    def share(self, w_raw: float, lost: bool) -> float:
        p = self.params
        self.w_slow += p.alpha_slow * (w_raw - self.w_slow)
        self.w_fast += p.alpha_fast * (w_raw - self.w_fast)
        return augmented_share(self.w_slow, self.w_fast, p.injection_max)

    def inject(self, pf: FilterView, slots: NDArray[np.int64], obs: NDArray[np.float64], pose: RobotPose) -> int:
        pf.parts[slots] = pf.uniform_poses(slots.shape[0])
        return int(slots.shape[0])
