"""Head control: where the camera looks, as an explicit state machine on :class:`Beliefs`.

The head serves two masters: the ball (behaviors need it in view) and localization (it needs
landmarks, which the ball rarely lies in front of). The CMU paper (Sec. IV.A) adds a third:
when the world model holds a *suspicious* ball hypothesis it asks the behaviors to look
there (``Beliefs.look_at``, active gaze), so that the hypothesis becomes valid or dies fast.

=======  ==========================================================================================
state    behaviour (checked in this order each frame)
=======  ==========================================================================================
scan     the pose estimate is ``lost`` or its position std exceeds ``uncertain_std`` (until it is
         below ``certain_std`` again), or a routine scan is due: ``scan_duration`` s every
         ``scan_period`` s, player n shifted by n * ``player_offset`` s so that the team does not
         look away from the ball all at once. A triangle sweep of the yaw (robot frame) between
         ``-scan_yaw`` and ``+scan_yaw`` at ``scan_pitch``, upper camera, starting on the side the
         head points to (:class:`HeadSweep`). The lost scan comes first; the routine scan yields
         to ``look_at``
look_at  the world model asks to check a suspicious ball (``Beliefs.look_at``, robot frame)
search   nobody knows where the ball is: the same sweep as ``scan``
ball     look at the ball (``Beliefs.best_ball()`` through the estimated pose)
=======  ==========================================================================================

With truth beliefs (``Beliefs.source == "truth"``) the pose is exact and the ball always
known: the state is always ``ball``.

Looking at a ground point (robot frame, m): yaw is its bearing (limited to ``max_yaw``);
the camera is the lower one for points nearer than ``lower_below`` m (back to the upper one
beyond ``upper_above`` m, hysteresis), and the pitch puts the point at the image centre
(camera heights and tilts of the NAO V6, :mod:`cognition.camera`), limited to
[``pitch_min``, ``pitch_max``].

=================  =======  ==============  ========================================================
HeadParams         default  range           meaning
=================  =======  ==============  ========================================================
scan_period        5.0      (0, 3600]       s between the starts of two routine scans
scan_duration      1.0      (0, 3600]       s for one sweep from one side to the other (<= scan_period)
scan_yaw           1.4      [0, pi]         sweep amplitude (rad, both sides)
scan_pitch         0.3      [-pi/2, pi/2]   head pitch while scanning (rad, positive looks down)
scan_speed         4.0      (0, 100]        head speed requested while scanning (rad/s)
player_offset      0.7      [0, 3600]       routine scan of player n starts n * offset s later
uncertain_std      0.6      (0, 100]        position std (m) above which the head scans ...
certain_std        0.35     (0, 100]        ... until it is below this again (m; <= uncertain_std)
track_speed        4.0      (0, 100]        head speed requested while tracking (rad/s)
max_yaw            1.5      (0, pi]         largest tracking yaw (rad)
lower_below        0.7      (0, 100]        ball distance (m) below which the lower camera is read
upper_above        0.9      (0, 100]        ball distance (m) above which the upper camera is read
pitch_min          -0.3     [-pi/2, pi/2]   pitch limits while tracking (rad; pitch_min < pitch_max)
pitch_max          0.5      [-pi/2, pi/2]
=================  =======  ==============  ========================================================

Every value is checked against its range when the parameters are built
(:func:`cognition.params.check_ranges`).

The routine timing and the sweep (``scan_period`` to ``player_offset``) live in
:class:`HeadSweep`, which reads only those six rows.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar, Literal

from cognition.brain import BrainContext
from cognition.params import Range, Ranges, check_ranges, non_negative, positive
from cognition.representations import HeadRequest
from cognition.worldmodel.beliefs import Beliefs

HeadStateName = Literal["ball", "look_at", "scan", "search"]
HEAD_STATES: tuple[str, ...] = ("ball", "look_at", "scan", "search")

_UPPER_HEIGHT, _UPPER_TILT = 0.504, math.radians(1.2)
_LOWER_HEIGHT, _LOWER_TILT = 0.458, math.radians(39.7)


@dataclass(frozen=True)
class HeadParams:
    """Tuning of the head control (table in the module docstring)."""

    scan_period: float = 5.0
    scan_duration: float = 1.0
    scan_yaw: float = 1.4
    scan_pitch: float = 0.3
    scan_speed: float = 4.0
    player_offset: float = 0.7
    uncertain_std: float = 0.6
    certain_std: float = 0.35
    track_speed: float = 4.0
    max_yaw: float = 1.5
    lower_below: float = 0.7
    upper_above: float = 0.9
    pitch_min: float = -0.3
    pitch_max: float = 0.5

    RANGES: ClassVar[Ranges] = {
        "scan_period": positive(3600.0),
        "scan_duration": positive(3600.0),
        "scan_yaw": non_negative(math.pi),
        "scan_pitch": Range(-math.pi / 2, math.pi / 2),
        "scan_speed": positive(100.0),
        "player_offset": non_negative(3600.0),
        "uncertain_std": positive(100.0),
        "certain_std": positive(100.0),
        "track_speed": positive(100.0),
        "max_yaw": positive(math.pi),
        "lower_below": positive(100.0),
        "upper_above": positive(100.0),
        "pitch_min": Range(-math.pi / 2, math.pi / 2),
        "pitch_max": Range(-math.pi / 2, math.pi / 2),
    }

    def __post_init__(self) -> None:
        check_ranges(self)
        o = "HeadParams"
        if self.scan_duration > self.scan_period:
            raise ValueError(f"{o}.scan_duration ({self.scan_duration}) exceeds scan_period ({self.scan_period})")
        if self.certain_std > self.uncertain_std:
            raise ValueError(f"{o}.certain_std ({self.certain_std}) exceeds uncertain_std ({self.uncertain_std})")
        if self.lower_below > self.upper_above:
            raise ValueError(f"{o}.lower_below ({self.lower_below}) must not exceed upper_above ({self.upper_above})")
        if self.pitch_min >= self.pitch_max:
            raise ValueError(f"{o}.pitch_min ({self.pitch_min}) must be below pitch_max ({self.pitch_max})")


class HeadSweep:
    """The landmark scan: when routine scans run, and the triangle sweep of the head yaw.

    Reads the ``scan_*`` rows and ``player_offset`` of :class:`HeadParams` (module docstring).
    One sweep goes from ``side * scan_yaw`` to ``-side * scan_yaw`` (rad, robot frame) in
    ``scan_duration`` s and then back, at ``scan_pitch`` with the upper camera.
    """

    def __init__(self, params: HeadParams) -> None:
        self.params = params
        self.start = 0.0
        """When the current sweep began (s, match time)."""
        self.side = 1.0
        """The side it began on: +1 left (positive yaw), -1 right."""

    def routine_due(self, now: float, player_number: int) -> bool:
        """Whether the routine scan of ``player_number`` runs at ``now`` (s, match time).

        ``scan_duration`` s every ``scan_period`` s, player n shifted by n * ``player_offset`` s.
        """
        p = self.params
        phase = (now - player_number * p.player_offset) % p.scan_period
        return phase < p.scan_duration

    def begin(self, now: float, yaw: float) -> None:
        """Start a sweep at ``now`` (s) on the side the head points to (``yaw``, rad, robot frame)."""
        self.start = now
        self.side = 1.0 if yaw >= 0.0 else -1.0

    def request(self, now: float) -> HeadRequest:
        """The sweep's head request at ``now`` (s): the yaw (rad, robot frame) runs from ``side * scan_yaw``."""
        p = self.params
        u = max(0.0, now - self.start) / p.scan_duration
        leg = math.floor(u)
        frac = u - leg
        pos = frac if leg % 2 == 0 else 1.0 - frac
        yaw = self.side * p.scan_yaw * (1.0 - 2.0 * pos)
        return HeadRequest(yaw, p.scan_pitch, p.scan_speed, "upper")  # yaw, pitch, speed, camera


class HeadControl:
    """The head's state machine (module docstring); ``state`` names the current state."""

    def __init__(self, context: BrainContext, params: HeadParams | None = None) -> None:
        self.context = context
        self.params = params or HeadParams()
        self.state: HeadStateName = "ball"
        self.camera: Literal["upper", "lower"] = "upper"
        """The camera read while tracking (switched with hysteresis on the distance)."""
        self._uncertain = False
        self.sweep = HeadSweep(self.params)
        """The landmark sweep of the ``scan`` and ``search`` states."""
        self._yaw = 0.0
        """The latest requested yaw (rad): where the head points, roughly."""
        self._ball: tuple[float, float] | None = None
        """The ball (robot frame, m) the latest :meth:`_transition` found, if it looked for one."""

    def request(self, b: Beliefs) -> HeadRequest:
        """Decide the state on these beliefs and return the head request (robot frame)."""
        state = self._transition(b)
        if state in ("scan", "search"):
            if self.state not in ("scan", "search"):
                self.sweep.begin(b.time, self._yaw)
            self.state = state
            return self._sweep(b.time)
        self.state = state
        if state == "look_at":
            assert b.look_at is not None
            return self.look(*b.look_at)
        ball = self._ball if self._ball is not None else _ball_robot(b)  # found by _transition, if it looked
        assert ball is not None
        return self.look(*ball)

    def scan(self, b: Beliefs) -> HeadRequest:
        """Force a landmark scan now (a policy's ``scan`` macro-action)."""
        if self.state not in ("scan", "search"):
            self.sweep.begin(b.time, self._yaw)
        self.state = "scan"
        return self._sweep(b.time)

    def look(self, x: float, y: float) -> HeadRequest:
        """Point the camera at the ground point (x, y) (robot frame, m)."""
        p = self.params
        # the clamps below are max(lo, min(hi, v)) written as the comparisons those builtins make
        # (a tenth of their cost; the same results, NaN and signed zeros included)
        yaw, lim = math.atan2(y, x), p.max_yaw
        yaw = yaw if yaw < lim else lim
        yaw = yaw if yaw > -lim else -lim
        d = math.hypot(x, y)
        if self.camera == "upper" and d < p.lower_below:
            self.camera = "lower"
        elif self.camera == "lower" and d > p.upper_above:
            self.camera = "upper"
        far = 0.05 if d < 0.05 else d  # max(d, 0.05)
        if self.camera == "lower":
            pitch = math.atan2(_LOWER_HEIGHT, far) - _LOWER_TILT
        else:
            pitch = math.atan2(_UPPER_HEIGHT, far) - _UPPER_TILT
        self._yaw = yaw
        pitch = pitch if pitch < p.pitch_max else p.pitch_max
        pitch = pitch if pitch > p.pitch_min else p.pitch_min
        return HeadRequest(yaw, pitch, p.track_speed, self.camera)  # yaw, pitch, speed, camera

    # -- transitions -------------------------------------------------------------------------
    def _transition(self, b: Beliefs) -> HeadStateName:
        self._ball = None
        if b.source == "truth":
            return "ball"
        p = self.params
        std = b.pose.position_std
        if b.pose.lost or std > p.uncertain_std:
            self._uncertain = True
        elif std < p.certain_std:
            self._uncertain = False
        if self._uncertain:
            return "scan"
        if b.look_at is not None:
            return "look_at"
        if self.sweep.routine_due(b.time, self.context.player_number):
            return "scan"
        ball = self._ball = _ball_robot(b)  # kept for :meth:`request`, which looks at it
        return "ball" if ball is not None else "search"

    # -- the sweep ---------------------------------------------------------------------------
    def _sweep(self, now: float) -> HeadRequest:
        """The sweep's request (:meth:`HeadSweep.request`); the tracking camera is reset to the upper one."""
        r = self.sweep.request(now)
        self._yaw = r.yaw
        self.camera = "upper"
        return r


def _ball_robot(b: Beliefs) -> tuple[float, float] | None:
    """The ball to look at (robot frame, m): the own ball while valid, else ``best_ball()`` through the pose."""
    ball = b.ball
    if ball.level == "valid" and math.isfinite(ball.x):
        return (ball.x, ball.y)
    best = b.best_ball()
    return b.to_robot(*best) if best is not None else None
