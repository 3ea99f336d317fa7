"""Parameters of rendered camera images: the venue and the image effects.

Effects model the error sources of a real robot camera, in the order light takes: lens
vignetting, motion blur while the shutter is open (head and body motion, the error source
the Darmstadt paper's adaptive observation model is built on, section IV.B), rolling-shutter
skew, then the sensor (exposure gain, white balance, noise) and 8-bit quantisation.

=======================  =================  ==============================================
parameter                default            meaning
=======================  =================  ==============================================
brightness               1.0                global exposure gain (lighting of the venue)
brightness_jitter        0.05               sigma of the per-image log-gain (auto exposure)
white_balance            (1.0, 1.0, 1.0)    gains of the R, G, B channels
white_balance_jitter     0.02               sigma of the per-image log-gain of each channel
read_noise               2.0 DN             sensor noise sigma at black (digital numbers)
shot_noise               0.08 DN            variance per DN of signal: sigma^2 =
                                            read_noise^2 + shot_noise * value
exposure                 0.008 s            shutter time: motion blur = image speed x time
walking_shake            1.0 px             extra blur length (px) while the legs move
rolling_shutter          0.0 s              readout time per image row (0: global shutter)
vignetting               0.25               relative brightness loss in the image corners
grass_texture            0.06               amplitude of the carpet's brightness texture
venue_seed               0                  seed of the procedural venue (walls, people)
=======================  =================  ==============================================

Presets: ``ideal`` (no effect at all: the rendered scene exactly, deterministic and
noise-free), ``default`` (a well-lit hall, NAO-like sensor) and ``harsh`` (dim, tinted light,
strong noise and blur, rolling shutter). The venue (``grass_texture``, ``venue_seed``) is part
of the scene, not an effect: it is the same in every preset.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import ClassVar

from teamsim.params import check_non_negative, check_positive


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

    def __post_init__(self) -> None:
        o = "ImageParams"
        check_positive(o, brightness=self.brightness)
        check_non_negative(
            o,
            brightness_jitter=self.brightness_jitter,
            white_balance_jitter=self.white_balance_jitter,
            read_noise=self.read_noise,
            shot_noise=self.shot_noise,
            exposure=self.exposure,
            walking_shake=self.walking_shake,
            rolling_shutter=self.rolling_shutter,
            vignetting=self.vignetting,
            grass_texture=self.grass_texture,
        )
        wb = self.white_balance
        if isinstance(wb, list):
            object.__setattr__(self, "white_balance", wb := tuple(wb))
        if not isinstance(wb, tuple) or len(wb) != 3:
            raise ValueError(f"ImageParams.white_balance must be three channel gains (r, g, b), got {wb!r}")
        check_positive(o, **{f"white_balance[{i}]": g for i, g in enumerate(wb)})
        if self.vignetting >= 1.0:
            raise ValueError(f"ImageParams.vignetting must be < 1, got {self.vignetting!r}")
        if self.grass_texture > 0.5:
            raise ValueError(f"ImageParams.grass_texture must be <= 0.5, got {self.grass_texture!r}")
        if self.exposure > 0.2 or self.rolling_shutter > 1e-3:
            raise ValueError(
                "ImageParams.exposure must be <= 0.2 s and rolling_shutter <= 1 ms per row, "
                f"got {self.exposure!r} and {self.rolling_shutter!r}"
            )
        if isinstance(self.venue_seed, bool) or not isinstance(self.venue_seed, int) or self.venue_seed < 0:
            raise ValueError(f"ImageParams.venue_seed must be an integer >= 0, got {self.venue_seed!r}")

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
