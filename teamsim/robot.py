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
from typing import ClassVar, Literal

import numpy as np
import pymunk
from pymunk._chipmunk_cffi import lib as _chipmunk

from cognition.geometry import wrap_angle
from cognition.representations import HeadRequest, HeadState, KickRequest, WalkRequest
from teamsim.params import Range, Ranges, check_ranges, non_negative, positive

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

    def __init__(self, team: int, number: int, params: RobotParams, rng: np.random.Generator):
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
        self.in_space = False
        self.walk_target = WalkRequest()
        self.velocity = [0.0, 0.0, 0.0]  # executed walk speed (vx m/s, vy m/s, w rad/s), robot frame
        self._head_joints: tuple[float, float, float, float, Literal["upper", "lower"]] = (0.0, 0.0, 0.0, 0.0, "upper")
        """The head's (yaw rad, pitch rad, yaw rate rad/s, pitch rate rad/s, camera), advanced by
        :meth:`_step_head` at the physics rate; :attr:`head` packs it when someone reads it."""
        self._head: HeadState | None = HeadState()
        """:attr:`head` as last packed (``None`` after the joints moved)."""
        self.head_target = HeadRequest()
        self.kick_request: KickRequest | None = None
        self.busy_until = 0.0  # kicking
        self.fallen_until = -1.0
        self.fallen_since = -1.0
        self.picked_up = False
        self.penalized = False
        self.planned = (0.0, 0.0, 0.0)  # walking engine's own motion since last frame
        self.true_motion = (0.0, 0.0, 0.0)  # actual body motion since last frame
        self._target = (0.0, 0.0, 0.0)
        """The walk target clipped to the robot's limits (:meth:`_clipped_target`), set by :meth:`command`."""
        self._goal = self._head_goal()
        """The head target clipped to the joint limits (:meth:`_head_goal`), set by :meth:`command`."""
        self._control = (0.0, 0.0, 0.0)
        """The control body's (vx, vy, angular velocity) as last set (m/s, rad/s, world frame): a
        kinematic body keeps its velocity, so an unchanged command is not sent to pymunk again."""
        self.body_pose: tuple[float, float, float] = (0.0, 0.0, 0.0)
        """World pose as the physics body holds it (x m, y m, theta rad, not wrapped); read-only for
        everyone else. Read from pymunk after every physics step and set by :meth:`teleport`:
        nothing else moves the body, so reading it once per step serves the walking engine,
        :attr:`pose` and the referee's many looks (a plain attribute: they read it in every step)."""
        self._pose: tuple[float, float, float] | None = (0.0, 0.0, 0.0)
        """``body_pose`` with the angle wrapped (:attr:`pose`); ``None`` until first asked for after
        the body moved (the walking engine and the foul checks need only ``body_pose``)."""
        self._step_rotation: tuple[float, float] | None = None
        """cos and sin of the body angle at the start of the physics step in progress, computed by
        :meth:`pre_step` and reused by :meth:`post_step` (the body does not turn in between);
        ``None`` when pre_step did not need them."""
        self._head_resting = False
        """The head is at its clipped target with zero rates and reads the requested camera:
        :meth:`_step_head` would change nothing until :meth:`command` sets a new target."""

    # -- placement -------------------------------------------------------------------------
    def add_to(self, space: pymunk.Space) -> None:
        """Put the robot on the field (into the physics space)."""
        if not self.in_space:
            space.add(self.body, self.shape, self.control, self.pivot, self.gear)
            self.in_space = True

    def remove_from(self, space: pymunk.Space) -> None:
        """Take the robot off the field (out of the physics space)."""
        if self.in_space:
            space.remove(self.body, self.shape, self.control, self.pivot, self.gear)
            self.in_space = False

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
        self._control = (0.0, 0.0, 0.0)
        self.velocity = [0.0, 0.0, 0.0]
        self._read_body()
        if self.body.space is not None:
            self.body.space.reindex_shapes_for_body(self.body)

    @property
    def pose(self) -> tuple[float, float, float]:
        """World pose (x m, y m, theta rad wrapped)."""
        pose = self._pose
        if pose is None:
            x, y, th = self.body_pose
            pose = self._pose = (x, y, wrap_angle(th))
        return pose

    @property
    def head(self) -> HeadState:
        """Measured head joint angles and rates (relative to the torso) after the last physics step."""
        head = self._head
        if head is None:
            yaw, pitch, yaw_rate, pitch_rate, camera = self._head_joints
            head = self._head = HeadState(yaw=yaw, pitch=pitch, yaw_rate=yaw_rate, pitch_rate=pitch_rate, camera=camera)
        return head

    @property
    def head_joints(self) -> tuple[float, float, float, float, Literal["upper", "lower"]]:
        """The head's (yaw rad, pitch rad, yaw rate rad/s, pitch rate rad/s, camera read) now:
        :attr:`head` unpacked, without building it."""
        return self._head_joints

    def _read_body(self) -> None:
        """Read the body's pose from pymunk into :attr:`body_pose` (:attr:`pose` follows on demand)."""
        handle = self.body._body
        v = get_position(handle)
        self.body_pose = (v.x, v.y, get_angle(handle))
        self._pose = None

    # -- commands --------------------------------------------------------------------------
    def command(self, walk: WalkRequest, kick: KickRequest | None, head: HeadRequest) -> None:
        """Take a new motion request (called once per cognition frame)."""
        self.walk_target = walk
        self._target = self._clipped_target()
        self.head_target = head
        self._goal = self._head_goal()
        self._head_resting = False
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
        self.velocity = [0.0, 0.0, 0.0]
        return self.fallen_until

    def _clipped_target(self) -> tuple[float, float, float]:
        """The walk target clipped to the speed limits per axis, then scaled into the limits'
        ellipsoid (m/s, m/s, rad/s; robot frame)."""
        p = self.params
        w = self.walk_target
        fwd = min(max(w.forward, -p.max_backward), p.max_forward)
        left = min(max(w.left, -p.max_sideways), p.max_sideways)
        turn = min(max(w.turn, -p.max_turn), p.max_turn)
        norm = math.sqrt(
            (fwd / (p.max_forward if fwd >= 0 else p.max_backward)) ** 2
            + (left / p.max_sideways) ** 2
            + (turn / p.max_turn) ** 2
        )
        scale = 1.0 / norm if norm > 1.0 else 1.0
        return (fwd * scale, left * scale, turn * scale)

    # -- per physics step ------------------------------------------------------------------
    def pre_step(self, now: float, dt: float) -> None:
        """Advance the walking engine and head by ``dt`` (s) and set the control body.

        The executed walk speed (robot frame) moves toward the clipped target by at most
        ``max_linear_accel * dt`` (m/s) and ``max_angular_accel * dt`` (rad/s) per axis; the control
        body gets that speed rotated into the world frame by the body angle at the start of the
        step, and the planned motion integrates it in the robot frame.
        """
        if not self._head_resting:
            self._step_head(dt)
        if not self.in_space:
            return
        fallen_until = self.fallen_until
        if fallen_until >= 0 and now >= fallen_until:
            self.fallen_until = fallen_until = -1.0
            self.fallen_since = -1.0
        if self.picked_up or fallen_until >= 0:
            vx = vy = w = 0.0
            self.velocity = [0.0, 0.0, 0.0]
        else:
            p = self.params
            tx, ty, tw = (0.0, 0.0, 0.0) if now < self.busy_until else self._target
            lin, ang = p.max_linear_accel * dt, p.max_angular_accel * dt
            vx, vy, w = self.velocity
            # each axis: v + min(limit, max(-limit, target - v)), written as comparisons
            d = tx - vx
            vx += lin if d > lin else (-lin if d < -lin else d)
            d = ty - vy
            vy += lin if d > lin else (-lin if d < -lin else d)
            d = tw - w
            w += ang if d > ang else (-ang if d < -ang else d)
            self.velocity = [vx, vy, w]
        last = self._control
        if vx == 0.0 and vy == 0.0 and w == 0.0 and last == (0.0, 0.0, 0.0):
            # Standing with a still control body: the rotated speed would compare equal to the
            # last one sent (nothing to send), and adding zero motion leaves the planned motion
            # as it is bit for bit (its components start at +0.0 and a sum is -0.0 only when
            # both terms are).
            self._step_rotation = None
            return
        th = self.body_pose[2]
        c, s = math.cos(th), math.sin(th)
        self._step_rotation = (c, s)
        cvx, cvy = c * vx - s * vy, s * vx + c * vy
        if cvx != last[0] or cvy != last[1] or w != last[2]:
            # A kinematic body keeps its velocity (the solver adds at most a zero to it), so a
            # non-zero value equal to the last one sent is already there bit for bit; zeros are
            # sent again, as they may differ in sign.
            if cvx != last[0] or cvy != last[1] or cvx == 0.0 or cvy == 0.0:
                set_velocity(self.control._body, (cvx, cvy))
            if w != last[2] or w == 0.0:
                set_angular_velocity(self.control._body, w)
            self._control = (cvx, cvy, w)
        # planned = compose(planned, (vx dt, vy dt, w dt)), inlined
        px, py, pth = self.planned
        pc, ps = math.cos(pth), math.sin(pth)
        dx, dy = vx * dt, vy * dt
        self.planned = (px + pc * dx - ps * dy, py + ps * dx + pc * dy, pth + w * dt)

    def post_step(self) -> None:
        """Accumulate the true body motion of the step just simulated (after :meth:`pre_step`)."""
        if not self.in_space:
            return
        x0, y0, th0 = self.body_pose
        handle = self.body._body
        v = get_position(handle)  # body.position and body.angle, read in C (see get_position)
        x1, y1 = v.x, v.y
        th1 = get_angle(handle)
        self.body_pose = (x1, y1, th1)  # as _read_body
        self._pose = None
        if x1 == x0 and y1 == y0 and th1 == th0:
            return  # adding zero motion leaves the true motion as it is (see pre_step)
        rotation = self._step_rotation
        c, s = (math.cos(th0), math.sin(th0)) if rotation is None else rotation
        dxw, dyw = x1 - x0, y1 - y0
        lx, ly = c * dxw + s * dyw, -s * dxw + c * dyw
        # true_motion = compose(true_motion, (lx, ly, th1 - th0)), inlined
        ax, ay, ath = self.true_motion
        ac, as_ = math.cos(ath), math.sin(ath)
        self.true_motion = (ax + ac * lx - as_ * ly, ay + as_ * lx + ac * ly, ath + (th1 - th0))

    def take_motion(self) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
        """Return and reset (planned, true) motion since the last call, robot frame."""
        out = (self.planned, self.true_motion)
        self.planned = (0.0, 0.0, 0.0)
        self.true_motion = (0.0, 0.0, 0.0)
        return out

    def _head_goal(self) -> tuple[float, float, float]:
        """The head target's (yaw rad, pitch rad, speed rad/s) clipped to the joint limits."""
        p = self.params
        t = self.head_target
        ty = min(max(t.yaw, -p.head_yaw_limit), p.head_yaw_limit)
        tp = min(max(t.pitch, p.head_pitch_min), p.head_pitch_max)
        return (ty, tp, min(t.speed, p.head_max_speed))

    def _step_head(self, dt: float) -> None:
        """Move the head joints toward the clipped target by at most ``speed * dt`` (rad) each."""
        yaw, pitch, yaw_rate, pitch_rate, camera_now = self._head_joints
        ty, tp, speed = self._goal
        camera = self.head_target.camera
        if ty == yaw and tp == pitch and yaw_rate == 0.0 and pitch_rate == 0.0 and camera_now == camera:
            self._head_resting = True  # until the next command
            return
        reach = speed * dt
        # min(max(target - angle, -reach), reach), written as comparisons
        dy = ty - yaw
        if -reach > dy:
            dy = -reach
        if reach < dy:
            dy = reach
        dp = tp - pitch
        if -reach > dp:
            dp = -reach
        if reach < dp:
            dp = reach
        if dy == 0.0 and dp == 0.0 and yaw_rate == 0.0 and pitch_rate == 0.0 and camera_now == camera:
            return
        self._head_joints = (yaw + dy, pitch + dp, dy / dt, dp / dt, camera)
        self._head = None

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
