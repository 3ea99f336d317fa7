"""Top-down view of a match for people to look at (not the robots' camera model).

:class:`TopDownRenderer` draws a :class:`~teamsim.state.WorldSnapshot` (ground truth, world
frame) onto a pre-rendered, cached image of the field and returns an RGB ``uint8`` array,
optionally with robots' localization beliefs (:class:`Belief`: particles as small dots and the
estimated pose as an outlined robot, in the team colour);
:class:`VideoWriter` streams such frames to an MP4 or an animated GIF (:mod:`teamsim.video`),
creating the file at once so that a path that cannot be written fails before a match is run.

The image shows the carpet including the border strip, with a header strip on top for the
score, game state, clock and simulated time. World x runs to the right, world y **up** on
screen; the field is drawn in the world frame (the field's own goal, at -x, is team 0's own
goal in the first half).

=====================  ==========  =====================================================
parameter              default     meaning
=====================  ==========  =====================================================
pixels_per_metre       60.0        image scale (px/m), finite, in [5, 400]
team_names             Home, Away  names shown in the header for team index 0 and 1
HEADER_HEIGHT          40          height of the text strip above the field (px)
ROBOT_RADIUS           0.15        radius of a drawn robot (m)
PARTICLE_RADIUS        0.02        radius of a drawn particle (m; at least 1 px)
VideoWriter.fps        15.0        frames per second of the written video (> 0)
VideoWriter.gif_scale  2           GIF frames are shrunk by this integer factor (1: none)
=====================  ==========  =====================================================
"""

from __future__ import annotations

import contextlib
import math
import os
from collections.abc import Sequence
from dataclasses import dataclass
from dataclasses import field as dataclass_field
from pathlib import Path
from types import TracebackType
from typing import BinaryIO

import cv2
import numpy as np
from numpy.typing import NDArray

from cognition.field import ColourScheme, Field
from cognition.gamestate import GameControlData, GameStateId
from teamsim.state import RobotTruth, WorldSnapshot
from teamsim.video import GifStream, VideoError

HEADER_HEIGHT = 40
"""Height of the header text strip (px)."""
ROBOT_RADIUS = 0.15
"""Radius of a drawn robot (m)."""
PARTICLE_RADIUS = 0.02
"""Radius of a drawn particle (m; at least one pixel)."""

RGB = tuple[int, int, int]
Img = np.ndarray
_SHIFT = 4  # sub-pixel bits for cv2 drawing
_ONE = 1 << _SHIFT
_AA = cv2.LINE_AA
_FONT = cv2.FONT_HERSHEY_SIMPLEX
_BLACK: RGB = (0, 0, 0)
_WHITE: RGB = (255, 255, 255)
_GREY: RGB = (140, 140, 140)
_HEADER_BG: RGB = (30, 30, 30)
_KEEPER_RING: RGB = (255, 255, 255)
_PICKUP_RING: RGB = (255, 255, 0)


@dataclass(frozen=True)
class Overlay:
    """An extra item drawn on top of a frame (world frame).

    With ``theta`` set it is a pose arrow of ``length`` metres from (x, y) in direction
    ``theta``; otherwise a filled dot of ``radius`` metres. ``label`` is written beside it.
    """

    x: float
    """Position (m, world frame)."""
    y: float
    """Position (m, world frame)."""
    colour: RGB = (255, 0, 255)
    """RGB colour, components 0-255."""
    theta: float | None = None
    """Heading (rad, world frame) for a pose arrow; ``None`` for a dot."""
    label: str = ""
    """Text drawn next to the item."""
    radius: float = 0.05
    """Dot radius (m)."""
    length: float = 0.3
    """Arrow length (m)."""

    def __post_init__(self) -> None:
        if len(self.colour) != 3 or any(not 0 <= int(c) <= 255 for c in self.colour):
            raise ValueError(f"Overlay.colour must be three components in 0-255, got {self.colour}")
        if not (math.isfinite(self.x) and math.isfinite(self.y)):
            raise ValueError(f"Overlay position must be finite, got ({self.x}, {self.y})")


@dataclass(frozen=True)
class Belief:
    """One robot's localization belief for drawing, already converted to the **world frame**."""

    team: int
    """Team index (0 or 1); picks the jersey colour."""
    x: float
    """Estimated position (m, world frame)."""
    y: float
    """Estimated position (m, world frame)."""
    theta: float
    """Estimated heading (rad, world frame)."""
    particles: NDArray[np.float64] = dataclass_field(default_factory=lambda: np.zeros((0, 3)))
    """N x 3 particle poses (x m, y m, theta rad; world frame); may be empty."""
    lost: bool = False
    """Whether the localization flags itself lost (drawn as a "?" beside the estimate)."""
    ball: tuple[float, float] | None = None
    """The robot's ball estimate (m, world frame): a ring in the team colour, or ``None``."""
    ball_level: str = "valid"
    """``valid``, ``suspicious`` (drawn thinner) or ``invalid`` (not drawn)."""
    team_ball: tuple[float, float] | None = None
    """The fused team ball (m, world frame): a cross, or ``None``."""
    obstacles: NDArray[np.float64] = dataclass_field(default_factory=lambda: np.zeros((0, 2)))
    """K x 2 obstacle positions the robot believes in (m, world frame): small squares."""
    goal: tuple[tuple[float, float], tuple[float, float]] | None = None
    """The goal model's two posts (m, world frame): joined by a line, or ``None``."""

    def __post_init__(self) -> None:
        if self.team not in (0, 1):
            raise ValueError(f"Belief.team must be 0 or 1, got {self.team!r}")
        obs = np.asarray(self.obstacles)
        if obs.ndim != 2 or obs.shape[1] != 2:
            raise ValueError(f"Belief.obstacles must be K x 2, got shape {obs.shape}")
        if not (math.isfinite(self.x) and math.isfinite(self.y) and math.isfinite(self.theta)):
            raise ValueError(f"Belief pose must be finite, got ({self.x}, {self.y}, {self.theta})")
        p = np.asarray(self.particles)
        if p.ndim != 2 or p.shape[1] != 3:
            raise ValueError(f"Belief.particles must be N x 3, got shape {p.shape}")


class TopDownRenderer:
    """Draws world snapshots onto a cached picture of the field.

    The static background (carpet, lines, marks, goals, corner poles, empty header) is drawn
    once in the constructor; :meth:`render` copies it and adds the moving things.
    """

    def __init__(
        self,
        field: Field,
        scheme: ColourScheme,
        pixels_per_metre: float = 60.0,
        team_names: tuple[str, str] = ("Home", "Away"),
    ) -> None:
        ppm = float(pixels_per_metre)
        if not math.isfinite(ppm) or not 5.0 <= ppm <= 400.0:
            v = pixels_per_metre
            raise ValueError(f"pixels_per_metre must be finite and between 5 and 400, got {v!r}")
        if len(team_names) != 2 or not all(isinstance(n, str) for n in team_names):
            raise ValueError(f"team_names must be two strings, got {team_names!r}")
        if len(scheme.team_colours) != 2:
            raise ValueError("scheme.team_colours must hold two colours (team 0, team 1)")
        self.field = field
        self.scheme = scheme
        self.pixels_per_metre = ppm
        self.team_names = (team_names[0], team_names[1])
        d = field.dims
        self._ox = field.half_length + d.border_strip  # world x at the image's left edge, negated
        self._oy = field.half_width + d.border_strip  # world y at the field top edge
        self.width = round((d.length + 2 * d.border_strip) * ppm)
        """Image width (px)."""
        self.height = HEADER_HEIGHT + round((d.width + 2 * d.border_strip) * ppm)
        """Image height including the header (px)."""
        bg = self._draw_background()
        bg.flags.writeable = False
        self._background = bg

    @property
    def background(self) -> np.ndarray:
        """The cached static image (read-only RGB ``uint8``, H x W x 3)."""
        return self._background

    # ----------------------------------------------------------------- transforms
    def to_pixel(self, x: float, y: float) -> tuple[float, float]:
        """World point (m) -> (column, row) in pixels; integer values are pixel centres."""
        ppm = self.pixels_per_metre
        return (x + self._ox) * ppm - 0.5, HEADER_HEIGHT + (self._oy - y) * ppm - 0.5

    def _pt(self, x: float, y: float) -> tuple[int, int]:
        c, r = self.to_pixel(x, y)
        return round(c * _ONE), round(r * _ONE)

    def _ipt(self, x: float, y: float) -> tuple[int, int]:
        c, r = self.to_pixel(x, y)
        return round(c), round(r)

    def _r(self, metres: float, minimum: float = 0.0) -> int:
        return round(max(metres * self.pixels_per_metre, minimum) * _ONE)

    # ----------------------------------------------------------------- primitives
    def _bar(self, img: Img, x1: float, y1: float, x2: float, y2: float, w: float, c: RGB) -> None:
        """Filled rectangle of width ``w`` (m) along a segment, ends extended by w/2."""
        dx, dy = x2 - x1, y2 - y1
        n = math.hypot(dx, dy) or 1.0
        ux, uy = dx / n * w / 2, dy / n * w / 2
        pts = [(x1 - ux - uy, y1 - uy + ux), (x2 + ux - uy, y2 + uy + ux)]
        pts += [(x2 + ux + uy, y2 + uy - ux), (x1 - ux + uy, y1 - uy - ux)]
        poly = np.array([self._pt(px, py) for px, py in pts], np.int32)
        cv2.fillPoly(img, [poly], c, _AA, _SHIFT)

    def _disc(self, img: Img, x: float, y: float, r: float, col: RGB, thick: int = -1) -> None:
        cv2.circle(img, self._pt(x, y), self._r(r, 0.5), col, thick, _AA, _SHIFT)

    @staticmethod
    def _text(img: np.ndarray, s: str, org: tuple[int, int], col: RGB, scale: float = 0.45) -> None:
        cv2.putText(img, s, org, _FONT, scale, col, 1, _AA)

    def _centred_text(self, img: Img, s: str, x: float, y: float, col: RGB, scale: float) -> None:
        (tw, th), _ = cv2.getTextSize(s, _FONT, scale, 1)
        c, r = self._ipt(x, y)
        self._text(img, s, (c - tw // 2, r + th // 2), col, scale)

    # ----------------------------------------------------------------- background
    def _draw_background(self) -> np.ndarray:
        f, d, s = self.field, self.field.dims, self.scheme
        img = np.empty((self.height, self.width, 3), np.uint8)
        img[:] = s.field_green
        img[:HEADER_HEIGHT] = _HEADER_BG
        white, lw = tuple(s.line_white), d.line_width
        cc = f.centre_circle
        cx, cy, cr = cc.x, cc.y, cc.radius
        self._disc(img, cx, cy, cr + lw / 2, white)
        self._disc(img, cx, cy, cr - lw / 2, tuple(s.field_green))
        for seg in f.lines:
            self._bar(img, seg.x1, seg.y1, seg.x2, seg.y2, lw, white)
        marks = [(m.x, m.y) for m in f.penalty_marks]
        if getattr(d, "centre_mark", True):
            marks.append((cx, cy))
        half = getattr(d, "penalty_mark_size", 0.1) / 2
        for mx, my in marks:  # crosses
            self._bar(img, mx - half, my, mx + half, my, lw, white)
            self._bar(img, mx, my - half, mx, my + half, lw, white)
        for sign, col in ((-1.0, s.own_goal), (1.0, s.opponent_goal)):
            self._draw_goal(img, sign, tuple(col))
        pole = getattr(d, "corner_pole_diameter", 0.1) / 2
        for p in f.corner_poles:  # striped like the goals: near goal's colour outside
            near, far = (s.own_goal, s.opponent_goal) if p.x < 0 else (s.opponent_goal, s.own_goal)
            self._disc(img, p.x, p.y, pole, tuple(near))
            self._disc(img, p.x, p.y, pole / 2, tuple(far))
            self._disc(img, p.x, p.y, pole, _BLACK, 1)
        return np.ascontiguousarray(img)

    def _draw_goal(self, img: np.ndarray, sign: float, col: RGB) -> None:
        """Net (hatched box behind the goal line) and posts of the goal at x = sign * L/2."""
        d, hl = self.field.dims, self.field.half_length
        hw, depth = d.goal_inner_width / 2 + d.goal_post_diameter / 2, d.goal_depth
        back = sign * (hl + depth)
        net = img.copy()
        x0, x1 = sorted((sign * hl, back))
        poly = np.array([self._pt(x0, -hw), self._pt(x1, -hw), self._pt(x1, hw), self._pt(x0, hw)])
        cv2.fillPoly(net, [poly.astype(np.int32)], col, _AA, _SHIFT)
        cv2.addWeighted(net, 0.35, img, 0.65, 0.0, dst=img)
        step = 0.1
        for k in range(1, math.ceil(2 * hw / step)):
            yk = -hw + k * step
            cv2.line(img, self._pt(sign * hl, yk), self._pt(back, yk), col, 1, _AA, _SHIFT)
        thin = max(0.02, 1.0 / self.pixels_per_metre)
        for side in (-hw, hw):
            self._bar(img, sign * hl, side, back, side, thin, col)
        self._bar(img, back, -hw, back, hw, thin, col)
        for gp in self.field.goal_posts:
            if (gp.x > 0) == (sign > 0):
                self._disc(img, gp.x, gp.y, d.goal_post_diameter / 2, col)
                self._disc(img, gp.x, gp.y, d.goal_post_diameter / 2, _BLACK, 1)

    # ----------------------------------------------------------------- frames
    def render(
        self,
        snapshot: WorldSnapshot,
        game: GameControlData | None = None,
        overlays: Sequence[Overlay] = (),
        beliefs: Sequence[Belief] = (),
    ) -> np.ndarray:
        """One RGB ``uint8`` frame (H x W x 3, C-contiguous) of this snapshot.

        ``beliefs`` are drawn over the robots and under the ball and ``overlays``.
        """
        img = self._background.copy()
        for robot in snapshot.robots:
            self._draw_robot(img, robot, game)
        for belief in beliefs:
            self._draw_belief(img, belief)
        d, s = self.field.dims, self.scheme
        bx, by = snapshot.ball_x, snapshot.ball_y
        rad = max(d.ball_diameter / 2 * self.pixels_per_metre, 3.0) / self.pixels_per_metre
        self._disc(img, bx, by, rad, tuple(s.ball_primary))
        self._disc(img, bx, by, rad, tuple(s.ball_secondary), 1)
        for ov in overlays:
            self._draw_overlay(img, ov)
        self._draw_header(img, snapshot, game)
        return img

    def _draw_robot(self, img: np.ndarray, r: RobotTruth, game: GameControlData | None) -> None:
        penalized = r.penalized
        if r.team not in (0, 1):
            raise ValueError(f"RobotTruth.team must be 0 or 1, got {r.team!r}")
        players = game.teams[r.team].players if game is not None else ()
        if 1 <= r.number <= len(players):
            penalized = penalized or players[r.number - 1].penalty != 0
        jersey = tuple(self.scheme.team_colours[r.team])
        fill = _GREY if penalized else jersey
        ring_px = 2.0 / self.pixels_per_metre
        if r.picked_up:
            self._disc(img, r.x, r.y, ROBOT_RADIUS + 2 * ring_px, _PICKUP_RING, 2)
        self._disc(img, r.x, r.y, ROBOT_RADIUS, fill)
        keeper = r.number == 1
        edge = _KEEPER_RING if keeper else _BLACK
        self._disc(img, r.x, r.y, ROBOT_RADIUS, edge, 3 if keeper else 1)
        hx = r.x + 1.3 * ROBOT_RADIUS * math.cos(r.theta)
        hy = r.y + 1.3 * ROBOT_RADIUS * math.sin(r.theta)
        cv2.line(img, self._pt(r.x, r.y), self._pt(hx, hy), _BLACK, 2, _AA, _SHIFT)
        if r.fallen:
            k = ROBOT_RADIUS * 0.7
            for sx in (-1.0, 1.0):
                a, b = self._pt(r.x - k, r.y - sx * k), self._pt(r.x + k, r.y + sx * k)
                cv2.line(img, a, b, (200, 0, 0), 2, _AA, _SHIFT)
        luminance = 0.299 * fill[0] + 0.587 * fill[1] + 0.114 * fill[2]
        ink = _BLACK if luminance > 140 else _WHITE
        scale = max(0.25, ROBOT_RADIUS * self.pixels_per_metre / 24.0)
        self._centred_text(img, str(r.number), r.x, r.y, ink, scale)
        if penalized:
            self._centred_text(img, "P", r.x, r.y + 1.8 * ROBOT_RADIUS, _WHITE, scale)

    def _draw_belief(self, img: np.ndarray, b: Belief) -> None:
        """Particles as small dots, the estimate as an outlined robot with a heading line, the
        believed ball as a ring, the team ball as a cross, the modelled goal as a line between
        its posts and obstacles as small squares."""
        col = tuple(int(c) for c in self.scheme.team_colours[b.team])
        parts = np.asarray(b.particles, dtype=np.float64)
        if parts.shape[0]:
            ppm = self.pixels_per_metre
            cols = np.rint((parts[:, 0] + self._ox) * ppm - 0.5).astype(np.int64)
            rows = np.rint(HEADER_HEIGHT + (self._oy - parts[:, 1]) * ppm - 0.5).astype(np.int64)
            inside = (cols >= 0) & (cols < self.width) & (rows >= HEADER_HEIGHT) & (rows < self.height)
            radius = max(1, round(PARTICLE_RADIUS * ppm))
            for c, r in zip(cols[inside].tolist(), rows[inside].tolist(), strict=True):
                cv2.circle(img, (c, r), radius, col, -1, cv2.LINE_8)
        self._disc(img, b.x, b.y, ROBOT_RADIUS, _BLACK, 4)
        self._disc(img, b.x, b.y, ROBOT_RADIUS, col, 2)
        hx = b.x + 1.6 * ROBOT_RADIUS * math.cos(b.theta)
        hy = b.y + 1.6 * ROBOT_RADIUS * math.sin(b.theta)
        cv2.line(img, self._pt(b.x, b.y), self._pt(hx, hy), col, 2, _AA, _SHIFT)
        if b.lost:
            c, r = self._ipt(b.x + ROBOT_RADIUS, b.y + ROBOT_RADIUS)
            self._text(img, "?", (c, r), col, 0.6)
        if b.ball is not None and b.ball_level != "invalid":
            self._disc(img, b.ball[0], b.ball[1], 0.09, col, 2 if b.ball_level == "valid" else 1)
        if b.team_ball is not None:
            k = 0.08
            tx, ty = b.team_ball
            for sx in (-1.0, 1.0):
                cv2.line(img, self._pt(tx - k, ty - sx * k), self._pt(tx + k, ty + sx * k), col, 2, _AA, _SHIFT)
        if b.goal is not None:
            (lx, ly), (rx, ry) = b.goal
            cv2.line(img, self._pt(lx, ly), self._pt(rx, ry), col, 2, _AA, _SHIFT)
        for ox, oy in np.asarray(b.obstacles, dtype=np.float64).reshape(-1, 2):
            a, c2 = self._pt(ox - 0.05, oy - 0.05), self._pt(ox + 0.05, oy + 0.05)
            cv2.rectangle(img, a, c2, col, 1, _AA, _SHIFT)

    def _draw_overlay(self, img: np.ndarray, ov: Overlay) -> None:
        col = (int(ov.colour[0]), int(ov.colour[1]), int(ov.colour[2]))
        if ov.theta is None:
            self._disc(img, ov.x, ov.y, ov.radius, col)
        else:
            tip = (ov.x + ov.length * math.cos(ov.theta), ov.y + ov.length * math.sin(ov.theta))
            p0, p1 = self._ipt(ov.x, ov.y), self._ipt(*tip)
            cv2.arrowedLine(img, p0, p1, col, 2, _AA, 0, 0.3)
        if ov.label:
            c, r = self._ipt(ov.x, ov.y)
            self._text(img, ov.label, (c + 6, r - 6), col, 0.4)

    def _draw_header(self, img: Img, snap: WorldSnapshot, game: GameControlData | None) -> None:
        cols = self.scheme.team_colours
        x = 6
        for i, name in enumerate(self.team_names):
            cv2.rectangle(img, (x, 6), (x + 10, 16), tuple(cols[i]), -1)
            label = name if game is None else f"{name} {game.teams[i].score}"
            self._text(img, label, (x + 14, 16), _WHITE)
            x += 24 + cv2.getTextSize(label, _FONT, 0.45, 1)[0][0]
        line = f"t={snap.time:.1f}s"
        if game is not None:
            try:
                state = GameStateId(game.state).name
            except ValueError:
                state = f"STATE {game.state}"
            half = "1st" if game.first_half else "2nd"
            secs = int(game.secs_remaining)
            clock = f"{'-' if secs < 0 else ''}{abs(secs) // 60}:{abs(secs) % 60:02d}"
            line = f"{state}  {half} {clock}  {line}"
        self._text(img, line, (6, 34), _WHITE)


class VideoWriter:
    """Writes RGB frames to ``.mp4`` (cv2, ``mp4v`` codec) or ``.gif`` (:class:`~teamsim.video.GifStream`).

    The constructor checks at once that the file can be created (it creates missing parent
    directories and opens the file for appending, which leaves an existing file untouched), so
    a path that cannot be written fails before any frame is computed, with a
    :class:`~teamsim.video.VideoError` (an ``OSError``) naming the path and the reason. The
    first frame truncates the file; frames are streamed to disk as they come, so memory stays
    bounded by a few frames whatever the length of the video. GIF frames are shrunk by the
    integer factor ``gif_scale`` (default 2, 1 keeps full size) to keep files small, loop forever
    and last ``1 / fps`` s each (whole centiseconds, without cumulative drift); identical
    consecutive GIF frames are merged into one longer frame. A writer closed without any frame
    leaves no new file. After a failed :meth:`write` the file is left incomplete and :meth:`close`
    only releases it.
    """

    SUFFIXES = (".mp4", ".gif")

    def __init__(self, path: str | Path, fps: float = 15.0, gif_scale: int = 2) -> None:
        self.path = Path(path)
        suffix = self.path.suffix.lower()
        if suffix not in self.SUFFIXES:
            raise ValueError(f"video path must end in one of {self.SUFFIXES}, got {str(path)!r}")
        if not (math.isfinite(fps) and fps > 0):
            raise ValueError(f"fps must be a finite number > 0, got {fps!r}")
        if int(gif_scale) != gif_scale or gif_scale < 1:
            raise ValueError(f"gif_scale must be an integer >= 1, got {gif_scale!r}")
        self.fps = float(fps)
        self.gif_scale = int(gif_scale)
        self._gif = suffix == ".gif"
        self._shape: tuple[int, ...] | None = None
        self._cv: cv2.VideoWriter | None = None
        self._file: BinaryIO | None = None
        self._stream: GifStream | None = None
        self._opened = False  # the file was opened for writing (truncated)
        self._closed = False
        self._failed = False
        self.frame_count = 0
        """Frames written so far."""
        self._check_writable()

    def _check_writable(self) -> None:
        """Create the file (or open an existing one for appending) and close it again."""
        existed = os.path.lexists(self.path)
        where = f"cannot create video file {str(self.path)!r}"
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
        except FileExistsError as exc:  # the parent, or one above it, is a file
            raise VideoError(f"{where}: {str(exc.filename)!r} is not a directory") from exc
        except OSError as exc:
            raise VideoError(f"{where}: cannot create directory {str(exc.filename)!r}: {exc.strerror or exc}") from exc
        try:
            with self.path.open("ab"):
                pass
        except OSError as exc:
            raise VideoError(f"{where}: {exc.strerror or exc}") from exc
        if not existed:
            with contextlib.suppress(OSError):  # created again by the first frame
                self.path.unlink()

    def write(self, frame_rgb: np.ndarray) -> None:
        """Append one RGB ``uint8`` frame (H x W x 3), same shape as the first frame.

        Raises ``ValueError`` for a bad frame (nothing written) and :class:`~teamsim.video.VideoError`
        when the file cannot be written (the writer is then unusable; :meth:`close` releases it).
        """
        if self._closed:
            raise RuntimeError(f"VideoWriter for {self.path} is closed")
        if self._failed:
            raise VideoError(f"video {str(self.path)!r} failed earlier and takes no more frames")
        frame = np.asarray(frame_rgb)
        if frame.dtype != np.uint8 or frame.ndim != 3 or frame.shape[2] != 3:
            raise ValueError(f"frame must be uint8 H x W x 3, got {frame.dtype} {frame.shape}")
        shape = frame.shape
        if self._shape is not None and shape != self._shape:
            raise ValueError(f"frame shape {shape} differs from the first {self._shape}")
        try:
            if self._gif:
                k = self.gif_scale
                if k > 1:
                    size = (max(1, frame.shape[1] // k), max(1, frame.shape[0] // k))
                    frame = cv2.resize(frame, size, interpolation=cv2.INTER_AREA)
                if self._stream is None:
                    self._opened = True
                    self._file = self.path.open("wb")
                    self._stream = GifStream(self._file, self.fps)
                self._stream.add(frame)
            else:
                if self._cv is None:
                    self._open_mp4(frame.shape[1], frame.shape[0])
                assert self._cv is not None
                self._cv.write(cv2.cvtColor(frame, cv2.COLOR_RGB2BGR))
        except OSError as exc:
            self._failed = True
            if isinstance(exc, VideoError):
                raise
            reason = exc.strerror or str(exc)
            raise VideoError(f"writing video {str(self.path)!r} failed at frame {self.frame_count}: {reason}") from exc
        self._shape = shape
        self.frame_count += 1

    def _open_mp4(self, width: int, height: int) -> None:
        self._opened = True
        fourcc = cv2.VideoWriter_fourcc(*"mp4v")
        self._cv = cv2.VideoWriter(str(self.path), fourcc, self.fps, (width, height))
        if not self._cv.isOpened():
            self._cv = None
            raise VideoError(f"cv2 could not open an mp4v video writer ({width} x {height} px) for {str(self.path)!r}")

    def close(self) -> None:
        """Finish the file; further writes raise ``RuntimeError``. Safe to call twice.

        Raises :class:`~teamsim.video.VideoError` if the end of the file cannot be written; the
        file is released in any case.
        """
        if self._closed:
            return
        self._closed = True
        error: VideoError | None = None
        try:
            if self._stream is not None and not self._failed:
                self._stream.finish()
        except OSError as exc:
            error = VideoError(f"finishing video {str(self.path)!r} failed: {exc.strerror or exc}")
        if self._cv is not None:
            self._cv.release()
            self._cv = None
            if not self._failed and not (self.path.is_file() and self.path.stat().st_size > 0):
                error = VideoError(f"cv2 wrote nothing to {str(self.path)!r} ({self.frame_count} frames given)")
        if self._file is not None:
            try:
                self._file.close()
            except OSError as exc:  # flushing the buffer; after a failed write its error was raised already
                if not self._failed:
                    error = error or VideoError(f"finishing video {str(self.path)!r} failed: {exc.strerror or exc}")
            self._file = None
        self._stream = None
        if self.frame_count == 0 and self._opened:
            with contextlib.suppress(OSError):  # an empty file left behind is harmless
                self.path.unlink()
        if error is not None:
            raise error

    def __enter__(self) -> VideoWriter:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()
