"""Colour classification: HSV thresholds, automatic green calibration and a lookup table.

Implements DNT sections 3.1 and 3.5 (Table 1): pixels are classified in HSV, where the hue
carries the colour and does not change with the light. Table 1's saturation and value
bounds are the defaults (green and goal colours need saturation >= 100, white at most 60,
white and colours a minimum value); its hue numbers are not usable as published (they
place green at 20-37, which is yellow-orange in every HSV convention), so the hue ranges
here are those of the rendered and real SPL colours in OpenCV's 8-bit convention (hue
0..179, i.e. degrees / 2; saturation and value 0..255).

**Automatic calibration.** Exposure and white balance change from image to image (auto
exposure, the ``harsh`` image effects, halls lit unevenly), so fixed value thresholds fail.
Before classifying, :class:`ColourClassifier` samples the image below the horizon on a sparse
grid, takes the pixels whose hue and saturation are plausibly carpet, and sets every
threshold relative to their medians: the green hue window around the median hue, the
minimum green value and the darkest "white" relative to the median carpet value, "black"
as darker than a fraction of it. The thresholds are quantized, and one lookup table per
quantized calibration is built once and cached.

**Fast path.** The classification of a pixel is one lookup in a table indexed by its
RGB value quantized to 5 bits per channel (32 Kb, in the first-level cache), compiled with
numba; a 320 x 240 image takes about 0.04 ms.

=====================  ==============  ==========  ===========================================
ColourParams           default         range       meaning
=====================  ==============  ==========  ===========================================
green_hue              (45, 90)        [0, 179]    hue window searched for the carpet
green_hue_width        14              [1, 45]     half-width of the calibrated green hue window
min_saturation         100             [0, 255]    minimum saturation of colours (Table 1)
white_max_saturation   70              [0, 255]    maximum saturation of white (Table 1: 60)
white_value            1.08            [0, 3]      white needs value >= this x the carpet's median
green_value            0.35            [0, 1]      green needs value >= this x the carpet's median
black_value            0.45            [0, 1]      black is value <= this x the carpet's median
colour_value           0.45            [0, 1]      colours need value >= this x the carpet's median
orange_hue             (3, 20)         [0, 179]    hue window of the classic ball
yellow_hue             (21, 38)        [0, 179]    hue window of yellow goals
blue_hue               (95, 130)       [0, 179]    hue window of blue (jerseys, KidSize goal)
red_hue                (165, 2)        [0, 179]    hue window of red jerseys (wraps past 179)
default_green          (68, 230, 130)  [0, 255]    carpet (hue, saturation, value) used when
                                                   calibration finds too few carpet pixels
pale_saturation        0.6             [0, 1]      carpet-hued pixels this much paler than the carpet ...
pale_value             1.12            [0, 3]      ... and this much brighter are white: the blend of a
                                                   thin or blurred line with the carpet around it
=====================  ==============  ==========  ===========================================
"""

from __future__ import annotations

import math
from collections import OrderedDict
from dataclasses import dataclass
from enum import IntEnum
from typing import ClassVar

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.camera import CameraMatrix
from cognition.params import Range, Ranges, check_ranges
from cognition.vision.projection import horizon_row_nb


class Colour(IntEnum):
    """Colour class codes of a class image (``uint8``)."""

    OTHER = 0
    """Anything not classified (hall, robots' grey parts, shadows)."""
    GREEN = 1
    """Field carpet."""
    WHITE = 2
    """Lines, modern goals, modern ball, robot bodies."""
    BLACK = 3
    """Dark: the modern ball's patches, robot joints."""
    ORANGE = 4
    """The classic ball."""
    YELLOW = 5
    """Classic and KidSize goals."""
    BLUE = 6
    """KidSize goal, jerseys."""
    RED = 7
    """Jerseys."""


_HUE = Range(0, 179)
_LEVEL = Range(0, 255)


@dataclass(frozen=True)
class ColourParams:
    """Thresholds of the colour classes (module table; hue 0..179, saturation/value 0..255)."""

    green_hue: tuple[int, int] = (45, 90)
    green_hue_width: int = 14
    min_saturation: int = 100
    white_max_saturation: int = 70
    white_value: float = 1.08
    green_value: float = 0.35
    black_value: float = 0.45
    colour_value: float = 0.45
    orange_hue: tuple[int, int] = (3, 20)
    yellow_hue: tuple[int, int] = (21, 38)
    blue_hue: tuple[int, int] = (95, 130)
    red_hue: tuple[int, int] = (165, 2)
    default_green: tuple[int, int, int] = (68, 230, 130)
    pale_saturation: float = 0.6
    pale_value: float = 1.12

    RANGES: ClassVar[Ranges] = {
        "green_hue": _HUE,
        "green_hue_width": Range(1, 45),
        "min_saturation": _LEVEL,
        "white_max_saturation": _LEVEL,
        "white_value": Range(0.0, 3.0),
        "green_value": Range(0.0, 1.0),
        "black_value": Range(0.0, 1.0),
        "colour_value": Range(0.0, 1.0),
        "orange_hue": _HUE,
        "yellow_hue": _HUE,
        "blue_hue": _HUE,
        "red_hue": _HUE,
        "default_green": _LEVEL,
        "pale_saturation": Range(0.0, 1.0),
        "pale_value": Range(0.0, 3.0),
    }

    def __post_init__(self) -> None:
        check_ranges(self)


@dataclass(frozen=True)
class Calibration:
    """The carpet's median colour in one image (hue 0..179, saturation and value 0..255)."""

    hue: int
    saturation: int
    value: int
    samples: int
    """Carpet pixels the medians come from (0: the defaults were used)."""


_CALIBRATION_STEP = 12
"""Grid spacing (px at 320 x 240, scaled with the width) of the calibration samples."""
_MIN_SAMPLES = 24
"""Fewer carpet samples than this: keep the previous (or default) calibration."""
_NO_CAMERA = np.full(18, np.nan)
"""Camera row of "no camera matrix": calibrate on the whole image."""
_CACHE = 64
"""Lookup tables kept per classifier (one per quantized calibration)."""


def camera_row(camera: CameraMatrix | NDArray[np.float64] | None) -> NDArray[np.float64]:
    """The compact camera row of a camera matrix (a row passes through; ``None``: all NaN)."""
    if camera is None:
        return _NO_CAMERA
    if isinstance(camera, CameraMatrix):
        return camera.as_row()
    return camera


class ColourClassifier:
    """Classifies RGB images into :class:`Colour` codes, calibrated per image (module docstring)."""

    def __init__(self, params: ColourParams | None = None):
        self.params = params or ColourParams()
        h, s, v = self.params.default_green
        self.calibration = Calibration(h, s, v, 0)
        """The latest calibration (the defaults until an image had enough carpet)."""
        self._luts: OrderedDict[tuple[int, int, int], NDArray[np.uint8]] = OrderedDict()

    def calibrate(self, rgb: NDArray[np.uint8], camera: CameraMatrix | NDArray[np.float64] | None) -> Calibration:
        """Measure the carpet colour below the horizon of ``rgb`` (H x W x 3) and keep it.

        ``camera`` is the image's camera matrix or its row (:meth:`CameraMatrix.as_row`);
        ``None`` calibrates on the whole image."""
        width = rgb.shape[1]
        cam = camera_row(camera)
        step = max(2, round(_CALIBRATION_STEP * width / 320))
        lo, hi = self.params.green_hue
        h, s, v, n = _carpet_median(rgb, cam, step, lo, hi, 60.0)
        if n >= _MIN_SAMPLES:
            self.calibration = Calibration(int(h), int(s), int(v), n)
        return self.calibration

    def lut(self, calibration: Calibration | None = None) -> NDArray[np.uint8]:
        """The lookup table (32768 entries, index r>>3 << 10 | g>>3 << 5 | b>>3) of a calibration."""
        c = calibration or self.calibration
        key = (c.hue, c.saturation // 16, c.value // 8)
        table = self._luts.get(key)
        if table is None:
            table = np.empty(32768, dtype=np.uint8)
            _build_lut(self.thresholds(key), table)
            self._luts[key] = table
            if len(self._luts) > _CACHE:
                self._luts.popitem(last=False)
        else:
            self._luts.move_to_end(key)
        return table

    def class_of(self, rgb: tuple[int, int, int]) -> int:
        """The class of one RGB colour (0..255 each) under the default calibration: how vision
        sees a colour scheme's nominal colours (goals, jerseys)."""
        h, s, v = self.params.default_green
        r, g, b = (min(255, max(0, int(c))) for c in rgb)
        return int(self.lut(Calibration(h, s, v, 0))[((r >> 3) << 10) | ((g >> 3) << 5) | (b >> 3)])

    def thresholds(self, key: tuple[int, int, int]) -> NDArray[np.float64]:
        """The threshold vector of a quantized calibration (hue, saturation // 16, value // 8)."""
        p = self.params
        hue, sat, val = key[0], key[1] * 16 + 8, key[2] * 8 + 4
        w = p.green_hue_width
        return np.array(
            [
                hue - w, hue + w, max(40.0, 0.45 * sat), max(16.0, p.green_value * val),
                p.white_max_saturation, max(60.0, p.white_value * val), max(24.0, p.black_value * val),
                p.min_saturation, max(24.0, p.colour_value * val),
                *p.orange_hue, *p.yellow_hue, *p.blue_hue, *p.red_hue,
                p.pale_saturation * sat, p.pale_value * val,
            ],
            dtype=np.float64,
        )  # fmt: skip

    def classify(
        self,
        rgb: NDArray[np.uint8],
        camera: CameraMatrix | NDArray[np.float64] | None = None,
        out: NDArray[np.uint8] | None = None,
    ) -> NDArray[np.uint8]:
        """Calibrate on ``rgb`` (H x W x 3 uint8) and return its class image (H x W uint8; ``out``
        when that is a C-contiguous array of that shape)."""
        rgb = np.ascontiguousarray(rgb)
        self.calibrate(rgb, camera)
        if out is None or not out.flags.c_contiguous:
            out = np.empty(rgb.shape[:2], dtype=np.uint8)
        _classify(rgb, self.lut(), out)
        return out


@nb.njit(cache=True, error_model="python", fastmath=False)
def _hsv(r: float, g: float, b: float) -> tuple[float, float, float]:  # pragma: no cover - compiled
    """OpenCV 8-bit HSV of an RGB colour: hue 0..180 (degrees / 2), saturation and value 0..255."""
    mx = max(r, g, b)
    mn = min(r, g, b)
    d = mx - mn
    s = 0.0 if mx <= 0.0 else 255.0 * d / mx
    if d <= 0.0:
        return 0.0, s, mx
    if mx == r:
        h = 60.0 * (g - b) / d
    elif mx == g:
        h = 120.0 + 60.0 * (b - r) / d
    else:
        h = 240.0 + 60.0 * (r - g) / d
    if h < 0.0:
        h += 360.0
    return 0.5 * h, s, mx


@nb.njit(cache=True, error_model="python", fastmath=False)
def _in_hue(h: float, lo: float, hi: float) -> bool:  # pragma: no cover - compiled
    """Hue inside [lo, hi], wrapping past 180 when lo > hi."""
    if lo <= hi:
        return lo <= h <= hi
    return h >= lo or h <= hi


@nb.njit(cache=True, error_model="python", fastmath=False)
def _class_of(h: float, s: float, v: float, t: NDArray[np.float64]) -> int:  # pragma: no cover - compiled
    """The colour class of one HSV colour under thresholds ``t`` (layout of ``thresholds``)."""
    in_green = _in_hue(h, t[0], t[1])
    if in_green and s >= t[2] and v >= t[3]:
        return 1
    if in_green and s <= t[17] and v >= t[18]:
        return 2  # a white line blended with the carpet
    if v <= t[6]:
        return 3
    if s <= t[4] and v >= t[5]:
        return 2
    if s >= t[7] and v >= t[8]:
        if _in_hue(h, t[9], t[10]):
            return 4
        if _in_hue(h, t[11], t[12]):
            return 5
        if _in_hue(h, t[13], t[14]):
            return 6
        if _in_hue(h, t[15], t[16]):
            return 7
    return 0


@nb.njit(cache=True, error_model="python", fastmath=False)
def _build_lut(t: NDArray[np.float64], table: NDArray[np.uint8]) -> None:  # pragma: no cover - compiled
    for r in range(32):
        for g in range(32):
            for b in range(32):
                h, s, v = _hsv(r * 8.0 + 4.0, g * 8.0 + 4.0, b * 8.0 + 4.0)
                table[(r << 10) | (g << 5) | b] = _class_of(h, s, v, t)


_CHUNK = 256
"""Pixels classified per pass of :func:`_classify` (their table indices fit the first-level cache)."""


@nb.njit(cache=True, error_model="python", fastmath=False)
def _classify(rgb: NDArray[np.uint8], table: NDArray[np.uint8], out: NDArray[np.uint8]) -> None:  # pragma: no cover
    """``out`` (H x W) = ``table`` at the quantized colour of each pixel of ``rgb`` (H x W x 3);
    both C-contiguous, walked as flat arrays. Chunk by chunk, the table indices are computed
    first (16-bit arithmetic without lookups, which the compiler vectorizes) and looked up in a
    second loop: a third faster than computing and looking up pixel by pixel."""
    f = rgb.reshape(-1)
    o = out.reshape(-1)
    n = o.shape[0]
    idx = np.empty(_CHUNK, dtype=np.uint16)
    for s in range(0, n, _CHUNK):
        m = min(_CHUNK, n - s)
        c = f[3 * s : 3 * (s + m)]
        for k in range(m):
            r, g, b = np.uint16(c[3 * k]), np.uint16(c[3 * k + 1]), np.uint16(c[3 * k + 2])
            idx[k] = ((r & 0xF8) << 7) | ((g & 0xF8) << 2) | (b >> 3)
        p = o[s : s + m]
        for k in range(m):
            p[k] = table[idx[k]]


@nb.njit(cache=True, error_model="python", fastmath=False)
def _median_of_histogram(hist: NDArray[np.int64], n: int) -> float:  # pragma: no cover - compiled
    """The median bin of a histogram holding ``n`` counts (the lower median for even ``n``)."""
    half = (n + 1) // 2
    total = 0
    for b in range(hist.shape[0]):
        total += hist[b]
        if total >= half:
            return float(b)
    return float(hist.shape[0] - 1)


@nb.njit(cache=True, error_model="python", fastmath=False)
def _carpet_median(
    rgb: NDArray[np.uint8], cam: NDArray[np.float64], step: int, lo: float, hi: float, min_sat: float
) -> tuple[float, float, float, int]:  # pragma: no cover - compiled
    """Medians (hue, saturation, value; whole units) and count of the grid pixels below the
    horizon whose hue is in [lo, hi] with saturation >= min_sat (histograms, no sorting)."""
    height, width = rgb.shape[0], rgb.shape[1]
    top = 0
    if math.isfinite(cam[0]):
        hz = max(horizon_row_nb(cam, 0.0), horizon_row_nb(cam, float(width)))
        if math.isfinite(hz):
            top = int(min(max(hz + 2.0, 0.0), height - 1.0))
    hh = np.zeros(181, dtype=np.int64)
    hs = np.zeros(256, dtype=np.int64)
    hv = np.zeros(256, dtype=np.int64)
    n = 0
    for j in range(top + step // 2, height, step):
        for i in range(step // 2, width, step):
            h, s, v = _hsv(float(rgb[j, i, 0]), float(rgb[j, i, 1]), float(rgb[j, i, 2]))
            if lo <= h <= hi and s >= min_sat and v >= 12.0:
                hh[int(h)] += 1
                hs[int(s)] += 1
                hv[int(v)] += 1
                n += 1
    if n == 0:
        return 0.0, 0.0, 0.0, 0
    return _median_of_histogram(hh, n), _median_of_histogram(hs, n), _median_of_histogram(hv, n), n
