"""The two strategies a particle filter is built from: its resampling draw and its injection.

A Monte Carlo localization variant of the papers (module table of
:mod:`cognition.localization.particle_filter`) is one **resampling** draw and one
**injection** rule, each in a file named after its algorithm:

=====================  ===================================================  =================
strategy               what it decides                                      file
=====================  ===================================================  =================
multinomial            resampling: m independent draws (DNT 4.1)            :mod:`.multinomial`
low variance           resampling: one offset, m even steps (DNT 4.6)       :mod:`.low_variance`
none                   injection: nothing is replaced (``mcl``, ``lowvar``)  this module
AMCL                   injection: random poses, share from w_fast / w_slow  :mod:`.amcl`
                       (DNT 4.4)
sensor resetting       injection: poses from vision, at least a share while  :mod:`.resetting`
                       lost, adaptive particle count (CMU III.D)
particle maturing      injection: vision poses that stayed consistent over  :mod:`.maturing`
                       several frames (Darmstadt VI)
=====================  ===================================================  =================

The filter calls an :class:`Injection` at fixed points of its frame (:meth:`Injection.observe`
after the observation update, :meth:`~Injection.count` and :meth:`~Injection.share` before
resampling, :meth:`~Injection.inject` after it) and hands itself in, so that a strategy can use
its map, its sensor tables and its random state; the strategy keeps its own state (AMCL's
averages, the maturing candidates). For the built-in strategies, exactly of these classes, the
filter runs the same steps in one compiled call instead (:mod:`.frame_step`, which reads the
few numbers in which they differ); a subclass of a user's keeps these Python calls. All poses
are (x m, y m, theta rad) in the team frame.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from cognition.localization.fieldmodel import FieldModel
from cognition.localization.params import LocalizationParams
from cognition.representations import RobotPose


class FilterView(Protocol):
    """What a strategy may use of the particle filter that hands itself in (the filter,
    :class:`~cognition.localization.particle_filter.ParticleFilter`, provides it): its particles,
    map, compiled work space and random state. Poses are (x m, y m, theta rad), team frame."""

    parts: NDArray[np.float64]
    """The particles (capacity x 3; the first ``n`` in use)."""
    model: FieldModel
    """The field map in the kernels' arrays."""
    maps: tuple[NDArray[np.float64], ...]
    """The map arrays the compiled sensor model takes (posts, crossings, lines, marks, poles, grids, geometry)."""
    hough_params: NDArray[np.float64]
    """The Hough line model's parameters."""
    ll_buffer: NDArray[np.float64]
    """Log-likelihood work space."""
    scratch: NDArray[np.float64]
    """Sensor-model work space."""
    kernel_state: NDArray[np.uint64]
    """The xorshift64* state every compiled step draws from."""
    estimate: NDArray[np.float64]
    """This frame's pose estimate (x, y, theta) after the observation update."""

    def uniform_poses(self, m: int) -> NDArray[np.float64]:
        """``m`` poses uniform over the field (or the own half while the game says so)."""
        ...

    def away_from_mirror(self, fresh: NDArray[np.float64], pose: RobotPose) -> NDArray[np.float64]:
        """``fresh`` with every pose near the estimate's mirror image mirrored onto it."""
        ...


@dataclass(frozen=True)
class Resampling:
    """A resampling draw: its name and whether it is the low-variance draw (the compiled
    resampling step, :func:`cognition.localization.resample.resample_nb`, runs the draw of
    :mod:`.low_variance` or of :mod:`.multinomial` accordingly)."""

    name: str
    low_variance: bool


class Injection:
    """The injection step of a particle filter; this base injects nothing (the papers' plain
    filters ``mcl`` and ``lowvar``). Subclasses override what their algorithm changes."""

    name = "none"

    def __init__(self, params: LocalizationParams) -> None:
        self.params = params
        self.averages = np.zeros(2)
        """``w_slow`` and ``w_fast`` as one array, which the compiled frame
        (:mod:`cognition.localization.frame_step`) updates in place."""

    @property
    def w_slow(self) -> float:
        """Slow average of the per-observation evidence (DNT 4.4; 0 when the strategy does not use it)."""
        return float(self.averages[0])

    @w_slow.setter
    def w_slow(self, value: float) -> None:
        self.averages[0] = value

    @property
    def w_fast(self) -> float:
        """Fast average of the per-observation evidence (DNT 4.4)."""
        return float(self.averages[1])

    @w_fast.setter
    def w_fast(self, value: float) -> None:
        self.averages[1] = value

    def initial_count(self) -> int:
        """Particles in use when the filter is built."""
        return self.params.particles

    def count(self, n: int, w_avg: float) -> int:
        """Particles to draw at this resampling, from ``n`` in use and the per-observation
        evidence with the floors ``w_avg`` (default: keep ``n``)."""
        return n

    def observe(self, pf: FilterView, obs: NDArray[np.float64], dx: float, dy: float, dth: float) -> None:
        """Called once per frame after the observation update, with the frame's packed
        observations (K x N_O, possibly K = 0) and odometry (m, m, rad, robot frame)."""

    def share(self, w_raw: float, lost: bool) -> float:
        """Share of the particles to replace at this resampling (0..1), from the
        per-observation evidence without the floors and whether the pose is lost."""
        return 0.0

    def inject(self, pf: FilterView, slots: NDArray[np.int64], obs: NDArray[np.float64], pose: RobotPose) -> int:
        """Write fresh poses into ``pf.parts[slots]`` (the slots the resampling chose) and return
        how many were written (from the first slot on; 0: none)."""
        return 0

    def restart(self) -> None:
        """After an injection: the evidence averages start anew (DNT 4.4)."""
        self.w_slow = self.w_fast = 0.0

    def forget(self) -> None:
        """New beliefs (placement, penalty, repair): drop what was learnt about the filter's health."""
        self.w_slow = self.w_fast = 0.0

    def side_switch(self) -> None:
        """The teams changed sides: mirror any poses the strategy keeps."""
