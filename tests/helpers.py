"""Shared test helpers: simple brains, short-match configurations, polygon clipping for painted images."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np

from cognition.brain import BrainContext
from cognition.camera import CameraMatrix
from cognition.oracle import OracleInput
from cognition.representations import BrainOutput, MotionRequest, SensorFrame, WalkRequest
from teamsim.match import MatchConfig
from teamsim.referee import RefereeParams


class ScriptBrain:
    """A brain whose walk command is a function of (frame, oracle); records its frames."""

    uses_oracle = True

    def __init__(self, policy: Callable[[SensorFrame, OracleInput], WalkRequest] | None = None):
        self.policy = policy
        self.frames: list[SensorFrame] = []
        self.oracles: list[OracleInput] = []
        self.context: BrainContext | None = None

    def reset(self, context: BrainContext) -> None:
        self.context = context

    def think(self, frame: SensorFrame, oracle: OracleInput | None) -> BrainOutput:
        assert oracle is not None
        self.frames.append(frame)
        self.oracles.append(oracle)
        walk = self.policy(frame, oracle) if self.policy is not None else WalkRequest()
        return BrainOutput(motion=MotionRequest(walk=walk))


def short_config(**referee: object) -> MatchConfig:
    """A 5 v 5 config with short phases, for referee tests."""
    params = replace(RefereeParams(half_seconds=60.0, ready_seconds=10.0, halftime_seconds=2.0), **referee)
    return MatchConfig(referee=params)


def clip_front(camera: CameraMatrix, poly: np.ndarray, near: float = 0.05) -> np.ndarray:
    """Sutherland-Hodgman clip of a robot-frame polygon (N x 3, m) to camera depth >= ``near`` (m)."""
    depth = (poly - camera.position) @ camera.rotation[:, 0]
    out = []
    for k in range(len(poly)):
        a, b = poly[k], poly[(k + 1) % len(poly)]
        da, db = depth[k], depth[(k + 1) % len(poly)]
        if da >= near:
            out.append(a)
        if (da >= near) != (db >= near):
            out.append(a + (b - a) * (near - da) / (db - da))
    return np.array(out).reshape(-1, 3)
