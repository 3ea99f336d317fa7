"""Tests of the top-down renderer (teamsim.render) and the streaming video writer (teamsim.render, teamsim.video)."""

from __future__ import annotations

import dataclasses
import math
import tracemalloc
from pathlib import Path

import cv2
import hypothesis.extra.numpy as hnp
import hypothesis.strategies as st
import numpy as np
import pytest
from hypothesis import given, settings
from PIL import Image

import teamsim.render as render_module
from cognition.field import make_colour_scheme, make_field
from cognition.gamestate import GameControlData, GameStateId, TeamInfo
from teamsim.render import HEADER_HEIGHT, Overlay, TopDownRenderer, VideoWriter
from teamsim.state import RobotTruth, WorldSnapshot
from teamsim.video import VideoError

PPM = 50.0
RED, BLUE = (255, 0, 0), (0, 0, 255)


@pytest.fixture(scope="module")
def field():
    return make_field("spl2025")


@pytest.fixture(scope="module")
def scheme():
    base = make_colour_scheme("modern")
    return dataclasses.replace(base, team_colours=(RED, BLUE))


@pytest.fixture(scope="module")
def renderer(field, scheme):
    return TopDownRenderer(field, scheme, pixels_per_metre=PPM)


def expected_pixel(field, x: float, y: float, ppm: float = PPM) -> tuple[int, int]:
    """(row, col) of the pixel containing world point (x, y), computed independently."""
    b = field.dims.border_strip
    col = (x + field.dims.length / 2 + b) * ppm
    row = HEADER_HEIGHT + (field.dims.width / 2 + b - y) * ppm
    return math.floor(row), math.floor(col)


def snap(*robots: RobotTruth, ball=(1.0, -1.0), time: float = 0.0) -> WorldSnapshot:
    return WorldSnapshot(time=time, robots=tuple(robots), ball_x=ball[0], ball_y=ball[1])


def changed_centroid(frame: np.ndarray, background: np.ndarray) -> tuple[float, float]:
    """(row, col) centroid of pixels below the header that differ from the background."""
    diff = np.any(frame != background, axis=2)
    diff[:HEADER_HEIGHT] = False
    rows, cols = np.nonzero(diff)
    assert rows.size > 0
    return float(rows.mean()), float(cols.mean())


def test_output_dtype_shape_and_contiguity(renderer, field):
    img = renderer.render(snap())
    d = field.dims
    w = round((d.length + 2 * d.border_strip) * PPM)
    h = HEADER_HEIGHT + round((d.width + 2 * d.border_strip) * PPM)
    assert img.dtype == np.uint8
    assert img.shape == (h, w, 3) == (renderer.height, renderer.width, 3)
    assert img.flags["C_CONTIGUOUS"]


def test_team_colour_in_rgb_order_and_y_up(renderer, field):
    robot = RobotTruth(team=0, number=2, x=2.0, y=1.5, theta=0.0)
    r = TopDownRenderer(field, renderer.scheme, pixels_per_metre=100.0)
    img = r.render(snap(robot))
    # 0.1 m behind the robot (heading +x): inside the disc, clear of number and heading line.
    row, col = expected_pixel(field, 1.9, 1.5, ppm=100.0)
    assert tuple(img[row, col]) == RED
    # +y is up on screen: the robot's row is above the field's centre row.
    assert row < expected_pixel(field, 0.0, 0.0, ppm=100.0)[0]
    away = RobotTruth(team=1, number=3, x=-2.0, y=-1.5, theta=0.0)
    img = r.render(snap(away))
    assert tuple(img[expected_pixel(field, -2.1, -1.5, ppm=100.0)]) == BLUE


def test_ball_colour_and_position(renderer, field, scheme):
    bg = renderer.background
    for bx, by in ((1.0, -1.0), (-2.2, 0.7), (3.3, 2.4)):
        img = renderer.render(snap(ball=(bx, by)))
        row, col = expected_pixel(field, bx, by)
        assert tuple(img[row, col]) == tuple(scheme.ball_primary)
        crow, ccol = changed_centroid(img, bg)
        # pixel centres sit at index + 0.5 in the continuous coordinates of expected_pixel
        b = field.dims.border_strip
        exp_col = (bx + field.dims.length / 2 + b) * PPM - 0.5
        exp_row = HEADER_HEIGHT + (field.dims.width / 2 + b - by) * PPM - 0.5
        assert abs(crow - exp_row) <= 1.0 and abs(ccol - exp_col) <= 1.0


def test_tiny_ball_has_minimum_radius(field, scheme):
    r = TopDownRenderer(field, scheme, pixels_per_metre=5.0)
    img = r.render(snap(ball=(1.0, -1.0)))
    diff = np.any(img != r.background, axis=2)
    diff[:HEADER_HEIGHT] = False
    assert diff.sum() >= 20  # a disc of radius >= 3 px covers about 28 pixels


def test_background_is_cached_and_not_mutated(renderer):
    before = renderer.background.copy()
    s = snap(RobotTruth(team=0, number=1, x=0.5, y=0.5, theta=1.0), time=12.5)
    a = renderer.render(s)
    b = renderer.render(s)
    assert np.array_equal(a, b)
    assert a is not b and not np.shares_memory(a, renderer.background)
    assert np.array_equal(renderer.background, before)
    assert not renderer.background.flags.writeable
    assert renderer.background is renderer.background


def test_lines_are_white_and_carpet_is_green(renderer, field, scheme):
    img = renderer.render(snap())
    halfway = img[expected_pixel(field, 0.0, 1.0)]
    assert np.all(halfway > 200), halfway
    goal_line = img[expected_pixel(field, -field.half_length, 2.5)]
    assert np.all(goal_line > 200), goal_line
    assert tuple(img[expected_pixel(field, -2.0, 1.5)]) == tuple(scheme.field_green)
    assert tuple(img[expected_pixel(field, 2.0, -1.5)]) == tuple(scheme.field_green)


def test_robot_states_are_drawn_differently(renderer, field):
    base = RobotTruth(team=0, number=3, x=-1.5, y=-1.0, theta=0.0)
    at = expected_pixel(field, -1.5 - 0.09, -1.0)
    plain = renderer.render(snap(base))
    assert tuple(plain[at]) == RED
    penalized = renderer.render(snap(dataclasses.replace(base, penalized=True)))
    px = penalized[at].astype(int)
    assert px[0] == px[1] == px[2], "penalized robots are grey"
    fallen = renderer.render(snap(dataclasses.replace(base, fallen=True)))
    assert not np.array_equal(fallen, plain)
    picked = renderer.render(snap(dataclasses.replace(base, picked_up=True)))
    yellow = np.all(picked == (255, 255, 0), axis=2).sum()
    assert yellow > 20 and np.all(plain == (255, 255, 0), axis=2).sum() == 0
    keeper = renderer.render(snap(dataclasses.replace(base, number=1)))
    assert not np.array_equal(keeper, plain)


def test_game_penalty_greys_robot(renderer, field):
    robot = RobotTruth(team=1, number=2, x=1.0, y=1.0, theta=0.0)
    teams = (TeamInfo(team_number=1), TeamInfo(team_number=2))
    players = list(teams[1].players)
    players[1] = dataclasses.replace(players[1], penalty=5)
    game = GameControlData(teams=(teams[0], dataclasses.replace(teams[1], players=tuple(players))))
    px = renderer.render(snap(robot), game)[expected_pixel(field, 0.91, 1.0)].astype(int)
    assert px[0] == px[1] == px[2]


def test_header_shows_game_and_leaves_field_untouched(renderer):
    s = snap(time=3.0)
    plain = renderer.render(s)
    game = GameControlData(state=GameStateId.PLAYING, secs_remaining=125)
    with_game = renderer.render(s, game)
    scored = renderer.render(s, game.with_changes(teams=(TeamInfo(score=2), TeamInfo())))
    for img in (with_game, scored):
        assert np.array_equal(img[HEADER_HEIGHT:], plain[HEADER_HEIGHT:])
    assert not np.array_equal(with_game[:HEADER_HEIGHT], plain[:HEADER_HEIGHT])
    assert not np.array_equal(scored[:HEADER_HEIGHT], with_game[:HEADER_HEIGHT])
    later = renderer.render(snap(time=4.0), game)
    assert not np.array_equal(later[:HEADER_HEIGHT], with_game[:HEADER_HEIGHT])


def test_overlays(renderer, field):
    cyan = (0, 255, 255)
    img = renderer.render(snap(), overlays=[Overlay(x=-1.0, y=2.0, colour=cyan, label="est")])
    assert tuple(img[expected_pixel(field, -1.0, 2.0)]) == cyan
    arrow = renderer.render(snap(), overlays=[Overlay(x=-1.0, y=2.0, colour=cyan, theta=0.0)])
    assert tuple(arrow[expected_pixel(field, -0.85, 2.0)]) == cyan
    with pytest.raises(ValueError, match="colour"):
        Overlay(x=0.0, y=0.0, colour=(300, 0, 0))


@pytest.mark.parametrize("ppm", [0.0, 4.9, 401.0, -60.0, math.nan, math.inf])
def test_bad_pixels_per_metre(field, scheme, ppm):
    with pytest.raises(ValueError, match="pixels_per_metre"):
        TopDownRenderer(field, scheme, pixels_per_metre=ppm)


def frames(renderer, n: int) -> list[np.ndarray]:
    return [renderer.render(snap(ball=(-2.0 + 0.5 * i, 0.5), time=i / 15)) for i in range(n)]


def test_mp4_round_trip(renderer, tmp_path):
    path = tmp_path / "nested" / "dir" / "match.mp4"
    with VideoWriter(path, fps=10.0) as vw:
        for f in frames(renderer, 6):
            vw.write(f)
    assert path.exists() and path.stat().st_size > 0
    cap = cv2.VideoCapture(str(path))
    try:
        count = 0
        while True:
            ok, frame = cap.read()
            if not ok:
                break
            assert frame.shape == (renderer.height, renderer.width, 3)
            count += 1
    finally:
        cap.release()
    assert count == 6


def test_gif_round_trip(renderer, tmp_path):
    path = tmp_path / "out" / "match.gif"
    with VideoWriter(path, fps=20.0) as vw:
        for f in frames(renderer, 4):
            vw.write(f)
    with Image.open(path) as im:
        assert im.n_frames == 4
        assert im.size == (renderer.width // 2, renderer.height // 2)
        assert im.info["duration"] == 50 and im.info["loop"] == 0


def test_video_writer_errors(renderer, tmp_path):
    with pytest.raises(ValueError, match=r"\.mp4.*\.gif"):
        VideoWriter(tmp_path / "clip.avi")
    with pytest.raises(ValueError, match="fps"):
        VideoWriter(tmp_path / "clip.mp4", fps=0)
    for suffix in (".mp4", ".gif"):
        vw = VideoWriter(tmp_path / f"clip{suffix}")
        vw.write(renderer.render(snap()))
        with pytest.raises(ValueError, match="shape"):
            vw.write(np.zeros((10, 10, 3), np.uint8))
        vw.close()
        with pytest.raises(RuntimeError, match="closed"):
            vw.write(renderer.render(snap()))


# -- streaming GIF: bounded memory, faithful frames and timing, paths checked at once ------------


def gif_frames(path) -> list[tuple[np.ndarray, int]]:
    """Every frame of a GIF file as (RGB array, duration in ms), decoded by Pillow."""
    out = []
    with Image.open(path) as im:
        for k in range(im.n_frames):
            im.seek(k)
            out.append((np.asarray(im.convert("RGB")), im.info["duration"]))
    return out


def test_gif_writer_memory_is_bounded_by_a_few_frames(tmp_path):
    h, w = 480, 640
    rows, cols = np.mgrid[0:h, 0:w]
    base = np.stack([cols * 255 // w, rows * 255 // h, np.full_like(cols, 90)], axis=2).astype(np.uint8)
    del rows, cols
    path = tmp_path / "long.gif"
    size_halfway = 0
    tracemalloc.start()
    try:
        vw = VideoWriter(path, fps=10.0)
        for i in range(400):
            frame = base.copy()
            r, c = (7 * i) % (h - 60), (11 * i) % (w - 80)
            frame[r : r + 60, c : c + 80] = (255 - 3 * (i % 50), 40, 200)
            vw.write(frame)
            del frame
            if i == 199:
                size_halfway = path.stat().st_size if path.exists() else 0
        _, peak = tracemalloc.get_traced_memory()
        vw.close()
    finally:
        tracemalloc.stop()
    # a writer that kept its 400 half-size frames would hold 100 input frames' worth of bytes
    assert peak < 4 * base.nbytes, f"peak {peak / base.nbytes:.1f} frames of {base.nbytes} bytes"
    assert size_halfway > 0.3 * path.stat().st_size  # the first half was on disk before the end
    with Image.open(path) as im:
        assert im.n_frames == 400 and im.size == (w // 2, h // 2)


def test_gif_decodes_to_the_frames_with_their_timing(renderer, tmp_path):
    path = tmp_path / "match.gif"
    fps = 15.0
    shots = frames(renderer, 7)
    with VideoWriter(path, fps=fps) as vw:
        for f in shots:
            vw.write(f)
    decoded = gif_frames(path)
    assert len(decoded) == len(shots)
    size = (renderer.width // 2, renderer.height // 2)
    with Image.open(path) as im:
        assert im.size == size and im.info["loop"] == 0
    for (got, _), sent in zip(decoded, shots, strict=True):
        want = cv2.resize(sent, size, interpolation=cv2.INTER_AREA).astype(int)
        err = np.abs(got.astype(int) - want)
        assert err.mean() < 0.5 and np.percentile(err, 99) <= 8, (err.mean(), np.percentile(err, 99))
    # 1/15 s is not a whole number of centiseconds: 6 and 7 cs alternate so that frame i starts
    # at round(i * 100 / 15) cs and seven frames last 47 cs, not 7 * 6 or 7 * 7
    durations = [d for _, d in decoded]
    assert set(durations) == {60, 70}
    assert np.cumsum(durations).tolist() == [10 * round((i + 1) * 100 / fps) for i in range(7)]


def test_gif_identical_frames_lengthen_the_previous_frame(renderer, tmp_path):
    a, b = frames(renderer, 2)
    path = tmp_path / "still.gif"
    with VideoWriter(path, fps=10.0) as vw:
        for f in (a, a, a, b, b, a):
            vw.write(f)
    assert vw.frame_count == 6
    decoded = gif_frames(path)
    assert [d for _, d in decoded] == [300, 200, 100]
    # the last frame returns to the first picture (each block has its own palette: near, not equal)
    back = np.abs(decoded[2][0].astype(int) - decoded[0][0].astype(int))
    assert back.mean() < 0.5
    assert np.abs(decoded[1][0].astype(int) - decoded[0][0].astype(int)).mean() > 2 * back.mean()


few_colour_clips = st.tuples(st.integers(1, 12), st.integers(1, 12), st.integers(1, 6)).flatmap(
    lambda hwn: st.lists(
        hnp.arrays(np.uint8, (hwn[0], hwn[1]), elements=st.integers(0, 5)), min_size=hwn[2], max_size=hwn[2]
    )
)


@settings(max_examples=60, deadline=None)
@given(clip=few_colour_clips, repeats=st.lists(st.booleans(), min_size=6, max_size=6), fps=st.floats(0.5, 100.0))
def test_gif_of_few_colours_decodes_exactly(tmp_path_factory, clip, repeats, fps):
    palette = np.array([(0, 0, 0), (255, 255, 255), (200, 30, 30), (30, 160, 60), (20, 40, 220), (250, 200, 0)])
    sent: list[np.ndarray] = []
    for k, indices in enumerate(clip):
        sent.append(sent[-1] if repeats[k] and sent else palette[indices].astype(np.uint8))
    path = tmp_path_factory.mktemp("gif") / "clip.gif"
    with VideoWriter(path, fps=fps, gif_scale=1) as vw:
        for f in sent:
            vw.write(f)
    starts = [k for k in range(len(sent)) if k == 0 or not np.array_equal(sent[k], sent[k - 1])]
    decoded = gif_frames(path)
    assert len(decoded) == len(starts)
    ends = [*starts[1:], len(sent)]
    for (got, duration), first, end in zip(decoded, starts, ends, strict=True):
        assert np.array_equal(got, sent[first])  # <= 256 colours: the palette is exact
        assert duration == 10 * (round(end * 100 / fps) - round(first * 100 / fps))


def test_gif_delay_limits(renderer, tmp_path):
    a, b = frames(renderer, 2)
    slow = tmp_path / "slow.gif"
    with VideoWriter(slow, fps=0.001) as vw:  # 1000 s a frame: beyond the 655.35 s a GIF delay holds
        vw.write(a)
        vw.write(b)
    durations = [d for _, d in gif_frames(slow)]
    assert sum(durations) == 2_000_000 and max(durations) == 655_350
    fast = tmp_path / "fast.gif"
    with VideoWriter(fast, fps=400.0) as vw:  # a delay is at least one centisecond
        for f in (a, b, a, b):
            vw.write(f)
    assert [d for _, d in gif_frames(fast)] == [10, 10, 10, 10]


@pytest.mark.parametrize("suffix", [".gif", ".mp4"])
def test_unwritable_video_path_fails_in_the_constructor(tmp_path, suffix):
    blocker = tmp_path / "notes.txt"
    blocker.write_text("a file, not a directory")
    bad = {
        blocker / f"clip{suffix}": "not a directory",
        blocker / "deeper" / f"clip{suffix}": "Not a directory",
        tmp_path / f"folder{suffix}": "Is a directory",
    }
    (tmp_path / f"folder{suffix}").mkdir()
    for path, reason in bad.items():
        with pytest.raises(VideoError) as info:
            VideoWriter(path)
        assert isinstance(info.value, OSError)
        assert str(path) in str(info.value) and reason in str(info.value)


@pytest.mark.parametrize("suffix", [".gif", ".mp4"])
def test_writer_without_frames_leaves_no_file_and_spares_an_existing_one(tmp_path, suffix):
    fresh = tmp_path / "new" / f"clip{suffix}"
    VideoWriter(fresh).close()
    assert not fresh.exists() and fresh.parent.is_dir()
    old = tmp_path / f"old{suffix}"
    old.write_bytes(b"an earlier video")
    VideoWriter(old).close()
    assert old.read_bytes() == b"an earlier video"


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full to simulate a full disk")
def test_gif_on_a_full_disk_raises_video_error_naming_the_file(renderer, tmp_path):
    path = tmp_path / "full.gif"
    path.symlink_to("/dev/full")
    vw = VideoWriter(path)
    with pytest.raises(VideoError, match=r"full\.gif.*No space left on device"):
        for f in frames(renderer, 20):
            vw.write(f)
    with pytest.raises(VideoError, match="failed earlier"):
        vw.write(frames(renderer, 1)[0])
    vw.close()  # releases the file without raising again
    with pytest.raises(RuntimeError, match="closed"):
        vw.write(frames(renderer, 1)[0])


def test_mp4_encoder_that_cannot_open_is_a_video_error(renderer, tmp_path, monkeypatch):
    class ClosedEncoder:
        def __init__(self, *args: object) -> None:
            pass

        def isOpened(self) -> bool:
            return False

    monkeypatch.setattr(render_module.cv2, "VideoWriter", ClosedEncoder)
    path = tmp_path / "clip.mp4"
    vw = VideoWriter(path)
    with pytest.raises(VideoError, match=r"mp4v.*clip\.mp4"):
        vw.write(frames(renderer, 1)[0])
    vw.close()
    assert not path.exists()
