"""Percepts drawn on a camera image, for people: debugging vision on rendered frames or logs.

:func:`draw_percepts` draws every percept of a :class:`~cognition.percepts.Percepts` on a copy
of an RGB image, one marker style per kind, so that a detection can be told from the
simulator's ground-truth annotations (:func:`teamsim.images.draw_annotations`, drawn thin) on
the same image. It needs nothing but the percepts: pixels that a log lacks (NaN) are found by
projecting the robot-frame positions with the percepts' camera matrix (on the ground, z = 0),
and percepts that have neither are skipped. :func:`percept_pixels` gives those pixels.

==========  =================  =============================================================
kind        colour (RGB)       marker
==========  =================  =============================================================
POST        (255, 0, 160)      2 px line from the base pixel to the top pixel (or 12 px up),
                               a triangle at the base, ``L`` / ``R`` / ``?`` at the top
CROSS       (255, 80, 0)       2 px diamond with ``L`` / ``T`` / ``X`` below right
LINE        (255, 215, 0)      2 px segment with a dot at each end
CIRCLE      (255, 140, 255)    the projected circle of ``circle_radius`` (1 px) and a star at
                               its centre
MARK        (255, 40, 40)      2 px square
BALL        (0, 230, 255)      2 px circle of the reported image radius (4 px if unknown) and
                               a dot at its centre
ROBOT       by team guess      2 px upward triangle at the feet, ``own`` / ``opp`` / ``?``;
                               own (60, 140, 255), opponent (255, 60, 60), unknown (200, 200, 200)
POLE        (0, 255, 140)      2 px line up from the base pixel and a triangle at the base
==========  =================  =============================================================

``scale`` multiplies every pixel (draw on an image enlarged by that factor, for legible
labels); line widths and marker sizes stay in output pixels.
"""

from __future__ import annotations

import math

import cv2
import numpy as np
from numpy.typing import NDArray

from cognition.camera import CameraMatrix
from cognition.percepts import Kind, Percepts, PostSide, RobotTeam

COLOURS: dict[Kind, tuple[int, int, int]] = {
    Kind.POST: (255, 0, 160),
    Kind.CROSS: (255, 80, 0),
    Kind.LINE: (255, 215, 0),
    Kind.CIRCLE: (255, 140, 255),
    Kind.MARK: (255, 40, 40),
    Kind.BALL: (0, 230, 255),
    Kind.POLE: (0, 255, 140),
}
"""Drawing colour (RGB) per kind (robots: :data:`TEAM_COLOURS`)."""
TEAM_COLOURS: dict[RobotTeam, tuple[int, int, int]] = {
    RobotTeam.OWN: (60, 140, 255),
    RobotTeam.OPPONENT: (255, 60, 60),
    RobotTeam.UNKNOWN: (200, 200, 200),
}
"""Drawing colour (RGB) of robot percepts by their team guess."""
_SIDE_LABEL = {PostSide.UNKNOWN: "?", PostSide.LEFT: "L", PostSide.RIGHT: "R"}
_TEAM_LABEL = {RobotTeam.UNKNOWN: "?", RobotTeam.OWN: "own", RobotTeam.OPPONENT: "opp"}
_AA = cv2.LINE_AA
_FONT = cv2.FONT_HERSHEY_SIMPLEX


def percept_pixels(percepts: Percepts, kind: Kind) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """First and second pixels (n x 2 each) of one kind's percepts.

    NaN pixels are replaced by the projection of the robot-frame point on the ground (second
    pixels: of ``x2, y2``; lines only) when the percepts carry a camera matrix; whatever stays
    NaN cannot be drawn.
    """
    t = percepts.table(kind)
    uv = t.uv.copy()
    uv2 = t.uv2.copy()
    cam = percepts.camera
    if cam is not None and len(t):
        _fill_missing(cam, uv, t.xy)
        if kind == Kind.LINE:
            _fill_missing(cam, uv2, t.xy2)
    return uv, uv2


def _fill_missing(cam: CameraMatrix, uv: NDArray[np.float64], xy: NDArray[np.float64]) -> None:
    missing = ~np.isfinite(uv).all(axis=1) & np.isfinite(xy).all(axis=1)
    if missing.any():
        pts = np.column_stack([xy[missing], np.zeros(int(missing.sum()))])
        uv[missing] = cam.project(pts)[0]


def _ok(*values: float) -> bool:
    return all(math.isfinite(v) and abs(v) < 1e6 for v in values)


def draw_percepts(
    rgb: NDArray[np.uint8], percepts: Percepts, scale: float = 1.0, circle_radius: float = 0.75
) -> NDArray[np.uint8]:
    """A copy of ``rgb`` (H x W x 3 uint8) with ``percepts`` drawn on it (module table).

    ``scale``: factor from the percepts' pixels to ``rgb``'s pixels (> 0); ``circle_radius``:
    radius (m) of the centre circle to draw around a circle percept (0: centre only).
    """
    a = np.asarray(rgb)
    if a.dtype != np.uint8 or a.ndim != 3 or a.shape[2] != 3:
        raise ValueError(f"draw_percepts expects an H x W x 3 uint8 RGB image, got {a.shape} {a.dtype}")
    if not isinstance(percepts, Percepts):
        raise TypeError(f"draw_percepts expects Percepts, got {type(percepts).__name__}")
    if not (math.isfinite(scale) and scale > 0.0):
        raise ValueError(f"scale must be a finite number > 0, got {scale!r}")
    out = np.ascontiguousarray(a).copy()

    def pt(u: float, v: float) -> tuple[int, int]:
        return round(u * scale), round(v * scale)

    def text(s: str, u: float, v: float, colour: tuple[int, int, int]) -> None:
        cv2.putText(out, s, (u, v), _FONT, 0.4, (0, 0, 0), 3, _AA)  # dark outline: readable on any colour
        cv2.putText(out, s, (u, v), _FONT, 0.4, colour, 1, _AA)

    uv, uv2 = percept_pixels(percepts, Kind.LINE)
    for (u1, v1), (u2, v2) in zip(uv, uv2, strict=True):
        if _ok(u1, v1, u2, v2):
            cv2.line(out, pt(u1, v1), pt(u2, v2), COLOURS[Kind.LINE], 2, _AA)
            for u, v in ((u1, v1), (u2, v2)):
                cv2.circle(out, pt(u, v), 3, COLOURS[Kind.LINE], -1, _AA)
    _draw_circles(out, percepts, scale, circle_radius)
    uv, _ = percept_pixels(percepts, Kind.CROSS)
    for (u, v), sub in zip(uv, percepts.crossings.subtype, strict=True):
        if _ok(u, v):
            p = pt(u, v)
            cv2.drawMarker(out, p, COLOURS[Kind.CROSS], cv2.MARKER_DIAMOND, 12, 2, _AA)
            text("LTX"[int(sub)] if 0 <= sub <= 2 else "?", p[0] + 6, p[1] + 14, COLOURS[Kind.CROSS])
    uv, _ = percept_pixels(percepts, Kind.MARK)
    for u, v in uv:
        if _ok(u, v):
            cv2.drawMarker(out, pt(u, v), COLOURS[Kind.MARK], cv2.MARKER_SQUARE, 10, 2, _AA)
    uv, uv2 = percept_pixels(percepts, Kind.POST)
    for (u, v), (ut, vt), side in zip(uv, uv2, percepts.posts.subtype, strict=True):
        if not _ok(u, v):
            continue
        base = pt(u, v)
        top = pt(ut, vt) if _ok(ut, vt) else (base[0], base[1] - 12)
        cv2.line(out, base, top, COLOURS[Kind.POST], 2, _AA)
        cv2.drawMarker(out, base, COLOURS[Kind.POST], cv2.MARKER_TRIANGLE_UP, 10, 2, _AA)
        label = _SIDE_LABEL[PostSide(side)] if 0 <= side <= 2 else "?"
        text(label, top[0] + 4, top[1] + 4, COLOURS[Kind.POST])
    uv, uv2 = percept_pixels(percepts, Kind.POLE)
    for (u, v), (ut, vt) in zip(uv, uv2, strict=True):
        if _ok(u, v):
            base = pt(u, v)
            top = pt(ut, vt) if _ok(ut, vt) else (base[0], base[1] - 12)
            cv2.line(out, base, top, COLOURS[Kind.POLE], 2, _AA)
            cv2.drawMarker(out, base, COLOURS[Kind.POLE], cv2.MARKER_TRIANGLE_UP, 10, 2, _AA)
    uv, _ = percept_pixels(percepts, Kind.ROBOT)
    for (u, v), team in zip(uv, percepts.robots.subtype, strict=True):
        if _ok(u, v):
            t = RobotTeam(team) if 0 <= team <= 2 else RobotTeam.UNKNOWN
            p = pt(u, v)
            cv2.drawMarker(out, p, TEAM_COLOURS[t], cv2.MARKER_TRIANGLE_UP, 14, 2, _AA)
            text(_TEAM_LABEL[t], p[0] + 8, p[1] + 4, TEAM_COLOURS[t])
    uv, _ = percept_pixels(percepts, Kind.BALL)
    for (u, v), r in zip(uv, percepts.ball.radius_px, strict=True):
        if _ok(u, v):
            radius = r if math.isfinite(r) and r > 0 else 4.0
            cv2.circle(out, pt(u, v), max(2, round(radius * scale)), COLOURS[Kind.BALL], 2, _AA)
            cv2.circle(out, pt(u, v), 2, COLOURS[Kind.BALL], -1, _AA)
    return out


def _draw_circles(out: NDArray[np.uint8], percepts: Percepts, scale: float, radius: float) -> None:
    """Circle percepts: a star at the centre's pixel and the ring of ``radius`` (m) projected."""
    t = percepts.circle
    uv, _ = percept_pixels(percepts, Kind.CIRCLE)
    cam = percepts.camera
    colour = COLOURS[Kind.CIRCLE]
    for k in range(len(t)):
        if cam is not None and radius > 0.0:
            a = np.linspace(0.0, 2.0 * math.pi, 97)
            ring = np.column_stack([t.x[k] + radius * np.cos(a), t.y[k] + radius * np.sin(a), np.zeros(len(a))])
            ring_uv, front = cam.project(ring)
            good = front & np.isfinite(ring_uv).all(axis=1) & (np.abs(ring_uv) < 1e5).all(axis=1)
            pts = np.round(np.where(good[:, None], ring_uv, 0.0) * scale).astype(np.int64)  # no NaN cast
            for j in range(len(a) - 1):  # only consecutive pairs in front of the camera
                if good[j] and good[j + 1]:
                    cv2.line(
                        out, (int(pts[j, 0]), int(pts[j, 1])), (int(pts[j + 1, 0]), int(pts[j + 1, 1])), colour, 1, _AA
                    )
        u, v = uv[k]
        if _ok(u, v):
            cv2.drawMarker(out, (round(u * scale), round(v * scale)), colour, cv2.MARKER_STAR, 12, 1, _AA)
