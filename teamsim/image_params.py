"""Parameters of rendered camera images: the venue and the image effects.

Effects model the error sources of a real robot camera, in the order light takes: uneven
lighting of the hall (sun stripes from the windows, soft shadows, darker corners; fixed in
the world frame and rendered with the scene, see :func:`teamsim.image_venue.light_map`), lens
vignetting, motion blur while the shutter is open (head and body motion, the error source
the Darmstadt paper's adaptive observation model is built on, section IV.B), rolling-shutter
skew, then the sensor (exposure gain, white balance, noise) and 8-bit quantisation.

=======================  =================  ============  ==============================================
parameter                default            range         meaning
=======================  =================  ============  ==============================================
brightness               1.0                (0, 10]       global exposure gain (lighting of the venue)
brightness_jitter        0.05               [0, 2]        sigma of the per-image log-gain (auto exposure)
white_balance            (1.0, 1.0, 1.0)    (0, 10]       gains of the R, G, B channels (each)
white_balance_jitter     0.02               [0, 2]        sigma of the per-image log-gain of each channel
read_noise               2.0 DN             [0, 255]      sensor noise sigma at black (digital numbers)
shot_noise               0.08 DN            [0, 255]      variance per DN of signal: sigma^2 =
                                                          read_noise^2 + shot_noise * value
exposure                 0.008 s            [0, 0.2]      shutter time: motion blur = image speed x time
walking_shake            1.0 px             [0, 100]      extra blur length (px) while the legs move
rolling_shutter          0.0 s              [0, 0.001]    readout time per image row (0: global shutter)
vignetting               0.25               [0, 1)        relative brightness loss in the image corners
sun_stripes              0.3                [0, 2]        relative brightness gain in the middle of a sun
                                                          stripe on the floor (and on objects in it)
sun_stripe_width         0.6 m              (0, 10]       mean width of a sun stripe
sun_direction            0.5 rad            [-pi, pi]     direction the stripes run along (world frame,
                                                          from +x counter-clockwise)
shadows                  0.25               [0, 1)        relative brightness loss in the core of a soft
                                                          shadow
light_falloff            0.2                [0, 1)        relative brightness loss of the hall light at
                                                          the carpet's corners (none at the centre)
light_softness           0.1 m              [0, 5]        sigma of the blur of the stripes' edges (m);
                                                          shadows are four times as soft
light_tint               0.15               [0, 1]        colour of the light: a channel gain of l - 1
                                                          becomes (1 + t)(l - 1) in red and (1 - t)(l - 1)
                                                          in blue (warm sun, bluish shadow)
grass_texture            0.06               [0, 0.5]      amplitude of the carpet's brightness texture
venue_seed               0                  [0, 2^63-1]   seed of the procedural venue (walls, people)
=======================  =================  ============  ==============================================

Every value is checked against its range when the parameters are built
(:func:`cognition.params.check_ranges`).

Presets: ``ideal`` (no effect at all: the rendered scene exactly, deterministic and
noise-free, evenly lit), ``default`` (a hall lit unevenly as real ones are: sun stripes of
+30 %, shadows of -25 %, corners -20 %; NAO-like sensor) and ``harsh`` (dim, tinted light,
sun stripes of +60 %, shadows of -45 %, corners -35 %, strong noise and blur, rolling
shutter). The venue (``grass_texture``, ``venue_seed``) is part of the scene, not an effect:
it is the same in every preset; so is the layout of the stripes and shadows (drawn from
``venue_seed``), only their strengths differ.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import ClassVar

from teamsim.params import Range, Ranges, check_ranges, non_negative, positive


@dataclass(frozen=True)
class ImageParams:
    """Venue and image-effect parameters (see the module table); presets in ``PRESETS``."""

    brightness: float = 1.0
    """Global exposure gain (1: as rendered)."""
    brightness_jitter: float = 0.05
    """Sigma of the per-image change of the log exposure gain."""
    white_balance: tuple[float, float, float] = (1.0, 1.0, 1.0)
    """Gains of the red, green and blue channels."""
    white_balance_jitter: float = 0.02
    """Sigma of the per-image change of each channel's log gain."""
    read_noise: float = 2.0
    """Sensor noise sigma at black (digital numbers, 0..255 scale)."""
    shot_noise: float = 0.08
    """Signal-dependent noise: variance grows by this many DN^2 per DN of signal."""
    exposure: float = 0.008
    """Shutter time (s); the image moves ``rate * focal length * exposure`` pixels meanwhile."""
    walking_shake: float = 1.0
    """Extra blur length (px) while the robot walks."""
    rolling_shutter: float = 0.0
    """Readout time of one image row (s); 0 is a global shutter."""
    vignetting: float = 0.25
    """Relative brightness loss in the image corners (0: none, < 1)."""
    sun_stripes: float = 0.3
    """Relative brightness gain in the middle of a sun stripe (0: no sun)."""
    sun_stripe_width: float = 0.6
    """Mean width of a sun stripe on the floor (m)."""
    sun_direction: float = 0.5
    """Direction the sun stripes run along (world frame, rad from +x counter-clockwise)."""
    shadows: float = 0.25
    """Relative brightness loss in the core of a soft shadow (0: no shadows, < 1)."""
    light_falloff: float = 0.2
    """Relative brightness loss of the hall light at the carpet's corners (0: even, < 1)."""
    light_softness: float = 0.1
    """Sigma of the blur of the sun stripes' edges (m; shadows: four times this)."""
    light_tint: float = 0.15
    """Colour of the uneven light: warm where brighter, bluish where darker (0: grey)."""
    grass_texture: float = 0.06
    """Relative amplitude of the carpet's brightness texture (0: flat colour, <= 0.5)."""
    venue_seed: int = 0
    """Seed of the procedural venue beyond the field (walls, boards, spectators)."""

    PRESETS: ClassVar[dict[str, ImageParams]]

    RANGES: ClassVar[Ranges] = {
        "brightness": positive(10.0),
        "brightness_jitter": non_negative(2.0),
        "white_balance": positive(10.0),
        "white_balance_jitter": non_negative(2.0),
        "read_noise": non_negative(255.0),
        "shot_noise": non_negative(255.0),
        "exposure": non_negative(0.2),
        "walking_shake": non_negative(100.0),
        "rolling_shutter": non_negative(1e-3),
        "vignetting": Range(0.0, 1.0, high_open=True),
        "sun_stripes": non_negative(2.0),
        "sun_stripe_width": positive(10.0),
        "sun_direction": Range(-math.pi, math.pi),
        "shadows": Range(0.0, 1.0, high_open=True),
        "light_falloff": Range(0.0, 1.0, high_open=True),
        "light_softness": non_negative(5.0),
        "light_tint": non_negative(1.0),
        "grass_texture": non_negative(0.5),
        "venue_seed": Range(0, 2**63 - 1),
    }

    def __post_init__(self) -> None:
        check_ranges(self)

    @classmethod
    def preset(cls, name: str) -> ImageParams:
        """A named preset: ``ideal``, ``default`` or ``harsh``."""
        if name not in cls.PRESETS:
            raise ValueError(f"unknown ImageParams preset {name!r}; valid presets: {sorted(cls.PRESETS)}")
        return cls.PRESETS[name]

    @property
    def has_illumination(self) -> bool:
        """True when the hall is lit unevenly (sun stripes, shadows or a falloff to the corners)."""
        return self.sun_stripes > 0.0 or self.shadows > 0.0 or self.light_falloff > 0.0

    @property
    def has_effects(self) -> bool:
        """False when the image is exactly the rendered scene (the ``ideal`` preset)."""
        return self.has_illumination or not (
            self.brightness == 1.0
            and self.brightness_jitter == 0.0
            and self.white_balance == (1.0, 1.0, 1.0)
            and self.white_balance_jitter == 0.0
            and self.read_noise == 0.0
            and self.shot_noise == 0.0
            and self.exposure == 0.0
            and self.walking_shake == 0.0
            and self.rolling_shutter == 0.0
            and self.vignetting == 0.0
        )


ImageParams.PRESETS = {
    "ideal": ImageParams(
        brightness_jitter=0.0,
        white_balance_jitter=0.0,
        read_noise=0.0,
        shot_noise=0.0,
        exposure=0.0,
        walking_shake=0.0,
        vignetting=0.0,
        sun_stripes=0.0,
        shadows=0.0,
        light_falloff=0.0,
    ),
    "default": ImageParams(),
    "harsh": replace(
        ImageParams(),
        brightness=0.75,
        brightness_jitter=0.15,
        white_balance=(1.08, 1.0, 0.88),
        white_balance_jitter=0.06,
        read_noise=5.0,
        shot_noise=0.3,
        exposure=0.025,
        walking_shake=3.0,
        rolling_shutter=30e-6,
        vignetting=0.5,
        sun_stripes=0.6,
        shadows=0.45,
        light_falloff=0.35,
        light_tint=0.25,
    ),
}
