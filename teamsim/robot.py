"""A simulated NAO-like robot body: walking engine, kick, falls and head joints.

The body is a pymunk circle driven the way pymunk's ``tank`` example drives a top-down
vehicle: a kinematic *control body* carries the commanded velocity and a pivot joint plus a
gear joint (``max_bias = 0``) pull the robot along with bounded force and torque. Those
bounds act as floor friction, so a robot that is pushed hard enough slides.

Parameters (:class:`RobotParams`, SI units, robot frame: +x forward, +y left):

========================  ============  ==================  =======================================================
parameter                 default       range               meaning
========================  ============  ==================  =======================================================
radius                    0.14 m        (0, 1]              collision radius of the body
mass                      5.3 kg        (0, 1000]           NAO V6 mass
max_forward               0.25 m/s      (0, 10]             walking speed limits (NAO-like)
max_backward              0.15 m/s      (0, 10]
max_sideways              0.15 m/s      (0, 10]
max_turn                  1.0 rad/s     (0, 20]
max_linear_accel          0.5 m/s2      (0, 100]            acceleration limit of the walking engine
max_angular_accel         3.0 rad/s2    (0, 1000]
floor_force               40 N          (0, 100000]         pivot force limit (floor friction)
floor_torque              8 N m         (0, 10000]          gear torque limit
kick_reach                0.12 m        [0, 1]              gap between body and ball within which a kick connects
kick_half_angle           0.7 rad       (0, pi]             ball bearing window for a kick
kick_duration             0.8 s         (0, 10]             the kick motion blocks walking for this long
kick_max_speed            3.0 m/s       (0, 20]             ball speed of a full-strength kick
kick_direction_sigma      0.1 rad       [0, pi]             noise of the kick direction
kick_strength_sigma       0.1           [0, 1]              relative noise of the kick speed
kick_max_angle            1.05 rad      [0, pi]             largest ball direction a kick can reach (robot frame)
fall_speed_threshold      0.45 m/s      [0, 100]            impact speed above which a collision may topple the robot
fall_probability_slope    1.2 s/m       [0, 1000]           fall probability per m/s of impact speed above threshold
getup_mean                4.0 s         (0, 600]            time to get up: normal with this mean and sigma,
getup_sigma               0.7 s         [0, 600]            clipped to >= getup_min
getup_min                 2.5 s         (0, 600]
head_yaw_limit            2.0857 rad    [0, pi]             NAO head yaw limit (both sides)
head_pitch_min            -0.672 rad    [-pi/2, pi/2]       NAO head pitch limits (positive looks down);
head_pitch_max            0.515 rad     [-pi/2, pi/2]       head_pitch_min <= head_pitch_max
head_max_speed            8.0 rad/s     (0, 100]
========================  ============  ==================  =======================================================

Every value is checked against its range when the parameters are built
(:func:`cognition.params.check_ranges`); a value outside it, a non-number, NaN or infinity
raises an error naming the field.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pymunk
from pymunk._chipmunk_cffi import lib as _chipmunk

from cognition.geometry import wrap_angle
from cognition.representations import HeadRequest, HeadState, KickRequest, WalkRequest
from teamsim.params import Range, Ranges, check_ranges, non_negative, positive
from teamsim.walking import (
    ANG_ACC,
    BTH,
    BUSY_UNTIL,
    BX,
    BY,
    CX,
    FALLEN_SINCE,
    FALLEN_UNTIL,
    GCAM,
    GPITCH,
    GSPEED,
    GYAW,
    HCAM,
    HEAD_MOVED,
    HPITCH,
    HPR,
    HYAW,
    HYR,
    IN_SPACE,
    LIN_ACC,
    MX,
    PENALIZED,
    PICKED,
    PX,
    RESTING,
    TW,
    TX,
    TY,
    VX,
    WIDTH,
    WTH,
    RobotStates,
)

get_position = _chipmunk.cpBodyGetPosition
"""pymunk's C getter of a body's position: ``get_position(body._body)`` is a C struct whose ``x``
and ``y`` are the floats of ``body.position``, read without the property and the ``Vec2d`` it
builds (a fifth of the cost; the physics loop reads every robot's pose in every step)."""
get_angle = _chipmunk.cpBodyGetAngle
"""pymunk's C getter of a body's angle (``body.angle``; see :data:`get_position`)."""
get_velocity = _chipmunk.cpBodyGetVelocity
"""pymunk's C getter of a body's velocity (``body.velocity``; see :data:`get_position`)."""
get_angular_velocity = _chipmunk.cpBodyGetAngularVelocity
"""pymunk's C getter of a body's angular velocity (``body.angular_velocity``; see :data:`get_position`)."""
set_velocity = _chipmunk.cpBodySetVelocity
"""pymunk's C setter of a body's velocity: ``set_velocity(body._body, (vx, vy))`` is what
``body.velocity = (vx, vy)`` calls, without the per-attribute ``__setattr__`` shim pymunk's bodies
carry for type checkers and the property's Python function (the physics loop sets the control
bodies' velocities in most steps)."""
set_angular_velocity = _chipmunk.cpBodySetAngularVelocity
"""pymunk's C setter of a body's angular velocity (``body.angular_velocity = w``; see :data:`set_velocity`)."""

_ZEROS6 = memoryview(np.zeros(6))
"""Six zeros, for resetting the planned and true motion of a state row in one copy."""

COLLISION_ROBOT = 1
COLLISION_BALL = 2
COLLISION_POST = 3
COLLISION_WALL = 4


@dataclass(frozen=True)
class RobotParams:
    """Physical and motion parameters of one robot (see module table)."""

    radius: float = 0.14
    mass: float = 5.3
    max_forward: float = 0.25
    max_backward: float = 0.15
    max_sideways: float = 0.15
    max_turn: float = 1.0
    max_linear_accel: float = 0.5
    max_angular_accel: float = 3.0
    floor_force: float = 40.0
    floor_torque: float = 8.0
    kick_reach: float = 0.12
    kick_half_angle: float = 0.7
    kick_duration: float = 0.8
    kick_max_speed: float = 3.0
    kick_direction_sigma: float = 0.1
    kick_strength_sigma: float = 0.1
    kick_max_angle: float = 1.05
    fall_speed_threshold: float = 0.45
    fall_probability_slope: float = 1.2
    getup_mean: float = 4.0
    getup_sigma: float = 0.7
    getup_min: float = 2.5
    head_yaw_limit: float = 2.0857
    head_pitch_min: float = -0.672
    head_pitch_max: float = 0.515
    head_max_speed: float = 8.0

    RANGES: ClassVar[Ranges] = {
        "radius": positive(1.0),
        "mass": positive(1000.0),
        "max_forward": positive(10.0),
        "max_backward": positive(10.0),
        "max_sideways": positive(10.0),
        "max_turn": positive(20.0),
        "max_linear_accel": positive(100.0),
        "max_angular_accel": positive(1000.0),
        "floor_force": positive(100_000.0),
        "floor_torque": positive(10_000.0),
        "kick_reach": non_negative(1.0),
        "kick_half_angle": positive(math.pi),
        "kick_duration": positive(10.0),
        "kick_max_speed": positive(20.0),
        "kick_direction_sigma": non_negative(math.pi),
        "kick_strength_sigma": non_negative(1.0),
        "kick_max_angle": non_negative(math.pi),
        "fall_speed_threshold": non_negative(100.0),
        "fall_probability_slope": non_negative(1000.0),
        "getup_mean": positive(600.0),
        "getup_sigma": non_negative(600.0),
        "getup_min": positive(600.0),
        "head_yaw_limit": non_negative(math.pi),
        "head_pitch_min": Range(-math.pi / 2, math.pi / 2),
        "head_pitch_max": Range(-math.pi / 2, math.pi / 2),
        "head_max_speed": positive(100.0),
    }

    def __post_init__(self) -> None:
        check_ranges(self)
        if self.head_pitch_min > self.head_pitch_max:
            raise ValueError(
                f"RobotParams.head_pitch_min ({self.head_pitch_min}) must not exceed head_pitch_max "
                f"({self.head_pitch_max})"
            )


def compose(acc: tuple[float, float, float], d: tuple[float, float, float]) -> tuple[float, float, float]:
    """Append motion ``d`` (in the frame reached by ``acc``) to the accumulated motion ``acc``."""
    ax, ay, ath = acc
    c, s = math.cos(ath), math.sin(ath)
    return (ax + c * d[0] - s * d[1], ay + s * d[0] + c * d[1], ath + d[2])


class Robot:
    """One robot's body in the pymunk space, with its walking engine and head.

    Poses are in the world frame (m, rad). The robot never decides anything; it executes the
    last motion request until a new one arrives.
    """

    def __init__(
        self,
        team: int,
        number: int,
        params: RobotParams,
        rng: np.random.Generator,
        states: RobotStates | None = None,
        row: int = 0,
    ):
        """``states``, ``row``: the row of the motion state array this robot keeps its per-step state
        in (:mod:`teamsim.walking`; the world's, shared by all its robots), or a row of its own."""
        self.team = team
        self.number = number
        self.params = params
        self.rng = rng
        moment = pymunk.moment_for_circle(params.mass, 0.0, params.radius)
        self.body = pymunk.Body(params.mass, moment)
        self.shape = pymunk.Circle(self.body, params.radius)
        self.shape.collision_type = COLLISION_ROBOT
        self.shape.friction = 0.2
        self.shape.elasticity = 0.1
        self.control = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        self.pivot = pymunk.PivotJoint(self.control, self.body, (0, 0), (0, 0))
        self.pivot.max_bias = 0.0
        self.pivot.max_force = params.floor_force
        self.gear = pymunk.GearJoint(self.control, self.body, 0.0, 1.0)
        self.gear.max_bias = 0.0
        self.gear.max_force = params.floor_torque
        states = RobotStates(1) if states is None else states
        self._m = states.view
        """The motion state array, flat (a memoryview: single values read as plain floats)."""
        self._o = row * WIDTH
        """Offset of this robot's row in :attr:`_m` (columns: :mod:`teamsim.walking`)."""
        m, o = self._m, self._o
        for c in range(WIDTH):
            m[o + c] = 0.0
        m[o + FALLEN_UNTIL] = m[o + FALLEN_SINCE] = -1.0
        m[o + LIN_ACC], m[o + ANG_ACC] = params.max_linear_accel, params.max_angular_accel
        self.in_space = False
        """In the physics space (a plain attribute, mirrored into the state row by :meth:`add_to`
        and :meth:`remove_from`, the only places that change it)."""
        self.walk_target = WalkRequest()
        self._walk_limits = (params.max_backward, params.max_forward, params.max_sideways, params.max_turn)
        """The speed limits of :meth:`_clipped_target` (m/s, m/s, m/s, rad/s), read once."""
        self._head_limits = (params.head_yaw_limit, params.head_pitch_min, params.head_pitch_max, params.head_max_speed)
        """The joint limits of :meth:`_head_goal` (rad, rad, rad, rad/s), read once."""
        self._head: HeadState | None = HeadState()
        """:attr:`head` as last packed (rebuilt after the joints moved)."""
        self.head_target = HeadRequest()
        self.kick_request: KickRequest | None = None
        self.penalized = False
        self._set_goal()

    # -- the state row -----------------------------------------------------------------------
    def _triple(self, c: int) -> tuple[float, float, float]:
        m, o = self._m, self._o + c
        return (m[o], m[o + 1], m[o + 2])

    def _set_triple(self, c: int, v: tuple[float, float, float] | list[float]) -> None:
        m, o = self._m, self._o + c
        m[o], m[o + 1], m[o + 2] = float(v[0]), float(v[1]), float(v[2])

    @property
    def velocity(self) -> tuple[float, float, float]:
        """Executed walk speed (vx m/s, vy m/s, w rad/s; robot frame)."""
        return self._triple(VX)

    @velocity.setter
    def velocity(self, v: tuple[float, float, float] | list[float]) -> None:
        self._set_triple(VX, v)

    @property
    def planned(self) -> tuple[float, float, float]:
        """The walking engine's own motion since the last :meth:`take_motion` (m, m, rad; robot frame)."""
        return self._triple(PX)

    @property
    def true_motion(self) -> tuple[float, float, float]:
        """The body's true motion since the last :meth:`take_motion` (m, m, rad; robot frame)."""
        return self._triple(MX)

    @property
    def fallen_until(self) -> float:
        """Time (s) when the robot stands again; -1 while it is not fallen."""
        return self._m[self._o + FALLEN_UNTIL]

    @fallen_until.setter
    def fallen_until(self, t: float) -> None:
        self._m[self._o + FALLEN_UNTIL] = float(t)

    @property
    def fallen_since(self) -> float:
        """Time (s) when the robot fell; -1 while it is not fallen."""
        return self._m[self._o + FALLEN_SINCE]

    @fallen_since.setter
    def fallen_since(self, t: float) -> None:
        self._m[self._o + FALLEN_SINCE] = float(t)

    @property
    def busy_until(self) -> float:
        """Time (s) when the kick motion in progress ends (walking waits until then)."""
        return self._m[self._o + BUSY_UNTIL]

    @busy_until.setter
    def busy_until(self, t: float) -> None:
        self._m[self._o + BUSY_UNTIL] = float(t)

    @property
    def penalized(self) -> bool:
        """Penalised by the referee."""
        return self._m[self._o + PENALIZED] != 0.0

    @penalized.setter
    def penalized(self, value: bool) -> None:
        self._m[self._o + PENALIZED] = 1.0 if value else 0.0

    @property
    def picked_up(self) -> bool:
        """Both feet are off the ground (the referee carries the robot)."""
        return self._m[self._o + PICKED] != 0.0

    @picked_up.setter
    def picked_up(self, value: bool) -> None:
        self._m[self._o + PICKED] = 1.0 if value else 0.0

    def _set_goal(self) -> None:
        """Write the clipped head target (:meth:`_head_goal`) and the requested camera into the state
        row; the head moves again."""
        m, o = self._m, self._o
        m[o + GYAW], m[o + GPITCH], m[o + GSPEED] = self._head_goal()
        m[o + GCAM] = 1.0 if self.head_target.camera == "lower" else 0.0
        m[o + RESTING] = 0.0

    def _store_body_pose(self, x: float, y: float, theta: float) -> None:
        """Set :attr:`body_pose` (the start pose of the next step) and :attr:`pose` in the state row."""
        m, o = self._m, self._o
        m[o + BX], m[o + BY], m[o + BTH] = x, y, theta
        m[o + WTH] = wrap_angle(theta)

    @property
    def body_pose(self) -> tuple[float, float, float]:
        """World pose as the physics body holds it (x m, y m, theta rad, not wrapped), from the state
        row: read from pymunk after every physics step (:meth:`teamsim.world.World.step`) and set by
        :meth:`teleport`; nothing else moves the body."""
        m, o = self._m, self._o
        return (m[o + BX], m[o + BY], m[o + BTH])

    # -- placement -------------------------------------------------------------------------
    def add_to(self, space: pymunk.Space) -> None:
        """Put the robot on the field (into the physics space)."""
        if not self.in_space:
            space.add(self.body, self.shape, self.control, self.pivot, self.gear)
            self.in_space = True
            self._m[self._o + IN_SPACE] = 1.0

    def remove_from(self, space: pymunk.Space) -> None:
        """Take the robot off the field (out of the physics space)."""
        if self.in_space:
            space.remove(self.body, self.shape, self.control, self.pivot, self.gear)
            self.in_space = False
            self._m[self._o + IN_SPACE] = 0.0

    def teleport(self, x: float, y: float, theta: float) -> None:
        """Move the robot without any motion being sensed (placement, kidnapping)."""
        self.body.position = (x, y)
        self.body.angle = theta
        self.body.velocity = (0.0, 0.0)
        self.body.angular_velocity = 0.0
        self.control.position = (x, y)
        self.control.angle = theta
        self.control.velocity = (0.0, 0.0)
        self.control.angular_velocity = 0.0
        self._set_triple(CX, (0.0, 0.0, 0.0))
        self._set_triple(VX, (0.0, 0.0, 0.0))
        self._read_body()
        if self.body.space is not None:
            self.body.space.reindex_shapes_for_body(self.body)

    @property
    def pose(self) -> tuple[float, float, float]:
        """World pose (x m, y m, theta rad wrapped to (-pi, pi]): :attr:`body_pose` with the angle
        the walking engine wraps when it stores the pose (:func:`teamsim.walking.wrap_angle_nb`)."""
        m, o = self._m, self._o
        return (m[o + BX], m[o + BY], m[o + WTH])

    @property
    def head(self) -> HeadState:
        """Measured head joint angles and rates (relative to the torso) after the last physics step."""
        head = self._head
        m, o = self._m, self._o
        if head is None or m[o + HEAD_MOVED] != 0.0:
            head = self._head = HeadState(  # yaw, pitch, yaw_rate, pitch_rate, camera (by position: cheaper)
                m[o + HYAW], m[o + HPITCH], m[o + HYR], m[o + HPR], "lower" if m[o + HCAM] != 0.0 else "upper"
            )
            m[o + HEAD_MOVED] = 0.0
        return head

    def _read_body(self) -> None:
        """Read the body's pose from pymunk into :attr:`body_pose` and :attr:`pose`."""
        handle = self.body._body
        v = get_position(handle)
        self._store_body_pose(v.x, v.y, get_angle(handle))

    # -- commands --------------------------------------------------------------------------
    def command(self, walk: WalkRequest, kick: KickRequest | None, head: HeadRequest) -> None:
        """Take a new motion request (called once per cognition frame)."""
        self.walk_target = walk
        self.head_target = head
        m, o = self._m, self._o
        m[o + TX], m[o + TY], m[o + TW] = self._clipped_target()  # floats (see there)
        self._set_goal()
        if kick is not None and self.kick_request is None and self.can_walk_at_all():
            self.kick_request = kick

    def can_walk_at_all(self) -> bool:
        return self.in_space and not self.picked_up and self.fallen_until < 0

    def is_fallen(self) -> bool:
        return self.fallen_until >= 0

    def fall(self, now: float, duration: float | None = None) -> float:
        """Topple over; returns the time when the robot will stand again (s)."""
        p = self.params
        if duration is None:
            duration = max(p.getup_min, float(self.rng.normal(p.getup_mean, p.getup_sigma)))
        if not self.is_fallen():
            self.fallen_since = now
        self.fallen_until = max(self.fallen_until, now + duration)
        self.kick_request = None
        self._set_triple(VX, (0.0, 0.0, 0.0))
        return self.fallen_until

    def _clipped_target(self) -> tuple[float, float, float]:
        """The walk target clipped to the speed limits per axis, then scaled into the limits'
        ellipsoid (m/s, m/s, rad/s; robot frame)."""
        max_backward, max_forward, max_sideways, max_turn = self._walk_limits
        w = self.walk_target
        # min(max(v, -limit), limit) per axis, written as the comparisons min and max make
        fwd, left, turn = w.forward, w.left, w.turn
        if fwd < -max_backward:
            fwd = -max_backward
        if fwd > max_forward:
            fwd = max_forward
        if left < -max_sideways:
            left = -max_sideways
        if left > max_sideways:
            left = max_sideways
        if turn < -max_turn:
            turn = -max_turn
        if turn > max_turn:
            turn = max_turn
        norm = math.sqrt(
            (fwd / (max_forward if fwd >= 0 else max_backward)) ** 2
            + (left / max_sideways) ** 2
            + (turn / max_turn) ** 2
        )
        scale = 1.0 / norm if norm > 1.0 else 1.0
        return (fwd * scale, left * scale, turn * scale)  # floats, even for integer requests (scale is one)

    def take_motion(self) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
        """Return and reset (planned, true) motion since the last call, robot frame."""
        m, o = self._m, self._o + PX
        out = m[o : o + 6].tolist()  # planned (PX, PY, PTH), then true (MX, MY, MTH)
        m[o : o + 6] = _ZEROS6
        return (tuple(out[:3]), tuple(out[3:]))

    def _head_goal(self) -> tuple[float, float, float]:
        """The head target's (yaw rad, pitch rad, speed rad/s) clipped to the joint limits."""
        yaw_limit, pitch_min, pitch_max, max_speed = self._head_limits
        t = self.head_target
        # min(max(v, lower), upper), written as the comparisons min and max make
        ty, tp, speed = t.yaw, t.pitch, t.speed
        if ty < -yaw_limit:
            ty = -yaw_limit
        if ty > yaw_limit:
            ty = yaw_limit
        if tp < pitch_min:
            tp = pitch_min
        if tp > pitch_max:
            tp = pitch_max
        if speed > max_speed:
            speed = max_speed
        return (float(ty), float(tp), float(speed))

    def try_kick(self, now: float, ball: pymunk.Body, ball_radius: float) -> bool:
        """Execute a pending kick; returns True if the ball was struck."""
        kick = self.kick_request
        if kick is None or now < self.busy_until or not self.can_walk_at_all():
            return False
        self.kick_request = None
        p = self.params
        self.busy_until = now + p.kick_duration
        x, y, th = self.pose
        b = get_position(ball._body)  # ball.position (see get_position)
        dx, dy = b.x - x, b.y - y
        dist = math.hypot(dx, dy)
        bearing = wrap_angle(math.atan2(dy, dx) - th)
        if dist - p.radius - ball_radius > p.kick_reach or abs(bearing) > p.kick_half_angle:
            return False
        direction = min(max(kick.direction, -p.kick_max_angle), p.kick_max_angle)
        direction += float(self.rng.normal(0.0, p.kick_direction_sigma))
        speed = kick.strength * p.kick_max_speed
        speed *= max(0.0, 1.0 + float(self.rng.normal(0.0, p.kick_strength_sigma)))
        ang = th + direction
        ball.velocity = (speed * math.cos(ang), speed * math.sin(ang))
        return True
