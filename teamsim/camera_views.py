"""Camera images for people: PNG snapshots, side-by-side match videos and the gallery.

=====================  ===================================================================
function               what it does
=====================  ===================================================================
parse_robot            ``"T:N"`` (team index 0/1, player number) -> (team, number)
CameraPanel            renders one robot's camera next to the top-down view of a match
side_by_side           joins a top-down frame and a camera frame into one video frame
belief_overlay         one robot's localization belief (particles, estimate) in the world
                       frame, for the top-down view
write_snapshots        runs a match to given times and writes robots' images as PNG
                       (raw and with ground-truth annotations)
gallery_scenes         the fixed scenes of the README gallery (file stem, field, colours,
                       image preset, scene, robot index)
write_gallery          renders the fixed scenes of the README gallery (``docs/gallery``)
=====================  ===================================================================

Everything here draws its random numbers from its own generator, so looking at a match
never changes it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import cv2
import numpy as np
from numpy.typing import NDArray

from cognition.camera import CameraRig
from cognition.field import FIELD_PRESETS, Field
from cognition.representations import RobotPose
from cognition.worldmodel.representations import Beliefs
from teamsim.image_params import ImageParams
from teamsim.images import ImageRenderer, draw_annotations, save_png
from teamsim.match import Match
from teamsim.percepts import Scene, SceneRobot
from teamsim.placement import team_to_world
from teamsim.render import Belief

VIDEO_CAMERA_SIZE = (640, 480)
"""Resolution (width, height) of the camera panel in videos (px)."""


def parse_robot(text: str, players_per_team: int) -> tuple[int, int]:
    """``"T:N"`` -> (team index, player number), checked against ``players_per_team``."""
    try:
        team_s, number_s = text.split(":")
        team, number = int(team_s), int(number_s)
    except ValueError:
        raise ValueError(f"a robot is TEAM:NUMBER with team 0 or 1, e.g. 0:3; got {text!r}") from None
    if team not in (0, 1) or not 1 <= number <= players_per_team:
        raise ValueError(f"robot {text!r} does not exist: team must be 0 or 1, number 1..{players_per_team}")
    return team, number


class CameraPanel:
    """One robot's camera view of a running match, for videos (world state read each frame)."""

    def __init__(self, match: Match, team: int, number: int, annotate: bool = False, seed: int = 0):
        c = match.config
        self.match = match
        self.index = team * c.players_per_team + number - 1
        self.label = f"team {team} player {number}"
        self.annotate = annotate
        rig = c.camera.with_resolution(*VIDEO_CAMERA_SIZE)
        rng = np.random.default_rng([c.seed, seed, 7])
        self.renderer = ImageRenderer(match.field, c.colours, rig, c.images, rng)

    def render(self) -> NDArray[np.uint8]:
        """The robot's current camera image (grey with a note when its camera sees nothing)."""
        scene = self.match.scene()
        w, h = VIDEO_CAMERA_SIZE
        o = scene.observers[self.index]
        if o[9] < 0.5:
            img = np.full((h, w, 3), 40, dtype=np.uint8)
            cv2.putText(img, "camera off (fallen, picked up or removed)", (20, h // 2), cv2.FONT_HERSHEY_SIMPLEX,
                        0.6, (220, 220, 220), 1, cv2.LINE_AA)  # fmt: skip
        else:
            img = self.renderer.render(scene, self.index)
            if self.annotate:
                img = draw_annotations(img, self.renderer.annotate(scene)[self.index])
        camera = "upper" if o[7] < 0.5 else "lower"
        cv2.putText(img, f"{self.label}, {camera} camera", (8, 20), cv2.FONT_HERSHEY_SIMPLEX, 0.55,
                    (255, 255, 255), 1, cv2.LINE_AA)  # fmt: skip
        return img


def side_by_side(top: NDArray[np.uint8], camera: NDArray[np.uint8]) -> NDArray[np.uint8]:
    """The top-down frame with the camera frame scaled to its height on the right."""
    h = top.shape[0]
    w = max(1, round(camera.shape[1] * h / camera.shape[0]))
    cam = cv2.resize(camera, (w, h), interpolation=cv2.INTER_AREA)
    return np.ascontiguousarray(np.concatenate([top, cam], axis=1))


def belief_overlay(match: Match, team: int, number: int) -> Belief | None:
    """The robot's latest pose estimate and particles, ball, team ball, obstacles and goal,
    converted from its team (or robot) frame to the world frame.

    Reads the brain's ``beliefs`` (:class:`~cognition.worldmodel.representations.Beliefs`) when it has
    them; a brain without beliefs (or before its first frame) but with a ``pose``
    :class:`~cognition.representations.RobotPose` gets only the pose and particles drawn.
    ``None`` when the robot's brain has neither.
    """
    brain = match.brains[team * match.config.players_per_team + number - 1]
    beliefs = getattr(brain, "beliefs", None)
    if not isinstance(beliefs, Beliefs):
        beliefs = None
    pose = beliefs.pose if beliefs is not None else getattr(brain, "pose", None)
    if not isinstance(pose, RobotPose):
        return None
    sign = match.referee.sign(team)
    x, y, theta = team_to_world(sign, pose.x, pose.y, pose.theta)
    parts = np.array(pose.particles, dtype=np.float64).reshape(-1, 3)
    if sign < 0:
        parts[:, :2] *= -1.0
        parts[:, 2] += math.pi
    parts[:, 2] = (parts[:, 2] + math.pi) % (2.0 * math.pi) - math.pi
    if beliefs is None:
        return Belief(team, x, y, theta, parts, bool(pose.lost), None, "invalid")
    ball = beliefs.ball
    ball_xy, level = None, "invalid"
    if math.isfinite(ball.field_x):
        ball_xy, level = (sign * ball.field_x, sign * ball.field_y), ball.level
    tb = beliefs.team_ball
    team_xy = (sign * tb.x, sign * tb.y) if tb is not None else None
    c, s = math.cos(theta), math.sin(theta)  # robot frame -> world frame via the estimate
    rel = np.asarray(beliefs.obstacles, dtype=np.float64).reshape(-1, 2)
    obstacles = np.column_stack([x + c * rel[:, 0] - s * rel[:, 1], y + s * rel[:, 0] + c * rel[:, 1]])
    goal = None
    if beliefs.goal is not None:
        (lx, ly), (rx, ry) = beliefs.goal.left, beliefs.goal.right
        goal = ((x + c * lx - s * ly, y + s * lx + c * ly), (x + c * rx - s * ry, y + s * rx + c * ry))
    return Belief(team, x, y, theta, parts, bool(pose.lost), ball_xy, level, team_xy, obstacles, goal)


def write_snapshots(
    match: Match,
    times: Sequence[float],
    robots: Sequence[tuple[int, int]],
    out_dir: Path,
    size: tuple[int, int] = (320, 240),
) -> list[Path]:
    """Run ``match`` to each time (s) and write each robot's image, raw and annotated, as PNG.

    Files are ``t{time}_team{T}_player{N}.png`` and ``..._annotated.png``; returns the paths.
    """
    if not times:
        raise ValueError("give at least one time")
    if any(not math.isfinite(t) or t < 0 for t in times):
        raise ValueError(f"times must be finite and >= 0 s, got {list(times)}")
    c = match.config
    rig = c.camera.with_resolution(*size)
    ren = ImageRenderer(match.field, c.colours, rig, c.images, np.random.default_rng([c.seed, 11]))
    written: list[Path] = []
    for t in sorted(times):
        match.run(until=t)
        scene = match.scene()
        annotations = ren.annotate(scene)
        for team, number in robots:
            r = team * c.players_per_team + number - 1
            stem = f"t{t:07.2f}_team{team}_player{number}"
            if scene.observers[r, 9] < 0.5:
                continue
            img = ren.render(scene, r)
            written.append(save_png(out_dir / f"{stem}.png", img))
            written.append(save_png(out_dir / f"{stem}_annotated.png", draw_annotations(img, annotations[r])))
    return written


def gallery_scenes() -> list[tuple[str, str, str, str, Scene, int]]:
    """(file stem, field, scheme, image preset, scene, robot index) of the gallery."""
    out = []
    robots = [
        SceneRobot(0, 1, -2.2, 0.2, 0.05, head_pitch=0.05),
        SceneRobot(0, 2, -3.6, -0.6, 0.3),
        SceneRobot(1, 1, 4.3, 0.1, math.pi),
        SceneRobot(1, 2, 0.8, 0.5, math.pi - 0.3),
        SceneRobot(1, 3, 2.0, -1.1, 2.5, fallen=True),
    ]
    out.append(("across_the_field", "spl2025", "classic", "ideal", Scene.build(robots, (1.6, -0.4), 3), 0))
    robots = [SceneRobot(0, 1, 3.05, -0.95, 0.2, head_pitch=0.25, camera="lower")]
    out.append(("ball_at_the_feet", "spl2025", "modern", "ideal", Scene.build(robots, (3.4, -0.8), 1), 0))
    robots = [
        SceneRobot(0, 1, 2.4, 1.2, -0.35, head_yaw=0.1, head_pitch=0.1),
        SceneRobot(1, 1, 4.3, 0.0, math.pi),
        SceneRobot(0, 2, 3.6, -0.4, 0.0),
    ]
    out.append(("opponent_goal_modern", "spl2025", "modern", "default", Scene.build(robots, (3.9, 0.3), 2), 0))
    robots = [SceneRobot(0, 1, -0.5, -0.8, 0.6, head_yaw=0.2, head_pitch=0.08)]
    out.append(("kidsize_field", "kidsize", "kidsize", "ideal", Scene.build(robots, (0.6, 0.1), 1), 0))
    robots = [
        SceneRobot(0, 1, -1.0, 0.0, 0.0, head_yaw=0.4, yaw_rate=2.5, walking=True, turn_rate=0.6),
        SceneRobot(1, 1, 0.6, 0.3, math.pi),
    ]
    out.append(("harsh_effects_turning", "spl2025", "classic", "harsh", Scene.build(robots, (0.2, -0.2), 1), 0))
    return out


def write_gallery(out_dir: Path, size: tuple[int, int] = (320, 240)) -> list[Path]:
    """Render the gallery scenes (raw and annotated PNGs) into ``out_dir``; returns the paths."""
    written: list[Path] = []
    for stem, field_name, scheme, preset, scene, r in gallery_scenes():
        field = Field(FIELD_PRESETS[field_name], field_name)
        rig = CameraRig().with_resolution(*size)
        ren = ImageRenderer(field, scheme, rig, ImageParams.preset(preset), np.random.default_rng(1))
        img = ren.render(scene, r)
        written.append(save_png(out_dir / f"{stem}.png", img))
        written.append(save_png(out_dir / f"{stem}_annotated.png", draw_annotations(img, ren.annotate(scene)[r])))
    return written
