"""The walking engines and heads of all robots: two compiled calls per physics step.

Every robot's per-step motion state lives in one row of a float array owned by the world
(:class:`RobotStates`); :class:`teamsim.robot.Robot` reads and writes its own row through
properties. :func:`pre_step_nb` advances, for every robot, the head joints toward their
clipped target, the executed walk speed toward the clipped walk target (bounded
accelerations), the planned motion (what the walking engine believes it did), and computes the
world-frame velocity of each control body; it lists the control bodies whose velocity pymunk
must be told. :func:`post_step_nb` then turns the body poses read back from pymunk into the
true motion of the step. Only the pymunk calls stay in Python (:meth:`teamsim.world.World.step`):
the bodies live in Chipmunk, whose getters and setters numba cannot call.

The arithmetic is that of the earlier per-robot Python methods, operation for operation
(``math.cos`` and ``math.sin`` are the C library's in both; no fast-math, no fused
multiply-adds), so a seed gives the same match to the bit.

Frames and units: walk speeds, targets and the planned and true motion are in the robot frame
(m/s, m/s, rad/s; m, m, rad); the control body's velocity and the body pose are in the world
frame (m/s, rad/s; m, rad, angle not wrapped); head angles in rad, rates in rad/s; times in s.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

# columns of a robot's row
VX, VY, VW = 0, 1, 2
"""Executed walk speed (m/s, m/s, rad/s; robot frame)."""
TX, TY, TW = 3, 4, 5
"""Walk target clipped to the limits (:meth:`~teamsim.robot.Robot.command`)."""
CX, CY, CW = 6, 7, 8
"""The control body's velocity as last sent to pymunk (m/s, m/s, rad/s; world frame)."""
PX, PY, PTH = 9, 10, 11
"""Planned motion since the last :meth:`~teamsim.robot.Robot.take_motion` (robot frame)."""
MX, MY, MTH = 12, 13, 14
"""True body motion since the last ``take_motion`` (robot frame)."""
BX, BY, BTH = 15, 16, 17
"""Body pose at the start of the step (world frame, angle not wrapped)."""
NX, NY, NTH = 18, 19, 20
"""Body pose read from pymunk after the step (:func:`post_step_nb` writes it, then moves it to ``BX``..)."""
HYAW, HPITCH, HYR, HPR, HCAM = 21, 22, 23, 24, 25
"""Head joints: yaw, pitch (rad), their rates (rad/s), camera read (0 upper, 1 lower)."""
GYAW, GPITCH, GSPEED, GCAM = 26, 27, 28, 29
"""Head target clipped to the joint limits, its speed (rad/s) and camera."""
IN_SPACE, PICKED, RESTING = 30, 31, 32
"""Flags (1.0 or 0.0): in the physics space, picked up, head resting at its target."""
FALLEN_UNTIL, FALLEN_SINCE, BUSY_UNTIL = 33, 34, 35
"""Times (s): standing again (-1: not fallen), fallen since (-1), kick motion ends."""
ROT_C, ROT_S, HAS_ROT = 36, 37, 38
"""cos and sin of the body angle at the start of the step, when :func:`pre_step_nb` needed them."""
LIN_ACC, ANG_ACC = 39, 40
"""Acceleration limits (m/s2, rad/s2) of the walking engine."""
HEAD_MOVED = 41
"""1.0 after the head joints changed (the robot's packed :class:`~cognition.representations.HeadState` is stale)."""
PENALIZED = 42
"""1.0 while the referee has the robot penalised (read by the foul checks, :func:`teamsim.fouls.field_fouls_nb`)."""
WTH = 43
"""``BTH`` wrapped to (-pi, pi] (:attr:`teamsim.robot.Robot.pose`), written with it."""
WIDTH = 44
"""Columns per robot."""

SEND_VELOCITY, SEND_ANGULAR = 1, 2
"""Bits of :func:`pre_step_nb`'s send list: set the control body's velocity, its angular velocity."""

CAMERAS = ("upper", "lower")
"""Camera names by their code in ``HCAM`` and ``GCAM``."""


class RobotStates:
    """The motion state of ``n`` robots: an ``n x WIDTH`` float array and a flat memoryview of it
    (Python reads and writes single values through the view: a tenth of the cost of numpy's
    scalar indexing, and a plain ``float`` back)."""

    def __init__(self, n: int):
        self.array: NDArray[np.float64] = np.zeros((n, WIDTH))
        self.view = memoryview(self.array.reshape(-1))
        self.sends: NDArray[np.int64] = np.zeros((n, 2), dtype=np.int64)
        """Rows (robot, bits) filled by :func:`pre_step_nb`."""
        self.send_view = memoryview(self.sends.reshape(-1))
        """:attr:`sends`, flat (robot, bits, robot, bits, ...), as a memoryview."""


@nb.njit(cache=True, error_model="python", fastmath=False)
def _step_head(s: NDArray[np.float64], r: int, dt: float) -> None:  # pragma: no cover - compiled
    """Move robot ``r``'s head joints toward the clipped target by at most ``speed * dt`` (rad) each."""
    yaw, pitch, yaw_rate, pitch_rate, camera_now = s[r, HYAW], s[r, HPITCH], s[r, HYR], s[r, HPR], s[r, HCAM]
    ty, tp, speed, camera = s[r, GYAW], s[r, GPITCH], s[r, GSPEED], s[r, GCAM]
    if ty == yaw and tp == pitch and yaw_rate == 0.0 and pitch_rate == 0.0 and camera_now == camera:
        s[r, RESTING] = 1.0  # until the next command
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
    s[r, HYAW] = yaw + dy
    s[r, HPITCH] = pitch + dp
    s[r, HYR] = dy / dt
    s[r, HPR] = dp / dt
    s[r, HCAM] = camera
    s[r, HEAD_MOVED] = 1.0


@nb.njit(cache=True, error_model="python", fastmath=False)
def pre_step_nb(
    s: NDArray[np.float64], now: float, dt: float, sends: NDArray[np.int64]
) -> int:  # pragma: no cover - compiled
    """Advance every robot's walking engine and head by ``dt`` (s) at time ``now`` (s).

    The executed walk speed moves toward the clipped target by at most ``LIN_ACC * dt`` (m/s)
    and ``ANG_ACC * dt`` (rad/s) per axis (toward zero while fallen, picked up or kicking); the
    control body gets that speed rotated into the world frame by the body angle at the start of
    the step, and the planned motion integrates it in the robot frame. A fall whose time is up
    ends here. Returns the number of rows written to ``sends``: (robot, bits) for every control
    body whose velocity (:data:`SEND_VELOCITY`) or angular velocity (:data:`SEND_ANGULAR`) the
    caller must set in pymunk to ``CX``, ``CY`` and ``CW``.
    """
    n_send = 0
    for r in range(s.shape[0]):
        if s[r, RESTING] == 0.0:
            _step_head(s, r, dt)
        if s[r, IN_SPACE] == 0.0:
            continue
        fallen_until = s[r, FALLEN_UNTIL]
        if fallen_until >= 0 and now >= fallen_until:
            fallen_until = -1.0
            s[r, FALLEN_UNTIL] = -1.0
            s[r, FALLEN_SINCE] = -1.0
        if s[r, PICKED] != 0.0 or fallen_until >= 0:
            vx = vy = w = 0.0
        else:
            if now < s[r, BUSY_UNTIL]:
                tx, ty, tw = 0.0, 0.0, 0.0
            else:
                tx, ty, tw = s[r, TX], s[r, TY], s[r, TW]
            lin, ang = s[r, LIN_ACC] * dt, s[r, ANG_ACC] * dt
            vx, vy, w = s[r, VX], s[r, VY], s[r, VW]
            # each axis: v + min(limit, max(-limit, target - v)), written as comparisons
            d = tx - vx
            vx += lin if d > lin else (-lin if d < -lin else d)
            d = ty - vy
            vy += lin if d > lin else (-lin if d < -lin else d)
            d = tw - w
            w += ang if d > ang else (-ang if d < -ang else d)
        s[r, VX], s[r, VY], s[r, VW] = vx, vy, w
        lx, ly, lw = s[r, CX], s[r, CY], s[r, CW]
        if vx == 0.0 and vy == 0.0 and w == 0.0 and lx == 0.0 and ly == 0.0 and lw == 0.0:
            # Standing with a still control body: the rotated speed would compare equal to the
            # last one sent (nothing to send), and adding zero motion leaves the planned motion
            # as it is bit for bit (its components start at +0.0 and a sum is -0.0 only when
            # both terms are).
            s[r, HAS_ROT] = 0.0
            continue
        th = s[r, BTH]
        c, sn = math.cos(th), math.sin(th)
        s[r, ROT_C], s[r, ROT_S], s[r, HAS_ROT] = c, sn, 1.0
        cvx, cvy = c * vx - sn * vy, sn * vx + c * vy
        if cvx != lx or cvy != ly or w != lw:
            # A kinematic body keeps its velocity (the solver adds at most a zero to it), so a
            # non-zero value equal to the last one sent is already there bit for bit; zeros are
            # sent again, as they may differ in sign.
            bits = 0
            if cvx != lx or cvy != ly or cvx == 0.0 or cvy == 0.0:
                bits |= SEND_VELOCITY
            if w != lw or w == 0.0:
                bits |= SEND_ANGULAR
            if bits:
                sends[n_send, 0] = r
                sends[n_send, 1] = bits
                n_send += 1
            s[r, CX], s[r, CY], s[r, CW] = cvx, cvy, w
        # planned = compose(planned, (vx dt, vy dt, w dt))
        px, py, pth = s[r, PX], s[r, PY], s[r, PTH]
        pc, ps = math.cos(pth), math.sin(pth)
        dx, dy = vx * dt, vy * dt
        s[r, PX], s[r, PY], s[r, PTH] = px + pc * dx - ps * dy, py + ps * dx + pc * dy, pth + w * dt
    return n_send


@nb.njit(cache=True, error_model="python", fastmath=False)
def post_step_nb(
    s: NDArray[np.float64], poses: NDArray[np.float64], ids: NDArray[np.uint64], n: int, body_ids: NDArray[np.uint64]
) -> None:  # pragma: no cover - compiled
    """Take the body poses read from pymunk and accumulate every robot's true body motion over
    the step just simulated.

    ``poses`` holds (x, y, angle) of the first ``n`` bodies of the space and ``ids`` their body
    ids, in the order Chipmunk lists them (:class:`teamsim.world.BodyPoses`); row ``r``'s body
    has the id ``body_ids[r]``. Its pose goes to ``NX``..; bodies that are no robot's (the ball,
    the control bodies) are skipped. The true motion runs from the pose at the start (``BX``..)
    to that new pose, which becomes the start pose (and ``WTH`` its wrapped angle). ``ValueError``
    if ``n`` is more than ``poses`` and ``ids`` hold or ``body_ids`` has fewer rows than ``s``.
    """
    rows = s.shape[0]
    if n < 0 or n > ids.shape[0] or 3 * n > poses.shape[0] or body_ids.shape[0] < rows:
        raise ValueError("post_step_nb: n bodies need 3 n poses and n ids, and every row a body id")
    for k in range(n):
        bid = ids[k]
        for r in range(rows):
            if body_ids[r] == bid:
                s[r, NX], s[r, NY], s[r, NTH] = poses[3 * k], poses[3 * k + 1], poses[3 * k + 2]
                break
    for r in range(rows):
        if s[r, IN_SPACE] == 0.0:
            continue
        x0, y0, th0 = s[r, BX], s[r, BY], s[r, BTH]
        x1, y1, th1 = s[r, NX], s[r, NY], s[r, NTH]
        s[r, BX], s[r, BY], s[r, BTH] = x1, y1, th1
        if x1 == x0 and y1 == y0 and th1 == th0:
            continue  # adding zero motion leaves the true motion as it is (see pre_step_nb)
        s[r, WTH] = wrap_angle_nb(th1)
        if s[r, HAS_ROT] != 0.0:
            c, sn = s[r, ROT_C], s[r, ROT_S]
        else:
            c, sn = math.cos(th0), math.sin(th0)
        dxw, dyw = x1 - x0, y1 - y0
        lx, ly = c * dxw + sn * dyw, -sn * dxw + c * dyw
        # true_motion = compose(true_motion, (lx, ly, th1 - th0))
        ax, ay, ath = s[r, MX], s[r, MY], s[r, MTH]
        ac, as_ = math.cos(ath), math.sin(ath)
        s[r, MX], s[r, MY], s[r, MTH] = ax + ac * lx - as_ * ly, ay + as_ * lx + ac * ly, ath + (th1 - th0)


@nb.njit(cache=True, error_model="python", fastmath=False)
def wrap_angle_nb(a: float) -> float:  # pragma: no cover - compiled
    """:func:`cognition.geometry.wrap_angle` compiled, operation for operation (``fmod`` is exact,
    the rest are the same IEEE operations), so both give the same bits: ``a`` (rad) in (-pi, pi]."""
    a = np.fmod(a + math.pi, 2.0 * math.pi)
    if a <= 0.0:
        a += 2.0 * math.pi
    return a - math.pi


@nb.njit(cache=True, error_model="python", fastmath=False)
def take_motions_nb(s: NDArray[np.float64], out: NDArray[np.float64]) -> None:  # pragma: no cover - compiled
    """Copy every robot's planned and true motion since the last call (``PX``..``MTH``, robot
    frame) into the rows of ``out`` (N x 6) and restart both from zero."""
    for r in range(s.shape[0]):
        for c in range(6):
            out[r, c] = s[r, PX + c]
            s[r, PX + c] = 0.0


@nb.njit(cache=True, error_model="python", fastmath=False)
def team_poses_nb(s: NDArray[np.float64], sign: float, out: NDArray[np.float64]) -> None:  # pragma: no cover
    """Every robot's pose in the frame of a team that attacks world +x if ``sign`` > 0 (else
    world -x), with its flags, into the rows of ``out`` (N x 5): x, y (m), theta (rad), 1.0 if not
    penalised, 1.0 if fallen. The pose is :func:`teamsim.placement.world_to_team` of
    :attr:`~teamsim.robot.Robot.pose` (from ``BX``, ``BY``, ``WTH``) to the bit: the same negations,
    the same sum and :func:`wrap_angle_nb`. ``ValueError`` if ``out`` is smaller than that."""
    if out.shape[0] < s.shape[0] or out.shape[1] < 5:
        raise ValueError("team_poses_nb: out needs a row of 5 for every robot")
    for r in range(s.shape[0]):
        x, y, th = s[r, BX], s[r, BY], s[r, WTH]
        o = out[r]
        if sign > 0:
            o[0], o[1], o[2] = x, y, wrap_angle_nb(th)
        else:
            o[0], o[1], o[2] = -x, -y, wrap_angle_nb(th + math.pi)
        o[3] = 1.0 if s[r, PENALIZED] == 0.0 else 0.0
        o[4] = 1.0 if s[r, FALLEN_UNTIL] >= 0.0 else 0.0


@nb.njit(cache=True, error_model="python", fastmath=False)
def scene_rows_nb(
    s: NDArray[np.float64],
    teams: NDArray[np.float64],
    sign0: float,
    sign1: float,
    radius: float,
    standing: float,
    lying: float,
    observers: NDArray[np.float64],
    occluders: NDArray[np.float64],
) -> None:  # pragma: no cover - compiled
    """The robots' rows of the camera model's scene (:class:`teamsim.percepts.Scene`, world
    frame): ``observers`` (x, y, theta, head yaw, pitch, yaw rate, pitch rate, camera, walking,
    sees, team sign, team) and ``occluders`` (x, y, radius, height, on field), from the state
    rows. ``sign0``, ``sign1``: +1 or -1, whether each team attacks world +x; ``radius`` (m),
    ``standing`` and ``lying`` heights (m) of a robot."""
    for r in range(s.shape[0]):
        on = s[r, IN_SPACE] != 0.0
        fallen = s[r, FALLEN_UNTIL] >= 0.0
        o = observers[r]
        o[0], o[1], o[2] = s[r, BX], s[r, BY], s[r, BTH]
        o[3], o[4], o[5], o[6], o[7] = s[r, HYAW], s[r, HPITCH], s[r, HYR], s[r, HPR], s[r, HCAM]
        o[8] = 1.0 if s[r, VX] != 0.0 or s[r, VY] != 0.0 or s[r, VW] != 0.0 else 0.0  # walking
        o[9] = 1.0 if on and not fallen and s[r, PICKED] == 0.0 else 0.0  # sees
        o[10] = sign0 if teams[r] == 0.0 else sign1
        o[11] = teams[r]
        c = occluders[r]
        c[0], c[1], c[2] = s[r, BX], s[r, BY], radius
        c[3] = lying if fallen else standing
        c[4] = 1.0 if on else 0.0
