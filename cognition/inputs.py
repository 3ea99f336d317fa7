"""Sensor input a brain cannot trust: what is dropped, and how it is counted.

A real robot's sensors glitch (a NaN from a joint sensor, a walking engine that reports a
jump) and logs and users hand cognition data of every kind. A single non-finite odometry
frame used to poison every particle filter for good, and the Kalman ball and the goal model
with it. :class:`InputCheck` sits where a frame enters cognition
(:class:`~cognition.worldmodel.beliefs.CognitionBeliefs` and every
:class:`~cognition.localization.base.Localizer`) and replaces unusable parts of the frame by
the safest reading, counting each replacement by kind and warning once per kind:

=====================  ==================================================================  ==============
kind                   rejected when                                                        replaced by
=====================  ==================================================================  ==============
odometry_nonfinite     dx, dy or dtheta is NaN or infinite                                  no motion
odometry_implausible   the motion exceeds :data:`MAX_ODOMETRY_SPEED` (m/s) or               no motion
                       :data:`MAX_ODOMETRY_TURN_RATE` (rad/s) over the time since the
                       previous frame (at least :data:`MIN_FRAME_SECONDS`)
=====================  ==================================================================  ==============

The limits are sanity limits far beyond any walking robot (a NAO walks at about 0.3 m/s and
turns at about 1.5 rad/s), not a motion model. Percepts are checked where they are built
(:class:`~cognition.percepts.Percepts` raises :class:`~cognition.percepts.PerceptError`),
team messages where they are decoded (:mod:`cognition.worldmodel.team`).
Odometry is in the robot frame of the previous frame (m, rad); times in s.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from dataclasses import replace

from cognition.representations import OdometryReading, SensorFrame

MAX_ODOMETRY_SPEED = 5.0
"""Largest believable translation speed of reported odometry (m/s)."""
MAX_ODOMETRY_TURN_RATE = 20.0
"""Largest believable rotation rate of reported odometry (rad/s)."""
MIN_FRAME_SECONDS = 0.1
"""The time a frame's odometry may cover is taken as at least this (s): the first frame and
frames that arrive in bursts are not judged by a tiny interval."""

_NO_MOTION = OdometryReading(0.0, 0.0, 0.0)


class InputCheck:
    """Checks each frame's odometry (module table) and counts what it replaced."""

    def __init__(self, owner: str = "cognition") -> None:
        self.owner = owner
        """Named in the warnings (e.g. ``localization`` or ``cognition``)."""
        self.rejected: dict[str, int] = {}
        """Replacements so far, by kind."""
        self._last_time: float | None = None

    def frame(self, frame: SensorFrame) -> SensorFrame:
        """``frame``, or a copy with its unusable parts replaced (and counted)."""
        o = frame.odometry
        dt = MIN_FRAME_SECONDS
        if self._last_time is not None and math.isfinite(frame.time):
            dt = frame.time - self._last_time
            dt = MIN_FRAME_SECONDS if dt < MIN_FRAME_SECONDS else dt  # max(dt, MIN_FRAME_SECONDS)
        if math.isfinite(frame.time):
            self._last_time = frame.time
        if not (math.isfinite(o.dx) and math.isfinite(o.dy) and math.isfinite(o.dtheta)):
            return self._reject(frame, "odometry_nonfinite", f"non-finite odometry {o}")
        if math.hypot(o.dx, o.dy) > MAX_ODOMETRY_SPEED * dt or abs(o.dtheta) > MAX_ODOMETRY_TURN_RATE * dt:
            return self._reject(frame, "odometry_implausible", f"odometry {o} over {dt:.3f} s exceeds the limits")
        return frame

    def _reject(self, frame: SensorFrame, kind: str, what: str) -> SensorFrame:
        if kind not in self.rejected:
            warnings.warn(
                f"{self.owner} of player {frame.player_number}: {what} at t={frame.time:.2f} s replaced by no "
                f"motion (further {kind} inputs are counted, not reported)",
                RuntimeWarning,
                stacklevel=3,
            )
        self.rejected[kind] = self.rejected.get(kind, 0) + 1
        return replace(frame, odometry=_NO_MOTION)


def merge_counts(*counts: Mapping[str, int]) -> dict[str, int]:
    """The sum of several kind -> count mappings, sorted by kind."""
    out: dict[str, int] = {}
    for c in counts:
        for k, v in c.items():
            out[k] = out.get(k, 0) + v
    return dict(sorted(out.items()))
