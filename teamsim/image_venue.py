"""The static world of rendered camera images: paint on the carpet, the hall, the colours.

Everything here is built once per renderer (it depends on the field, the colour scheme and
:class:`~teamsim.image_params.ImageParams`, never on the match state) and handed to the
compiled kernel in :mod:`teamsim.image_kernel` as packed arrays:

* ``strips`` (N x 8): straight paint in the world frame (m): start ``a``, unit direction
  ``e``, unit normal ``n``, length, half width. Field lines are lengthened by half a line
  width at both ends so that corners are filled; penalty marks and the centre mark are
  crosses of two short strips.
* ``circles`` (N x 4): the centre circle as an annulus: centre, radius of the line centre,
  half width (m).
* ``floor``: a smooth brightness texture (factor around 1) over the hall floor, texel
  :data:`FLOOR_TEXEL`, origin at the hall corner (-x, -y); with uneven illumination
  multiplied by the light map.
* ``light``: the illumination of the hall floor (:func:`light_map`, a gain around 1 on the
  grid of ``floor``): sun stripes from the windows, soft shadows, the hall light falling off
  toward the corners. It is fixed in the world frame and lights the floor, the paint and
  the objects standing on it (each by the light at its foot point).
* ``walls``: the hall's walls unrolled into one RGB texture (packed ``0x00BBGGRR``), texel
  :data:`WALL_TEXEL`: the column is the distance along the perimeter, counter-clockwise
  from the corner (-x, -y) (first the wall at -y, then +x, +y, -x); the row is the height
  above the floor, row 0 at the top of the wall. Advertising boards in saturated colours
  (orange, yellow, white among them, to fool colour classifiers), spectators in coloured
  clothes, a bright window band.
* ``colours`` (N x 3, float32 RGB 0..255) indexed by :class:`C`, and ``geo`` (float64)
  indexed by :class:`GEO`.

The hall: a floor of :data:`HALL_MARGIN` metres around the carpet (field plus border strip),
walls :data:`WALL_HEIGHT` high, a dark ceiling above.
"""

from __future__ import annotations

from enum import IntEnum

import cv2
import numpy as np
from numpy.typing import NDArray

from cognition.field import ColourScheme, Field
from teamsim.image_params import ImageParams

HALL_MARGIN = 1.5
"""Floor between the carpet's edge and the walls (m)."""
WALL_HEIGHT = 3.0
"""Height of the hall's walls (m)."""
FLOOR_TEXEL = 0.05
"""Texel size of the floor brightness texture (m); larger for huge fields (see MAX_TEXELS)."""
WALL_TEXEL = 0.02
"""Texel size of the wall texture (m); larger for huge fields (see MAX_TEXELS)."""
MAX_TEXELS = 1 << 22
"""Largest texture (texels): a bigger hall gets coarser texels instead of more memory."""
POLE_HEIGHT = 0.9
"""Height of a corner pole (m)."""
NET_SPACING = 0.1
"""Mesh width of the goal nets (m)."""

FLOOR_RGB = (92, 92, 98)
CEILING_RGB = (48, 48, 56)
BODY_RGB = (215, 215, 218)
JOINT_RGB = (80, 80, 88)
VISOR_RGB = (30, 30, 36)
NET_RGB = (235, 235, 235)


class C(IntEnum):
    """Rows of the packed colour table."""

    GREEN = 0
    FLOOR = 1
    WHITE = 2
    GOAL_NEG = 3
    """Goal at -x of the world frame."""
    GOAL_POS = 4
    BALL_A = 5
    BALL_B = 6
    TEAM0 = 7
    TEAM1 = 8
    BODY = 9
    JOINT = 10
    VISOR = 11
    CEILING = 12
    NET = 13


class GEO(IntEnum):
    """Entries of the packed geometry vector (m)."""

    NECK = 0
    CARPET_X = 1
    """Half length of the carpet (field plus border strip)."""
    CARPET_Y = 2
    HALL_X = 3
    """Half length of the hall (walls at +-HALL_X)."""
    HALL_Y = 4
    WALL_H = 5
    POST_R = 6
    GOAL_H = 7
    GOAL_DEPTH = 8
    GOAL_HALF_W = 9
    """Half of the inner goal width plus a post radius: the posts' centres."""
    HALF_LENGTH = 10
    BALL_R = 11
    POLE_R = 12
    POLE_H = 13
    FLOOR_TEXEL = 14
    WALL_TEXEL = 15
    NET_SPACING = 16
    GRASS = 17
    """1 if the floor texture is used, 0 for a flat carpet."""
    MODERN_BALL = 18
    """1 for a ball with black patches, 0 for a single colour."""
    LIT = 19
    """1 if the floor texture holds the illumination (sampled bilinearly), 0 if not (nearest texel)."""
    TINT = 20
    """Colour of the uneven light (``ImageParams.light_tint``): a gain l gives red 1 + (1 + t)(l - 1),
    green l, blue 1 + (1 - t)(l - 1)."""


N_GEO = len(GEO)


def paint_strips(field: Field) -> NDArray[np.float64]:
    """Straight paint of ``field`` as strips (rows: ax, ay, ex, ey, nx, ny, length, half width)."""
    d = field.dims
    hw = d.line_width / 2
    rows: list[list[float]] = []

    def strip(x1: float, y1: float, x2: float, y2: float, extend: float) -> None:
        length = float(np.hypot(x2 - x1, y2 - y1))
        ex, ey = (x2 - x1) / length, (y2 - y1) / length
        rows.append([x1 - ex * extend, y1 - ey * extend, ex, ey, -ey, ex, length + 2 * extend, hw])

    for s in field.lines:
        strip(s.x1, s.y1, s.x2, s.y2, hw)
    half = d.penalty_mark_size / 2
    for m in field.penalty_marks:
        strip(m.x - half, m.y, m.x + half, m.y, 0.0)
        strip(m.x, m.y - half, m.x, m.y + half, 0.0)
    if d.centre_mark:
        c = field.centre_circle
        strip(c.x - half, c.y, c.x + half, c.y, 0.0)
    return np.asarray(rows, dtype=np.float64).reshape(-1, 8)


def paint_circles(field: Field) -> NDArray[np.float64]:
    """The centre circle as an annulus row (cx, cy, radius, half width)."""
    c = field.centre_circle
    return np.array([[c.x, c.y, c.radius, field.dims.line_width / 2]], dtype=np.float64)


def hall_size(field: Field) -> tuple[float, float]:
    """Half length and half width of the hall (m, walls at +-x and +-y)."""
    b = field.dims.border_strip + HALL_MARGIN
    return field.half_length + b, field.half_width + b


def _texel_size(area: float, nominal: float) -> float:
    """``nominal`` texel size (m), or larger so that ``area`` (m^2) needs at most MAX_TEXELS."""
    return max(nominal, float(np.sqrt(area / MAX_TEXELS)))


def floor_texel(field: Field) -> float:
    """Texel size (m) of the floor texture of ``field``'s hall."""
    hx, hy = hall_size(field)
    return _texel_size(4 * hx * hy, FLOOR_TEXEL)


def wall_texel(field: Field) -> float:
    """Texel size (m) of the wall texture of ``field``'s hall."""
    hx, hy = hall_size(field)
    return _texel_size(4 * (hx + hy) * WALL_HEIGHT, WALL_TEXEL)


def floor_texture(field: Field, amplitude: float, seed: int) -> NDArray[np.float32]:
    """Smooth brightness factors (mean 1, about +-``amplitude``) over the hall floor.

    Texels of :func:`floor_texel` metres; a 1 x 1 texture when ``amplitude`` is 0.
    """
    hx, hy = hall_size(field)
    texel = floor_texel(field)
    w, h = int(np.ceil(2 * hx / texel)) + 2, int(np.ceil(2 * hy / texel)) + 2
    if amplitude <= 0.0:
        return np.ones((1, 1), dtype=np.float32)
    rng = np.random.default_rng([seed, 1])
    tex = np.zeros((h, w), dtype=np.float32)
    for scale, weight in ((0.15, 0.5), (0.6, 0.35), (2.0, 0.15)):
        n = rng.standard_normal((h, w)).astype(np.float32)
        s = scale / texel
        n = cv2.GaussianBlur(n, (0, 0), sigmaX=s, sigmaY=s, borderType=cv2.BORDER_REFLECT)
        tex += weight * n / max(float(n.std()), 1e-6)
    # faint stripes across the carpet, as rolls of artificial turf show
    xs = (np.arange(w) + 0.5) * texel - hx
    tex += 0.6 * np.sign(np.sin(np.pi * xs / 1.0))[None, :].astype(np.float32)
    tex /= max(float(np.abs(tex).max()), 1e-6)
    return (1.0 + amplitude * tex).astype(np.float32)


SHADOW_SOFTNESS = 4.0
"""Shadows are this many times as soft (blur sigma) as the sun stripes' edges."""
MIN_LIGHT = 0.05
"""Lowest gain of the light map (the far hall corners with a strong falloff)."""


def light_map(field: Field, params: ImageParams) -> NDArray[np.float32]:
    """The hall floor's illumination: a gain per texel (1: the nominal light), on the grid of
    :func:`floor_texture` (texels of :func:`floor_texel` m, origin at the hall corner (-x, -y),
    row = y, column = x). A 1 x 1 map of ones when ``params`` has no illumination.

    Three parts, multiplied (then at least :data:`MIN_LIGHT`):

    * **sun stripes**: parallel bands along ``sun_direction``, as low sun through a row of
      windows throws them; widths about ``sun_stripe_width`` (0.6 to 1.4 times), spaced about
      2.2 to 3.2 widths apart, each of a random length (half the hall to all of it) and
      strength (0.75 to 1 of ``sun_stripes``); edges blurred with sigma ``light_softness``;
    * **soft shadows**: about one per 10 m^2 of carpet, ellipses 0.3 to 1.2 m by 0.3 to 3 m
      centred on the carpet (roof beams, stands, people), each 0.6 to 1 of ``shadows`` deep,
      blurred with sigma :data:`SHADOW_SOFTNESS` ``light_softness``;
    * **falloff**: the hall light is brightest over the centre, the gain
      ``1 - light_falloff (a^2 + b^2 + a^2 b^2) / 3`` with a, b the position as fractions of
      the carpet's half length and half width: ``1 - light_falloff`` at the carpet's corners,
      a third of the loss in the middle of its edges.

    The layout comes from ``venue_seed`` alone (the same in every preset); the strengths
    scale it.
    """
    if not params.has_illumination:
        return np.ones((1, 1), dtype=np.float32)
    hx, hy = hall_size(field)
    kx, ky = field.half_length + field.dims.border_strip, field.half_width + field.dims.border_strip
    texel = floor_texel(field)
    w, h = int(np.ceil(2 * hx / texel)) + 2, int(np.ceil(2 * hy / texel)) + 2
    xs = ((np.arange(w) + 0.5) * texel - hx)[None, :]
    ys = ((np.arange(h) + 0.5) * texel - hy)[:, None]
    rng = np.random.default_rng([params.venue_seed, 3])
    gain = np.ones((h, w), dtype=np.float32)

    def blur(a: NDArray[np.float32], sigma: float) -> NDArray[np.float32]:
        s = sigma / texel
        return a if s < 0.05 else cv2.GaussianBlur(a, (0, 0), sigmaX=s, sigmaY=s, borderType=cv2.BORDER_REPLICATE)

    shift = 4  # fractional bits of the drawing coordinates

    def at(x: float, y: float) -> tuple[int, int]:  # a world point (m) as drawing coordinates (texel centres)
        return round(((x + hx) / texel - 0.5) * (1 << shift)), round(((y + hy) / texel - 0.5) * (1 << shift))

    # sun stripes: bands at coordinate q across them (along n), from p0 to p0 + length along e
    e = np.array([np.cos(params.sun_direction), np.sin(params.sun_direction)])
    n = np.array([-e[1], e[0]])
    reach = abs(hx * e[0]) + abs(hy * e[1]), abs(hx * e[1]) + abs(hy * e[0])  # the hall's half extents along e, n
    sun = np.zeros((h, w), dtype=np.float32)
    width = params.sun_stripe_width
    q = -reach[1] + float(rng.uniform(0.0, 3.0)) * width
    while q < reach[1] + width:  # bands do not overlap: the next starts at least 1.5 widths on
        wq = width * float(rng.uniform(0.6, 1.4))
        length = 2 * reach[0] * float(rng.uniform(0.5, 1.0))
        p0 = -reach[0] + float(rng.uniform(0.0, 2 * reach[0] - length))
        corners = [a * e + b * n for a, b in ((p0, q - wq / 2), (p0 + length, q - wq / 2), (p0 + length, q + wq / 2))]
        corners.append(p0 * e + (q + wq / 2) * n)
        poly = np.array([at(float(c[0]), float(c[1])) for c in corners], dtype=np.int32)
        cv2.fillPoly(sun, [poly], float(rng.uniform(0.75, 1.0)), cv2.LINE_8, shift)
        q += wq / 2 + width * float(rng.uniform(2.2, 3.2))
    gain *= 1.0 + params.sun_stripes * blur(sun, params.light_softness)
    # soft shadows, centred on the carpet; where they overlap the deepest counts (drawn last)
    shades = []
    for _ in range(max(1, round(4 * kx * ky / 10.0))):
        cx, cy = float(rng.uniform(-kx, kx)), float(rng.uniform(-ky, ky))
        a, b, th = float(rng.uniform(0.3, 1.2)), float(rng.uniform(0.3, 3.0)), float(rng.uniform(0.0, 180.0))
        shades.append((float(rng.uniform(0.6, 1.0)), cx, cy, a, b, th))
    dark = np.zeros((h, w), dtype=np.float32)
    scale = (1 << shift) / texel
    for depth, cx, cy, a, b, th in sorted(shades, key=lambda t: t[0]):
        axes = round(a * scale), round(b * scale)
        cv2.ellipse(dark, at(cx, cy), axes, th, 0.0, 360.0, depth, -1, cv2.LINE_8, shift)
    gain *= 1.0 - params.shadows * blur(dark, SHADOW_SOFTNESS * params.light_softness)
    # the hall light falls off toward the corners
    a2, b2 = (xs / kx) ** 2, (ys / ky) ** 2
    gain *= 1.0 - params.light_falloff * (a2 + b2 + a2 * b2) / 3.0
    return np.ascontiguousarray(np.maximum(gain, MIN_LIGHT), dtype=np.float32)


_BOARD_COLOURS = (
    (255, 120, 0), (250, 210, 0), (240, 240, 240), (0, 150, 60), (20, 60, 200), (200, 20, 30), (250, 140, 40),
    (30, 30, 30), (0, 170, 220), (255, 255, 255),
)  # fmt: skip
_CLOTHES = (
    (200, 30, 40), (30, 60, 200), (250, 200, 20), (255, 120, 0), (240, 240, 240), (40, 40, 40), (0, 140, 60),
    (120, 60, 160), (0, 180, 200), (250, 100, 150), (110, 80, 50),
)  # fmt: skip
_SKIN = ((230, 190, 160), (200, 150, 110), (140, 95, 65), (90, 60, 40))


def wall_texture(field: Field, seed: int) -> NDArray[np.uint32]:
    """The hall's walls unrolled (see the module docstring), packed 0x00BBGGRR."""
    hx, hy = hall_size(field)
    perimeter = 4 * (hx + hy)
    texel = wall_texel(field)
    w, h = int(np.ceil(perimeter / texel)), int(np.ceil(WALL_HEIGHT / texel))
    rng = np.random.default_rng([seed, 2])
    px = WALL_TEXEL / texel  # drawing sizes below are in nominal texels
    img = np.empty((h, w, 3), dtype=np.uint8)

    def row(z: float) -> int:
        return round((WALL_HEIGHT - z) / texel)

    def col(s: float) -> int:
        return round(s / texel)

    def n(k: float) -> int:
        return max(1, round(k * px))

    img[:] = (150, 150, 158)  # painted wall
    img[row(2.6) : row(2.2)] = (225, 230, 240)  # window band, bright
    for s in np.arange(0.0, perimeter, 1.6):
        img[row(2.6) : row(2.2), col(s) : col(s) + n(4)] = (90, 90, 96)  # window frames
    img[row(2.2) : row(0.9)] = (70, 65, 70)  # stands
    for _ in range(int(perimeter * 5)):  # spectators
        s, z = rng.uniform(0, perimeter), rng.uniform(1.0, 2.0)
        cloth = _CLOTHES[int(rng.integers(len(_CLOTHES)))]
        skin = _SKIN[int(rng.integers(len(_SKIN)))]
        x0, y0 = col(s), row(z)
        cv2.rectangle(img, (x0 - n(9), y0), (x0 + n(9), y0 + n(22)), cloth, -1)
        cv2.circle(img, (x0, y0 - n(7)), n(6), skin, -1)
    s = 0.0
    while s < perimeter:  # advertising boards
        length = float(rng.uniform(1.0, 3.0))
        colour = _BOARD_COLOURS[int(rng.integers(len(_BOARD_COLOURS)))]
        x0, x1 = col(s), col(min(s + length, perimeter))
        img[row(0.9) : row(0.1), x0:x1] = colour
        letter = (255, 255, 255) if sum(colour) < 500 else (20, 20, 20)
        for xl in range(x0 + n(10), x1 - n(20), n(24)):  # "lettering"
            if rng.random() < 0.8:
                img[row(0.65) : row(0.35), xl : xl + n(14)] = letter
        img[row(0.9) : row(0.1), x0 : x0 + n(2)] = (20, 20, 20)
        s += length
    img[row(0.1) :] = (40, 40, 44)  # skirting
    packed = img[..., 0].astype(np.uint32) | (img[..., 1].astype(np.uint32) << 8)
    packed |= img[..., 2].astype(np.uint32) << 16
    return np.ascontiguousarray(packed)


def colour_table(scheme: ColourScheme) -> NDArray[np.float32]:
    """The packed colour table (rows indexed by :class:`C`, RGB 0..255)."""
    rows = [None] * len(C)
    rows[C.GREEN] = scheme.field_green
    rows[C.FLOOR] = FLOOR_RGB
    rows[C.WHITE] = scheme.line_white
    rows[C.GOAL_NEG] = scheme.own_goal
    rows[C.GOAL_POS] = scheme.opponent_goal
    rows[C.BALL_A] = scheme.ball_primary
    rows[C.BALL_B] = scheme.ball_secondary
    rows[C.TEAM0] = scheme.team_colours[0]
    rows[C.TEAM1] = scheme.team_colours[1]
    rows[C.BODY] = BODY_RGB
    rows[C.JOINT] = JOINT_RGB
    rows[C.VISOR] = VISOR_RGB
    rows[C.CEILING] = CEILING_RGB
    rows[C.NET] = NET_RGB
    return np.asarray(rows, dtype=np.float32)


def geometry(
    field: Field, neck_height: float, grass: bool, lit: bool = False, tint: float = 0.0
) -> NDArray[np.float64]:
    """The packed geometry vector (entries indexed by :class:`GEO`). ``grass``: the floor has a
    texture; ``lit``: the floor texture holds the light map (and is used), whose colour is
    ``tint`` (see :class:`GEO`)."""
    d = field.dims
    hx, hy = hall_size(field)
    g = np.zeros(N_GEO)
    g[GEO.NECK] = neck_height
    g[GEO.CARPET_X] = field.half_length + d.border_strip
    g[GEO.CARPET_Y] = field.half_width + d.border_strip
    g[GEO.HALL_X], g[GEO.HALL_Y], g[GEO.WALL_H] = hx, hy, WALL_HEIGHT
    g[GEO.POST_R], g[GEO.GOAL_H], g[GEO.GOAL_DEPTH] = d.goal_post_diameter / 2, d.goal_height, d.goal_depth
    g[GEO.GOAL_HALF_W] = d.goal_inner_width / 2 + d.goal_post_diameter / 2
    g[GEO.HALF_LENGTH] = field.half_length
    g[GEO.BALL_R] = d.ball_diameter / 2
    g[GEO.POLE_R], g[GEO.POLE_H] = d.corner_pole_diameter / 2, POLE_HEIGHT
    g[GEO.FLOOR_TEXEL], g[GEO.WALL_TEXEL], g[GEO.NET_SPACING] = floor_texel(field), wall_texel(field), NET_SPACING
    g[GEO.GRASS] = 1.0 if grass or lit else 0.0
    g[GEO.LIT] = 1.0 if lit else 0.0
    g[GEO.TINT] = tint if lit else 0.0
    return g
