"""Automatic foul detection: the evidence behind the referee's automatic penalties.

The detector looks at the world after each physics step and names the robots that committed
a foul; the referee then penalises them. Thresholds (:class:`FoulParams`, seconds and metres):

======================  ========  ===========  ===========================================================
parameter               default   range        foul
======================  ========  ===========  ===========================================================
pushing_seconds         2.0 s     (0, 3600]    PLAYER_PUSHING: a robot's walking engine drives it into an
                                               opponent (faster than the opponent drives back, by at least
push_min_speed          0.05 m/s  (0, 10]      ``push_min_speed``) for this long, or its charge topples the
                                               opponent
inactive_seconds        20 s      (0, 3600]    INACTIVE_PLAYER: fallen for this long
stuck_seconds           20 s      (0, 3600]    LOCAL_GAME_STUCK: the ball stayed within ``stuck_radius``
stuck_radius            0.3 m     (0, 100]     for this long while a robot stood within
stuck_robot_distance    0.5 m     (0, 100]     ``stuck_robot_distance`` of it; the nearest robot is named
======================  ========  ===========  ===========================================================

Every value is checked against its range when the parameters are built
(:func:`cognition.params.check_ranges`).

LEAVING_THE_FIELD: a robot that had entered the field is entirely outside the outer edges of
the field lines (more than its radius beyond them) and not inside its goal.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import ClassVar

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.field import Field
from cognition.gamestate import Penalty
from teamsim.params import Ranges, check_ranges, positive
from teamsim.robot import get_position
from teamsim.walking import BX, BY, FALLEN_SINCE, FALLEN_UNTIL, IN_SPACE, PENALIZED
from teamsim.world import CollisionEvent, RobotId, World

LEFT_FIELD, INACTIVE = 0, 1
"""The fouls :func:`field_fouls_nb` reports (codes of its own, turned into :class:`Penalty` values)."""


@nb.njit(cache=True, error_model="python", fastmath=False)
def field_fouls_nb(
    s: NDArray[np.float64],
    entered: NDArray[np.float64],
    lines_x: float,
    lines_y: float,
    margin: float,
    goal_x: float,
    goal_y: float,
    now: float,
    inactive_seconds: float,
    out: NDArray[np.int64],
) -> int:  # pragma: no cover - compiled
    """The leaving-the-field and inactive-player fouls of every robot on the field and not
    penalised, from the walking state rows ``s`` (:mod:`teamsim.walking`; world frame, m and s).

    ``entered`` (one entry per robot, 1.0 or 0.0) says whether the robot has been inside the
    field lines since it was last placed; it is updated here. A robot that has entered and is
    more than ``margin`` beyond the lines' outer edges (``lines_x``, ``lines_y``: half extents),
    and not inside a goal (``|x| < goal_x``, ``|y| < goal_y``), left the field; otherwise one that
    has lain since more than ``inactive_seconds`` before ``now`` is inactive. Writes (robot,
    :data:`LEFT_FIELD` or :data:`INACTIVE`) rows into ``out`` in robot order and returns their
    number. The field and goals are symmetric about both axes, so world coordinates serve either
    team."""
    k = 0
    for r in range(s.shape[0]):
        if s[r, IN_SPACE] == 0.0 or s[r, PENALIZED] != 0.0:
            continue
        ax, ay = abs(s[r, BX]), abs(s[r, BY])
        if ax <= lines_x and ay <= lines_y:  # is_inside_field
            entered[r] = 1.0
        elif entered[r] != 0.0 and not (ax <= lines_x + margin and ay <= lines_y + margin):
            in_goal = ay < goal_y and ax < goal_x
            if not in_goal:
                out[k, 0], out[k, 1] = r, LEFT_FIELD
                k += 1
                continue
        if s[r, FALLEN_UNTIL] >= 0 and now - s[r, FALLEN_SINCE] >= inactive_seconds:  # fallen that long
            out[k, 0], out[k, 1] = r, INACTIVE
            k += 1
    return k


@dataclass(frozen=True)
class FoulParams:
    """Thresholds of the automatic fouls (see module table)."""

    pushing_seconds: float = 2.0
    push_min_speed: float = 0.05
    inactive_seconds: float = 20.0
    stuck_seconds: float = 20.0
    stuck_radius: float = 0.3
    stuck_robot_distance: float = 0.5

    RANGES: ClassVar[Ranges] = {
        "pushing_seconds": positive(3600.0),
        "push_min_speed": positive(10.0),
        "inactive_seconds": positive(3600.0),
        "stuck_seconds": positive(3600.0),
        "stuck_radius": positive(100.0),
        "stuck_robot_distance": positive(100.0),
    }

    def __post_init__(self) -> None:
        check_ranges(self)


@dataclass
class _PushTrack:
    seconds: float = 0.0
    last_seen: float = -1.0


Foul = tuple[RobotId, Penalty]


class FoulDetector:
    """Stateful detector of the automatic fouls (see the module docstring)."""

    def __init__(self, world: World, field_map: Field, params: FoulParams):
        self.world = world
        self.field = field_map
        self.params = params
        self._index = {(r.team, r.number): i for i, r in enumerate(world.robots)}
        """Each robot's row in the world's walking state."""
        self._entered = np.zeros(len(world.robots))
        """Whether each robot has entered the field since it was last placed (1.0 or 0.0)."""
        self._found = np.zeros((len(world.robots), 2), dtype=np.int64)
        """Rows (robot, foul) of :func:`field_fouls_nb`."""
        self._margin = world.params.robot.radius
        """How far beyond the lines a robot may be before it has left the field (m: its radius)."""
        self._push: dict[tuple[RobotId, RobotId], _PushTrack] = {}
        self._stuck_anchor = (0.0, 0.0, 0.0)
        self._robots = [(r, (r.team, r.number)) for r in world.robots]
        d = field_map.dims
        lw = d.line_width / 2
        self._lines_x = field_map.half_length + lw
        """Half extent (m) of the field lines' outer edges along x (as :func:`teamsim.placement.is_inside_field`)."""
        self._lines_y = field_map.half_width + lw
        """Half extent (m) of the field lines' outer edges along y."""
        self._goal_x = field_map.half_length + d.goal_depth
        """|x| (m) of the back of the goals."""
        self._goal_y = d.goal_inner_width / 2
        """|y| (m) of the inner sides of the goal posts."""

    def placed(self, robot: RobotId, inside: bool) -> None:
        """A robot was put somewhere; ``inside``: whether that spot is inside the field."""
        self._entered[self._index[robot]] = 1.0 if inside else 0.0

    @property
    def entered_field(self) -> dict[RobotId, bool]:
        """Whether each robot has entered the field since it was last placed."""
        return {key: bool(self._entered[i]) for key, i in self._index.items()}

    def reset_stuck(self, x: float, y: float, now: float) -> None:
        """The ball was (re)placed at (x, y) world frame: restart the stuck clock."""
        self._stuck_anchor = (x, y, now)

    def detect(self, now: float, events: Sequence[CollisionEvent], check_stuck: bool) -> list[Foul]:
        """Fouls committed in the step that ended at ``now``, in a deterministic order.

        The field-leaving test reads world positions: the field lines and the goals are
        symmetric about both axes and the test looks only at ``|x|`` and ``|y|``, which are the
        same in the world frame and in either team frame.
        """
        fouls: list[Foul] = []
        found = self._found
        k = field_fouls_nb(
            self.world.motion.array, self._entered, self._lines_x, self._lines_y, self._margin, self._goal_x,
            self._goal_y, now, self.params.inactive_seconds, found,
        )  # fmt: skip
        if k:
            robots = self._robots
            for r, code in found[:k].tolist():
                penalty = Penalty.LEAVING_THE_FIELD if code == LEFT_FIELD else Penalty.INACTIVE_PLAYER
                fouls.append((robots[r][1], penalty))
        if events:
            fouls.extend(self._pushing(now, events))
        if check_stuck:
            fouls.extend(self._stuck(now))
        return fouls

    def _pushing(self, now: float, events: Sequence[CollisionEvent]) -> list[Foul]:
        p = self.params
        seen: dict[tuple[RobotId, RobotId], CollisionEvent] = {}
        for ev in events:
            if ev.kind == "robot_robot" and ev.b is not None and ev.a[0] != ev.b[0]:
                seen[(ev.a, ev.b)] = ev
        fouls: list[Foul] = []
        for ev in seen.values():
            assert ev.b is not None
            for pusher, victim, push, other in ((ev.a, ev.b, ev.push_a, ev.push_b), (ev.b, ev.a, ev.push_b, ev.push_a)):
                if push < p.push_min_speed or push <= other + p.push_min_speed:
                    continue
                track = self._push.setdefault((pusher, victim), _PushTrack())
                if now - track.last_seen > 0.5:
                    track.seconds = 0.0
                track.seconds += self.world.dt
                track.last_seen = now
                toppled = ev.first and self.world.robot(*victim).is_fallen() and push > 0.1
                if track.seconds >= p.pushing_seconds or toppled:
                    fouls.append((pusher, Penalty.PLAYER_PUSHING))
                    track.seconds = 0.0
        return fouls

    def _stuck(self, now: float) -> list[Foul]:
        p = self.params
        b = get_position(self.world.ball._body)  # ball.position, read in C
        bx, by = b.x, b.y
        ax, ay, since = self._stuck_anchor
        if math.hypot(bx - ax, by - ay) > p.stuck_radius:
            self._stuck_anchor = (bx, by, now)
            return []
        if now - since < p.stuck_seconds:
            return []
        self._stuck_anchor = (bx, by, now)
        best: tuple[float, RobotId] | None = None
        for r in self.world.robots:
            if not r.in_space:
                continue
            x, y, _ = r.body_pose
            d = math.hypot(x - bx, y - by)
            if d <= p.stuck_robot_distance + r.params.radius and (best is None or d < best[0]):
                best = (d, (r.team, r.number))
        return [] if best is None else [(best[1], Penalty.LOCAL_GAME_STUCK)]
