"""A match: the world, the referee, the team channel and one brain per robot.

Physics runs at ``physics.physics_hz`` (100 Hz by default) and cognition at
``cognition_hz`` (30 Hz). At each cognition frame every robot gets a
:class:`~cognition.representations.SensorFrame` (odometry since its previous frame, head
state, the GameController packet, received team messages, picked-up and fallen signals),
its brain answers with a motion request and an optional team message, and the body executes
that request until the next frame. Only brains that declare ``uses_oracle`` also get the
ground truth (:class:`~cognition.oracle.OracleInput`).

All randomness comes from one ``numpy.random.SeedSequence`` built from ``seed``, spawned
into one generator per consumer in a fixed order, so a seed and a configuration give an
identical match.

=======================  ==============  ============  =============================================
MatchConfig field        default         range         meaning
=======================  ==============  ============  =============================================
seed                     0               [0, 2^63-1]   root of all randomness
players_per_team         5               [1, 7]        robots per team
field                    spl2025                       field preset (spl2025, spl2013, kidsize)
colours                  classic                       colour scheme (classic, modern, kidsize)
cognition_hz             30              (0, 1000]     cognition frames per second (<= physics_hz)
physics                  PhysicsParams                 world and robot bodies
referee                  RefereeParams                 rules and timing (half_seconds, rules, ...)
odometry                 OdometryParams                odometry error model
channel                  ChannelParams                 team-message delay, loss, budget
observation              percepts                      what sensor frames carry: ``percepts`` (synthesized
                                                       by the camera model), ``images`` (rendered camera
                                                       images with their camera matrix) or ``none``
percepts                 default                       PerceptParams or a preset name (ideal, default, harsh);
                                                       with ``images``, its angular noise sets the error of
                                                       the camera matrices (below)
images                   default                       ImageParams or a preset name (ideal, default, harsh)
camera                   CameraRig                     head height and the two NAO cameras (320 x 240)
events                   ()                            scripted events (kidnap, penalties, ...) for players
                                                       of these teams, on this field's carpet
cognition                None                          the default brains' cognition frame: ``None``: scripted
                                                       players on truth beliefs (the oracle baseline); a
                                                       CognitionConfig (or a mapping): which provider fills
                                                       each slot (``localization``, ``ball``, ``obstacles``,
                                                       ``vision``, ...) and their parameters
                                                       (:mod:`cognition.pipeline`); its localization's
                                                       ``return_rule`` is taken from ``referee.rules``
players                  scripted                      default brains: ``scripted`` (team play on beliefs:
                                                       truth without ``cognition``, else that cognition
                                                       frame) or ``random`` (random walkers)
=======================  ==============  ============  =============================================

The numbers are checked against their ranges, and every section (``physics``, ``referee``,
...) must be an instance of its parameters class, when the config is built
(:func:`cognition.params.check_ranges`); each section checks its own fields the same way.

Camera images are taken ``percepts.latency`` seconds before the cognition frame that
receives them (rounded to physics steps); :attr:`cognition.percepts.Percepts.time` and
:attr:`cognition.camera.CameraImage.time` say when.

With ``observation="images"`` an image's camera matrix is the robot's estimate, off from the
true camera by the share of the Darmstadt angular noise of ``percepts`` that percepts of one
image have in common (:func:`teamsim.images.camera_errors`); ``shared_noise_fraction=0`` (or
the ``ideal`` percepts preset) gives exact camera matrices.
"""

from __future__ import annotations

import math
import time as wallclock
from collections import deque
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from dataclasses import field as dataclass_field
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from cognition.brain import Brain, BrainContext, rejected_inputs, think_all
from cognition.camera import CameraImage, CameraRig
from cognition.field import COLOUR_SCHEMES, FIELD_PRESETS, Field, make_colour_scheme, make_field
from cognition.gamestate import GameControlData, GameStateId
from cognition.inputs import merge_counts
from cognition.oracle import OracleInput, OraclePose
from cognition.percepts import Percepts
from cognition.pipeline import CognitionConfig, PipelineError, plan
from cognition.representations import MotionRequest, RobotPose, SensorFrame
from teamsim import walking as wk
from teamsim.brains import BrainFactory, LocalizationErrors, default_brains
from teamsim.channel import ChannelParams, TeamChannel
from teamsim.events import (
    EventLog,
    ForceFall,
    ForcePenalty,
    Kidnap,
    PlaceBall,
    ScriptedEvent,
    event_from_mapping,
)
from teamsim.gc_referee import GameControllerReferee
from teamsim.image_params import ImageParams
from teamsim.images import ImageRenderer, camera_errors
from teamsim.odometry import OdometryModel, OdometryParams, TrueOdometry
from teamsim.params import Range, Ranges, check_choice, check_ranges, from_mapping, positive
from teamsim.percept_params import PerceptParams
from teamsim.percepts import PerceptSynthesizer, Scene
from teamsim.profile import MatchProfile
from teamsim.referee import Referee, RefereeParams
from teamsim.robot import get_position, get_velocity
from teamsim.state import WorldSnapshot
from teamsim.summary import MatchSummary as MatchSummary  # re-exported
from teamsim.world import PhysicsParams, World

MAX_PLAYERS_PER_TEAM = 7
OBSERVATIONS = ("percepts", "images", "none")
"""Valid values of :attr:`MatchConfig.observation`."""
PLAYERS = ("scripted", "random")
"""Valid values of :attr:`MatchConfig.players` (the default brains)."""


@dataclass(frozen=True)
class MatchConfig:
    """Everything that defines a match (see the module table)."""

    seed: int = 0
    players_per_team: int = 5
    field: str = "spl2025"
    colours: str = "classic"
    cognition_hz: float = 30.0
    physics: PhysicsParams = dataclass_field(default_factory=PhysicsParams)
    referee: RefereeParams = dataclass_field(default_factory=RefereeParams)
    odometry: OdometryParams = dataclass_field(default_factory=OdometryParams)
    channel: ChannelParams = dataclass_field(default_factory=ChannelParams)
    observation: str = "percepts"
    percepts: PerceptParams = dataclass_field(default_factory=PerceptParams)
    images: ImageParams = dataclass_field(default_factory=ImageParams)
    camera: CameraRig = dataclass_field(default_factory=CameraRig)
    events: tuple[ScriptedEvent, ...] = ()
    cognition: CognitionConfig | None = None
    players: str = "scripted"

    RANGES: ClassVar[Ranges] = {
        "seed": Range(0, 2**63 - 1),
        "players_per_team": Range(1, MAX_PLAYERS_PER_TEAM),
        "cognition_hz": positive(1000.0),
    }

    def __post_init__(self) -> None:
        if isinstance(self.percepts, str):
            object.__setattr__(self, "percepts", PerceptParams.preset(self.percepts))
        if isinstance(self.images, str):
            object.__setattr__(self, "images", ImageParams.preset(self.images))
        if isinstance(self.cognition, Mapping):
            object.__setattr__(self, "cognition", CognitionConfig.from_mapping(self.cognition, "MatchConfig.cognition"))
        check_ranges(self)  # numbers, and every section an instance of its parameters class
        check_choice("MatchConfig", "field", self.field, FIELD_PRESETS)
        check_choice("MatchConfig", "colours", self.colours, COLOUR_SCHEMES)
        check_choice("MatchConfig", "observation", self.observation, OBSERVATIONS)
        if self.players == "oracle":
            raise ValueError(self._removed_players_message())
        check_choice("MatchConfig", "players", self.players, PLAYERS)
        if self.cognition is not None and self.players != "random":
            try:  # the frames this match delivers must carry what the configured modules require
                plan(self.cognition, self.observation)
            except PipelineError as exc:
                raise ValueError(f"MatchConfig.cognition: {exc}") from None
        if self.cognition_hz > self.physics.physics_hz:
            raise ValueError(
                f"MatchConfig.cognition_hz ({self.cognition_hz}) must not exceed physics_hz ({self.physics.physics_hz})"
            )
        self._check_events()

    def _removed_players_message(self) -> str:
        """Why ``players="oracle"`` is refused, and what plays in its place with this configuration."""
        if self.cognition is None:
            instead = "players='scripted' with no cognition: scripted team play on truth beliefs"
        else:
            instead = (
                f"players='scripted' with this cognition ({self.cognition.summary()}): scripted team play "
                "on that cognition stack"
            )
        return (
            f"MatchConfig.players={self.players!r}: the oracle players were removed; use {instead} "
            f"(valid players: {list(PLAYERS)})"
        )

    def _check_events(self) -> None:
        """Every event is a scripted event for a player of these teams, on this field's carpet."""
        if not isinstance(self.events, tuple | list):
            raise TypeError(f"MatchConfig.events must be a tuple of scripted events, got {self.events!r}")
        dims = FIELD_PRESETS[self.field]
        reach_x = dims.length / 2 + dims.border_strip
        reach_y = dims.width / 2 + dims.border_strip
        for i, ev in enumerate(self.events):
            where = f"MatchConfig.events[{i}]"
            if not isinstance(ev, Kidnap | PlaceBall | ForcePenalty | ForceFall):
                raise TypeError(f"{where}: unknown scripted event {ev!r}")
            if not isinstance(ev, PlaceBall) and ev.number > self.players_per_team:
                raise ValueError(
                    f"{where}: {type(ev).__name__} names player {ev.number} but teams have {self.players_per_team}"
                )
            spot = ev.pose[:2] if isinstance(ev, Kidnap) and ev.pose is not None else None
            if isinstance(ev, PlaceBall):
                spot = (ev.x, ev.y)
            if spot is not None and not (abs(spot[0]) <= reach_x and abs(spot[1]) <= reach_y):
                raise ValueError(
                    f"{where}: {type(ev).__name__} at ({spot[0]}, {spot[1]}) is off the carpet of the {self.field} "
                    f"field (|x| <= {reach_x:g} m, |y| <= {reach_y:g} m)"
                )

    @classmethod
    def from_mapping(cls, data: Mapping[str, Any]) -> MatchConfig:
        """Build a config from a plain mapping (e.g. JSON); unknown keys are an error.

        ``events`` is a list of mappings, each with a ``kind`` (``kidnap``, ``place_ball``,
        ``penalty``, ``fall``) and the event's fields (:func:`teamsim.events.event_from_mapping`).
        """
        data = dict(data)
        if "events" in data:
            events = data["events"]
            if not isinstance(events, list | tuple):
                raise TypeError(f"MatchConfig.events: expected a list of events, got {type(events).__name__}")
            data["events"] = tuple(
                e if isinstance(e, ScriptedEvent) else event_from_mapping(e, f"MatchConfig.events[{i}]")
                for i, e in enumerate(events)
            )
        return from_mapping(cls, data)


class Match:
    """One simulated match (see the module docstring)."""

    def __init__(
        self,
        config: MatchConfig | None = None,
        brains: BrainFactory | None = None,
        log: EventLog | None = None,
        external_referee: bool = False,
        profile: bool = False,
    ):
        """``brains`` makes each robot's brain; ``None``: :func:`teamsim.brains.default_brains`.
        ``external_referee``: an external GameController makes the decisions
        (:class:`teamsim.gc_referee.GameControllerReferee`, fed by :mod:`teamsim.gc_bridge`).
        ``profile``: time every stage and the brains' modules into :attr:`profile`
        (:mod:`teamsim.profile`; the results are the same)."""
        self.config = config or MatchConfig()
        self.profile: MatchProfile | None = MatchProfile() if profile else None
        """Where the time goes (``None`` unless built with ``profile=True``)."""
        c = self.config
        self.field: Field = make_field(c.field)
        n = c.players_per_team
        seq = np.random.SeedSequence(c.seed)
        children = seq.spawn(6 + 6 * n)
        gens = [np.random.Generator(np.random.PCG64(s)) for s in children]
        # fixed consumer order; new consumers go at the end so existing streams stay the same
        fall_rng, channel_rng, self._event_rng, percept_rng = gens[:4]
        robot_rngs = gens[4 : 4 + 2 * n]
        odo_rngs = gens[4 + 2 * n : 4 + 4 * n]
        image_rng = gens[4 + 4 * n]
        brain_rngs = gens[5 + 4 * n : 5 + 6 * n]
        self._camera_error_rng = gens[5 + 6 * n]
        """Draws the error of the camera matrices of images (``observation="images"``)."""
        self.log = log or EventLog()
        self.world = World(self.field, n, c.physics, robot_rngs, fall_rng)
        referee = GameControllerReferee if external_referee else Referee
        self.referee: Referee = referee(self.world, self.field, c.referee, self.log)
        self.channel = TeamChannel(c.channel, n, channel_rng)
        self.odometry = [OdometryModel(c.odometry, g) for g in odo_rngs]
        scheme = make_colour_scheme(c.colours)
        self.camera_model: PerceptSynthesizer | None = None
        """The percept synthesizer (``None`` when ``observation`` is ``none``)."""
        if c.observation == "percepts":
            self.camera_model = PerceptSynthesizer(
                self.field, c.percepts, percept_rng, c.camera, scheme.own_goal != scheme.opponent_goal
            )
        self.image_renderer: ImageRenderer | None = None
        """The camera-image renderer (only when ``observation`` is ``images``)."""
        if c.observation == "images":
            self.image_renderer = ImageRenderer(self.field, scheme, c.camera, c.images, image_rng)
        self._scene = Scene(n)
        self._teams = np.array([float(r.team) for r in self.world.robots])
        """Team index of every robot (scene building)."""
        rows = len(self.world.robots)
        self._team_rows = (np.empty((rows, 5)), np.empty((rows, 5)))
        """Every robot's pose in each team's frame, with its flags (:func:`teamsim.walking.team_poses_nb`)."""
        self._numbers = [r.number for r in self.world.robots]
        self._captures: deque[list[Percepts] | list[CameraImage | None]] = deque()
        self._capture_index = 0
        self.percept_count = 0
        """Percepts delivered to brains so far (all robots)."""
        self.image_count = 0
        """Camera images delivered to brains so far (all robots)."""
        if brains is None:
            brains = default_brains(c.players, c.cognition, c.referee.rules)
        self.localization_errors = LocalizationErrors()
        """Errors of the brains' pose estimates (brains with a ``pose`` RobotPose; evaluation only)."""
        self.brains: list[Brain] = []
        for i, robot in enumerate(self.world.robots):
            brain = brains(robot.team, robot.number)
            brain.reset(
                BrainContext(
                    team_number=c.referee.team_numbers[robot.team],
                    player_number=robot.number,
                    players_per_team=n,
                    field=self.field,
                    cognition_hz=c.cognition_hz,
                    rng=brain_rngs[i],
                    colours=scheme,
                    team=robot.team,
                    observation=c.observation,
                )
            )
            self.brains.append(brain)
        self.time = 0.0
        self.steps = 0
        self.frames = 0
        self._next_cognition = 0.0
        self._events = sorted(c.events, key=lambda e: e.time)
        self._event_index = 0
        self.true_odometry: list[TrueOdometry] = [TrueOdometry(0.0, 0.0, 0.0)] * (2 * n)
        """Per robot, the true body motion over its latest cognition frame (evaluation only)."""
        self.last_frames: list[SensorFrame | None] = [None] * (2 * n)
        self.wall_seconds = 0.0
        self._cognition_done = False
        self.referee.start()

    # -- access ----------------------------------------------------------------------------
    @property
    def finished(self) -> bool:
        """True after the second half has ended."""
        return self.referee.finished

    def game_state(self) -> GameControlData:
        """The current GameController packet."""
        return self.referee.game_state()

    def snapshot(self) -> WorldSnapshot:
        """The true state of the world now."""
        return self.world.snapshot(self.time)

    # -- scripted events -------------------------------------------------------------------
    def apply_event(self, ev: ScriptedEvent) -> None:
        """Carry out a scripted event now."""
        if isinstance(ev, Kidnap):
            self.kidnap(ev.team, ev.number, ev.pose, ev.sense_pickup)
        elif isinstance(ev, PlaceBall):
            self.world.place_ball(ev.x, ev.y, ev.vx, ev.vy)
            self.log.add(self.time, "ball_placed", x=ev.x, y=ev.y)
        elif isinstance(ev, ForcePenalty):
            self.referee.penalize(ev.team, ev.number, ev.code, self.time, reason="script")
        elif isinstance(ev, ForceFall):
            robot = self.world.robot(ev.team, ev.number)
            if robot.in_space:
                robot.fall(self.time, ev.duration)
                self.log.add(self.time, "forced_fall", team=ev.team, number=ev.number, duration=ev.duration)
        else:
            raise TypeError(f"unknown scripted event {ev!r}")

    def kidnap(
        self,
        team: int,
        number: int,
        pose: tuple[float, float, float] | None = None,
        sense_pickup: bool = False,
    ) -> tuple[float, float, float]:
        """Teleport a robot (world frame pose, random on the field if ``None``); returns the pose."""
        robot = self.world.robot(team, number)
        if pose is None:
            f = self.field
            g = self._event_rng
            pose = (
                float(g.uniform(-f.half_length + 0.3, f.half_length - 0.3)),
                float(g.uniform(-f.half_width + 0.3, f.half_width - 0.3)),
                float(g.uniform(-math.pi, math.pi)),
            )
        robot.teleport(*pose)
        if sense_pickup:
            robot.picked_up = True
            self.referee.status[(team, number)].carried_until = self.time + self.config.referee.carry_seconds
        self.log.add(self.time, "kidnap", team=team, number=number, x=pose[0], y=pose[1], theta=pose[2])
        return pose

    # -- running ---------------------------------------------------------------------------
    def step(self) -> None:
        """Advance by one physics step, running cognition when a frame is due."""
        if not self._cognition_done:
            self._before_physics()
        self._cognition_done = False
        prof = self.profile
        t0 = wallclock.perf_counter() if prof is not None else 0.0
        events = self.world.step(self.time)
        self.steps += 1
        self.time = self.steps * self.world.dt
        t1 = wallclock.perf_counter() if prof is not None else 0.0
        self.referee.update(self.time, events)
        if prof is not None:
            prof.world.add("physics", t1 - t0)
            prof.world.add("referee", wallclock.perf_counter() - t1)

    def advance_frame(self) -> None:
        """Run physics steps until the next cognition frame, run that frame and stop before the
        physics step that follows it, so that the caller can still change robots' commands
        (:meth:`command`): how an environment applies a policy's action from that frame on."""
        while True:
            if not self._cognition_done:
                self._cognition_done = True  # what is due before this physics step is done now
                if self._before_physics():
                    return
            self.step()
            if self.finished:
                return

    def command(self, index: int, motion: MotionRequest) -> None:
        """Replace the command of robot ``index`` (ignored while it is penalised)."""
        robot = self.world.robots[index]
        if not robot.penalized:
            robot.command(motion.walk, motion.kick, motion.head)

    def _before_physics(self) -> bool:
        """Scripted events, camera captures and, when due, a cognition frame; True if one ran."""
        while self._event_index < len(self._events) and self._events[self._event_index].time <= self.time:
            self.apply_event(self._events[self._event_index])
            self._event_index += 1
        if self.camera_model is not None or self.image_renderer is not None:
            hz, latency = self.config.cognition_hz, self.config.percepts.latency
            while self.time >= self._capture_index / hz - latency - 1e-9:
                t0 = wallclock.perf_counter()
                self._captures.append(self.capture() if self.camera_model is not None else self.capture_images())
                self._capture_index += 1
                if self.profile is not None:
                    self.profile.world.add("camera", wallclock.perf_counter() - t0)
        if self.time >= self._next_cognition - 1e-9:
            t0 = wallclock.perf_counter()
            self._cognition()
            if self.profile is not None:
                self.profile.cognition_frames += wallclock.perf_counter() - t0
            self._next_cognition += 1.0 / self.config.cognition_hz
            return True
        return False

    def run(self, until: float | None = None, on_step: Callable[[Match], None] | None = None) -> MatchSummary:
        """Run until the match is finished (or until simulated time ``until``)."""
        start = wallclock.perf_counter()
        while not self.finished and (until is None or self.time < until - 1e-9):
            self.step()
            if on_step is not None:
                on_step(self)
        self.wall_seconds += wallclock.perf_counter() - start
        return self.summary()

    def scene(self) -> Scene:
        """The world as the camera model sees it now (reused buffer, world frame)."""
        sc = self._scene
        p = self.config.percepts
        standing, lying = p.robot_height, p.fallen_height
        radius = self.config.physics.robot.radius
        sign0, sign1 = self.referee.sign(0), self.referee.sign(1)
        wk.scene_rows_nb(
            self.world.motion.array, self._teams, sign0, sign1, radius, standing, lying, sc.observers, sc.occluders
        )  # fmt: skip
        robots = self.world.robots
        sc.turn_rates[:] = [robot.body.angular_velocity for robot in robots]
        b = self.world.ball
        bx, by = b.position
        bvx, bvy = b.velocity
        sc.ball[:] = (bx, by, bvx, bvy, 1.0)
        return sc

    def capture(self) -> list[Percepts]:
        """Take one image per robot now and return what vision reports (robot index order)."""
        if self.camera_model is None:
            raise RuntimeError("this match has observation='none': there is no camera model")
        return self.camera_model.synthesize(self.scene(), self.time)

    def capture_images(self) -> list[CameraImage | None]:
        """Take one camera image per robot now (``None`` for robots that cannot see)."""
        if self.image_renderer is None:
            raise RuntimeError(f"this match has observation={self.config.observation!r}: no images are rendered")
        scene = self.scene()
        return self.image_renderer.camera_images(scene, self.time, camera_errors=self._camera_errors(scene))

    def _camera_errors(self, scene: Scene) -> NDArray[np.float64]:
        """This capture's camera-matrix errors (:func:`teamsim.images.camera_errors`), own stream."""
        return camera_errors(scene.observers, self.config.percepts, self._camera_error_rng)

    def _cognition(self) -> None:
        now = self.time
        capture = self._captures.popleft() if self._captures else None
        percepts = capture if self.camera_model is not None else None
        images = capture if self.image_renderer is not None else None
        self.referee.set_message_budget(self.channel.budget_left)
        game = self.referee.game_state()
        inbox = [self.channel.receive(0, now), self.channel.receive(1, now)]
        oracle_cache: dict[int, tuple[list[OraclePose], float, float, float, float]] = {}
        frames: list[SensorFrame] = []
        oracles: list[OracleInput | None] = []
        team_numbers = self.config.referee.team_numbers
        frame_index = self.frames
        motions = self.world.take_motions()
        for i, (robot, brain) in enumerate(zip(self.world.robots, self.brains, strict=True)):
            mo = motions[i]  # planned (dx, dy, dtheta), then true, robot frame
            self.true_odometry[i] = TrueOdometry(mo[3], mo[4], mo[5])
            odo = self.odometry[i].report((mo[0], mo[1], mo[2]))
            frame = SensorFrame(  # by position: a call with twelve keywords costs twice as much
                now,  # time
                frame_index,
                team_numbers[robot.team],  # team_number
                robot.number,  # player_number
                odo,  # odometry
                robot.head,
                game,
                robot.picked_up,
                robot.fallen_until >= 0,  # fallen: is_fallen()
                tuple(inbox[robot.team].get(robot.number, ())),  # messages
                percepts[i] if percepts is not None else None,  # type: ignore[arg-type]
                images[i] if images is not None else None,  # type: ignore[arg-type]  # image
            )
            if percepts is not None:
                self.percept_count += len(percepts[i])  # type: ignore[arg-type]
            if images is not None and images[i] is not None:
                self.image_count += 1
            self.last_frames[i] = frame
            frames.append(frame)
            oracle = None
            if brain.uses_oracle:
                if robot.team not in oracle_cache:
                    oracle_cache[robot.team] = self._oracle_poses(robot.team)
                oracle = self._oracle_for(robot.team, robot.number, oracle_cache[robot.team])
            oracles.append(oracle)
        # every brain's frame at once: brains with stages run module by module over all robots
        prof = self.profile
        t0 = wallclock.perf_counter() if prof is not None else 0.0
        outs = think_all(self.brains, frames, oracles, None if prof is None else prof.modules)
        if prof is not None:
            prof.brains += wallclock.perf_counter() - t0
            prof.robot_frames += len(outs)
        truths: tuple[list[list[float]], ...] | None = None
        for i, (robot, brain, out) in enumerate(zip(self.world.robots, self.brains, outs, strict=True)):
            estimate = getattr(brain, "pose", None)
            if isinstance(estimate, RobotPose) and not robot.penalized:
                if truths is None:  # every robot's true pose in both teams' frames, in one call each
                    truths = (self._team_frame(0), self._team_frame(1))
                x, y, th = truths[robot.team][i][:3]
                self.localization_errors.add(estimate, (x, y, th))
            if not robot.penalized:
                m = out.motion
                robot.command(m.walk, m.kick, m.head)
            if out.message is not None:
                self.channel.send(robot.team, robot.number, out.message, now)
        self.frames += 1

    def _team_frame(self, team: int) -> list[list[float]]:
        """Every robot's row in team ``team``'s frame: x, y (m), theta (rad), 1.0 if not penalised,
        1.0 if fallen; the pose is ``world_to_team(sign, *robot.pose)`` to the bit."""
        rows = self._team_rows[team]
        wk.team_poses_nb(self.world.motion.array, self.referee.sign(team), rows)
        return rows.tolist()  # type: ignore[no-any-return]

    def _oracle_poses(self, team: int) -> tuple[list[OraclePose], float, float, float, float]:
        sign = self.referee.sign(team)
        poses = [
            OraclePose(number, x, y, th, active != 0.0, fallen != 0.0)
            for number, (x, y, th, active, fallen) in zip(self._numbers, self._team_frame(team), strict=True)
        ]
        ball = self.world.ball._body
        b, v = get_position(ball), get_velocity(ball)  # ball.position and ball.velocity, read in C
        return (poses, sign * b.x, sign * b.y, sign * v.x, sign * v.y)

    def _oracle_for(
        self, team: int, number: int, cached: tuple[list[OraclePose], float, float, float, float]
    ) -> OracleInput:
        poses, bx, by, bvx, bvy = cached
        n = self.config.players_per_team
        own = poses[team * n : (team + 1) * n]
        other = poses[(1 - team) * n : (2 - team) * n]
        return OracleInput(  # by position: self_pose, teammates, opponents, ball x, y, vx, vy
            own[number - 1], tuple([p for p in own if p.number != number]), tuple(other), bx, by, bvx, bvy
        )

    def summary(self) -> MatchSummary:
        """What happened so far."""
        c = self.referee.counters
        half = self.log.of_kind("half_time")
        return MatchSummary(
            seed=self.config.seed,
            players_per_team=self.config.players_per_team,
            field=self.config.field,
            score=(self.referee.score[0], self.referee.score[1]),
            goals=list(c.goals),
            kickoffs=list(c.kickoffs),
            penalties=list(c.penalties),
            returns=list(c.returns),
            half_time=half[0].time if half else None,
            side_switch=bool(self.log.of_kind("side_switch")),
            set_plays=len(c.set_plays),
            placements=c.placements,
            messages_sent=(self.channel.stats[0].sent, self.channel.stats[1].sent),
            percepts_per_frame=self.percept_count / max(1, self.frames * len(self.world.robots)),
            images=self.image_count,
            sim_seconds=self.time,
            wall_seconds=self.wall_seconds,
            physics_steps=self.steps,
            localization=self.localization_errors.summary(),
            rejected_inputs=merge_counts(*(rejected_inputs(b) for b in self.brains)),
        )

    def is_playing(self) -> bool:
        """Whether the game is in PLAYING."""
        return self.referee.state == GameStateId.PLAYING
