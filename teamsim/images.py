"""Rendered camera images per robot, with ground-truth annotations.

:class:`ImageRenderer` draws what a robot's camera sees in a :class:`~teamsim.percepts.Scene`
(the same packed world state the percept synthesis reads): the carpet with its mild
texture, white lines of the true width in perspective (lines, boxes, centre circle,
penalty and centre marks), goals (posts, crossbar, net) in the colour scheme's colours,
the ball as a shaded sphere (orange in ``classic``, white with black patches in
``modern``), other robots with team-coloured jerseys, and the hall beyond the field
(boards, spectators, windows). The compiled work is in :mod:`teamsim.image_kernel`; image
effects (lighting, noise, motion blur, rolling shutter, vignetting) in
:mod:`teamsim.image_effects`, parameters in :mod:`teamsim.image_params`. The uneven light of
the hall (sun stripes, soft shadows, darker corners; :func:`teamsim.image_venue.light_map`)
is an image effect too, but fixed in the world: the renderer draws it with the scene
(floor, paint and objects), and only when effects are on.

:meth:`ImageRenderer.annotate` gives the ground truth of an image: for every visible
feature its pixels (crossing and penalty-mark points, line end points, post bottoms and
boxes, ball circle, robot boxes, centre-circle points), computed by the camera model
(:mod:`cognition.camera`) exactly as the ``ideal`` percepts are, including occlusion by
robots. The image is rendered from the same camera pose, so a feature and its annotation
agree to a pixel. :func:`draw_annotations` and :func:`save_png` write them for people.

Frames: scenes are in the world frame; pixels ``u`` right, ``v`` down, pixel (i, j) covers
[i, i + 1) x [j, j + 1). Ground-truth ids are those of the percepts (the observer's own
team-frame field map), except robots, which carry their world index (``team *
players_per_team + number - 1``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np
from numpy.typing import NDArray

from cognition.camera import CAMERA_NAMES, CameraImage, CameraMatrix, CameraRig
from cognition.field import ColourScheme, Field, make_colour_scheme
from cognition.percepts import Percepts
from teamsim.image_effects import ImageEffects
from teamsim.image_kernel import render_nb
from teamsim.image_objects import icosahedron
from teamsim.image_params import ImageParams
from teamsim.image_venue import (
    GEO,
    POLE_HEIGHT,
    colour_table,
    floor_texture,
    geometry,
    light_map,
    paint_circles,
    paint_strips,
    wall_texture,
)
from teamsim.percept_params import PerceptParams
from teamsim.percept_parts import OBS, OC
from teamsim.percepts import CIRCLE_SAMPLES, PerceptSynthesizer, Scene

_BOX_SAMPLES = 16  # points on each end circle of a cylinder for its image box
# observer columns as plain ints (faster numpy indexing than the IntEnum)
_YAW, _PITCH, _YAWR, _PITCHR, _CAM, _WALK = (
    int(c) for c in (OBS.YAW, OBS.PITCH, OBS.YAWR, OBS.PITCHR, OBS.CAM, OBS.WALK)
)


@dataclass(frozen=True, eq=False)
class ImageAnnotations:
    """Ground truth of one camera image (pixels as in the module docstring).

    Every array has one row per visible feature; ``truth`` columns are ids as in the
    percepts (robots: world index).
    """

    camera: CameraMatrix
    """The camera model the annotations come from (robot frame)."""
    posts: NDArray[np.float64]
    """N x 8: bottom centre (u, v), box (u0, v0, u1, v1), side (PostSide), truth."""
    crossings: NDArray[np.float64]
    """N x 4: (u, v), kind (0 L, 1 T, 2 X), truth."""
    lines: NDArray[np.float64]
    """N x 5: end points (u1, v1, u2, v2) of the visible piece, truth (line index)."""
    circle: NDArray[np.float64]
    """N x 2: visible points (u, v) of the centre circle's line centre."""
    marks: NDArray[np.float64]
    """N x 3: (u, v), truth."""
    ball: NDArray[np.float64]
    """0 or 1 x 3: centre (u, v) and image radius (px)."""
    robots: NDArray[np.float64]
    """N x 7: feet (u, v), box (u0, v0, u1, v1), world index."""
    poles: NDArray[np.float64]
    """N x 7: bottom (u, v), box (u0, v0, u1, v1), truth."""

    def __len__(self) -> int:
        return sum(len(a) for a in (self.posts, self.crossings, self.lines, self.marks, self.ball, self.robots))


def camera_errors(
    observers: NDArray[np.float64], params: PerceptParams, rng: np.random.Generator
) -> NDArray[np.float64]:
    """Per robot (rows of ``observers``), the error (rad) of its camera matrix around the pitch and
    the yaw axis, for :meth:`ImageRenderer.camera_images`.

    A real robot knows its camera's pose only through its joint angles and its torso's sway, so
    the matrix it projects with is off from the true camera (Darmstadt IV.B). Synthesized
    percepts model this as the share ``params.shared_noise_fraction`` of the angular variance
    (eqs. 3-6, :meth:`PerceptParams.sigmas`) that all percepts of one image have in common; the
    same share is drawn here per image, for every robot (seeing or not, so that the stream does
    not depend on who sees). The rest of an image's error comes from its pixels."""
    z = rng.standard_normal((observers.shape[0], 2))
    p = params
    walking = observers[:, OBS.WALK] > 0.5
    sa = p.sigma_alpha_base + p.c_tilt * np.abs(observers[:, OBS.PITCHR]) + np.where(walking, p.sigma_alpha_moving, 0.0)
    sb = p.sigma_beta_base + p.c_pan * np.abs(observers[:, OBS.YAWR]) + np.where(walking, p.sigma_beta_moving, 0.0)
    share = math.sqrt(p.shared_noise_fraction)
    z[:, 0] *= share * sa
    z[:, 1] *= share * sb
    return z


class ImageRenderer:
    """Renders camera images of the robots of a :class:`Scene` (see the module docstring).

    ``scheme`` is a :class:`ColourScheme` or its name; ``params`` an :class:`ImageParams` or
    a preset name. The image size is the rig's (at least 8 x 8 pixels). Image effects draw
    their random numbers from ``rng`` (not needed for the ``ideal`` preset).
    """

    def __init__(
        self,
        field: Field,
        scheme: ColourScheme | str = "modern",
        rig: CameraRig | None = None,
        params: ImageParams | str = "default",
        rng: np.random.Generator | None = None,
    ):
        if isinstance(scheme, str):
            scheme = make_colour_scheme(scheme)
        if not isinstance(scheme, ColourScheme):
            raise TypeError(f"scheme must be a ColourScheme or a scheme name, got {scheme!r}")
        if isinstance(params, str):
            params = ImageParams.preset(params)
        if not isinstance(params, ImageParams):
            raise TypeError(f"params must be ImageParams or a preset name, got {params!r}")
        self.field = field
        self.scheme = scheme
        self.rig = rig or CameraRig()
        self.params = params
        self.effects = ImageEffects(params, rng if rng is not None else np.random.default_rng(0))
        self._geo = geometry(field, self.rig.neck_height, params.grass_texture > 0.0)
        self._geo[GEO.MODERN_BALL] = 1.0 if scheme.ball_primary != scheme.ball_secondary else 0.0
        self._colours = colour_table(scheme).astype(np.float64)
        self._strips = paint_strips(field)
        self._circles = paint_circles(field)
        self._floor = floor_texture(field, params.grass_texture, params.venue_seed)
        self._light = self._no_light = np.ones((1, 1), dtype=np.float32)
        self._geo_lit, self._floor_lit = self._geo, self._floor
        if params.has_illumination:  # the scene lit unevenly: the floor texture times the light
            self._light = light_map(field, params)
            self._floor_lit = np.ascontiguousarray(self._floor * self._light, dtype=np.float32)
            self._geo_lit = geometry(field, self.rig.neck_height, True, lit=True, tint=params.light_tint)
            self._geo_lit[GEO.MODERN_BALL] = self._geo[GEO.MODERN_BALL]
        self._walls = wall_texture(field, params.venue_seed)
        self._posts = np.ascontiguousarray(field.post_array, dtype=np.float64)
        self._poles = np.array([(p.x, p.y) for p in field.corner_poles], dtype=np.float64).reshape(-1, 2)
        self._ico = icosahedron()
        self._cams = np.array([_camera_columns(self.rig, c) for c in CAMERA_NAMES])
        self._annotator: PerceptSynthesizer | None = None
        # per call only the scene changes: the kernel's other inputs, evenly lit and lit, and per camera
        # the image size and focal lengths
        venue = (self._walls, self._posts, self._poles, self._ico)
        self._inputs = tuple(
            (self._cams, geo, self._colours, self._strips, self._circles, floor, light, *venue)
            for geo, floor, light in (
                (self._geo, self._floor, self._no_light),
                (self._geo_lit, self._floor_lit, self._light),
            )
        )
        self._lit = params.has_illumination
        self._shapes = [(self.rig.spec(c).height, self.rig.spec(c).width, 3) for c in CAMERA_NAMES]
        self._focal = [(self.rig.spec(c).fx, self.rig.spec(c).fy) for c in CAMERA_NAMES]

    def size(self, camera: str = "upper") -> tuple[int, int]:
        """(height, width) of the images of ``camera`` (pixels)."""
        s = self.rig.spec(camera)  # type: ignore[arg-type]
        return s.height, s.width

    def light_at(self, xy: NDArray[np.float64]) -> NDArray[np.float64]:
        """The gain of the hall's uneven light at world points ``xy`` (N x 2, m; bilinear in
        the light map, as objects are lit). All ones without illumination (e.g. ``ideal``)."""
        pts = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
        lm = self._light
        if lm.shape[0] < 2 or lm.shape[1] < 2:
            return np.full(len(pts), float(lm[0, 0]))
        texel, hx, hy = self._geo[GEO.FLOOR_TEXEL], self._geo[GEO.HALL_X], self._geo[GEO.HALL_Y]
        tx = np.clip((pts[:, 0] + hx) / texel - 0.5, 0.0, lm.shape[1] - 1.0001)
        ty = np.clip((pts[:, 1] + hy) / texel - 0.5, 0.0, lm.shape[0] - 1.0001)
        ix, iy = tx.astype(np.int64), ty.astype(np.int64)
        a, b = tx - ix, ty - iy
        t0 = lm[iy, ix] + a * (lm[iy, ix + 1] - lm[iy, ix])
        t1 = lm[iy + 1, ix] + a * (lm[iy + 1, ix + 1] - lm[iy + 1, ix])
        return (t0 + b * (t1 - t0)).astype(np.float64)

    def camera_matrix(self, scene: Scene, robot: int) -> CameraMatrix:
        """The camera model of robot ``robot``'s image (robot frame)."""
        o = scene.observers[self._check(scene, robot)]
        return self.rig.camera_matrix(int(o[_CAM]), float(o[_YAW]), float(o[_PITCH]))

    def render(
        self, scene: Scene, robot: int, out: NDArray[np.uint8] | None = None, effects: bool = True
    ) -> NDArray[np.uint8]:
        """Robot ``robot``'s camera image (H x W x 3 uint8, RGB), into ``out`` if given.

        With ``effects=False`` (or the ``ideal`` preset) the image is the rendered scene
        exactly, evenly lit; otherwise the hall's uneven light is rendered with it and the
        image effects are applied (drawing random numbers).
        """
        return self._render(scene, self._check(scene, robot), out, effects)

    def camera_image(self, scene: Scene, robot: int, time: float = 0.0, effects: bool = True) -> CameraImage:
        """Robot ``robot``'s image with its camera model, as a brain receives it."""
        r = self._check(scene, robot)
        return self._image_record(scene.observers[r], self._render(scene, r, None, effects), time)

    def camera_images(
        self, scene: Scene, time: float = 0.0, effects: bool = True, camera_errors: NDArray[np.float64] | None = None
    ) -> list[CameraImage | None]:
        """Every robot's :meth:`camera_image` (``None`` for a robot whose camera sees nothing: a
        penalised or carried one), the same images to the bit.

        ``camera_errors`` (robots x 2, rad), if given, is the error of each robot's estimate of its
        camera's orientation (around the pitch axis, then the yaw axis): the image shows the
        true view and its :attr:`~cognition.camera.CameraImage.camera` is computed with the head
        angles off by these (``Match`` draws them from the Darmstadt noise model).

        All images are rendered first and the image effects applied to them afterwards, in robot
        order (the effects draw their random numbers in that order, as one image at a time
        does; rendering draws none): the effects stream megabytes per image (float buffers and
        the noise pool), which in between renders pushed the renderer's textures out of the
        cache. In a 5 v 5 image match the captures take about 7 % less time this way.
        """
        if not isinstance(scene, Scene):
            raise TypeError(f"expected a Scene, got {type(scene).__name__}")
        obs = scene.observers
        if camera_errors is not None:
            camera_errors = np.asarray(camera_errors, dtype=np.float64)
            shaped = camera_errors.shape == (obs.shape[0], 2)
            if not (shaped and np.all(np.isfinite(camera_errors))):
                raise ValueError(
                    f"camera_errors must be finite angles (rad) of shape ({obs.shape[0]}, 2), one row per robot, "
                    f"got shape {camera_errors.shape}" + ("" if not shaped else " with NaN/inf")
                )
        seeing = [r for r in range(obs.shape[0]) if obs[r, OBS.ACTIVE] > 0.5]
        effects = effects and self.effects.active
        inputs = self._inputs[effects and self._lit]
        pixels = {}
        for r in seeing:
            out = pixels[r] = np.empty(self._shapes[int(obs[r, _CAM])], dtype=np.uint8)
            render_nb(obs, r, scene.occluders, scene.ball, *inputs, out)
        if effects:
            for r in seeing:
                self._apply_effects(scene, r, pixels[r])
        images: list[CameraImage | None] = [None] * obs.shape[0]
        for r in seeing:
            da, db = (0.0, 0.0) if camera_errors is None else (float(camera_errors[r, 0]), float(camera_errors[r, 1]))
            images[r] = self._image_record(obs[r], pixels[r], time, da, db)
        return images

    def _apply_effects(self, scene: Scene, r: int, pixels: NDArray[np.uint8]) -> None:
        """The image effects on robot ``r``'s rendered image, with its head and body rates."""
        o = scene.observers[r]
        fx, fy = self._focal[int(o[_CAM])]
        yaw_rate = float(o[_YAWR] + scene.turn_rates[r])
        self.effects.apply(pixels, fx, fy, yaw_rate, float(o[_PITCHR]), bool(o[_WALK] > 0.5))

    def _image_record(
        self, o: NDArray[np.float64], pixels: NDArray[np.uint8], time: float, da: float = 0.0, db: float = 0.0
    ) -> CameraImage:
        """The :class:`CameraImage` of an observer row ``o`` and its pixels; its camera matrix is
        off by ``da`` around the pitch axis and ``db`` around the yaw axis (rad)."""
        ci, yaw, pitch = int(o[_CAM]), float(o[_YAW]), float(o[_PITCH])
        return CameraImage(
            time=time,
            pixels=pixels,
            camera=self.rig.camera_matrix(ci, yaw + db, pitch + da),
            camera_name=CAMERA_NAMES[ci],
            head_yaw=yaw,
            head_pitch=pitch,
        )

    def _render(self, scene: Scene, r: int, out: NDArray[np.uint8] | None, effects: bool) -> NDArray[np.uint8]:
        """:meth:`render` of a checked robot index."""
        shape = self._shapes[int(scene.observers[r, _CAM])]
        if out is None:
            out = np.empty(shape, dtype=np.uint8)
        elif out.shape != shape or out.dtype != np.uint8 or not out.flags.c_contiguous:
            raise ValueError(f"out must be a C-contiguous uint8 array of shape {shape}, got {out.shape} {out.dtype}")
        effects = effects and self.effects.active
        render_nb(scene.observers, r, scene.occluders, scene.ball, *self._inputs[effects and self._lit], out)
        if effects:
            self._apply_effects(scene, r, out)
        return out

    def annotate(self, scene: Scene) -> list[ImageAnnotations | None]:
        """Ground truth of every robot's image (``None`` for robots whose camera sees nothing)."""
        if self._annotator is None:
            self._annotator = PerceptSynthesizer(
                self.field,
                PerceptParams.preset("ideal"),
                np.random.default_rng(0),
                self.rig,
                self.scheme.own_goal != self.scheme.opponent_goal,
            )
        percepts = self._annotator.synthesize(scene)
        return [
            self._annotations(scene, r, p) if scene.observers[r, OBS.ACTIVE] > 0.5 else None
            for r, p in enumerate(percepts)
        ]

    def _annotations(self, scene: Scene, r: int, p: Percepts) -> ImageAnnotations:
        cam = self.camera_matrix(scene, r)
        o = scene.observers[r]
        pose = (float(o[OBS.X]), float(o[OBS.Y]), float(o[OBS.TH]))
        d = self.field.dims
        posts = p.posts
        post_rows = []
        for k in range(len(posts)):
            box = _cylinder_box(cam, pose, posts.xy[k], d.goal_post_diameter / 2, d.goal_height, relative=True)
            post_rows.append([*posts.uv[k], *box, posts.subtype[k], posts.truth[k]])
        cr = p.crossings
        lines = p.lines
        marks = p.penalty_marks
        ball = p.ball
        npt = scene.players_per_team
        team = int(o[OBS.TEAM])
        robot_rows = []
        rb = p.robots
        for k in range(len(rb)):
            t = int(rb.truth[k])
            index = team * npt + t if t < npt else (1 - team) * npt + (t - npt)
            oc = scene.occluders[index]
            box = _cylinder_box(cam, pose, oc[[OC.X, OC.Y]], float(oc[OC.R]), float(oc[OC.H]), relative=False)
            robot_rows.append([*rb.uv[k], *box, index])
        pole_rows = []
        pl = p.poles
        for k in range(len(pl)):
            box = _cylinder_box(cam, pose, pl.xy[k], d.corner_pole_diameter / 2, POLE_HEIGHT, relative=True)
            pole_rows.append([*pl.uv[k], *box, pl.truth[k]])
        return ImageAnnotations(
            camera=cam,
            posts=np.asarray(post_rows, dtype=np.float64).reshape(-1, 8),
            crossings=np.column_stack([cr.uv, cr.subtype, cr.truth]).astype(np.float64).reshape(-1, 4),
            lines=np.column_stack([lines.uv, lines.uv2, lines.truth]).astype(np.float64).reshape(-1, 5),
            circle=self._circle_points(scene, r, cam, pose) if len(p.circle) else np.zeros((0, 2)),
            marks=np.column_stack([marks.uv, marks.truth]).astype(np.float64).reshape(-1, 3),
            ball=np.column_stack([ball.uv, ball.radius_px]).astype(np.float64).reshape(-1, 3),
            robots=np.asarray(robot_rows, dtype=np.float64).reshape(-1, 7),
            poles=np.asarray(pole_rows, dtype=np.float64).reshape(-1, 7),
        )

    def _circle_points(
        self, scene: Scene, r: int, cam: CameraMatrix, pose: tuple[float, float, float]
    ) -> NDArray[np.float64]:
        """Visible points of the centre circle (in the image, not hidden by robots)."""
        c = self.field.centre_circle
        a = 2.0 * np.pi * (np.arange(4 * CIRCLE_SAMPLES) + 0.5) / (4 * CIRCLE_SAMPLES)
        world = np.stack([c.x + c.radius * np.cos(a), c.y + c.radius * np.sin(a)], axis=1)
        uv, ok = cam.project(_to_robot(world, pose, 0.0))
        ok &= cam.in_image(uv)
        ok &= ~_hidden(scene, r, world, cam, pose)
        return uv[ok]

    def _check(self, scene: Scene, robot: int) -> int:
        if not isinstance(scene, Scene):
            raise TypeError(f"expected a Scene, got {type(scene).__name__}")
        n = scene.observers.shape[0]
        if isinstance(robot, bool) or not isinstance(robot, int | np.integer) or not 0 <= robot < n:
            raise ValueError(f"robot index must be an integer in [0, {n}), got {robot!r}")
        return int(robot)


def _camera_columns(rig: CameraRig, name: str) -> list[float]:
    s = rig.spec(name)  # type: ignore[arg-type]
    return [s.tilt, s.offset_x, s.offset_z, s.fx, s.fy, s.cx, s.cy, float(s.width), float(s.height)]


def _to_robot(world_xy: NDArray[np.float64], pose: tuple[float, float, float], z: float) -> NDArray[np.float64]:
    """World-frame ground points (N x 2) at height ``z`` as robot-frame points (N x 3)."""
    x, y, th = pose
    c, s = np.cos(th), np.sin(th)
    dx, dy = world_xy[:, 0] - x, world_xy[:, 1] - y
    return np.stack([c * dx + s * dy, -s * dx + c * dy, np.full(len(world_xy), z)], axis=1)


def _cylinder_box(
    cam: CameraMatrix,
    pose: tuple[float, float, float],
    centre: NDArray[np.float64],
    radius: float,
    height: float,
    relative: bool,
) -> tuple[float, float, float, float]:
    """Image box (u0, v0, u1, v1) of a vertical cylinder, clipped to the image.

    ``centre`` is robot-relative if ``relative`` else in the world frame.
    """
    a = 2.0 * np.pi * np.arange(_BOX_SAMPLES) / _BOX_SAMPLES
    ring = np.stack([centre[0] + radius * np.cos(a), centre[1] + radius * np.sin(a)], axis=1)
    if relative:
        pts = np.concatenate(
            [np.column_stack([ring, np.zeros(len(ring))]), np.column_stack([ring, np.full(len(ring), height)])]
        )
    else:
        pts = np.concatenate([_to_robot(ring, pose, 0.0), _to_robot(ring, pose, height)])
    uv, front = cam.project(pts)
    uv = uv[front]
    s = cam.spec
    if len(uv) == 0:
        return (0.0, 0.0, 0.0, 0.0)
    u0, v0 = np.clip(uv.min(axis=0), 0, [s.width, s.height])
    u1, v1 = np.clip(uv.max(axis=0), 0, [s.width, s.height])
    return (float(u0), float(v0), float(u1), float(v1))


def _hidden(
    scene: Scene, r: int, world: NDArray[np.float64], cam: CameraMatrix, pose: tuple[float, float, float]
) -> NDArray[np.bool_]:
    """Ground points (world frame) hidden behind another robot's body, as the percepts decide."""
    x, y, th = pose
    c, s = np.cos(th), np.sin(th)
    cx = x + c * cam.position[0] - s * cam.position[1]
    cy = y + s * cam.position[0] + c * cam.position[1]
    hc = cam.position[2]
    rel = world - [cx, cy]
    d = np.hypot(rel[:, 0], rel[:, 1])
    b = np.arctan2(rel[:, 1], rel[:, 0])
    hidden = np.zeros(len(world), dtype=bool)
    for j, oc in enumerate(scene.occluders):
        if j == r or oc[OC.PRESENT] < 0.5:
            continue
        od = float(np.hypot(oc[OC.X] - cx, oc[OC.Y] - cy))
        if od <= oc[OC.R]:
            continue
        ob = np.arctan2(oc[OC.Y] - cy, oc[OC.X] - cx)
        ow = np.arcsin(min(1.0, oc[OC.R] / od))
        rel_b = np.abs((b - ob + np.pi) % (2 * np.pi) - np.pi)
        behind = d > od
        below = hc - hc * od / np.maximum(d, 1e-9) < oc[OC.H]  # line of sight passes below its top
        hidden |= behind & below & (rel_b < ow)
    return hidden


def draw_annotations(image: NDArray[np.uint8], ann: ImageAnnotations | None) -> NDArray[np.uint8]:
    """A copy of ``image`` (RGB) with the annotations drawn on it (for people)."""
    out = np.ascontiguousarray(image).copy()
    if ann is None:
        return out
    aa = cv2.LINE_AA

    def pt(u: float, v: float) -> tuple[int, int]:
        return round(u), round(v)

    for u1, v1, u2, v2, _ in ann.lines:
        cv2.line(out, pt(u1, v1), pt(u2, v2), (255, 0, 255), 1, aa)
    for u, v in ann.circle:
        cv2.circle(out, pt(u, v), 1, (0, 255, 255), -1, aa)
    for u, v, kind, _ in ann.crossings:
        cv2.drawMarker(out, pt(u, v), (255, 0, 0), cv2.MARKER_CROSS, 8, 1, aa)
        cv2.putText(out, "LTX"[int(kind)], pt(u + 3, v - 3), cv2.FONT_HERSHEY_SIMPLEX, 0.35, (255, 0, 0), 1, aa)
    for u, v, _ in ann.marks:
        cv2.drawMarker(out, pt(u, v), (0, 0, 255), cv2.MARKER_TILTED_CROSS, 8, 1, aa)
    for row in ann.posts:
        cv2.rectangle(out, pt(row[2], row[3]), pt(row[4], row[5]), (255, 255, 0), 1, aa)
        cv2.drawMarker(out, pt(row[0], row[1]), (255, 255, 0), cv2.MARKER_TRIANGLE_UP, 6, 1, aa)
    for row in ann.poles:
        cv2.rectangle(out, pt(row[2], row[3]), pt(row[4], row[5]), (0, 255, 128), 1, aa)
    for row in ann.robots:
        cv2.rectangle(out, pt(row[2], row[3]), pt(row[4], row[5]), (255, 128, 0), 1, aa)
    for u, v, rad in ann.ball:
        cv2.circle(out, pt(u, v), max(1, round(rad)), (255, 0, 0), 1, aa)
    return out


def save_png(path: str | Path, image: NDArray[np.uint8]) -> Path:
    """Write an RGB image to ``path`` as PNG (parent folders are created); returns the path."""
    p = Path(path)
    if p.suffix.lower() != ".png":
        raise ValueError(f"save_png writes .png files, got {str(p)!r}")
    a = np.asarray(image)
    if a.dtype != np.uint8 or a.ndim != 3 or a.shape[2] != 3:
        raise ValueError(f"save_png expects an H x W x 3 uint8 RGB image, got {a.shape} {a.dtype}")
    p.parent.mkdir(parents=True, exist_ok=True)
    if not cv2.imwrite(str(p), cv2.cvtColor(a, cv2.COLOR_RGB2BGR)):
        raise OSError(f"could not write {str(p)!r}")
    return p
