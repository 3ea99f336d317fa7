"""Which brains play a match, and how well the localizing ones know where they are.

=========================  ==================================================================
name                       what it is
=========================  ==================================================================
BrainFactory               ``(team index, player number) -> Brain``
scripted_brains            scripted team play on beliefs (truth or the cognition stack)
random_brains              random walkers, the baseline opponents
default_brains             the factory a match uses when the caller gives none
LocalizationErrors         collects, per robot and cognition frame, the error of a brain's pose
                           estimate against the truth (evaluation only; brains never see it)
LocalizationSummary        the collected errors in a few numbers (printed by ``teamsim match``)
=========================  ==================================================================

Errors are measured in the robot's team frame: position error is the Euclidean distance (m)
between estimate and true position, heading error the absolute wrapped angle difference.
"""

from __future__ import annotations

import math
from array import array
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from cognition.brain import Brain
from cognition.geometry import wrap_angle
from cognition.localization import VARIANTS, LocalizationParams
from cognition.representations import RobotPose
from cognition.vision import VisionParams

BrainFactory = Callable[[int, int], Brain]
"""Makes the brain of (team index, player number)."""


def scripted_brains(
    localization: str | None,
    params: LocalizationParams | None = None,
    return_rule: str | None = None,
    obstacle_model: str = "sectors",
    vision: VisionParams | None = None,
) -> BrainFactory:
    """A factory of scripted team players (:class:`~cognition.behaviors.team_play.ScriptedBrain`):
    on truth beliefs without ``localization``, else on the cognition stack with that variant."""
    from cognition.behaviors.team_play import ScriptedBrain

    if localization is None:
        return lambda team, number: ScriptedBrain(beliefs="truth")
    if localization not in VARIANTS:
        raise ValueError(f"unknown localization variant {localization!r}; valid: {list(VARIANTS)}")
    p = params or LocalizationParams()
    if return_rule is not None:
        p = replace(p, return_rule=return_rule)
    return lambda team, number: ScriptedBrain(
        beliefs="cognition", variant=localization, localization_params=p, obstacle_model=obstacle_model, vision=vision
    )


def random_brains(team: int, number: int) -> Brain:
    """Random walkers (:class:`~cognition.behaviors.random_walk.RandomWalkBrain`)."""
    from cognition.behaviors.random_walk import RandomWalkBrain

    return RandomWalkBrain()


def default_brains(
    players: str,
    localization: str | None,
    params: LocalizationParams,
    return_rule: str,
    obstacle_model: str = "sectors",
    vision: VisionParams | None = None,
) -> BrainFactory:
    """The brains named by ``players``: ``scripted`` (:func:`scripted_brains`) or ``random``."""
    if players == "scripted":
        return scripted_brains(localization, params, return_rule, obstacle_model, vision)
    if players == "random":
        return random_brains
    raise ValueError(f"unknown players {players!r}; valid: ['scripted', 'random']")


@dataclass(frozen=True)
class LocalizationSummary:
    """Localization quality over a match (all non-penalised robots and cognition frames)."""

    variant: str
    """Variant name(s) of the estimates, comma separated if brains used different ones."""
    frames: int
    """Robot frames counted (robots x cognition frames, penalised robots left out)."""
    position_error_mean: float
    """Mean position error (m)."""
    position_error_p90: float
    """90th percentile of the position error (m)."""
    heading_error_mean: float
    """Mean absolute heading error (deg)."""
    lost_share: float
    """Share of frames in which the estimate was flagged ``lost`` (0..1)."""

    def to_dict(self) -> dict[str, Any]:
        """Plain mapping (JSON)."""
        return {
            "variant": self.variant,
            "frames": self.frames,
            "position_error_mean": self.position_error_mean,
            "position_error_p90": self.position_error_p90,
            "heading_error_mean": self.heading_error_mean,
            "lost_share": self.lost_share,
        }

    def format(self) -> str:
        """One line for the match report."""
        return (
            f"localization   {self.variant}: position error mean {self.position_error_mean:.3f} m, "
            f"p90 {self.position_error_p90:.3f} m; heading error mean {self.heading_error_mean:.1f} deg; "
            f"lost {100.0 * self.lost_share:.1f}% of {self.frames} robot frames"
        )


class LocalizationErrors:
    """Accumulates estimate-versus-truth errors (team frame) frame by frame."""

    def __init__(self) -> None:
        self._position = array("d")
        self._heading = array("d")
        self._lost = 0
        self._variants: dict[str, None] = {}

    def __len__(self) -> int:
        return len(self._position)

    def add(self, estimate: RobotPose, truth: tuple[float, float, float]) -> None:
        """Record one robot frame: ``estimate`` and the true team-frame pose (m, m, rad)."""
        self._position.append(math.hypot(estimate.x - truth[0], estimate.y - truth[1]))
        self._heading.append(abs(wrap_angle(estimate.theta - truth[2])))
        self._lost += bool(estimate.lost)
        self._variants.setdefault(estimate.variant or "?", None)

    def summary(self) -> LocalizationSummary | None:
        """The errors so far (``None`` before the first recorded frame)."""
        n = len(self._position)
        if n == 0:
            return None
        pos = np.array(self._position, dtype=np.float64)
        head = np.array(self._heading, dtype=np.float64)
        return LocalizationSummary(
            variant=",".join(self._variants),
            frames=n,
            position_error_mean=float(pos.mean()),
            position_error_p90=float(np.percentile(pos, 90.0)),
            heading_error_mean=math.degrees(float(head.mean())),
            lost_share=self._lost / n,
        )
