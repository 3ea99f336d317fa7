"""Wall time per cognition module, for ``teamsim match --profile``.

:func:`cognition.brain.think_all` runs the brains of a match stage by stage and, given a
:class:`ModuleProfile`, adds the wall time of every stage (a module: localization, ball model,
behaviour, ...) summed over the brains that ran it. The simulator divides the totals by the
robot-frames it played (:mod:`teamsim.profile`).
"""

from __future__ import annotations

__all__ = ["ModuleProfile"]


class ModuleProfile:
    """Seconds of wall time per module name, summed over brains and frames (insertion order: the
    order in which the modules first ran, which is the order of the cognition frame)."""

    def __init__(self) -> None:
        self.seconds: dict[str, float] = {}

    def add(self, module: str, seconds: float) -> None:
        """Add ``seconds`` (wall time, s) to ``module``'s total."""
        self.seconds[module] = self.seconds.get(module, 0.0) + seconds

    def total(self) -> float:
        """Seconds over all modules."""
        return sum(self.seconds.values())
