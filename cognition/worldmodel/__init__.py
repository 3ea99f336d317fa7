"""The world model: what a robot believes about the ball, the goals, obstacles and its team.

Each model is chosen by name (:func:`make_ball_model`, :func:`make_obstacle_model`), like the
localization variants.

========================================  ================================================
module                                    content
========================================  ================================================
:mod:`cognition.worldmodel.messages`      the team message (58 bytes), checked on receipt
:mod:`cognition.worldmodel.kalman_ball`   functional core of the Darmstadt Kalman ball
:mod:`cognition.worldmodel.ball`          the Kalman ball module (percepts, odometry, team)
:mod:`cognition.worldmodel.hypotheses`    multi-hypothesis ball with CMU's three levels
:mod:`cognition.worldmodel.team`          teammates' reports and the fused team ball
:mod:`cognition.worldmodel.goal`          goal pose from a scan's two posts (CMU IV.B)
:mod:`cognition.worldmodel.obstacles`     occupancy grid and 72-sector obstacles (Darmstadt VII)
========================================  ================================================
"""

from __future__ import annotations

from cognition.worldmodel.ball import KalmanBallModel
from cognition.worldmodel.hypotheses import BallHypotheses
from cognition.worldmodel.obstacles import ObstacleGrid, ObstacleSectors

BALL_MODELS: tuple[str, ...] = ("kalman", "hypotheses")
"""Ball models by name: the Darmstadt Kalman ball or the CMU multi-hypothesis ball."""
OBSTACLE_MODELS: tuple[str, ...] = ("grid", "sectors")
"""Obstacle models by name: the Darmstadt occupancy grid or the 72-sector model."""


def make_ball_model(name: str, ball_radius: float) -> KalmanBallModel | BallHypotheses:
    """The ball model called ``name`` (one of :data:`BALL_MODELS`); ``ball_radius`` in m."""
    if name == "kalman":
        return KalmanBallModel(ball_radius)
    if name == "hypotheses":
        return BallHypotheses()
    raise ValueError(f"unknown ball model {name!r}; valid: {list(BALL_MODELS)}")


def make_obstacle_model(name: str) -> ObstacleGrid | ObstacleSectors:
    """The obstacle model called ``name`` (one of :data:`OBSTACLE_MODELS`)."""
    if name == "grid":
        return ObstacleGrid()
    if name == "sectors":
        return ObstacleSectors()
    raise ValueError(f"unknown obstacle model {name!r}; valid: {list(OBSTACLE_MODELS)}")


__all__ = ["BALL_MODELS", "OBSTACLE_MODELS", "make_ball_model", "make_obstacle_model"]
