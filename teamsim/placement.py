"""Where robots stand: team frames, initial positions, legality, return spots.

The predefined kickoff positions and the start positions of a half are robot knowledge and
live in :mod:`cognition.positions` and :mod:`cognition.localization.places`.

Team frame (a team's field frame, :mod:`cognition.field`): +x toward the goal the team
attacks. Team 0 attacks world +x in the first half; the teams switch sides at half time, so
a team's frame is the world frame rotated by 0 or pi.

Return rules for penalised robots:

* ``spl2025``: about 0.5 m outside the touchline nearest to where the robot was removed, at
  the x of its own penalty mark, facing the field.
* ``spl2010`` (the CMU paper, Sec. III.A): on the midfield line at the touchline on the side
  opposite the ball, facing the field.
"""

from __future__ import annotations

import math
from typing import Literal

from cognition.field import Field
from cognition.geometry import wrap_angle
from cognition.localization.places import initial_position as initial_position  # re-exported
from cognition.localization.places import return_poses

ReturnRule = Literal["spl2025", "spl2010"]
RETURN_RULES: tuple[str, ...] = ("spl2025", "spl2010")


def attack_sign(team: int, first_half: bool) -> float:
    """+1 if ``team`` attacks world +x, else -1."""
    return 1.0 if (team == 0) == first_half else -1.0


def team_to_world(sign: float, x: float, y: float, theta: float) -> tuple[float, float, float]:
    """Convert a team-frame pose to the world frame (``sign`` from :func:`attack_sign`)."""
    if sign > 0:
        return (x, y, wrap_angle(theta))
    return (-x, -y, wrap_angle(theta + math.pi))


world_to_team = team_to_world
"""Convert a world-frame pose to the team frame: :func:`team_to_world` itself, the transform being
its own inverse (the same function, so that the per-frame conversions make one call, not two)."""


def is_inside_field(field_map: Field, x: float, y: float, margin: float = 0.0) -> bool:
    """Whether (x, y) lies within the outer edges of the field lines grown by ``margin`` (m)."""
    lw = field_map.dims.line_width / 2
    return abs(x) <= field_map.half_length + lw + margin and abs(y) <= field_map.half_width + lw + margin


def illegal_kickoff_robots(field_map: Field, poses: dict[int, tuple[float, float]], kicking: bool) -> list[int]:
    """Player numbers whose team-frame position is illegal for a kickoff.

    Legal: inside the field, in the own half (x <= 0), and outside the centre circle, except
    that the kicking team may have one robot inside the circle.
    """
    r_circle = field_map.centre_circle.radius
    illegal: list[int] = []
    inside_circle: list[int] = []
    for number in sorted(poses):
        x, y = poses[number]
        if not is_inside_field(field_map, x, y) or x > 0.0:
            illegal.append(number)
        elif math.hypot(x, y) < r_circle:
            inside_circle.append(number)
    if kicking:
        inside_circle.sort(key=lambda n: math.hypot(*poses[n]))
        illegal.extend(inside_circle[1:])
    else:
        illegal.extend(inside_circle)
    return sorted(illegal)


def return_position(
    field_map: Field,
    rule: ReturnRule,
    removed_at_y: float,
    ball_y: float,
    taken: list[tuple[float, float]],
) -> tuple[float, float, float]:
    """Team-frame pose where a robot comes back from a penalty.

    ``removed_at_y``: y (team frame) where it was taken off; ``ball_y``: ball y (team frame);
    ``taken``: team-frame spots already used by other returning robots (they are avoided by
    stepping 0.4 m toward the own goal).
    """
    if rule == "spl2025":
        side = 1.0 if removed_at_y >= 0 else -1.0
    elif rule == "spl2010":
        side = -1.0 if ball_y > 0 else 1.0
        if ball_y == 0.0:
            side = 1.0 if removed_at_y >= 0 else -1.0
    else:
        raise ValueError(f"unknown return rule {rule!r}; valid: {list(RETURN_RULES)}")
    # the two spots a robot knows (cognition.localization.places): +y touchline first
    x, y, theta = return_poses(field_map, rule)[0 if side > 0 else 1]
    while any(math.hypot(x - tx, y - ty) < 0.35 for tx, ty in taken):
        x -= 0.4
    return (float(x), float(y), float(theta))
