"""Wall time per cognition module, for ``teamsim match --profile``.

A brain told to profile (:attr:`cognition.brain.BrainContext.profile` is a
:class:`ModuleProfile`) times each of its modules with :class:`Laps`: ``laps = profile.laps()``
(or :data:`NO_LAPS` when not profiling), ``laps.start()`` before the first module and
``laps.lap("localization")`` after each, which adds the wall time (s) since the previous mark
to that module's total. One profile is shared by all brains of a match, so its totals are
sums over robots and frames; the simulator divides them by the robot-frames it ran. Without a
profile the marks are no-ops (a method call each, well under a microsecond per frame).
"""

from __future__ import annotations

import time

__all__ = ["NO_LAPS", "Laps", "ModuleProfile"]


class ModuleProfile:
    """Seconds of wall time per module name, summed over every brain that shares it (insertion
    order: the order in which modules first ran, which is the order of the cognition frame)."""

    def __init__(self) -> None:
        self.seconds: dict[str, float] = {}

    def add(self, module: str, seconds: float) -> None:
        """Add ``seconds`` (wall time, s) to ``module``'s total."""
        self.seconds[module] = self.seconds.get(module, 0.0) + seconds

    def laps(self) -> Laps:
        """A lap timer that adds into this profile."""
        return Laps(self)

    def total(self) -> float:
        """Seconds over all modules."""
        return sum(self.seconds.values())


class Laps:
    """Marks between modules: :meth:`start`, then :meth:`lap` after each module."""

    __slots__ = ("_last", "_seconds")

    def __init__(self, profile: ModuleProfile) -> None:
        self._seconds = profile.seconds
        self._last = time.perf_counter()

    def start(self) -> Laps:
        """Start timing the first module now."""
        self._last = time.perf_counter()
        return self

    def lap(self, module: str) -> None:
        """The module that just finished was ``module``: add the time since the last mark."""
        now = time.perf_counter()
        self._seconds[module] = self._seconds.get(module, 0.0) + (now - self._last)
        self._last = now


class _NoLaps(Laps):
    """Marks that record nothing (no profile)."""

    __slots__ = ()

    def __init__(self) -> None:
        pass

    def start(self) -> Laps:
        return self

    def lap(self, module: str) -> None:
        pass


NO_LAPS: Laps = _NoLaps()
"""The lap timer of a brain that is not profiled."""
