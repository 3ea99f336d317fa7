"""The fused passes of teamsim.image_effects (a blur in the same loop as the photometric step)
give exactly the bytes of the separate passes (the blur into a float image, then the photometric
step): the fusion saves a pass over the image and changes no value."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.typing import NDArray

from teamsim.image_effects import (
    _blur_cols,
    _blur_cols_photometric,
    _blur_rows,
    _blur_rows_photometric,
    _photometric,
)

SIZES = [(240, 320), (9, 13), (8, 8)]


def image(h: int, w: int, seed: int = 3) -> NDArray[np.uint8]:
    """Random values in the lower half, a smooth ramp in the upper half (H x 3W)."""
    img = np.random.default_rng(seed).integers(0, 256, (h, 3 * w), dtype=np.uint8)
    img[: h // 2] = np.linspace(0.0, 255.0, 3 * w).astype(np.uint8)
    return img


def photometry(h: int, w: int, seed: int = 4) -> tuple:
    """Gains, vignetting terms, a noise pool, its offset, read noise^2 and shot noise."""
    rng = np.random.default_rng(seed)
    gain = np.exp(rng.normal(0.0, 0.2, 3))
    k = 0.4 / (0.25 * (w * w + h * h))
    vrow = (1.0 - k * (np.arange(h) + 0.5 - 0.5 * h) ** 2).astype(np.float32)
    vcol = (k * (np.arange(w) + 0.5 - 0.5 * w) ** 2).astype(np.float32)
    pool = rng.standard_normal(3 * h * w + 100, dtype=np.float32)
    return gain, vrow, vcol, pool, 37, 9.0, 0.3


@pytest.mark.parametrize("size", SIZES)
@pytest.mark.parametrize("length", [0.3, 1.7, 2.0, 2.6, 3.9])
def test_horizontal_blur_with_photometry_equals_the_two_passes(size: tuple[int, int], length: float) -> None:
    h, w = size
    img, args = image(h, w), photometry(h, w)
    blurred = np.empty((h, 3 * w), np.float32)
    expected = img.copy()
    _blur_rows(img, blurred, length)
    _photometric(blurred, expected, *args)
    fused = img.copy()
    _blur_rows_photometric(fused, length, *args)
    np.testing.assert_array_equal(fused, expected)


@pytest.mark.parametrize("size", SIZES)
@pytest.mark.parametrize("length", [0.2, 1.0, 2.5, 7.3, 500.0])
def test_vertical_blur_with_photometry_equals_the_two_passes(size: tuple[int, int], length: float) -> None:
    h, w = size
    args = photometry(h, w)
    src = np.empty((h, 3 * w), np.float32)  # blurred horizontally, as the fused pass receives it
    _blur_rows(image(h, w), src, 1.3)
    blurred = np.empty_like(src)
    expected = np.empty((h, 3 * w), np.uint8)
    _blur_cols(src, blurred, length)
    _photometric(blurred, expected, *args)
    fused = np.empty_like(expected)
    _blur_cols_photometric(src, fused, length, *args)
    np.testing.assert_array_equal(fused, expected)
