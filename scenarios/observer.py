"""The observer: a study's robot whose cognition runs on its own frames while the script moves it.

An :class:`Observer` runs the full cognition stack (:class:`~cognition.worldmodel.beliefs.CognitionBeliefs`:
localization, Kalman ball, team ball, goal and obstacle models) on its sensor frames, exactly as
a scripted player does, but its body follows the experiment's script, which reads the ground
truth: it stands or walks a loop, and its head sweeps or follows the true ball. Its actions
therefore never depend on its beliefs, so every variant of a study sees the same world for a
seed (the paired design of :mod:`scenarios.sweep`). The localization experiments of the CMU and
Darmstadt papers use robots moved the same way (a fixed path, an active head).

=========  =====================================================================================
option     behaviour
=========  =====================================================================================
stand      stands where it is; while penalised or carried it does nothing
loop       walks the loop's corners in turn while PLAYING (0.2 m/s, turning toward the next one)
sweep      head yaw 1.4 sin(0.8 t) rad, pitch 0.35 rad (both cameras sweep the field)
ball       head aimed at the true ball (pitch 0.35 rad)
=========  =====================================================================================
"""

from __future__ import annotations

import math

import numpy as np

from cognition.brain import BrainContext
from cognition.gamestate import GameStateId
from cognition.oracle import OracleInput
from cognition.pipeline import CognitionConfig
from cognition.representations import BrainOutput, HeadRequest, MotionRequest, RobotPose, SensorFrame, WalkRequest
from cognition.worldmodel.beliefs import Beliefs, CognitionBeliefs

LOOP_SPEED = 0.2
"""Forward speed on the loop (m/s)."""
CORNER_RADIUS = 0.25
"""A loop corner counts as reached within this distance (m)."""


class Observer:
    """A scripted body around a real cognition stack (module docstring)."""

    uses_oracle = True  # the script steers by the truth; the cognition stack never sees it

    def __init__(
        self,
        cognition: CognitionConfig,
        drive: str = "stand",
        head: str = "sweep",
        loop: tuple[tuple[float, float], ...] = (),
        start: tuple[float, float, float] | None = None,
    ):
        """``cognition`` is the stack under study (:class:`~cognition.pipeline.CognitionConfig`);
        ``loop`` corners and ``start`` pose are in the robot's team frame (m, rad)."""
        self.cognition = cognition
        self.drive = drive
        self.head = head
        self.loop = loop
        self.start = start
        self.leg = 0
        self.provider: CognitionBeliefs | None = None
        self.beliefs: Beliefs | None = None
        """The latest beliefs."""
        self.pose: RobotPose | None = None
        """The latest pose estimate (the match records its error)."""

    def reset(self, context: BrainContext) -> None:
        """Build the cognition stack; a known start pose seeds the localization."""
        self.provider = CognitionBeliefs(context, self.cognition)
        if self.start is not None and self.provider.localizer is not None:
            self.provider.localizer.on_placement(np.array([self.start], dtype=np.float64))
        self.leg = 0
        self.beliefs = self.pose = None

    def rejected_inputs(self) -> dict[str, int]:
        """Inputs the cognition stack could not use, by kind."""
        return self.provider.rejected_inputs() if self.provider is not None else {}

    def think(self, frame: SensorFrame, oracle: OracleInput | None) -> BrainOutput:
        """Update the beliefs on the frame; move as the script says."""
        if self.provider is None or oracle is None:
            raise RuntimeError("Observer.think needs reset() first and the oracle input")
        me = oracle.self_pose
        self.beliefs = self.provider.update(frame, oracle)  # only a declared oracle module reads it
        self.pose = self.beliefs.pose
        if self.head == "ball":
            bearing = math.remainder(math.atan2(oracle.ball_y - me.y, oracle.ball_x - me.x) - me.theta, 2 * math.pi)
            head = HeadRequest(yaw=max(-1.5, min(1.5, bearing)), pitch=0.35)
        else:
            head = HeadRequest(yaw=1.4 * math.sin(0.8 * frame.time), pitch=0.35)
        walk = WalkRequest()
        if self.drive == "loop" and self.loop and frame.game.state == GameStateId.PLAYING and not frame.penalty:
            tx, ty = self.loop[self.leg]
            if math.hypot(tx - me.x, ty - me.y) < CORNER_RADIUS:
                self.leg = (self.leg + 1) % len(self.loop)
                tx, ty = self.loop[self.leg]
            err = math.remainder(math.atan2(ty - me.y, tx - me.x) - me.theta, 2 * math.pi)
            walk = WalkRequest(forward=LOOP_SPEED if abs(err) < 0.5 else 0.0, turn=max(-0.8, min(0.8, 1.5 * err)))
        return BrainOutput(MotionRequest(walk=walk, head=head))
