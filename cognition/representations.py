"""Robot-facing representations: what a robot senses each cognition frame and what it asks for.

These types cross the boundary between the simulator (or a real robot) and a brain. They
hold only what a robot can know; ground truth never appears here (see
:mod:`cognition.oracle` for the one explicit exception used by oracle brains).

Frames used below:

* **robot frame**: metres and radians, origin between the feet, +x forward, +y left,
  angles counter-clockwise.
* **team frame**: the field frame of :mod:`cognition.field`, origin at the centre, +x toward
  the opponent goal.

=====================  ==================================================================
type                   content
=====================  ==================================================================
OdometryReading        motion since the previous frame in the previous robot frame
HeadState              head yaw/pitch (rad) and their rates (rad/s)
TeamMessageIn          a teammate's message as received (bytes, sender, send time)
SensorFrame            everything one robot senses in one cognition frame (incl. percepts)
WalkRequest            forward/sideways (m/s) and turn (rad/s) in the robot frame
KickRequest            kick direction (rad, robot frame) and strength in [0, 1]
HeadRequest            target yaw/pitch (rad), max speed (rad/s), camera to read
MotionRequest          walk or kick, plus head
BrainOutput            motion request and an optional team message (<= 128 bytes)
RobotPose              the localization's pose estimate (team frame) with its uncertainty
=====================  ==================================================================

The requests are built every frame; they refuse NaN, infinity and anything that is not a
real number (bool, str, complex, None) with an error naming the field
(:func:`cognition.params.check_finite`, a cheap check).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from cognition.camera import CameraImage
from cognition.gamestate import TEAM_MESSAGE_MAX_BYTES, GameControlData
from cognition.params import check_finite
from cognition.percepts import Percepts
from cognition.records import fast_init


@fast_init
@dataclass(frozen=True)
class OdometryReading:
    """Reported own motion since the previous cognition frame.

    Expressed in the robot frame of the previous frame: ``dx`` forward (m), ``dy`` left (m),
    ``dtheta`` counter-clockwise rotation (rad). This is what the walking engine believes it
    did, with its errors; it is not ground truth.
    """

    dx: float = 0.0
    dy: float = 0.0
    dtheta: float = 0.0


@fast_init
@dataclass(frozen=True)
class HeadState:
    """Measured head joint angles and rates (relative to the torso)."""

    yaw: float = 0.0
    """Head yaw (rad), positive to the left."""
    pitch: float = 0.0
    """Head pitch (rad), positive looks down."""
    yaw_rate: float = 0.0
    """Yaw angular rate (rad/s)."""
    pitch_rate: float = 0.0
    """Pitch angular rate (rad/s)."""
    camera: Literal["upper", "lower"] = "upper"
    """The camera read in this frame."""


@fast_init
@dataclass(frozen=True)
class TeamMessageIn:
    """A team message as a robot receives it."""

    sender: int
    """Player number of the sender (1-based)."""
    payload: bytes
    """The raw message (at most 128 bytes)."""
    sent_at: float
    """Game time when it was sent (s since match start)."""


@fast_init
@dataclass(frozen=True)
class SensorFrame:
    """Everything one robot senses in one cognition frame.

    With the ``percepts`` observation, ``percepts`` holds what vision reported for the latest
    image (synthesized by the simulator's camera model, taken ``latency`` seconds before
    ``time``). With the ``images`` observation, ``image`` holds that image itself, with the
    camera matrix and head angles of its exposure, and the brain's own vision makes percepts.
    """

    time: float
    """Time of the frame (s since match start)."""
    frame_index: int
    """Counter of this robot's cognition frames, starting at 0."""
    team_number: int
    """Own team number as used by the GameController."""
    player_number: int
    """Own player number (1-based)."""
    odometry: OdometryReading
    head: HeadState
    game: GameControlData
    """The latest GameController packet."""
    picked_up: bool = False
    """Both feet are off the ground (foot pressure sensors)."""
    fallen: bool = False
    """The robot lies on the ground (inertial sensors) and is getting up."""
    messages: tuple[TeamMessageIn, ...] = ()
    """Team messages received since the previous frame."""
    percepts: Percepts | None = None
    """Percepts of the latest camera image (robot frame), or ``None`` without a camera model."""
    image: CameraImage | None = None
    """The latest camera image (image observation path), or ``None``."""

    @property
    def penalty(self) -> int:
        """Own penalty code from the game state (0 when playing)."""
        return int(self.game.team(self.team_number).players[self.player_number - 1].penalty)


@fast_init
@dataclass(frozen=True)
class WalkRequest:
    """Walk command in the robot frame; the walking engine clips it to its limits."""

    forward: float = 0.0
    """Forward speed (m/s)."""
    left: float = 0.0
    """Sideways speed (m/s), positive to the left."""
    turn: float = 0.0
    """Turn rate (rad/s), counter-clockwise."""

    def __post_init__(self) -> None:
        f, s, t = self.forward, self.left, self.turn
        # the fast path of check_finite, written out (every behaviour sends one request a frame)
        if not (f.__class__ is s.__class__ is t.__class__ is float and f - f == 0.0 and s - s == 0.0 and t - t == 0.0):
            check_finite("WalkRequest", forward=f, left=s, turn=t)


@fast_init
@dataclass(frozen=True)
class KickRequest:
    """A kick of the ball in front of the feet."""

    direction: float = 0.0
    """Intended ball direction (rad, robot frame)."""
    strength: float = 1.0
    """Fraction of the strongest kick, in [0, 1]."""

    def __post_init__(self) -> None:
        check_finite("KickRequest", direction=self.direction, strength=self.strength)
        if not 0.0 <= self.strength <= 1.0:
            raise ValueError(f"KickRequest.strength must be in [0, 1], got {self.strength}")


@fast_init
@dataclass(frozen=True)
class HeadRequest:
    """Head motion target; the joints move there at most at ``speed``."""

    yaw: float = 0.0
    """Target yaw (rad)."""
    pitch: float = 0.3
    """Target pitch (rad), positive looks down."""
    speed: float = 4.0
    """Maximum angular speed (rad/s)."""
    camera: Literal["upper", "lower"] = "upper"
    """The camera to read in the next frame."""

    def __post_init__(self) -> None:
        y, p, v = self.yaw, self.pitch, self.speed
        # the fast path of check_finite, written out (every behaviour sends one request a frame)
        if not (y.__class__ is p.__class__ is v.__class__ is float and y - y == 0.0 and p - p == 0.0 and v - v == 0.0):
            check_finite("HeadRequest", yaw=y, pitch=p, speed=v)
        if self.speed <= 0:
            raise ValueError(f"HeadRequest.speed must be > 0, got {self.speed}")
        if self.camera not in ("upper", "lower"):
            raise ValueError(f"HeadRequest.camera must be 'upper' or 'lower', got {self.camera!r}")


@fast_init
@dataclass(frozen=True)
class MotionRequest:
    """What the body should do until the next cognition frame.

    With ``kick`` set the robot kicks (if the ball is in reach the ball is struck, otherwise
    the kick misses) and ignores ``walk`` until the kick motion has finished.
    """

    walk: WalkRequest = field(default_factory=WalkRequest)
    kick: KickRequest | None = None
    head: HeadRequest = field(default_factory=HeadRequest)


@fast_init
@dataclass(frozen=True)
class BrainOutput:
    """A brain's answer to one sensor frame."""

    motion: MotionRequest = field(default_factory=MotionRequest)
    message: bytes | None = None
    """Team message to broadcast now, at most 128 bytes, or ``None``."""

    def __post_init__(self) -> None:
        if self.message is not None and len(self.message) > TEAM_MESSAGE_MAX_BYTES:
            raise ValueError(
                f"team message has {len(self.message)} bytes; at most {TEAM_MESSAGE_MAX_BYTES} are allowed"
            )


@fast_init
@dataclass(frozen=True)
class RobotPose:
    """The localization's estimate of the own pose (team frame), as behaviors read it.

    ``covariance`` is the weighted covariance of the particles around the estimate (x, y in
    m, theta in rad; the angle part from wrapped differences). ``lost`` is set when the
    particles are spread too widely to trust the estimate (CMU paper, Sec. III.E).
    ``particles`` (N x 3: x, y, theta) and ``weights`` (N, normalised) are the filter's set
    for drawing; they are empty for the ``odometry`` and ``oracle`` variants.
    """

    x: float
    """Position (m, team frame)."""
    y: float
    """Position (m, team frame)."""
    theta: float
    """Heading (rad, team frame), in (-pi, pi]."""
    covariance: NDArray[np.float64]
    """3 x 3 covariance of (x m, y m, theta rad)."""
    lost: bool
    """True when the estimate should not be trusted."""
    n_particles: int
    """Number of particles in the filter (0 for variants without particles)."""
    particles: NDArray[np.float64]
    """N x 3 particle poses (team frame), read-only."""
    weights: NDArray[np.float64]
    """N normalised particle weights, read-only."""
    variant: str = ""
    """Name of the localization variant that produced the estimate."""

    @property
    def pose(self) -> tuple[float, float, float]:
        """(x m, y m, theta rad) in the team frame."""
        return (self.x, self.y, self.theta)

    @property
    def position_std(self) -> float:
        """sqrt of the trace of the position covariance (m)."""
        c = self.covariance
        t = float(c[0, 0] + c[1, 1])
        return math.sqrt(t if t > 0.0 else 0.0)  # max(0.0, t); IEEE sqrt: the same bits as np.sqrt


BallLevel = Literal["valid", "suspicious", "invalid"]
"""CMU IV.A's three confidence levels of a ball belief."""


@fast_init
@dataclass(frozen=True)
class BallModel:
    """What the robot believes about the ball.

    ``x, y, vx, vy`` are in the **robot frame** (m, m/s); ``field_x, field_y`` in the team
    frame via the pose estimate (NaN without one). ``covariance`` is the 4 x 4 covariance of
    (x, y, vx, vy). ``age`` is the time since the own camera last saw the ball (s);
    ``source`` says what the latest update came from.
    """

    x: float
    y: float
    vx: float
    vy: float
    covariance: NDArray[np.float64]
    field_x: float
    field_y: float
    age: float
    level: BallLevel
    source: Literal["vision", "team", "prediction", "none"]

    @property
    def distance(self) -> float:
        """Distance from the robot (m)."""
        return float(math.hypot(self.x, self.y))

    @property
    def bearing(self) -> float:
        """Direction from the robot (rad, robot frame)."""
        return float(math.atan2(self.y, self.x))
