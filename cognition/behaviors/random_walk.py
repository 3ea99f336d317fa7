"""Random-walk players: the baseline opponents of the scripted team.

A :class:`RandomWalkBrain` stands outside PLAYING. While PLAYING it walks a random command
(forward, sideways and turn speeds drawn uniformly within the walking limits) and draws a new
one every 1 to 3 s from its own generator (``context.rng``), so a seed gives the same walk.
It never kicks on purpose; it does push the ball when it walks into it. It reads its true pose
(``uses_oracle``) only to turn back toward the centre near the field lines, so that it is not
penalised for leaving the field all the time.
"""

from __future__ import annotations

import math

import numpy as np

from cognition.brain import BrainContext
from cognition.gamestate import GameStateId
from cognition.oracle import OracleInput
from cognition.representations import BrainOutput, MotionRequest, SensorFrame, WalkRequest


class RandomWalkBrain:
    """A robot that walks at random (module docstring)."""

    uses_oracle = True

    def __init__(self, margin: float = 0.4) -> None:
        self.margin = margin
        """Distance (m) inside the field lines at which the robot turns back toward the centre."""
        self.context: BrainContext | None = None
        self.walk = WalkRequest()
        self._until = 0.0

    def reset(self, context: BrainContext) -> None:
        """Take the brain's random stream."""
        self.context = context
        self.rng = context.rng if context.rng is not None else np.random.default_rng(context.player_number)
        self.walk = WalkRequest()
        self._until = 0.0

    def think(self, frame: SensorFrame, oracle: OracleInput | None) -> BrainOutput:
        """Walk the current random command; draw a new one when it is due."""
        if self.context is None or oracle is None:
            raise RuntimeError("RandomWalkBrain.think needs reset() and the oracle input")
        if frame.game.state != GameStateId.PLAYING or frame.penalty or frame.fallen or frame.picked_up:
            return BrainOutput(motion=MotionRequest())
        f = self.context.field
        me = oracle.self_pose
        if abs(me.x) > f.half_length - self.margin or abs(me.y) > f.half_width - self.margin:
            to_centre = math.atan2(-me.y, -me.x) - me.theta
            turn = math.atan2(math.sin(to_centre), math.cos(to_centre))
            return BrainOutput(motion=MotionRequest(walk=WalkRequest(forward=0.15, turn=1.5 * turn)))
        if frame.time >= self._until:
            g = self.rng
            self.walk = WalkRequest(
                forward=float(g.uniform(-0.15, 0.25)),
                left=float(g.uniform(-0.15, 0.15)),
                turn=float(g.uniform(-1.0, 1.0)),
            )
            self._until = frame.time + float(g.uniform(1.0, 3.0))
        return BrainOutput(motion=MotionRequest(walk=self.walk))
