"""The physical world: a pymunk space with the field's border, goals, the ball and robots.

The space has no gravity (top-down 2D). Static shapes: the outer border of the carpet
(field plus border strip), the goal posts and the goal nets (sides and back). The ball is a
light dynamic circle whose rolling friction is a constant deceleration applied in its
velocity function (while the ball rests, pymunk's own integrator runs instead: for a ball
without speed and spin both give the same result). Robots are :class:`teamsim.robot.Robot`
bodies.

Collision handlers only *record* :class:`CollisionEvent` objects; :meth:`World.step` then
turns hard impacts into falls, and the referee reads the events for pushing evidence.

World frame: metres and radians, origin at the field centre, x toward the goal that team 0
attacks in the first half.

=====================  ==========  ===========  ===================================================
parameter              default     range        meaning
=====================  ==========  ===========  ===================================================
physics_hz             100         [10, 10000]  physics steps per simulated second
substeps               2           [1, 20]      pymunk sub-steps per physics step
ball_mass              0.045 kg    (0, 10]      SPL ball
ball_rolling_decel     1.0 m/s2    (0, 100]     constant deceleration of a rolling ball (turf)
ball_elasticity        0.5         [0, 1]       restitution against posts, nets and border
robot                  RobotParams              body and motion parameters of every robot
=====================  ==========  ===========  ===================================================
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, ClassVar, Literal

import numpy as np
import pymunk
from pymunk._chipmunk_cffi import ffi as _ffi
from pymunk._chipmunk_cffi import lib as _chipmunk

from cognition.field import Field
from cognition.records import fast_init
from teamsim.params import PROBABILITY, Range, Ranges, check_ranges, positive
from teamsim.robot import (
    COLLISION_BALL,
    COLLISION_POST,
    COLLISION_ROBOT,
    COLLISION_WALL,
    Robot,
    RobotParams,
    get_angular_velocity,
    get_velocity,
    set_angular_velocity,
    set_velocity,
)
from teamsim.state import RobotTruth, WorldSnapshot
from teamsim.walking import (
    CW,
    CX,
    CY,
    SEND_ANGULAR,
    SEND_VELOCITY,
    WIDTH,
    RobotStates,
    post_step_nb,
    pre_step_nb,
    take_motions_nb,
)

_space_step = _chipmunk.cpSpaceStep


def step_space(space: pymunk.Space, dt: float) -> None:
    """``space.step(dt)``, with Chipmunk's step called directly when pymunk has nothing to do
    around it (the usual case of every physics step).

    pymunk's ``Space.step`` checks the masses of bodies added since the last step, locks the
    space, steps Chipmunk, then adds, removes and calls back what collision handlers asked for
    during the step. The world adds nothing during a step, so this calls ``cpSpaceStep`` under
    the same lock and hands over to ``Space.step`` only when there is work: bodies to check
    before the step (it then steps itself), or requests made during the step (``Space.step(0)``
    then carries them out: Chipmunk does not step for a time step of 0). The simulation is the
    same to the bit (tests/test_world.py); a physics step of two sub-steps saves two Python
    calls and their bookkeeping each.
    """
    if space._bodies_to_check or space.threaded:
        space.step(dt)
        return
    space._locked = True
    try:
        _space_step(space._space, dt)
        space._removed_shapes.clear()
    finally:
        space._locked = False
    if space._add_later or space._remove_later or space._post_step_callbacks:
        space.step(0.0)


_BATCH_FIELDS = _chipmunk.BODY_ID | _chipmunk.POSITION | _chipmunk.ANGLE
_each_body = _chipmunk.cpSpaceEachBody
_read_batched = _ffi.addressof(_chipmunk, "pmSpaceBodyGetIteratorFuncBatched")


class BodyPoses:
    """Every body's pose in a space read from Chipmunk in one call, into numpy arrays.

    pymunk's batch iterator (the engine of :func:`pymunk.batch.get_space_bodies`) appends each
    body's id (the address of its ``cpBody``, :attr:`pymunk.Body.id`) to an integer array and its
    x, y (m) and angle (rad) to a float array, in the order Chipmunk keeps the bodies (which
    changes as bodies leave and rejoin the space; match rows by id; the space's static body is
    listed too). The arrays are allocated
    here, large enough for every body the space is expected to hold, and :attr:`poses` and
    :attr:`ids` are numpy views of them; should the space ever hold more, Chipmunk's array grows
    (it reallocates) and :meth:`read` makes the views anew before anyone reads them. One call
    reads every robot for about a fifth of the cost of two getters per body.
    """

    def __init__(self, space: pymunk.Space, bodies: int) -> None:
        """Read ``space``, which is expected to hold up to ``bodies`` bodies (it may hold more)."""
        self._space = space._space
        cap = 2 * bodies + 8
        self._floats = _ffi.gc(_chipmunk.pmFloatArrayNew(3 * cap), _chipmunk.pmFloatArrayFree)
        self._ints = _ffi.gc(_chipmunk.pmIntArrayNew(cap), _chipmunk.pmIntArrayFree)
        self._data = _ffi.new("pmBatchedData *")
        self._data.fields = _BATCH_FIELDS
        self._data.floatArray = self._floats
        self._data.intArray = self._ints
        self._views()

    def _views(self) -> None:
        f, i = self._floats, self._ints
        self.poses: np.ndarray = np.frombuffer(_ffi.buffer(f.arr, 8 * f.max), dtype=np.float64)
        """(x, y, angle) per body, flat (m, m, rad; world frame); the first :meth:`read` count are valid."""
        self.ids: np.ndarray = np.frombuffer(_ffi.buffer(i.arr, 8 * i.max), dtype=np.uint64)
        """Body ids in the order of :attr:`poses`."""
        self._room = min(f.max // 3, i.max) - 2
        """Bodies a read can list with certainty that neither array was reallocated."""

    def read(self) -> int:
        """Read every body's id and pose now; the number of bodies read."""
        f, i = self._floats, self._ints
        f.num = 0
        i.num = 0
        _each_body(self._space, _read_batched, self._data)
        n: int = i.num
        if n >= self._room:  # the arrays may have grown: view them where they are now
            self._views()
        return n


@dataclass(frozen=True)
class PhysicsParams:
    """Parameters of the physical world (see module table)."""

    physics_hz: float = 100.0
    substeps: int = 2
    ball_mass: float = 0.045
    ball_rolling_decel: float = 1.0
    ball_elasticity: float = 0.5
    robot: RobotParams = field(default_factory=RobotParams)

    RANGES: ClassVar[Ranges] = {
        "physics_hz": Range(10.0, 10_000.0),
        "substeps": Range(1, 20),
        "ball_mass": positive(10.0),
        "ball_rolling_decel": positive(100.0),
        "ball_elasticity": PROBABILITY,
    }

    def __post_init__(self) -> None:
        check_ranges(self)


RobotId = tuple[int, int]
"""(team index, player number)."""


@fast_init
@dataclass(frozen=True)
class CollisionEvent:
    """One contact observed during a physics step.

    ``kind`` says what touched what. ``first`` marks the first step of a contact, when
    ``impact_speed`` (m/s, relative normal speed before the solver) is meaningful. ``push_a``
    and ``push_b`` are the speeds (m/s) at which each robot's walking engine drove it toward
    the other at that moment: evidence for the referee's pushing rule.
    """

    time: float
    kind: Literal["robot_robot", "robot_post", "robot_wall", "robot_ball", "robot_kick"]
    a: RobotId
    b: RobotId | None
    first: bool
    impact_speed: float
    push_a: float = 0.0
    push_b: float = 0.0


class World:
    """The simulated field with ball and robots (see module docstring)."""

    def __init__(
        self,
        field_map: Field,
        players_per_team: int,
        params: PhysicsParams,
        robot_rngs: list[np.random.Generator],
        fall_rng: np.random.Generator,
    ):
        self.field = field_map
        self.params = params
        self.dt = 1.0 / params.physics_hz
        self.fall_rng = fall_rng
        self.space = pymunk.Space()
        self.space.gravity = (0.0, 0.0)
        self._add_statics()
        self.ball_radius = field_map.dims.ball_diameter / 2.0
        self.ball = pymunk.Body(params.ball_mass, pymunk.moment_for_circle(params.ball_mass, 0, self.ball_radius))
        self._rolling_decel = params.ball_rolling_decel
        self.ball.velocity_func = self._ball_velocity
        self._ball_integrator_c = False
        """Whether pymunk's own velocity integrator runs for the ball (only while it is at rest,
        :meth:`_choose_ball_integrator`) instead of :meth:`_ball_velocity`."""
        self._ball_may_rest = True
        """The ball may have come to rest since the integrator was last chosen."""
        self._ball_contacts = 0
        """Shapes touching the ball now: Chipmunk calls a handler's begin when two shapes start
        touching and its separate in the first step they no longer touch (or when one leaves the
        space), in pairs; so after a sub-step this is 0 exactly when nothing touched the ball in it."""
        self.ball_shape = pymunk.Circle(self.ball, self.ball_radius)
        self.ball_shape.collision_type = COLLISION_BALL
        self.ball_shape.elasticity = params.ball_elasticity
        self.ball_shape.friction = 0.1
        self.space.add(self.ball, self.ball_shape)
        self.robots: list[Robot] = []
        self._by_shape: dict[pymunk.Shape, Robot] = {}
        self.motion = RobotStates(2 * players_per_team)
        """Every robot's walking engine and head state, one row each (:mod:`teamsim.walking`)."""
        for i in range(2 * players_per_team):
            team, number = divmod(i, players_per_team)
            robot = Robot(team, number + 1, params.robot, robot_rngs[i], self.motion, i)
            self.robots.append(robot)
            self._by_shape[robot.shape] = robot
        self._controls = [(r.control._body, i * WIDTH) for i, r in enumerate(self.robots)]
        """Per robot: its control body's Chipmunk handle and its row's offset in the state view."""
        self._motions = np.zeros((2 * players_per_team, 6))
        self._body_ids = np.array([r.body.id for r in self.robots], dtype=np.uint64)
        """Per robot (state row): its body's id, as :class:`BodyPoses` lists it."""
        self._body_poses = BodyPoses(self.space, 2 * len(self.robots) + 2)
        self.players_per_team = players_per_team
        self._events: list[CollisionEvent] = []
        self._now = 0.0
        self._install_handlers()

    # -- construction ----------------------------------------------------------------------
    def _add_statics(self) -> None:
        d = self.field.dims
        hx = d.length / 2 + d.border_strip
        hy = d.width / 2 + d.border_strip
        body = self.space.static_body
        corners = [(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy)]
        shapes: list[pymunk.Shape] = []
        for i in range(4):
            seg = pymunk.Segment(body, corners[i], corners[(i + 1) % 4], 0.02)
            seg.collision_type = COLLISION_WALL
            shapes.append(seg)
        r_post = d.goal_post_diameter / 2
        for post in self.field.goal_posts:
            c = pymunk.Circle(body, r_post, (post.x, post.y))
            c.collision_type = COLLISION_POST
            shapes.append(c)
        y_post = d.goal_inner_width / 2 + r_post
        for sign in (-1.0, 1.0):
            x0 = sign * d.length / 2
            x1 = sign * (d.length / 2 + d.goal_depth)
            for a, b in (
                ((x0, y_post), (x1, y_post)),
                ((x0, -y_post), (x1, -y_post)),
                ((x1, -y_post), (x1, y_post)),
            ):
                net = pymunk.Segment(body, a, b, 0.01)
                net.collision_type = COLLISION_WALL
                shapes.append(net)
        for s in shapes:
            s.elasticity = self.params.ball_elasticity
            s.friction = 0.3
        self.space.add(*shapes)

    def _ball_velocity(self, body: pymunk.Body, gravity: Any, damping: float, dt: float) -> None:
        """pymunk's velocity integration of the ball (no damping), then the rolling friction:
        the speed drops by ``ball_rolling_decel * dt`` (m/s, not below 0) and the spin is zeroed."""
        pymunk.Body.update_velocity(body, gravity, 1.0, dt)
        v = get_velocity(body._body)  # body.velocity, read in C
        vx, vy = v.x, v.y
        speed = math.hypot(vx, vy)
        if speed > 0.0:
            new = speed - self._rolling_decel * dt
            if new < 0.0:  # max(0.0, new)
                new = 0.0
            set_velocity(body._body, (vx * new / speed, vy * new / speed))
        set_angular_velocity(body._body, 0.0)
        if speed == 0.0 or new == 0.0:
            self._ball_may_rest = True

    def _choose_ball_integrator(self) -> None:
        """Before a sub-step: pymunk's own velocity integrator while the ball is at rest, else
        :meth:`_ball_velocity`.

        For a ball without speed and spin, :meth:`_ball_velocity` does exactly what pymunk's
        integrator does (the same ``cpBodyUpdateVelocity`` call: no forces act on the ball, the
        space has neither gravity nor damping; the speed stays 0, the spin 0), so the Python
        callback runs only while the ball moves. The state is read before every sub-step in
        which the C integrator would run, so contacts, kicks and placements that set the ball
        moving switch back at once; except before a later sub-step of a physics step when no
        shape touched the ball in the one before (:attr:`_ball_contacts` is 0): only a contact
        could have set a resting ball moving within the step (nothing outside Chipmunk runs
        between the sub-steps), so it still rests.
        """
        ball = self.ball
        handle = ball._body
        v = get_velocity(handle)  # ball.velocity and ball.angular_velocity, read in C
        rest = v.x == 0.0 and v.y == 0.0 and get_angular_velocity(handle) == 0.0
        if rest != self._ball_integrator_c:
            ball.velocity_func = pymunk.Body.update_velocity if rest else self._ball_velocity
            self._ball_integrator_c = rest
        self._ball_may_rest = False

    def _install_handlers(self) -> None:
        self.space.on_collision(COLLISION_ROBOT, COLLISION_ROBOT, begin=self._rr_contact, pre_solve=self._rr_contact)
        self.space.on_collision(COLLISION_ROBOT, COLLISION_POST, begin=self._static_contact)
        self.space.on_collision(COLLISION_ROBOT, COLLISION_WALL, begin=self._static_contact)
        self.space.on_collision(COLLISION_ROBOT, COLLISION_BALL, begin=self._ball_contact)
        self.space.on_collision(COLLISION_BALL, None, begin=self._ball_touch, separate=self._ball_release)

    # -- collision recording ---------------------------------------------------------------
    def _drive_toward(self, robot: Robot, ux: float, uy: float) -> float:
        v = robot.control.velocity
        return v.x * ux + v.y * uy

    def _rr_contact(self, arbiter: pymunk.Arbiter, space: pymunk.Space, data: Any) -> None:
        sa, sb = arbiter.shapes
        ra, rb = self._by_shape[sa], self._by_shape[sb]
        pa, pb = ra.body.position, rb.body.position
        dx, dy = pb.x - pa.x, pb.y - pa.y
        dist = math.hypot(dx, dy) or 1e-9
        ux, uy = dx / dist, dy / dist
        va, vb = ra.body.velocity, rb.body.velocity
        impact = (va.x - vb.x) * ux + (va.y - vb.y) * uy
        self._events.append(
            CollisionEvent(
                self._now,
                "robot_robot",
                (ra.team, ra.number),
                (rb.team, rb.number),
                arbiter.is_first_contact,
                max(0.0, impact),
                self._drive_toward(ra, ux, uy),
                self._drive_toward(rb, -ux, -uy),
            )
        )

    def _static_contact(self, arbiter: pymunk.Arbiter, space: pymunk.Space, data: Any) -> None:
        shape = arbiter.shapes[0]
        robot = self._by_shape[shape]
        n = arbiter.normal
        v = robot.body.velocity
        impact = abs(v.x * n.x + v.y * n.y)
        kind: Literal["robot_post", "robot_wall"] = (
            "robot_post" if arbiter.shapes[1].collision_type == COLLISION_POST else "robot_wall"
        )
        self._events.append(CollisionEvent(self._now, kind, (robot.team, robot.number), None, True, impact))

    def _ball_touch(self, arbiter: pymunk.Arbiter, space: pymunk.Space, data: Any) -> None:
        self._ball_contacts += 1

    def _ball_release(self, arbiter: pymunk.Arbiter, space: pymunk.Space, data: Any) -> None:
        self._ball_contacts -= 1

    def _ball_contact(self, arbiter: pymunk.Arbiter, space: pymunk.Space, data: Any) -> None:
        robot = self._by_shape[arbiter.shapes[0]]
        v = self.ball.velocity - robot.body.velocity
        self._events.append(CollisionEvent(self._now, "robot_ball", (robot.team, robot.number), None, True, abs(v)))

    # -- access ----------------------------------------------------------------------------
    def robot(self, team: int, number: int) -> Robot:
        """The robot of team index ``team`` with player number ``number`` (1-based)."""
        if team not in (0, 1) or not 1 <= number <= self.players_per_team:
            raise ValueError(f"no robot {number} in team {team} (players per team: {self.players_per_team})")
        return self.robots[team * self.players_per_team + number - 1]

    def place_ball(self, x: float, y: float, vx: float = 0.0, vy: float = 0.0) -> None:
        """Put the ball at (x, y) world frame with the given velocity (m/s)."""
        if not all(math.isfinite(v) for v in (x, y, vx, vy)):
            raise ValueError(f"ball placement must be finite, got {(x, y, vx, vy)}")
        self.ball.position = (x, y)
        self.ball.velocity = (vx, vy)
        self._ball_may_rest = True
        self.space.reindex_shapes_for_body(self.ball)

    def take_motions(self) -> list[list[float]]:
        """Every robot's planned and true motion since the last call, robot frame (m, m, rad):
        ``[planned dx, dy, dtheta, true dx, dy, dtheta]`` per robot, in robot order; both restart
        from zero (:meth:`Robot.take_motion` for all robots in one call)."""
        out = self._motions
        take_motions_nb(self.motion.array, out)
        return out.tolist()  # type: ignore[no-any-return]

    # -- stepping --------------------------------------------------------------------------
    def step(self, now: float) -> list[CollisionEvent]:
        """Advance the world by one physics step starting at time ``now`` (s).

        The walking engines and heads of all robots advance in one compiled call
        (:func:`~teamsim.walking.pre_step_nb`), which lists the control bodies whose velocity
        changed; those are set in pymunk, the space steps, every body's pose is read back in one
        call (:class:`BodyPoses`), and a second compiled call (:func:`~teamsim.walking.post_step_nb`)
        stores the robots' poses and accumulates the true motion. Pending kicks are then tried robot by robot.
        """
        self._now = now
        events: list[CollisionEvent] = []
        self._events = events
        dt = self.dt
        motion = self.motion
        view = motion.view
        n_send = pre_step_nb(motion.array, now, dt, motion.sends)
        if n_send:
            controls = self._controls
            sends = motion.send_view
            for i in range(0, 2 * n_send, 2):
                handle, o = controls[sends[i]]
                bits = sends[i + 1]
                if bits & SEND_VELOCITY:
                    set_velocity(handle, (view[o + CX], view[o + CY]))
                if bits & SEND_ANGULAR:
                    set_angular_velocity(handle, view[o + CW])
        substeps = self.params.substeps
        sub = dt / substeps
        space = self.space
        for k in range(substeps):
            if self._ball_may_rest or (self._ball_integrator_c and (k == 0 or self._ball_contacts)):
                self._choose_ball_integrator()
            step_space(space, sub)
        poses = self._body_poses
        n = poses.read()
        post_step_nb(motion.array, poses.poses, poses.ids, n, self._body_ids)
        for robot in self.robots:
            # a busy robot cannot kick yet (try_kick would say no): the request waits, without a call
            if (
                robot.kick_request is not None
                and now >= robot.busy_until
                and robot.try_kick(now, self.ball, self.ball_radius)
            ):
                speed = abs(self.ball.velocity)
                events.append(CollisionEvent(now, "robot_kick", (robot.team, robot.number), None, True, speed))
        if events:
            self._apply_falls(now)
        return events

    def _apply_falls(self, now: float) -> None:
        p = self.params.robot
        for ev in self._events:
            if not ev.first or ev.kind not in ("robot_robot", "robot_post", "robot_wall"):
                continue
            excess = ev.impact_speed - p.fall_speed_threshold
            if excess <= 0:
                continue
            involved = [self.robot(*ev.a)] + ([self.robot(*ev.b)] if ev.b is not None else [])
            for i, robot in enumerate(involved):
                prob = min(0.9, excess * p.fall_probability_slope)
                if ev.b is not None:
                    # the robot that was driving into the other keeps its balance more often
                    own, other = (ev.push_a, ev.push_b) if i == 0 else (ev.push_b, ev.push_a)
                    if own > other:
                        prob *= 0.5
                if self.fall_rng.random() < prob and not robot.is_fallen():
                    robot.fall(now)

    def snapshot(self, now: float) -> WorldSnapshot:
        """The true state of everything at time ``now``."""
        robots = []
        for r in self.robots:
            x, y, th = r.pose
            v = r.body.velocity
            robots.append(
                RobotTruth(
                    team=r.team,
                    number=r.number,
                    x=x,
                    y=y,
                    theta=th,
                    vx=v.x,
                    vy=v.y,
                    fallen=r.is_fallen(),
                    penalized=r.penalized,
                    picked_up=r.picked_up,
                    head_yaw=r.head.yaw,
                )
            )
        b = self.ball
        return WorldSnapshot(now, tuple(robots), b.position.x, b.position.y, b.velocity.x, b.velocity.y)
