"""Self-localization: the Monte Carlo family from the papers, every variant selectable by name.

``make_localizer(name, field, params, rng, player_number, players_per_team)`` builds one
robot's localizer; ``update(frame, truth=None)`` returns a :class:`~cognition.representations.RobotPose`
(team frame). See :mod:`cognition.localization.params` for every parameter and its source.

=========  ==========================================================================  ===========
variant    what it does                                                                source
=========  ==========================================================================  ===========
mcl        sampling-importance-resampling particle filter (multinomial resampling)     DNT 4.1
lowvar     the same with low-variance resampling                                       DNT 4.6
amcl       augmented MCL: random poses injected when w_fast / w_slow drops              DNT 4.4
reset      sensor resetting from goal posts, adaptive particle count up to 300         CMU III
maturing   candidate poses from single observations mature before they replace         Darmstadt VI
           particles
odometry   dead reckoning from the last known placement                                baseline
oracle     the true pose (needs ground truth; for baselines)                           baseline
=========  ==========================================================================  ===========

Each particle variant is a resampling draw and an injection strategy, one file per paper
algorithm (:mod:`cognition.localization.strategy` lists them; ``ParticleFilter(...,
resampling=..., injection=...)`` composes others).
"""

from __future__ import annotations

import numpy as np

from cognition.field import Field
from cognition.localization.base import DeadReckoning, Localizer, Oracle
from cognition.localization.params import LocalizationParams

VARIANTS: tuple[str, ...] = ("mcl", "lowvar", "amcl", "reset", "maturing", "odometry", "oracle")
"""Names accepted by :func:`make_localizer`."""


def make_localizer(
    name: str,
    field: Field,
    params: LocalizationParams | None = None,
    rng: np.random.Generator | None = None,
    player_number: int = 1,
    players_per_team: int = 5,
) -> Localizer:
    """The localizer called ``name`` (one of :data:`VARIANTS`) for one robot."""
    if name not in VARIANTS:
        raise ValueError(f"unknown localization variant {name!r}; valid: {list(VARIANTS)}")
    if name == "odometry":
        return DeadReckoning(field, params, rng, player_number, players_per_team)
    if name == "oracle":
        return Oracle(field, params, rng, player_number, players_per_team)
    from cognition.localization.particle_filter import ParticleFilter

    return ParticleFilter(name, field, params, rng, player_number, players_per_team)


__all__ = ["VARIANTS", "LocalizationParams", "Localizer", "make_localizer"]
