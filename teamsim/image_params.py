"""Parameters of rendered camera images: the venue and the image effects.

Effects model the error sources of a real robot camera, in the order light takes: lens
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
grass_texture            0.06               [0, 0.5]      amplitude of the carpet's brightness texture
venue_seed               0                  [0, 2^63-1]   seed of the procedural venue (walls, people)
=======================  =================  ============  ==============================================

Every value is checked against its range when the parameters are built
(:func:`cognition.params.check_ranges`).

Presets: ``ideal`` (no effect at all: the rendered scene exactly, deterministic and
noise-free), ``default`` (a well-lit hall, NAO-like sensor) and ``harsh`` (dim, tinted light,
strong noise and blur, rolling shutter). The venue (``grass_texture``, ``venue_seed``) is part
of the scene, not an effect: it is the same in every preset.
"""

from __future__ import annotations

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
    def has_effects(self) -> bool:
        """False when the image is exactly the rendered scene (the ``ideal`` preset)."""
        return not (
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
    ),
}
