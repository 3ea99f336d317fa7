"""Predefined kickoff positions: where each player stands for a kickoff (team frame).

Robots know these positions (the referee places illegally positioned robots there, and the
CMU paper, Sec. III.A.2, moves particles to them when a robot is carried during READY or
SET), so they are part of the robot's map knowledge, shared by brains and the referee.

Positions are given for the 9 x 6 m SPL field and scaled to other fields; the goalkeeper
stands in front of its goal and the striker (player 3) inside the centre circle when its
team kicks off, just outside it otherwise. Team frame: metres, +x toward the opponent goal.
"""

from __future__ import annotations

from cognition.field import Field

_BASE: dict[int, tuple[float, float]] = {
    2: (-2.8, -0.8),
    4: (-1.5, 1.2),
    5: (-1.5, -1.5),
    6: (-2.8, 0.8),
    7: (-1.0, 2.2),
}


def kickoff_position(field_map: Field, number: int, kicking: bool) -> tuple[float, float, float]:
    """Kickoff pose (x m, y m, theta rad; team frame) of player ``number`` (1..7)."""
    if not 1 <= number <= 7:
        raise ValueError(f"player number must be in 1..7, got {number}")
    r_circle = field_map.centre_circle.radius
    if number == 1:
        return (-field_map.half_length + 0.25, 0.0, 0.0)
    if number == 3:
        if kicking:
            return (-min(0.35, 0.5 * r_circle), 0.0, 0.0)
        return (-(r_circle + 0.3), 0.0, 0.0)
    bx, by = _BASE[number]
    return (bx * field_map.dims.length / 9.0, by * field_map.dims.width / 6.0, 0.0)
