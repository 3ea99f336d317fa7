"""Percept synthesis: what every robot's camera sees, as a good vision module would report it.

:class:`PerceptSynthesizer` turns a :class:`Scene` (the true world as the camera model needs
it: robot poses, head angles and rates, which camera is read, the ball) into one
:class:`cognition.percepts.Percepts` per robot. It is a pure function of the scene plus its
own random stream (DESIGN principle 8); the compiled work is in
:mod:`teamsim.percept_kernel` and the parameters in :mod:`teamsim.percept_params`.

What is modelled (CMU paper section II for the feature set; Darmstadt paper section IV.B for
the noise):

* visibility: in front of the camera, inside the image, within the kind's maximum range,
  not hidden behind other robots (a standing robot hides the ground behind it, a lying one
  only a short shadow); lines are clipped to the image and the range and split where robots
  hide them; pieces shorter than ``min_line_length`` are dropped; the centre circle needs
  ``circle_min_visible`` of its sample points in view;
* goal posts are labelled left/right only when the other post of the goal is in the image or
  the crossbar next to the post is (the label is read from the image, so a robot behind a
  goal sees the labels swapped, as a real detector would);
* detection probabilities per kind (distance, camera motion, ball speed, occlusion), false
  positives (phantom crossings and penalty marks, posts beyond the field, balls at robots'
  feet and anywhere), crossing-type confusion, team-colour mistakes;
* measurement: two noisy viewing angles per point, projected back to the ground; the
  angular error of one image is partly shared by all its percepts.

Frames: the scene is in the **world frame**; percepts are robot-relative; ground-truth ids
refer to the observer's own field map (its team frame).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from cognition.camera import CAMERA_NAMES, CameraRig
from cognition.field import Field
from cognition.percepts import N_COLS, N_KINDS, Percepts
from teamsim.percept_kernel import draws_bound, synthesize_nb
from teamsim.percept_params import PerceptParams
from teamsim.percept_parts import MAX_PIECES, N_CAM_COLS, N_CONSTS, N_FMAP_COLS, N_OBS_COLS, G

CIRCLE_SAMPLES = 32
"""Points on the centre circle used to decide how much of it is visible."""
_BUFFER = 1 << 16


@dataclass(frozen=True)
class SceneRobot:
    """One robot in a :class:`Scene` (world frame, SI units)."""

    team: int
    """Team index 0 or 1."""
    number: int
    """Player number, 1-based."""
    x: float
    y: float
    theta: float
    head_yaw: float = 0.0
    head_pitch: float = 0.0
    yaw_rate: float = 0.0
    """Head yaw rate (rad/s)."""
    pitch_rate: float = 0.0
    """Head pitch rate (rad/s)."""
    camera: str = "upper"
    walking: bool = False
    """The legs are moving (Darmstadt eq. 6)."""
    sees: bool = True
    """The camera gives usable images (False when fallen, picked up or off the field)."""
    on_field: bool = True
    """The body is on the field (can hide things and be seen)."""
    fallen: bool = False
    turn_rate: float = 0.0
    """Body turn rate (rad/s, counter-clockwise); only image effects (motion blur) use it."""
    team_sign: float = 1.0
    """+1 if the robot's team frame equals the world frame, -1 if mirrored."""


class Scene:
    """The true state the camera model needs, as packed arrays (world frame).

    ``observers`` (N x 12): x, y, theta, head yaw, pitch, yaw rate, pitch rate, camera index,
    walking, sees, team sign, team. ``occluders`` (N x 5): x, y, radius, height, on field.
    ``ball``: x, y, vx, vy, present. ``turn_rates`` (N): body turn rates (rad/s), used only by
    image effects. Robot ``i`` is ``team * players_per_team + number - 1``.
    """

    __slots__ = ("ball", "observers", "occluders", "players_per_team", "turn_rates")

    def __init__(self, players_per_team: int):
        n = 2 * players_per_team
        self.players_per_team = players_per_team
        self.observers = np.zeros((n, N_OBS_COLS))
        self.occluders = np.zeros((n, 5))
        self.ball = np.zeros(5)
        self.turn_rates = np.zeros(n)

    @classmethod
    def build(
        cls,
        robots: list[SceneRobot],
        ball: tuple[float, float] | tuple[float, float, float, float] | None,
        players_per_team: int,
        robot_radius: float = 0.14,
        params: PerceptParams | None = None,
    ) -> Scene:
        """A scene from robot records (robots not listed are off the field) and a ball."""
        p = params or PerceptParams()
        s = cls(players_per_team)
        for rb in robots:
            if rb.team not in (0, 1) or not 1 <= rb.number <= players_per_team:
                raise ValueError(f"robot team {rb.team} number {rb.number} outside {players_per_team} per team")
            if rb.camera not in CAMERA_NAMES:
                raise ValueError(f"unknown camera {rb.camera!r}; valid: {list(CAMERA_NAMES)}")
            i = rb.team * players_per_team + rb.number - 1
            s.observers[i] = (
                rb.x, rb.y, rb.theta, rb.head_yaw, rb.head_pitch, rb.yaw_rate, rb.pitch_rate,
                CAMERA_NAMES.index(rb.camera), float(rb.walking), float(rb.sees), rb.team_sign, rb.team,
            )  # fmt: skip
            height = p.fallen_height if rb.fallen else p.robot_height
            s.occluders[i] = (rb.x, rb.y, robot_radius, height, float(rb.on_field))
            s.turn_rates[i] = rb.turn_rate
        for t in (0, 1):
            for k in range(players_per_team):
                s.observers[t * players_per_team + k, 11] = t
        if ball is not None:
            b = (*tuple(ball), 0.0, 0.0)
            s.ball[:] = (b[0], b[1], b[2], b[3], 1.0)
        return s


class PerceptSynthesizer:
    """Synthesizes percepts for every robot of a scene (see the module docstring)."""

    def __init__(
        self,
        field: Field,
        params: PerceptParams,
        rng: np.random.Generator,
        rig: CameraRig | None = None,
        distinct_goal_colours: bool = False,
    ):
        self.field = field
        self.params = params
        self.rig = rig or CameraRig()
        self.rng = rng
        self._prm = params.to_vector()
        self._cams = np.array([_camera_columns(self.rig, c) for c in CAMERA_NAMES])
        self._specs = (self.rig.upper, self.rig.lower)
        self._fmap, self._fidx = _field_map(field)
        d = field.dims
        self._fconst = np.zeros(N_CONSTS)
        self._fconst[:] = (
            self.rig.neck_height,
            d.goal_height,
            d.goal_post_diameter / 2,
            d.corner_pole_diameter / 2,
            d.ball_diameter / 2,
            field.centre_circle.x,
            field.centre_circle.y,
            field.half_length + d.border_strip,
            field.half_width + d.border_strip,
            1.0 if distinct_goal_colours else 0.0,
            0.0,
        )
        self._points = int(self._fidx[G.CIRCLE] - self._fidx[G.POST])
        """Point-like landmark rows of the field map (posts to the circle samples)."""
        self._lines = int(self._fidx[G.LINE + 1] - self._fidx[G.LINE])
        """Line rows of the field map."""
        self._bounds: dict[int, tuple[int, int]] = {}
        """:func:`draws_bound` per number of observers (the field map does not change)."""
        self._normals = np.zeros(0)
        self._uniforms = np.zeros(0)
        self._cursor = np.zeros(2, dtype=np.int64)
        self._scratch = np.empty((0, N_COLS))

    def _refill(self, n_obs: int) -> None:
        bound = self._bounds.get(n_obs)
        if bound is None:
            bound = self._bounds[n_obs] = draws_bound(n_obs, self._fidx)
        need_n, need_u = bound
        c = self._cursor
        if c[0] + need_n > len(self._normals) or c[1] + need_u > len(self._uniforms):
            size = max(_BUFFER, 4 * max(need_n, need_u))
            self._normals = self.rng.standard_normal(size)
            self._uniforms = self.rng.random(size)
            c[:] = 0

    def synthesize(self, scene: Scene, time: float = 0.0) -> list[Percepts]:
        """One :class:`Percepts` per robot of ``scene`` (robot index order), taken at ``time`` (s)."""
        n = scene.observers.shape[0]
        self._fconst[10] = scene.players_per_team
        self._refill(n)
        max_rows = n * (16 + self._points + MAX_PIECES * self._lines + 3 * n)
        if self._scratch.shape[0] < max_rows:
            self._scratch = np.empty((max_rows, N_COLS))
        out = self._scratch
        offsets = np.empty((n, N_KINDS + 1), dtype=np.int64)
        cam_rows = np.empty((n, 18))
        used = synthesize_nb(
            scene.observers, scene.occluders, scene.ball, self._cams, self._fmap, self._fidx, self._fconst,
            self._prm, self._normals, self._uniforms, self._cursor, out, offsets, cam_rows,
        )  # fmt: skip
        out = out[:used].copy()  # compact: frames kept by a brain hold only their own rows
        specs = self._specs
        sees, cameras = scene.observers[:, 9].tolist(), scene.observers[:, 7].tolist()
        taken = [specs[int(cameras[r])] if sees[r] >= 0.5 else None for r in range(n)]  # None: no image
        return Percepts.many(time, out, offsets, cam_rows, taken)  # every robot's checks in one compiled pass


def _camera_columns(rig: CameraRig, name: str) -> list[float]:
    s = rig.spec(name)  # type: ignore[arg-type]
    cols = [s.tilt, s.offset_x, s.offset_z, s.fx, s.fy, s.cx, s.cy, float(s.width), float(s.height)]
    assert len(cols) == N_CAM_COLS
    return cols


def _mirror_index(points: NDArray[np.float64], i: int) -> int:
    """Index of the landmark at the point-mirrored position of landmark ``i``."""
    target = -points[i]
    dist = np.abs(points - target).sum(axis=1)
    j = int(np.argmin(dist))
    if dist[j] > 1e-6:
        raise ValueError(f"field is not point-symmetric at landmark {i} {points[i]}")
    return j


def _field_map(field: Field) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Pack the landmarks into rows (x, y, a, b, mirror index, partner) and group starts."""
    rows: list[list[float]] = []
    fidx = np.zeros(7, dtype=np.int64)
    posts = field.post_array
    for i, p in enumerate(field.goal_posts):
        partner = next(j for j, o in enumerate(field.goal_posts) if o.goal == p.goal and j != i)
        goal_world = 0.0 if p.x < 0 else 1.0
        rows.append([p.x, p.y, 0.0, goal_world, _mirror_index(posts, i), partner])
    fidx[G.CROSS] = len(rows)
    cr = field.crossing_array
    for i in range(len(cr)):
        rows.append([cr[i, 0], cr[i, 1], cr[i, 2], float(field.crossing_kinds[i]), _mirror_index(cr[:, :2], i), -1])
    fidx[G.LINE] = len(rows)
    la = field.line_array
    for i in range(len(la)):
        a, b = la[i, :2], la[i, 2:]
        match = [
            j for j in range(len(la))
            if (np.allclose(la[j, :2], -a) and np.allclose(la[j, 2:], -b))
            or (np.allclose(la[j, :2], -b) and np.allclose(la[j, 2:], -a))
        ]  # fmt: skip
        if not match:
            raise ValueError(f"field is not point-symmetric at line {i}")
        rows.append([a[0], a[1], b[0], b[1], match[0], -1])
    fidx[G.MARK] = len(rows)
    marks = np.array([(m.x, m.y) for m in field.penalty_marks]).reshape(-1, 2)
    for i in range(len(marks)):
        rows.append([marks[i, 0], marks[i, 1], 0.0, 0.0, _mirror_index(marks, i), -1])
    fidx[G.POLE] = len(rows)
    poles = np.array([(p.x, p.y) for p in field.corner_poles]).reshape(-1, 2)
    for i in range(len(poles)):
        rows.append([poles[i, 0], poles[i, 1], 0.0, 0.0, _mirror_index(poles, i), -1])
    fidx[G.CIRCLE] = len(rows)
    c = field.centre_circle
    for k in range(CIRCLE_SAMPLES):
        a = 2.0 * math.pi * (k + 0.5) / CIRCLE_SAMPLES
        rows.append([c.x + c.radius * math.cos(a), c.y + c.radius * math.sin(a), 0.0, 0.0, -1, -1])
    fidx[G.CIRCLE + 1] = len(rows)
    fmap = np.asarray(rows, dtype=np.float64).reshape(-1, N_FMAP_COLS)
    return fmap, fidx
