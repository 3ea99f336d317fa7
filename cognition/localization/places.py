"""Known placements a robot can be carried to (CMU paper, Sec. III.A.2-3), in the team frame.

A robot knows where the referee puts robots: the touchline start positions of a half, the
predefined kickoff positions (manual placement during READY and SET) and the return
positions of a penalised robot under the active rule set (see :mod:`teamsim.placement`,
which puts robots exactly there):

* ``spl2025``: 0.5 m outside either touchline at the x of the own penalty mark, facing the
  field (the side is where the robot was removed, which the localization may not know);
* ``spl2010`` (the CMU paper): on the halfway line at either touchline, facing the field.

All poses are (x m, y m, theta rad), team frame.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from cognition.field import Field
from cognition.gamestate import GameStateId
from cognition.positions import kickoff_position

RETURN_OUTSIDE_TOUCHLINE = 0.5
"""How far outside the touchline (m) the ``spl2025`` rule returns a robot."""


def initial_position(field_map: Field, number: int, players_per_team: int) -> tuple[float, float, float]:
    """Pose (team frame) at the touchline of the own half where robots start a half.

    Odd player numbers stand on the right touchline (y < 0), even ones on the left, facing
    the field.
    """
    side = -1.0 if number % 2 == 1 else 1.0
    per_side = (players_per_team + 1) // 2
    slot = (number - 1) // 2
    span = field_map.half_length - 0.8
    step = span / max(1, per_side - 1) if per_side > 1 else 0.0
    x = -field_map.half_length + 0.5 + slot * step
    y = side * field_map.half_width
    return (x, y, -side * math.pi / 2)


def placement_poses(
    field_map: Field, number: int, players_per_team: int, state: int, kicking: bool
) -> NDArray[np.float64]:
    """Poses (K x 3) the robot may be put down at when carried in game state ``state``.

    INITIAL: its touchline start position; READY and SET: its kickoff position (manual
    placement), and the start position as a second candidate.
    """
    start = initial_position(field_map, number, players_per_team)
    if state == GameStateId.INITIAL:
        return np.array([start])
    return np.array([kickoff_position(field_map, number, kicking), start])


def return_poses(field_map: Field, rule: str) -> NDArray[np.float64]:
    """The return positions (K x 3, team frame) of a penalised robot under ``rule``."""
    if rule == "spl2025":
        x = -field_map.half_length + field_map.dims.penalty_mark_distance
        y = field_map.half_width + RETURN_OUTSIDE_TOUCHLINE
    elif rule == "spl2010":
        x, y = 0.0, field_map.half_width
    else:
        raise ValueError(f"unknown return rule {rule!r}; valid: ['spl2025', 'spl2010']")
    return np.array([(x, y, -math.pi / 2), (x, -y, math.pi / 2)])
