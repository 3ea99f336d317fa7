"""The modules of a cognition frame and the blackboard of representations they share.

Each class here is one provider of :mod:`cognition.pipeline`'s module table: it wraps one model
of the world model, localization or vision, reads the representations its declaration requires
and uses from the :class:`Blackboard`, and writes the one it provides. ``run(board)`` is the
whole per-frame interface; everything a module keeps between frames is its own. The
``beliefs`` providers (assembling :class:`~cognition.worldmodel.representations.Beliefs`, or
reading the ground truth) live in :mod:`cognition.worldmodel.beliefs`, which also enters every
built-in class into :data:`MODULES`, the factory of each (slot, provider) of the table;
:func:`register_provider` adds a team's own.

Frames: the robot pose and the team ball are in the team frame (m, rad); the ball carries both
frames; obstacles, the goal and the gaze target are in the robot frame (m).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Protocol

import numpy as np

from cognition.brain import BrainContext
from cognition.inputs import InputCheck
from cognition.localization import Localizer, make_localizer
from cognition.oracle import OracleInput
from cognition.pipeline import DECLARATIONS, FIXED_SLOTS, OBSERVATIONS, CognitionConfig, Declaration, providers
from cognition.representations import BallModel, RobotPose, SensorFrame
from cognition.vision import Vision
from cognition.worldmodel.ball import KalmanBallModel
from cognition.worldmodel.goal import GoalEstimate, GoalModel
from cognition.worldmodel.hypotheses import BallHypotheses
from cognition.worldmodel.messages import TeamMessage
from cognition.worldmodel.obstacles import ObstacleGrid, ObstacleModel, ObstacleSectors
from cognition.worldmodel.representations import Beliefs
from cognition.worldmodel.team import TeamBallEstimate, TeamState, carpet_limits, team_ball


@dataclass(eq=False, slots=True)
class Blackboard:
    """The representations of the current frame (module table of :mod:`cognition.pipeline`).

    ``frame`` is the ``sensor frame``; the input check replaces it with one whose odometry can
    be trusted (``odometry``), and vision with one that carries the percepts of its camera image
    (``percepts``). A slot nothing provided keeps its empty value.
    """

    frame: SensorFrame = None  # type: ignore[assignment]  # set by start() before any module runs
    """The sensor frame of this cognition frame."""
    ground_truth: OracleInput | None = None
    """The ground truth, for declared oracle providers only (``None`` for every other brain)."""
    pose: RobotPose | None = None
    """``robot pose``: the own pose estimate (team frame)."""
    teammates: list[TeamMessage] | None = None
    """``teammates``: the latest valid message of every teammate heard from recently."""
    heard: dict[int, float] | None = None
    """With ``teammates``: when each teammate's message arrived (s, by player number)."""
    ball: BallModel | None = None
    """``ball``: the own ball (robot and team frame)."""
    look_at: tuple[float, float] | None = None
    """``look at``: a suspicious ball hypothesis to check (robot frame, m)."""
    team_ball: TeamBallEstimate | None = None
    """``team ball``: the fused team ball (team frame)."""
    obstacles: ObstacleModel | None = None
    """``obstacles``: the obstacle model's output (robot frame)."""
    goal: GoalEstimate | None = None
    """``goal``: the goal of the latest head scans (robot frame)."""
    beliefs: Beliefs | None = None
    """``beliefs``: everything a behaviour reads (:class:`~cognition.worldmodel.representations.Beliefs`)."""

    def start(self, frame: SensorFrame, ground_truth: OracleInput | None) -> None:
        """Begin a frame: the new inputs; every provided representation is rewritten by its module."""
        self.frame = frame
        self.ground_truth = ground_truth


class Module(Protocol):
    """One provider of the frame: ``run`` reads and writes the blackboard."""

    def run(self, board: Blackboard) -> None:
        """Run on the current frame."""
        ...


ModuleFactory = Callable[[BrainContext, CognitionConfig], Module]
"""Builds one robot's module from its context and its cognition configuration."""

MODULES: dict[tuple[str, str], ModuleFactory] = {}
"""The module factory of every (slot, provider) of :data:`cognition.pipeline.DECLARATIONS`
(filled by :mod:`cognition.worldmodel.beliefs` for the built-in providers, and by
:func:`register_provider`)."""


def register_provider(
    slot: str, name: str, factory: ModuleFactory, requires: tuple[str, ...], uses: tuple[str, ...] = ()
) -> None:
    """Add the provider ``name`` of ``slot`` (one of the module table's configurable slots): a
    ``factory(context, config)`` of modules with ``run(board)`` that write the slot's
    representation, and what they require and use (representation names of the table).

    After this, ``CognitionConfig(**{slot: name})`` plans and runs it like a built-in provider
    (``stage`` and profile row of the slot). Register in every process that builds brains (a
    study's workers import the module that registers). A name that exists already is an error.
    """
    if slot not in DECLARATIONS or slot in FIXED_SLOTS:
        raise ValueError(f"register_provider: unknown slot {slot!r}; valid: {list(CognitionConfig.SLOTS)}")
    if name in providers(slot):
        raise ValueError(f"register_provider: {slot} already has a provider {name!r}")
    known = (
        {d.provides for opts in DECLARATIONS.values() for d in opts.values()}
        | {r for carried in OBSERVATIONS.values() for r in carried}
        | {"ground truth"}
    )
    for rep in (*requires, *uses):
        if rep not in known:
            raise ValueError(f"register_provider: unknown representation {rep!r}; valid: {sorted(known)}")
    if not callable(factory):
        raise TypeError(f"register_provider: factory must be callable, got {factory!r}")
    first = next(iter(DECLARATIONS[slot].values()))
    DECLARATIONS[slot][name] = Declaration(first.stage, tuple(requires), first.provides, tuple(uses))
    MODULES[(slot, name)] = factory


def unregister_provider(slot: str, name: str) -> None:
    """Remove a provider added by :func:`register_provider` (built-in providers stay)."""
    if (slot, name) in _BUILT_IN:
        raise ValueError(f"unregister_provider: {slot}={name!r} is built in")
    DECLARATIONS.get(slot, {}).pop(name, None)
    MODULES.pop((slot, name), None)


_BUILT_IN = frozenset((slot, name) for slot, opts in DECLARATIONS.items() for name in opts)
"""Every (slot, provider) of the module table as shipped."""


class InputCheckModule:
    """``input check``: non-finite or implausible odometry becomes no motion (:mod:`cognition.inputs`)."""

    def __init__(self, context: BrainContext, config: CognitionConfig) -> None:
        self.check = InputCheck("cognition")

    def run(self, board: Blackboard) -> None:
        board.frame = self.check.frame(board.frame)


class VisionModule:
    """``vision``: the percepts of the frame's camera image (DNT 3 or NimbRo 5, by the config)."""

    def __init__(self, context: BrainContext, config: CognitionConfig) -> None:
        self.context = context
        self.params = config.vision_params
        self.vision: Vision | None = None
        """The pipeline, built at the first frame that carries an image."""

    def run(self, board: Blackboard) -> None:
        frame = board.frame
        image = frame.image
        if frame.percepts is not None or image is None:
            return
        c = self.context
        if self.vision is None:
            self.vision = Vision(self.params, c.field, c.colours or "modern", c.team)
        o = frame.odometry
        # the home team (0) defends the scheme's own_goal colour in the first half; sides switch at half time
        own_goal = int((c.team == 1) != (frame.game.first_half == 0))
        percepts = self.vision.detect(
            image.pixels, image.camera, image.time, frame.head.yaw_rate, frame.head.pitch_rate,
            walking=o.dx != 0.0 or o.dy != 0.0 or o.dtheta != 0.0, own_goal=own_goal,
        )  # fmt: skip
        board.frame = replace(frame, percepts=percepts)


class LocalizationModule:
    """``localization``: the configured variant (:func:`cognition.localization.make_localizer`).

    :attr:`cpu_seconds` sums the CPU time (s, this thread) of its updates, so that a study can
    report the cost of a variant per update. The ``oracle`` variant reads the ground truth.
    """

    def __init__(self, context: BrainContext, config: CognitionConfig) -> None:
        self.variant = config.localization
        rng = context.rng if context.rng is not None else np.random.default_rng(context.player_number)
        self.localizer: Localizer = make_localizer(
            config.localization,
            context.field,
            params=config.localization_params,
            rng=rng,
            player_number=context.player_number,
            players_per_team=context.players_per_team,
        )
        self.cpu_seconds = 0.0
        self._oracle = config.localization == "oracle"

    def run(self, board: Blackboard) -> None:
        truth = None
        if self._oracle:
            g = board.ground_truth
            truth = None if g is None else (g.self_pose.x, g.self_pose.y, g.self_pose.theta)
        started = time.thread_time()
        board.pose = self.localizer.update(board.frame, truth, checked=True)  # the input check ran
        self.cpu_seconds += time.thread_time() - started


class TeamMessagesModule:
    """``team messages``: the teammates' latest valid messages (:class:`~cognition.worldmodel.team.TeamState`)."""

    def __init__(self, context: BrainContext, config: CognitionConfig) -> None:
        self.team = TeamState(context.player_number, context.field)

    def run(self, board: Blackboard) -> None:
        board.teammates = self.team.update(board.frame)
        board.heard = {number: t for number, (t, _) in self.team.latest.items()}


class BallModule:
    """``ball``: the Kalman ball (Darmstadt V) on the percepts, odometry and teammates' balls."""

    def __init__(self, context: BrainContext, config: CognitionConfig) -> None:
        radius = 0.5 * context.field.dims.ball_diameter
        self.model = KalmanBallModel(radius, config.ball_params, limits=carpet_limits(context.field))

    def run(self, board: Blackboard) -> None:
        board.ball = self.model.update(board.frame, board.pose, board.teammates or ())


class HypothesesModule:
    """``hypotheses``: CMU IV.A's multi-hypothesis ball; its suspicious hypothesis is the gaze target."""

    def __init__(self, context: BrainContext, config: CognitionConfig) -> None:
        self.model = BallHypotheses(config.hypotheses_params)

    def run(self, board: Blackboard) -> None:
        board.look_at = self.model.update(board.frame, board.pose, board.teammates or ()).look_at


class TeamBallModule:
    """``team ball``: the own ball and the teammates' balls fused (:func:`~cognition.worldmodel.team.team_ball`)."""

    def __init__(self, context: BrainContext, config: CognitionConfig) -> None:
        self.player_number = context.player_number
        self.limits = carpet_limits(context.field)
        self.terms: dict[int, tuple[TeamMessage, float, tuple[float, float, float, float, float] | None]] = {}
        """The teammates' messages' terms of the fusion (the memo of :func:`team_ball`)."""

    def run(self, board: Blackboard) -> None:
        assert board.ball is not None and board.pose is not None
        mates = board.teammates or ()
        terms = self.terms
        board.team_ball = team_ball(board.ball, board.pose, self.player_number, mates, limits=self.limits, terms=terms)
        if len(terms) > 2 * len(mates) + 8:  # forget messages that no longer count
            self.terms = {k: v for k, v in terms.items() if any(v[0] is m for m in mates)}


class ObstacleModule:
    """``obstacles``: the 72-sector model or the occupancy grid (Darmstadt VII)."""

    def __init__(self, context: BrainContext, config: CognitionConfig) -> None:
        self.model: ObstacleGrid | ObstacleSectors = (
            ObstacleGrid(config.obstacle_grid_params) if config.obstacles == "grid" else ObstacleSectors()
        )

    def run(self, board: Blackboard) -> None:
        f = board.frame
        board.obstacles = self.model.update(f.time, f.odometry, f.percepts)


class GoalModule:
    """``goal``: the goal from the posts of the latest head scans (CMU IV.B), moved with odometry."""

    def __init__(self, context: BrainContext, config: CognitionConfig) -> None:
        dims = context.field.dims
        self.model = GoalModel(dims.goal_inner_width + dims.goal_post_diameter, config.goal_params)
        self.dt = 1.0 / context.cognition_hz

    def run(self, board: Blackboard) -> None:
        f = board.frame
        o = f.odometry
        self.model.move_robot(o.dx, o.dy, o.dtheta, self.dt)
        self.model.add_percepts(f.percepts)
        board.goal = self.model.estimate()
