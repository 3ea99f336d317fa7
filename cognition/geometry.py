"""Small pure geometry helpers shared by the robot's brain and the simulator.

Angles are in radians; poses are (x m, y m, theta rad) in whatever frame the caller uses.
"""

from __future__ import annotations

import math


def wrap_angle(a: float) -> float:
    """Wrap an angle (rad) to (-pi, pi]."""
    a = math.fmod(a + math.pi, 2.0 * math.pi)
    if a <= 0.0:
        a += 2.0 * math.pi
    return a - math.pi
