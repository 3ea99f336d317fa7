"""Images in the pipeline: effects on rendered scenes, determinism, bad input, the match, the CLI."""

from __future__ import annotations

import dataclasses
import hashlib
import math

import numpy as np
import pytest

from cognition.brain import Brain, BrainContext
from cognition.camera import CameraImage, CameraRig
from cognition.field import FIELD_PRESETS, Field
from cognition.representations import BrainOutput
from teamsim.cli import main
from teamsim.image_params import ImageParams
from teamsim.images import ImageRenderer, draw_annotations, save_png
from teamsim.match import Match, MatchConfig
from teamsim.percept_params import PerceptParams
from teamsim.percept_parts import OBS
from teamsim.percepts import Scene, SceneRobot

SPL = Field(FIELD_PRESETS["spl2025"], "spl2025")
EXACT_CAMERA = PerceptParams(shared_noise_fraction=0.0)
"""Default percept noise without the share common to an image: image matches get exact camera matrices."""


def scene(yaw_rate: float = 0.0, walking: bool = False) -> Scene:
    robots = [
        SceneRobot(0, 1, -2.0, 0.3, 0.1, head_pitch=0.2, yaw_rate=yaw_rate, walking=walking),
        SceneRobot(1, 1, -0.5, 0.5, math.pi),
    ]
    return Scene.build(robots, (-1.0, 0.0), 1)


def render(params: ImageParams | str, sc: Scene, seed: int = 0) -> np.ndarray:
    return ImageRenderer(SPL, "classic", None, params, np.random.default_rng(seed)).render(sc, 0)


def test_ideal_images_are_noise_free_and_need_no_random_numbers():
    sc = scene(yaw_rate=2.0, walking=True)
    a, b = render("ideal", sc, seed=1), render("ideal", sc, seed=2)
    assert np.array_equal(a, b)
    assert np.array_equal(a, ImageRenderer(SPL, "classic", None, "default").render(sc, 0, effects=False))


def test_brightness_shifts_the_mean():
    sc = scene()
    ideal = render("ideal", sc).astype(float)
    dim = render(dataclasses.replace(ImageParams.preset("ideal"), brightness=0.6), sc).astype(float)
    assert dim.mean() == pytest.approx(0.6 * ideal.mean(), rel=0.02)


def test_motion_blur_lowers_high_frequency_energy_with_head_speed():
    params = dataclasses.replace(ImageParams.preset("ideal"), exposure=0.01)
    energy = []
    for rate in (0.0, 1.0, 4.0):
        img = render(params, scene(yaw_rate=rate)).astype(float)
        energy.append(float((np.diff(img, axis=1) ** 2).mean()))
    assert energy[0] > 1.3 * energy[1] > 1.3 * 1.3 * energy[2]


def test_default_effects_add_noise_with_the_model_sigma():
    sc = scene()
    params = dataclasses.replace(
        ImageParams.preset("ideal"), read_noise=3.0, shot_noise=0.0
    )  # noise only: the residual is the noise
    residual = render(params, sc).astype(float) - render("ideal", sc).astype(float)
    inside = (render("ideal", sc) > 10).all(axis=-1) & (render("ideal", sc) < 245).all(axis=-1)
    assert residual[inside].std() == pytest.approx(3.0, rel=0.1)
    assert abs(residual[inside].mean()) < 0.2


def test_images_are_deterministic_for_a_seed():
    sc = scene(yaw_rate=1.0, walking=True)
    ren_a = ImageRenderer(SPL, "modern", None, "harsh", np.random.default_rng(5))
    ren_b = ImageRenderer(SPL, "modern", None, "harsh", np.random.default_rng(5))
    ren_c = ImageRenderer(SPL, "modern", None, "harsh", np.random.default_rng(6))
    seq_a = [ren_a.render(sc, 0).copy() for _ in range(3)]
    seq_b = [ren_b.render(sc, 0).copy() for _ in range(3)]
    seq_c = [ren_c.render(sc, 0).copy() for _ in range(3)]
    assert all(np.array_equal(x, y) for x, y in zip(seq_a, seq_b, strict=True))
    assert not np.array_equal(seq_a[0], seq_c[0])
    assert not np.array_equal(seq_a[0], seq_a[1])  # fresh noise in every image


def test_bad_input_is_a_clear_error(tmp_path):
    with pytest.raises(ValueError, match=r"CameraSpec\.width must be an integer in \[8, 2048\], got 4"):
        ImageRenderer(SPL, "classic", CameraRig().with_resolution(4, 240))
    with pytest.raises(ValueError, match="unknown colour scheme 'neon'"):
        ImageRenderer(SPL, "neon")
    with pytest.raises(ValueError, match="unknown ImageParams preset 'blurry'"):
        ImageRenderer(SPL, "classic", None, "blurry")
    ren = ImageRenderer(SPL, "classic", None, "ideal")
    with pytest.raises(ValueError, match="robot index"):
        ren.render(scene(), 2)
    with pytest.raises(ValueError, match="out must be a C-contiguous uint8 array of shape"):
        ren.render(scene(), 0, out=np.zeros((10, 10, 3), dtype=np.uint8))
    with pytest.raises(TypeError, match="expected a Scene"):
        ren.render("scene", 0)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"writes \.png"):
        save_png(tmp_path / "x.jpg", np.zeros((8, 8, 3), dtype=np.uint8))
    with pytest.raises(ValueError, match="H x W x 3 uint8"):
        save_png(tmp_path / "x.png", np.zeros((8, 8), dtype=np.uint8))
    with pytest.raises(ValueError, match=r"unknown MatchConfig.images key\(s\) \[.brightnes.\]"):
        MatchConfig.from_mapping({"images": {"brightnes": 2.0}})
    with pytest.raises(ValueError, match=r"ImageParams\.vignetting must be a real number in \[0, 1\), got 1\.0"):
        ImageParams(vignetting=1.0)


class CameraBrain:
    """Keeps the image of every frame."""

    uses_oracle = False

    def __init__(self) -> None:
        self.frames: list[tuple[float, CameraImage | None, float, float]] = []

    def reset(self, context: BrainContext) -> None:
        self.context = context

    def think(self, frame, oracle=None) -> BrainOutput:  # type: ignore[no-untyped-def]
        self.frames.append((frame.time, frame.image, frame.head.yaw, frame.head.pitch))
        return BrainOutput()


def run_image_match(seed: int, percepts: str | PerceptParams = "default") -> tuple[Match, list[CameraBrain]]:
    brains: list[CameraBrain] = []

    def factory(team: int, number: int) -> Brain:
        b = CameraBrain()
        brains.append(b)
        return b

    config = MatchConfig(seed=seed, players_per_team=2, observation="images", images="default", percepts=percepts)
    match = Match(config, brains=factory)
    match.run(until=1.0)
    return match, brains


def test_a_match_delivers_images_with_their_camera_model():
    """With no shared angular noise the camera matrix is the exact one of the head angles."""
    match, brains = run_image_match(3, percepts=EXACT_CAMERA)
    latency = match.config.percepts.latency
    rig = match.config.camera
    for brain in brains:
        images = [img for _, img, _, _ in brain.frames if img is not None]
        assert len(images) >= 25
        for time, img, _, _ in brain.frames[5:]:
            assert isinstance(img, CameraImage)
            assert img.pixels.shape == (240, 320, 3) and img.pixels.dtype == np.uint8
            assert time - img.time == pytest.approx(latency, abs=0.011)
            expected = rig.camera_matrix(img.camera_name, img.head_yaw, img.head_pitch)
            assert np.allclose(img.camera.rotation, expected.rotation)
            assert np.allclose(img.camera.position, expected.position)
    assert match.image_count == sum(len([1 for f in b.frames if f[1] is not None]) for b in brains)


def _axis_angles(img: CameraImage) -> tuple[float, float]:
    """Elevation and azimuth (rad) of the optical axis of an image's camera matrix (robot frame)."""
    axis = img.camera.rotation[:, 0]
    return math.asin(axis[2]), math.atan2(axis[1], axis[0])


def test_camera_errors_turn_the_camera_matrix_not_the_image():
    """``camera_errors`` (rad, around the pitch and the yaw axis) turn the optical axis of the
    image's camera matrix down by the first and left by the second; the pixels stay the same."""
    sc = scene()
    ren = ImageRenderer(SPL, "classic", None, "ideal")
    exact = ren.camera_images(sc)
    errors = np.array([[0.02, -0.03], [-0.01, 0.04]])
    off = ren.camera_images(sc, camera_errors=errors)
    for r, (a, b) in enumerate(zip(exact, off, strict=True)):
        assert a is not None and b is not None
        assert np.array_equal(a.pixels, b.pixels)
        (e0, z0), (e1, z1) = _axis_angles(a), _axis_angles(b)
        assert e1 - e0 == pytest.approx(-errors[r, 0], abs=2e-3)  # more pitch looks further down
        assert z1 - z0 == pytest.approx(errors[r, 1], abs=2e-3)
    with pytest.raises(
        ValueError, match=r"camera_errors must be finite angles \(rad\) of shape \(2, 2\).*shape \(2,\)"
    ):
        ren.camera_images(sc, camera_errors=np.zeros(2))
    with pytest.raises(ValueError, match="with NaN/inf"):
        ren.camera_images(sc, camera_errors=np.array([[0.0, math.nan], [0.0, 0.0]]))


def test_match_draws_the_shared_darmstadt_error_of_each_image():
    """Per image the camera matrix is off by the share of the Darmstadt angular noise that
    synthesized percepts have in common (sigma from eqs. 3-6 for the robot's head rates and
    gait, times sqrt(shared_noise_fraction)), independently around each axis and per image."""
    match = Match(MatchConfig(seed=1, players_per_team=1, observation="images"))
    p = match.config.percepts
    sc = scene(yaw_rate=1.5, walking=True)
    obs = sc.observers
    draws = np.array([match._camera_errors(sc) for _ in range(4000)])  # images x robots x 2
    share = math.sqrt(p.shared_noise_fraction)
    for r in range(2):
        sa, sb = p.sigmas(float(obs[r, OBS.PITCHR]), float(obs[r, OBS.YAWR]), bool(obs[r, OBS.WALK] > 0.5))
        for axis, sigma in ((0, sa), (1, sb)):
            z = draws[:, r, axis] / (share * sigma)
            assert abs(z.mean()) < 0.07 and 0.95 < z.std() < 1.05
        assert abs(np.corrcoef(draws[:, r, 0], draws[:, r, 1])[0, 1]) < 0.06
        assert abs(np.corrcoef(draws[1:, r, 0], draws[:-1, r, 0])[0, 1]) < 0.06
    walking_sigma = p.sigmas(0.0, 1.5, True)[1]
    assert draws[:, 0, 1].std() == pytest.approx(share * walking_sigma, rel=0.05)  # robot 0 walks and turns
    assert draws[:, 1, 1].std() == pytest.approx(share * p.sigma_beta_base, rel=0.05)  # robot 1 stands
    exact = Match(MatchConfig(seed=1, players_per_team=1, observation="images", percepts=EXACT_CAMERA))
    assert not np.any(exact._camera_errors(sc))


def test_image_match_cameras_are_off_but_the_pixels_are_the_same():
    """In a match the camera matrices differ from the exact ones by a few sigma at most, and the
    images are those of a match with exact matrices (the error has its own random stream)."""
    match, brains = run_image_match(3)
    _, exact_brains = run_image_match(3, percepts=EXACT_CAMERA)
    p = match.config.percepts
    largest = math.sqrt(p.shared_noise_fraction) * max(p.sigmas(4.0, 4.0, True))
    off = []
    for brain, exact in zip(brains, exact_brains, strict=True):
        for (_, img, _, _), (_, ref, _, _) in zip(brain.frames, exact.frames, strict=True):
            if img is None:
                assert ref is None
                continue
            assert np.array_equal(img.pixels, ref.pixels)
            (e0, z0), (e1, z1) = _axis_angles(ref), _axis_angles(img)
            off.append((e1 - e0, z1 - z0))
    d = np.abs(np.array(off))
    assert len(d) >= 100 and np.all(d < 5.0 * largest)
    assert np.median(d) > 0.2 * math.sqrt(p.shared_noise_fraction) * p.sigma_alpha_base


def test_image_matches_are_deterministic():
    def digest(seed: int) -> str:
        _, brains = run_image_match(seed)
        h = hashlib.sha256()
        for b in brains:
            for _, img, _, _ in b.frames:
                if img is not None:
                    h.update(img.pixels.tobytes())
        return h.hexdigest()

    assert digest(4) == digest(4)
    assert digest(4) != digest(5)


def test_images_do_not_change_the_match():
    """The renderer has its own random stream: the game is the same with and without images."""
    a = Match(MatchConfig(seed=2, players_per_team=2, observation="images"))
    b = Match(MatchConfig(seed=2, players_per_team=2, observation="none"))
    a.run(until=3.0)
    b.run(until=3.0)
    assert a.snapshot() == b.snapshot()


def test_draw_annotations_marks_the_features():
    ren = ImageRenderer(SPL, "classic", None, "ideal")
    sc = scene()
    img = ren.render(sc, 0)
    ann = ren.annotate(sc)[0]
    assert ann is not None and len(ann.lines) > 0 and len(ann.robots) == 1
    drawn = draw_annotations(img, ann)
    assert drawn.shape == img.shape and not np.array_equal(drawn, img)
    u0, v0, u1, v1 = ann.robots[0, 2:6]
    assert u1 > u0 and v1 > v0
    box_edge = drawn[int(v0) : int(v1), int(u0)].astype(int) - img[int(v0) : int(v1), int(u0)].astype(int)
    assert (np.abs(box_edge).max(axis=-1) > 0).mean() > 0.5


def test_cli_camera_and_gallery_write_pngs(tmp_path, capsys):
    out = tmp_path / "shots"
    code = main(["camera", "--players-per-team", "2", "--time", "2", "--robot", "0:1", "1:2", "--out", str(out)])
    assert code == 0
    names = sorted(p.name for p in out.iterdir())
    assert names == [
        "t0002.00_team0_player1.png",
        "t0002.00_team0_player1_annotated.png",
        "t0002.00_team1_player2.png",
        "t0002.00_team1_player2_annotated.png",
    ]
    assert main(["gallery", "--out", str(tmp_path / "gallery"), "--size", "160x120"]) == 0
    assert len(list((tmp_path / "gallery").glob("*.png"))) == 10
    assert main(["camera", "--robot", "2:1", "--out", str(out)]) == 2
    assert "does not exist" in capsys.readouterr().err
    assert main(["camera", "--size", "4x4", "--time", "0", "--robot", "0:1", "--out", str(out)]) == 2


def test_cli_video_shows_the_camera_beside_the_field(tmp_path):
    from PIL import Image

    video = tmp_path / "m.gif"
    short = tmp_path / "short.json"  # a short match: the video's layout is what is checked
    short.write_text('{"referee": {"ready_seconds": 3.0, "set_seconds": 1.0, "halftime_seconds": 1.0}}')
    args = ["match", "--players-per-team", "2", "--half-seconds", "2", "--video", str(video), "--video-fps", "2"]
    args += ["--config", str(short)]
    assert main([*args, "--video-robot", "1:2"]) == 0
    with Image.open(video) as im:
        both, n_both = im.size, im.n_frames
    assert main([*args, "--video-robot", "none"]) == 0
    with Image.open(video) as im:
        top_only = im.size
    assert both[0] > 1.5 * top_only[0]  # the camera panel beside the field
    assert both[1] == top_only[1]
    assert n_both > 5


@pytest.mark.parametrize("preset", ["default", "harsh"])
def test_camera_images_render_all_then_apply_effects_with_the_same_result(preset: str) -> None:
    """ImageRenderer.camera_images (all images rendered, then the effects applied to each: the
    match's capture) gives every robot the image camera_image gives it one robot at a time, to
    the bit, through the random numbers of many captures; a penalised robot gets none."""
    match = Match(MatchConfig(seed=3, players_per_team=3, observation="none"))
    field = match.field
    together = ImageRenderer(field, "classic", None, preset, np.random.default_rng(11))
    alone = ImageRenderer(field, "classic", None, preset, np.random.default_rng(11))
    seen = blurred = unseen = 0
    for k in range(12):
        match.run(until=2.0 + 0.7 * k)
        if k == 4:
            match.referee.penalize(0, 2, 5, match.time)  # no image while penalised
        sc = match.scene()
        images = together.camera_images(sc, match.time)
        assert len(images) == sc.observers.shape[0]
        for r, image in enumerate(images):
            if sc.observers[r, OBS.ACTIVE] <= 0.5:
                assert image is None
                unseen += 1
                continue
            one = alone.camera_image(sc, r, match.time)
            assert image is not None and np.array_equal(image.pixels, one.pixels)
            assert (image.time, image.camera_name, image.head_yaw, image.head_pitch) == (
                one.time, one.camera_name, one.head_yaw, one.head_pitch,
            )  # fmt: skip
            assert np.array_equal(image.camera.rotation, one.camera.rotation)
            seen += 1
            o = sc.observers[r]
            blurred += o[OBS.WALK] > 0.5 or abs(o[OBS.YAWR]) + abs(o[OBS.PITCHR]) + abs(sc.turn_rates[r]) > 0.05
    assert seen > 50 and blurred > 5 and unseen >= 7 and match.world.robot(0, 2).penalized
