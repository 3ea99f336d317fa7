"""Tests of the camera image effects (teamsim.image_effects): motion blur, rolling shutter, photometry,
and the uneven illumination of the hall the renderer draws (teamsim.image_venue.light_map)."""

from __future__ import annotations

import dataclasses
import itertools
import math
import re

import numpy as np
import pytest

from cognition.camera import CameraRig
from cognition.field import FIELD_PRESETS, Field, make_colour_scheme
from teamsim.image_effects import ImageEffects
from teamsim.image_params import ImageParams
from teamsim.image_venue import light_map
from teamsim.images import ImageRenderer
from teamsim.percepts import Scene, SceneRobot

IDEAL = ImageParams.preset("ideal")
H, W = 240, 320


def only(**changes: object) -> ImageParams:
    """The ideal preset with just the given effects switched on."""
    return dataclasses.replace(IDEAL, **changes)


def run(
    params: ImageParams,
    image: np.ndarray,
    fx: float = 300.0,
    fy: float = 300.0,
    yaw: float = 0.0,
    pitch: float = 0.0,
    walking: bool = False,
    seed: int = 0,
) -> np.ndarray:
    """A degraded copy of ``image`` (one fresh ImageEffects per call)."""
    out = image.copy()
    ImageEffects(params, np.random.default_rng(seed)).apply(out, fx, fy, yaw, pitch, walking)
    return out


def flat(value: int, h: int = H, w: int = W) -> np.ndarray:
    return np.full((h, w, 3), value, dtype=np.uint8)


def random_image(seed: int = 1, h: int = H, w: int = W) -> np.ndarray:
    return np.random.default_rng(seed).integers(0, 256, (h, w, 3), dtype=np.uint8)


def column_stripes(seed: int = 2) -> np.ndarray:
    """Each column one random grey level: vertical stripes, vertically uniform."""
    cols = np.random.default_rng(seed).integers(0, 256, W, dtype=np.uint8)
    return np.ascontiguousarray(np.broadcast_to(cols[None, :, None], (H, W, 3)))


def row_stripes(seed: int = 3) -> np.ndarray:
    """Each row one random grey level: horizontal stripes, horizontally uniform."""
    rows = np.random.default_rng(seed).integers(0, 256, H, dtype=np.uint8)
    return np.ascontiguousarray(np.broadcast_to(rows[:, None, None], (H, W, 3)))


def energy(image: np.ndarray, axis: int) -> float:
    """Mean squared difference of neighbouring pixels along ``axis`` (1: horizontal, 0: vertical)."""
    return float(np.mean(np.diff(image.astype(np.float64), axis=axis) ** 2))


def box_reference(line: np.ndarray, length: float, samples: int = 4000) -> np.ndarray:
    """Time average of the linearly interpolated line shifted over [-L/2, L/2] (midpoint rule, edges clamped)."""
    n = line.size
    s = (np.arange(samples) + 0.5) / samples * length - 0.5 * length
    pos = np.arange(n)[:, None] - s[None, :]
    return np.interp(pos.ravel(), np.arange(n), line.astype(np.float64)).reshape(n, samples).mean(axis=1)


# ------------------------------------------------------------------------------------------ ideal, skipping


def test_ideal_preset_is_identity_and_draws_nothing() -> None:
    rng = np.random.default_rng(5)
    fx = ImageEffects(IDEAL, rng)
    assert not fx.active
    state = rng.bit_generator.state
    image = random_image()
    out = image.copy()
    fx.apply(out, 300.0, 300.0, 3.0, -2.0, True)
    np.testing.assert_array_equal(out, image)
    assert rng.bit_generator.state == state


@pytest.mark.parametrize("name", ["ideal", "default", "harsh"])
def test_active_follows_has_effects(name: str) -> None:
    params = ImageParams.preset(name)
    assert ImageEffects(params, np.random.default_rng(0)).active == params.has_effects


def test_identity_stages_are_skipped_and_draw_nothing() -> None:
    image = random_image()
    for params, yaw, pitch in [
        (only(rolling_shutter=30e-6), 0.0, 0.0),  # rolling shutter without motion
        (only(exposure=0.01), 0.0, 0.0),  # exposure without motion
        (only(exposure=0.01, rolling_shutter=30e-6), 1e-6, 0.0),  # far below MIN_BLUR / MIN_SHIFT
    ]:
        rng = np.random.default_rng(3)
        state = rng.bit_generator.state
        out = image.copy()
        ImageEffects(params, rng).apply(out, 300.0, 300.0, yaw, pitch, False)
        np.testing.assert_array_equal(out, image)
        assert rng.bit_generator.state == state
    # geometric effects alone draw no random numbers either
    rng = np.random.default_rng(3)
    state = rng.bit_generator.state
    ImageEffects(only(exposure=0.01, rolling_shutter=30e-6, walking_shake=2.0), rng).apply(
        image.copy(), 300.0, 300.0, 1.0, 1.0, True
    )
    assert rng.bit_generator.state == state


def test_uses_no_global_random_state() -> None:
    np.random.seed(123)  # noqa: NPY002 - the legacy global state must stay untouched
    state = np.random.get_state()  # noqa: NPY002
    fx = ImageEffects(ImageParams.preset("harsh"), np.random.default_rng(0))
    fx.apply(random_image(), 300.0, 300.0, 1.0, 0.5, True)
    after = np.random.get_state()  # noqa: NPY002
    assert state[0] == after[0] and np.array_equal(state[1], after[1]) and state[2:] == after[2:]


# ------------------------------------------------------------------------------------------ photometric


def test_brightness_halves_the_mean() -> None:
    image = np.random.default_rng(4).integers(118, 139, (H, W, 3), dtype=np.uint8)  # mid grey with texture
    out = run(only(brightness=0.5), image)
    assert abs(out.mean() - 0.5 * image.mean()) < 1.0
    assert abs(run(only(brightness=0.5), flat(128)).mean() - 64.0) < 1.0


def test_white_balance_scales_the_channels() -> None:
    out = run(only(white_balance=(1.2, 1.0, 0.8)), flat(100)).reshape(-1, 3).astype(np.float64)
    means = out.mean(axis=0)
    np.testing.assert_allclose(means, [120.0, 100.0, 80.0], atol=0.5)
    np.testing.assert_allclose(means / means[1], [1.2, 1.0, 0.8], rtol=0.01)


def test_gains_and_vignetting_follow_the_formula() -> None:
    params = only(brightness=0.8, white_balance=(1.1, 1.0, 0.9), vignetting=0.2)
    out = run(params, flat(150)).astype(np.float64)
    u, v = np.meshgrid(np.arange(W) + 0.5, np.arange(H) + 0.5)
    g = 1.0 - 0.2 * ((u - W / 2) ** 2 + (v - H / 2) ** 2) / ((W / 2) ** 2 + (H / 2) ** 2)
    expected = 150.0 * 0.8 * g[:, :, None] * np.array([1.1, 1.0, 0.9])
    assert np.abs(out - expected).max() <= 0.51


def test_vignetting_darkens_the_corners() -> None:
    out = run(only(vignetting=0.3), flat(200)).astype(np.float64)
    centre = out[H // 2 - 2 : H // 2 + 2, W // 2 - 2 : W // 2 + 2].mean()
    corners = np.mean([out[0, 0], out[0, -1], out[-1, 0], out[-1, -1]])
    assert centre == pytest.approx(200.0, abs=0.5)
    assert corners / centre == pytest.approx(0.7, abs=0.01)
    # brightness falls monotonically from the centre along the diagonal
    diag = out[np.arange(H // 2, H), np.arange(W // 2, W // 2 + H // 2), 1]
    assert np.all(np.diff(diag) <= 0)


@pytest.mark.parametrize(("read", "shot"), [(3.0, 0.0), (2.0, 0.5), (0.0, 1.0)])
def test_noise_has_the_model_sigma(read: float, shot: float) -> None:
    out = run(only(read_noise=read, shot_noise=shot), flat(100)).astype(np.float64)
    sigma = math.sqrt(read**2 + shot * 100.0)
    assert abs(out.mean() - 100.0) < 0.5
    assert out.std() == pytest.approx(sigma, rel=0.1)
    # independent across pixels and channels: neighbours are uncorrelated
    z = out - out.mean()
    assert abs(np.mean(z[:, 1:] * z[:, :-1])) / z.var() < 0.02
    assert abs(np.mean(z[..., 0] * z[..., 1])) / z.var() < 0.02


def test_shot_noise_grows_with_the_signal() -> None:
    image = flat(20)
    image[:, W // 2 :] = 200
    out = run(only(read_noise=1.0, shot_noise=0.5), image).astype(np.float64)
    dark, bright = out[:, : W // 2].std(), out[:, W // 2 :].std()
    assert dark == pytest.approx(math.sqrt(1.0 + 0.5 * 20), rel=0.1)
    assert bright == pytest.approx(math.sqrt(1.0 + 0.5 * 200), rel=0.1)
    assert dark < 0.5 * bright


def test_noise_is_new_in_every_image() -> None:
    fx = ImageEffects(only(read_noise=4.0), np.random.default_rng(0))
    fields = []
    for _ in range(4):
        out = flat(100)
        fx.apply(out, 300.0, 300.0, 0.0, 0.0, False)
        fields.append(out.astype(np.float64) - 100.0)
    for a, b in itertools.pairwise(fields):
        assert abs(np.corrcoef(a.ravel(), b.ravel())[0, 1]) < 0.02


def test_noise_pool_grows_for_large_images() -> None:
    fx = ImageEffects(only(read_noise=3.0), np.random.default_rng(0))
    fx.apply(flat(100, 8, 8), 300.0, 300.0, 0.0, 0.0, False)
    big = flat(100, 600, 700)  # 1.26 M values: more than half the default pool
    fx.apply(big, 300.0, 300.0, 0.0, 0.0, False)
    assert big.std() == pytest.approx(3.0, rel=0.05)


def test_exposure_and_white_balance_jitter_per_image() -> None:
    fx = ImageEffects(only(brightness_jitter=0.1, white_balance_jitter=0.05), np.random.default_rng(0))
    logs = []
    for _ in range(300):
        out = flat(200, 8, 8)
        fx.apply(out, 300.0, 300.0, 0.0, 0.0, False)
        assert np.all(out == out[0, 0])  # one gain per image and channel, no noise
        logs.append(np.log(out[0, 0].astype(np.float64) / 200.0))
    logs = np.array(logs)
    # log gain of channel c: N(0, 0.1^2 + 0.05^2); log ratio of two channels: N(0, 2 * 0.05^2)
    assert logs[:, 1].std() == pytest.approx(math.hypot(0.1, 0.05), rel=0.15)
    assert (logs[:, 0] - logs[:, 1]).std() == pytest.approx(0.05 * math.sqrt(2.0), rel=0.15)
    assert abs(logs.mean()) < 0.02


# ------------------------------------------------------------------------------------------ motion blur


def test_yaw_blur_removes_horizontal_detail_more_for_faster_turns() -> None:
    image = column_stripes()
    params = only(exposure=0.01)
    energies = [energy(run(params, image, yaw=rate), axis=1) for rate in (0.0, 0.5, 1.0, 2.0, 8.0)]
    assert all(a > 1.2 * b for a, b in itertools.pairwise(energies))
    # vertically uniform content stays vertically uniform, horizontally uniform content is untouched
    out = run(params, image, yaw=2.0)
    assert np.all(out == out[:1])
    rows = row_stripes()
    np.testing.assert_array_equal(run(params, rows, yaw=2.0), rows)
    np.testing.assert_array_equal(run(params, rows, yaw=-20.0), rows)


def test_blur_is_symmetric_in_the_rate_sign_and_keeps_flat_images() -> None:
    params = only(exposure=0.01)
    image = random_image()
    np.testing.assert_array_equal(run(params, image, yaw=1.5), run(params, image, yaw=-1.5))
    np.testing.assert_array_equal(run(params, image, pitch=1.5), run(params, image, pitch=-1.5))
    for yaw, pitch in [(0.3, 0.0), (1.0, 2.0), (30.0, 30.0)]:
        np.testing.assert_array_equal(run(params, flat(77), yaw=yaw, pitch=pitch), flat(77))


@pytest.mark.parametrize("length", [0.3, 1.0, 2.46, 4.7, 17.3, 60.0])
def test_blur_is_the_exact_time_average(length: float) -> None:
    """Fractional lengths: pixel = mean of the linearly interpolated image over the motion path."""
    image = random_image(7, 16, 96)
    params = only(exposure=0.01)
    out = run(params, image, fx=100.0 * length, yaw=1.0).astype(np.float64)
    ref = np.stack([np.stack([box_reference(image[j, :, c], length) for c in range(3)], -1) for j in range(16)])
    assert np.abs(out - ref).max() <= 0.6
    tall = np.ascontiguousarray(image.transpose(1, 0, 2))  # 96 x 16: blur the columns
    out = run(params, tall, fy=100.0 * length, pitch=1.0).astype(np.float64)
    assert np.abs(out - ref.transpose(1, 0, 2)).max() <= 0.6


@pytest.mark.parametrize("length", [3.0, 6.5, 12.0, 25.0])
def test_edge_is_spread_over_the_blur_length(length: float) -> None:
    image = flat(0)
    image[:, W // 2 :] = 255  # vertical edge between columns 159 and 160
    rate = 2.0
    out = run(only(exposure=0.01), image, fx=length / (rate * 0.01), yaw=rate)
    profile = out[H // 2, :, 0].astype(np.float64) / 255.0
    # the line spread function (profile derivative) has the width of a box of length L: sigma = L / sqrt(12)
    lsf = np.diff(profile)
    x = np.arange(lsf.size) + 1.0
    centre = np.sum(x * lsf) / lsf.sum()
    width = math.sqrt(12.0 * np.sum((x - centre) ** 2 * lsf) / lsf.sum())
    assert abs(centre - W // 2) < 0.6
    assert width == pytest.approx(length, abs=1.0)
    # pixels well inside the blur are intermediate, pixels beyond it untouched
    ramp = np.flatnonzero((profile > 0) & (profile < 1))
    assert ramp.size == pytest.approx(length, abs=2.0)
    assert ramp.min() >= W // 2 - length / 2 - 1.5 and ramp.max() <= W // 2 + length / 2 + 0.5


def test_pitch_blurs_horizontal_edges_only() -> None:
    params = only(exposure=0.01)
    rows, cols = row_stripes(), column_stripes()
    assert energy(run(params, rows, pitch=1.0), axis=0) < 0.7 * energy(rows, axis=0)
    assert energy(run(params, rows, pitch=3.0), axis=0) < 0.7 * energy(run(params, rows, pitch=1.0), axis=0)
    np.testing.assert_array_equal(run(params, cols, pitch=3.0), cols)


def test_walking_adds_vertical_blur() -> None:
    params = only(walking_shake=2.0)
    rows, cols = row_stripes(), column_stripes()
    np.testing.assert_array_equal(run(params, rows, walking=False), rows)
    assert energy(run(params, rows, walking=True), axis=0) < 0.7 * energy(rows, axis=0)
    np.testing.assert_array_equal(run(params, cols, walking=True), cols)
    # the shake adds to the pitch blur length
    params = only(exposure=0.01, walking_shake=2.0)
    still, walk = run(params, rows, pitch=1.0), run(params, rows, pitch=1.0, walking=True)
    assert energy(walk, axis=0) < 0.8 * energy(still, axis=0)


# ------------------------------------------------------------------------------------------ rolling shutter


def edge_shift(out: np.ndarray, edge: int) -> np.ndarray:
    """Per row, how far (px, + = right) a dark-to-bright (0 -> 200) vertical edge at column ``edge`` moved."""
    bright = out[:, :, 1].astype(np.float64).sum(axis=1) / 200.0
    return (W - edge) - bright


@pytest.mark.parametrize("yaw", [2.0, -3.0])
def test_rolling_shutter_slants_vertical_edges(yaw: float) -> None:
    rs, fx = 40e-6, 300.0
    image = flat(0)
    image[:, W // 2 :] = 200
    out = run(only(rolling_shutter=rs), image, fx=fx, yaw=yaw)
    shift = edge_shift(out, W // 2)
    t = np.arange(H) + 0.5 - H / 2
    slope, at_centre = np.polyfit(t, shift, 1)
    assert slope == pytest.approx(rs * yaw * fx, rel=0.03)  # px per row; lower rows move right for yaw > 0
    assert abs(at_centre) < 0.2
    assert np.abs(shift - slope * t).max() < 0.6


def test_rolling_shutter_pitch_squeezes_or_stretches_vertically() -> None:
    """Looking down (pitch > 0) moves content up against the top-down readout: objects look shorter."""
    rs, fy, pitch = 100e-6, 300.0, 4.0
    k = rs * fy * pitch  # 0.12: source row = j + k (j + 0.5 - H/2)
    image = flat(0)
    image[90:150] = 200  # a 60 px band around the centre row
    for sign in (1.0, -1.0):
        out = run(only(rolling_shutter=rs), image, fy=fy, pitch=sign * pitch)
        mass = out[:, :, 0].astype(np.float64).sum(axis=0) / 200.0
        assert np.all(np.abs(mass - 60.0 / (1.0 + sign * k)) < 0.6)
        centre = np.sum(np.arange(H) * out[:, 0, 0]) / out[:, 0, 0].astype(np.float64).sum()
        assert centre == pytest.approx(119.5, abs=0.3)


def test_rolling_shutter_keeps_flat_images_and_replicates_edges() -> None:
    params = only(rolling_shutter=1e-3)  # huge skew: hundreds of px
    np.testing.assert_array_equal(run(params, flat(90), yaw=5.0, pitch=-5.0), flat(90))
    image = flat(0)
    image[:, W // 2 :] = 200
    out = run(params, image, fx=300.0, yaw=5.0)  # 1.5 px per row: the edge leaves the image
    assert np.all(out[0, :, 1] == 200) and np.all(out[-1, :, 1] == 0)


# ------------------------------------------------------------------------------------------ determinism


@pytest.mark.parametrize("name", ["default", "harsh"])
def test_same_seed_same_images(name: str) -> None:
    params = ImageParams.preset(name)
    a, b, c = (ImageEffects(params, np.random.default_rng(s)) for s in (11, 11, 12))
    motions = [(0.0, 0.0, False), (1.2, -0.4, True), (-2.5, 0.8, False), (0.3, 0.0, True)]
    differs = False
    for k, (yaw, pitch, walking) in enumerate(motions):
        image = random_image(20 + k)
        outs = [image.copy() for _ in range(3)]
        for fx, out in zip((a, b, c), outs, strict=True):
            fx.apply(out, 300.0, 290.0, yaw, pitch, walking)
        np.testing.assert_array_equal(outs[0], outs[1])
        differs |= not np.array_equal(outs[0], outs[2])
        assert not np.array_equal(outs[0], image)
    assert differs


def test_mixed_image_sizes_share_one_instance() -> None:
    params = ImageParams.preset("harsh")
    a, b = ImageEffects(params, np.random.default_rng(1)), ImageEffects(params, np.random.default_rng(1))
    for shape in [(240, 320), (120, 160), (240, 320), (8, 8)]:
        image = random_image(5, *shape)
        x, y = image.copy(), image.copy()
        a.apply(x, 300.0, 300.0, 1.0, 0.5, True)
        b.apply(y, 300.0, 300.0, 1.0, 0.5, True)
        np.testing.assert_array_equal(x, y)


# ------------------------------------------------------------------------------------------ bad input


def test_params_must_be_image_params() -> None:
    with pytest.raises(TypeError, match="ImageParams"):
        ImageEffects({"brightness": 1.0}, np.random.default_rng(0))  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("image", "match"),
    [
        ([[[0, 0, 0]] * 8] * 8, "numpy uint8 array"),
        (np.zeros((16, 16, 3), np.float32), "uint8 array of shape"),
        (np.zeros((16, 16), np.uint8), r"shape \(H, W, 3\)"),
        (np.zeros((16, 16, 4), np.uint8), r"shape \(H, W, 3\)"),
        (np.zeros((16, 32, 3), np.uint8)[:, ::2], "C-contiguous"),
        (np.asfortranarray(np.zeros((16, 16, 3), np.uint8)), "C-contiguous"),
        (np.zeros((7, 16, 3), np.uint8), "at least 8"),
        (np.zeros((16, 5, 3), np.uint8), "at least 8"),
    ],
)
def test_bad_images_are_rejected(image: object, match: str) -> None:
    fx = ImageEffects(ImageParams.preset("default"), np.random.default_rng(0))
    with pytest.raises(ValueError, match=match):
        fx.apply(image, 300.0, 300.0, 0.0, 0.0, False)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("args", "match"),
    [
        ((0.0, 300.0, 0.0, 0.0), "fx"),
        ((-1.0, 300.0, 0.0, 0.0), "fx"),
        ((math.nan, 300.0, 0.0, 0.0), "fx"),
        ((300.0, math.inf, 0.0, 0.0), "fy"),
        ((300.0, 0.0, 0.0, 0.0), "fy"),
        ((300.0, 300.0, math.nan, 0.0), "yaw_rate"),
        ((300.0, 300.0, -math.inf, 0.0), "yaw_rate"),
        ((300.0, 300.0, 0.0, math.inf), "pitch_rate"),
    ],
)
def test_bad_camera_values_are_rejected(args: tuple[float, float, float, float], match: str) -> None:
    for preset in ("ideal", "default"):
        fx = ImageEffects(ImageParams.preset(preset), np.random.default_rng(0))
        with pytest.raises(ValueError, match=match):
            fx.apply(flat(0, 16, 16), *args, False)


# ------------------------------------------------------------------------------------------ uneven illumination
# The hall's light (sun stripes, soft shadows, darker corners) is rendered with the scene by
# teamsim.images.ImageRenderer, fixed in the world frame (teamsim.image_venue.light_map).

SPL = Field(FIELD_PRESETS["spl2025"], "spl2025")
GREEN = np.array(make_colour_scheme("modern").field_green)
LIT = dataclasses.replace(IDEAL, grass_texture=0.0, sun_stripes=0.3, shadows=0.25, light_falloff=0.2)
"""Only the uneven light (no sensor effects, flat carpet): a lit image is the ideal one times the light."""
FLAT = dataclasses.replace(IDEAL, grass_texture=0.0)


def renderer(params: ImageParams, size: tuple[int, int] = (320, 240), seed: int = 0) -> ImageRenderer:
    return ImageRenderer(SPL, "modern", CameraRig().with_resolution(*size), params, np.random.default_rng(seed))


def carpet_grid(step: float = 0.05) -> np.ndarray:
    """World points (N x 2, m) on a grid over the carpet (field plus border strip)."""
    kx, ky = SPL.half_length + SPL.dims.border_strip, SPL.half_width + SPL.dims.border_strip
    gx, gy = np.meshgrid(np.arange(-kx, kx, step) + step / 2, np.arange(-ky, ky, step) + step / 2)
    return np.column_stack([gx.ravel(), gy.ravel()])


def world_to_pixels(ren: ImageRenderer, scene: Scene, r: int, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Integer pixels (N x 2: column, row) of world ground points in robot ``r``'s image, and a mask of those seen."""
    o = scene.observers[r]
    c, s = math.cos(o[2]), math.sin(o[2])
    dx, dy = xy[:, 0] - o[0], xy[:, 1] - o[1]
    rel = np.column_stack([c * dx + s * dy, -s * dx + c * dy, np.zeros(len(xy))])
    cam = ren.camera_matrix(scene, r)
    uv, front = cam.project(rel)
    ok = front & cam.in_image(uv)
    px = np.zeros((len(xy), 2), dtype=np.int64)
    px[ok] = np.floor(uv[ok]).astype(np.int64)
    return px, ok


def gain_ratio(lit: np.ndarray, even: np.ndarray, channel: int = 1) -> np.ndarray:
    """Per pixel lit / evenly lit value of one channel (float; NaN where the even image is 0)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return lit[..., channel].astype(np.float64) / even[..., channel].astype(np.float64)


def test_illumination_parameters_are_range_checked() -> None:
    for name, value, shown in [
        ("sun_stripes", -0.1, "[0, 2]"),
        ("sun_stripes", 2.5, "[0, 2]"),
        ("sun_stripe_width", 0.0, "(0, 10]"),
        ("sun_direction", 3.2, "[-pi, pi]"),
        ("shadows", 1.0, "[0, 1)"),
        ("light_falloff", 1.0, "[0, 1)"),
        ("light_falloff", -0.2, "[0, 1)"),
        ("light_softness", 6.0, "[0, 5]"),
        ("light_tint", 1.5, "[0, 1]"),
    ]:
        with pytest.raises(ValueError, match=rf"ImageParams\.{name}.*{re.escape(shown)}"):
            dataclasses.replace(IDEAL, **{name: value})


def test_illumination_counts_as_an_effect_only_with_a_strength() -> None:
    assert not IDEAL.has_illumination and not IDEAL.has_effects
    for name in ("default", "harsh"):
        assert ImageParams.preset(name).has_illumination and ImageParams.preset(name).has_effects
    for name in ("sun_stripes", "shadows", "light_falloff"):
        p = dataclasses.replace(IDEAL, **{name: 0.2})
        assert p.has_illumination and p.has_effects
        assert ImageEffects(p, np.random.default_rng(0)).active
        # the renderer draws the light; ImageEffects.apply leaves the image alone and draws no numbers
        rng = np.random.default_rng(3)
        state, image = rng.bit_generator.state, random_image()
        out = image.copy()
        ImageEffects(p, rng).apply(out, 300.0, 300.0, 1.0, 1.0, True)
        np.testing.assert_array_equal(out, image)
        assert rng.bit_generator.state == state
    shape_only = dataclasses.replace(
        IDEAL, sun_stripe_width=2.0, sun_direction=-1.0, light_softness=0.5, light_tint=0.5
    )
    assert not shape_only.has_illumination and not shape_only.has_effects
    # stronger light in the harsh preset
    d, h = ImageParams.preset("default"), ImageParams.preset("harsh")
    assert h.sun_stripes > d.sun_stripes and h.shadows > d.shadows and h.light_falloff > d.light_falloff


def scene_two_views() -> tuple[Scene, Scene]:
    """The same robot at one spot with two head angles, and from another spot: both see the carpet around (1, 0.3)."""
    a = Scene.build([SceneRobot(0, 1, -0.8, -0.4, 0.2, head_yaw=0.25, head_pitch=0.35)], (-4.0, -2.8), 1)
    b = Scene.build([SceneRobot(0, 1, 2.9, 1.6, -2.6, head_yaw=-0.2, head_pitch=0.3)], (-4.0, -2.8), 1)
    return a, b


def test_ideal_images_have_no_illumination() -> None:
    even = renderer(IDEAL)
    np.testing.assert_array_equal(even.light_at(carpet_grid(0.5)), 1.0)
    for sc in scene_two_views():
        img = even.render(sc, 0)
        # the shape parameters alone light nothing, and turning the light's strengths off gives the ideal image
        shape_only = dataclasses.replace(IDEAL, sun_stripe_width=2.0, sun_direction=1.0, light_tint=0.5)
        np.testing.assert_array_equal(renderer(shape_only).render(sc, 0), img)
        # without effects, an unevenly lit renderer draws the evenly lit scene, bit for bit
        lit = renderer(dataclasses.replace(LIT, grass_texture=IDEAL.grass_texture))
        np.testing.assert_array_equal(lit.render(sc, 0, effects=False), img)
        assert not np.array_equal(lit.render(sc, 0), img)


def test_light_is_fixed_in_the_world() -> None:
    """A carpet point has the same gain whichever way the camera looks at it: the light map's gain there."""
    lit, even = renderer(LIT, (640, 480)), renderer(FLAT, (640, 480))
    rng = np.random.default_rng(4)
    xy = np.column_stack([rng.uniform(-0.5, 2.5, 6000), rng.uniform(-1.2, 1.8, 6000)])
    truth = lit.light_at(xy)
    scenes = [
        *scene_two_views(),
        Scene.build([SceneRobot(0, 1, -0.8, -0.4, 0.2, head_yaw=-0.1, head_pitch=0.5)], None, 1),
    ]
    ratios = []
    for sc in scenes:
        a, b = lit.render(sc, 0), even.render(sc, 0)
        px, ok = world_to_pixels(lit, sc, 0, xy)
        carpet = np.zeros(len(xy), dtype=bool)
        carpet[ok] = np.all(b[px[ok, 1], px[ok, 0]] == GREEN, axis=-1)  # plain carpet, no paint
        ratio = np.full(len(xy), np.nan)
        ratio[carpet] = gain_ratio(a, b)[px[carpet, 1], px[carpet, 0]]
        ratios.append(ratio)
    ratios = np.array(ratios)
    assert np.all(np.sum(np.isfinite(ratios), axis=1) > 800)
    for k in range(len(scenes)):  # each view shows the gain of the world point it looks at
        seen = np.isfinite(ratios[k])
        assert np.abs(ratios[k][seen] - truth[seen]).max() < 0.02
    both = np.isfinite(ratios[0]) & np.isfinite(ratios[1])
    assert both.sum() > 300
    assert np.abs(ratios[0][both] - ratios[1][both]).max() < 0.02  # two poses, the same point, the same light
    assert np.ptp(truth[both]) > 0.2  # and the light does vary over the points compared


def test_light_map_parts_behave_as_documented() -> None:
    xy = carpet_grid()
    kx, ky = SPL.half_length + SPL.dims.border_strip, SPL.half_width + SPL.dims.border_strip
    # falloff alone: 1 at the centre, 1 - falloff at the carpet's corners, a third of the loss mid-edge
    fall = renderer(dataclasses.replace(FLAT, light_falloff=0.2))
    g = fall.light_at(np.array([[0.0, 0.0], [kx, ky], [-kx, ky], [0.0, ky], [kx, 0.0]]))
    np.testing.assert_allclose(g, [1.0, 0.8, 0.8, 1 - 0.2 / 3, 1 - 0.2 / 3], atol=0.01)
    # sun alone: never darker, stripes up to 1 + sun_stripes, running along sun_direction
    for direction in (0.5, -1.2):
        sun = renderer(dataclasses.replace(FLAT, sun_stripes=0.3, sun_direction=direction))
        g = sun.light_at(xy)
        assert g.min() >= 1.0 - 1e-6 and 1.2 < g.max() <= 1.3 + 1e-6
        assert 0.1 < np.mean(g > 1.1) < 0.6  # stripes cover part of the carpet, not all of it
        e = np.array([math.cos(direction), math.sin(direction)])
        n = np.array([-e[1], e[0]])
        along = np.abs(sun.light_at(xy + 0.1 * e) - g).mean()
        across = np.abs(sun.light_at(xy + 0.1 * n) - g).mean()
        assert across > 4.0 * along
    # shadows alone: never brighter, as deep as 1 - shadows at most, some deep cores
    shade = renderer(dataclasses.replace(FLAT, shadows=0.25))
    g = shade.light_at(xy)
    assert g.max() <= 1.0 + 1e-6 and g.min() >= 0.75 - 1e-6 and g.min() < 0.85
    assert 0.1 < np.mean(g < 0.95) < 0.8


def test_sun_stripes_have_soft_edges() -> None:
    step = 0.01
    y = np.arange(-3.0, 3.0, step)
    line = np.column_stack([np.zeros_like(y), y])  # across stripes running along x
    soft = renderer(dataclasses.replace(FLAT, sun_stripes=0.3, sun_direction=0.0, light_softness=0.1))
    hard = renderer(dataclasses.replace(FLAT, sun_stripes=0.3, sun_direction=0.0, light_softness=0.0))
    # a blurred step of 0.3 with sigma 0.1 m rises by at most 0.3 / (sqrt(2 pi) 0.1) = 1.2 per metre
    assert np.abs(np.diff(soft.light_at(line))).max() / step < 1.5
    assert np.abs(np.diff(hard.light_at(line))).max() / step > 4.0  # steps as sharp as the map's texels


def test_default_light_shows_a_real_spread_of_carpet_brightness() -> None:
    spreads = {}
    for name in ("default", "harsh"):
        g = renderer(ImageParams.preset(name)).light_at(carpet_grid())
        lo, hi = np.percentile(g, [2, 98])
        spreads[name] = hi / lo
        assert g.min() < 0.8 and g.max() > 1.2
    assert spreads["default"] > 1.4
    assert spreads["harsh"] > spreads["default"] + 0.3
    # and in an image with all the default effects (noise, vignetting, gains): the carpet's
    # green differs by far more than the noise between its brighter and darker parts
    params = dataclasses.replace(ImageParams.preset("default"), grass_texture=0.0)
    sc = Scene.build([SceneRobot(0, 1, -0.6, -2.9, 2.1, head_pitch=0.25)], None, 1)
    img = renderer(params, (640, 480)).render(sc, 0)
    even = renderer(FLAT, (640, 480)).render(sc, 0)
    carpet = np.all(even == GREEN, axis=-1)
    assert carpet.mean() > 0.4
    lo, hi = np.percentile(img[..., 1][carpet], [5, 95])
    assert hi / lo > 1.3


def test_light_is_tinted_warm_in_the_sun_and_blue_in_shadow() -> None:
    """The hall floor (grey, 92/92/98) off the carpet: red moves (1 + t) times as much as green, blue (1 - t)."""
    tint = 0.3
    lit = renderer(dataclasses.replace(LIT, sun_stripes=0.6, light_tint=tint), (640, 480))
    even = renderer(FLAT, (640, 480))
    sc = Scene.build([SceneRobot(0, 1, 3.5, 3.0, math.pi / 2, head_pitch=0.3)], None, 1)  # looks at the side wall
    a, b = lit.render(sc, 0), even.render(sc, 0)
    floor = np.all(b == (92, 92, 98), axis=-1)
    assert floor.sum() > 10000
    g, r, bl = (gain_ratio(a, b, c)[floor] - 1.0 for c in (1, 0, 2))
    for part in (g > 0.04, g < -0.04):  # sunlit (warm: more red than blue), shaded (bluish: more blue than red)
        assert part.sum() > 2000
        assert r[part].sum() / g[part].sum() == pytest.approx(1 + tint, abs=0.05)
        assert bl[part].sum() / g[part].sum() == pytest.approx(1 - tint, abs=0.05)


def test_objects_are_lit_by_the_light_at_their_foot_point() -> None:
    """A robot walking through the light gets brighter where its feet are lit (the body is scaled alike)."""
    lit, even = renderer(LIT, (640, 480)), renderer(FLAT, (640, 480))
    watcher = SceneRobot(0, 1, -2.5, 0.0, 0.0, head_pitch=0.05)
    ratios, truths = [], []
    for y in np.linspace(-1.2, 1.2, 9):
        walker = SceneRobot(1, 1, 0.0, float(y), math.pi)
        with_it, without = Scene.build([watcher, walker], None, 1), Scene.build([watcher], None, 1)
        empty = even.render(without, 0)
        b = even.render(with_it, 0)
        body = np.all(b != empty, axis=-1) & (b[..., 1] > 20) & (b[..., 1] < 180)  # unclipped robot pixels
        assert body.sum() > 300
        ratios.append(float(np.median(gain_ratio(lit.render(with_it, 0), b)[body])))
        truths.append(float(lit.light_at(np.array([[0.0, y]]))[0]))
    ratios, truths = np.array(ratios), np.array(truths)
    assert np.ptp(truths) > 0.1  # the walk crosses brighter and darker ground
    np.testing.assert_allclose(ratios, truths, atol=0.02)


def test_illumination_is_deterministic_and_seeded_by_the_venue() -> None:
    np.random.seed(7)  # noqa: NPY002 - the legacy global state must stay untouched
    state = np.random.get_state()  # noqa: NPY002
    default = ImageParams.preset("default")
    a, b = light_map(SPL, default), light_map(SPL, default)
    np.testing.assert_array_equal(a, b)
    c = light_map(SPL, dataclasses.replace(default, venue_seed=1))
    assert a.shape == c.shape and np.abs(a - c).mean() > 0.03
    sc = scene_two_views()[0]
    img1, img2 = renderer(default, seed=3).render(sc, 0), renderer(default, seed=3).render(sc, 0)
    np.testing.assert_array_equal(img1, img2)
    after = np.random.get_state()  # noqa: NPY002
    assert state[0] == after[0] and np.array_equal(state[1], after[1]) and state[2:] == after[2:]
    # the layout is the same in every preset, only the strengths differ
    harsh = light_map(SPL, ImageParams.preset("harsh"))
    assert np.corrcoef(np.log(a).ravel(), np.log(harsh).ravel())[0, 1] > 0.95
    assert light_map(SPL, IDEAL).shape == (1, 1)
