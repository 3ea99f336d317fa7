"""The brain interface: one instance per robot, called once per cognition frame.

A brain receives the robot's :class:`~cognition.representations.SensorFrame` and returns a
:class:`~cognition.representations.BrainOutput` (motion request and optional team message).
That is all a real robot's cognition gets, so a brain written against this interface could
run on a robot.

A brain may also offer ``rejected_inputs() -> dict[str, int]``: how many sensor inputs of
each kind it could not use (:mod:`cognition.inputs`); :func:`rejected_inputs` reads it.

The single exception is the *oracle* input: a brain whose ``uses_oracle`` attribute is
``True`` also receives an :class:`~cognition.oracle.OracleInput` with ground truth. Oracle
brains exist for baselines and for the foundation's scripted players; every other brain gets
``None`` there.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np

from cognition.field import ColourScheme, Field
from cognition.oracle import OracleInput
from cognition.profiling import NO_LAPS, Laps, ModuleProfile
from cognition.representations import BrainOutput, SensorFrame


@dataclass(frozen=True)
class BrainContext:
    """Static facts a brain is told once, before the first frame."""

    team_number: int
    """Own team number (GameController numbering)."""
    player_number: int
    """Own player number, 1-based; 1 is the goalkeeper."""
    players_per_team: int
    """Number of players in each team."""
    field: Field
    """The field map."""
    cognition_hz: float
    """Cognition frames per second."""
    rng: np.random.Generator | None = None
    """The brain's own random stream, a child of the match seed (``None``: the brain seeds its own)."""
    colours: ColourScheme | None = None
    """Colours of goals, ball and jerseys, for vision on camera images (``None``: the ``modern`` scheme)."""
    team: int = 0
    """Own jersey: index into ``colours.team_colours`` (0 or 1)."""
    profile: ModuleProfile | None = None
    """When set, the brain adds the wall time of each of its modules to it (:mod:`cognition.profiling`;
    shared by all brains of a match)."""

    def laps(self) -> Laps:
        """The lap timer for the brain's modules: into :attr:`profile`, or one that records nothing."""
        return NO_LAPS if self.profile is None else self.profile.laps()


@runtime_checkable
class Brain(Protocol):
    """A robot's cognition."""

    uses_oracle: bool
    """``True`` only for oracle brains that read ground truth."""

    def reset(self, context: BrainContext) -> None:
        """Prepare for a new match."""
        ...

    def think(self, frame: SensorFrame, oracle: OracleInput | None) -> BrainOutput:
        """Process one frame and decide what to do."""
        ...


def rejected_inputs(brain: Brain) -> dict[str, int]:
    """The sensor inputs ``brain`` could not use so far, by kind (non-finite odometry, invalid
    team messages, ...), from its optional ``rejected_inputs()`` method; empty when it has none.
    The simulator sums them into the match summary."""
    method = getattr(brain, "rejected_inputs", None)
    return dict(method()) if callable(method) else {}
