"""``teamsim match --video``: a bad video path fails before the match, a failing video never costs the results."""

from __future__ import annotations

import errno
import json
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from teamsim.cli import main
from teamsim.match import Match
from teamsim.render import TopDownRenderer, VideoWriter
from teamsim.video import GifStream

TINY = [
    "match",
    "--half-seconds",
    "2",
    "--players-per-team",
    "1",
    "--localization",
    "none",
    "--observation",
    "none",
    "--video-robot",
    "none",
    "--video-fps",
    "2",
]


def unwritable(tmp_path: Path, kind: str, suffix: str) -> Path:
    """A video path that cannot be created, of the given kind."""
    if kind == "directory":
        path = tmp_path / f"taken{suffix}"
        path.mkdir()
        return path
    blocker = tmp_path / "blocker.txt"
    blocker.write_text("a file where a directory should be")
    return blocker / "videos" / f"m{suffix}" if kind == "under-a-file" else blocker / f"m{suffix}"


@pytest.mark.parametrize("suffix", [".gif", ".mp4"])
@pytest.mark.parametrize("kind", ["directory", "parent-is-a-file", "under-a-file"])
def test_unwritable_video_path_exits_2_before_the_match(tmp_path, capsys, monkeypatch, kind, suffix):
    def no_match(self: Match, *args: object, **kwargs: object) -> None:
        raise AssertionError("the match ran although the video path cannot be written")

    monkeypatch.setattr(Match, "run", no_match)
    video = unwritable(tmp_path, kind, suffix)
    out = tmp_path / "run"
    code = main([*TINY, "--video", str(video), "--out", str(out)])
    captured = capsys.readouterr()
    assert code == 2
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in captured.err
    assert lines[0].startswith("teamsim match: error:") and str(video) in lines[0]
    assert not out.exists()  # nothing of the run was written
    assert captured.out == ""


def fail_after(frames: int, exc: Exception):
    """A VideoWriter.write that writes ``frames`` frames and then raises ``exc``."""
    original = VideoWriter.write

    def write(self: VideoWriter, frame: np.ndarray) -> None:
        if self.frame_count >= frames:
            raise exc
        original(self, frame)

    return write


def _wall(summary: dict) -> dict:
    """The wall-clock entries of a summary (they differ from run to run)."""
    return {k: v for k, v in summary.items() if "wall" in k or "real_time" in k}


def test_video_failing_mid_match_keeps_the_summary_and_exits_1(tmp_path, capsys, monkeypatch):
    reference = tmp_path / "reference"
    assert main([*TINY[: TINY.index("--video-robot")], "--out", str(reference)]) == 0
    capsys.readouterr()

    monkeypatch.setattr(VideoWriter, "write", fail_after(3, OSError(errno.ENOSPC, "No space left on device")))
    video, out = tmp_path / "m.gif", tmp_path / "run"
    code = main([*TINY, "--video", str(video), "--out", str(out)])
    captured = capsys.readouterr()
    assert code == 1
    assert "final score" in captured.out and "video written" not in captured.out
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in captured.err
    assert str(video) in lines[0] and "after 3 frames" in lines[0] and "No space left on device" in lines[0]
    summary = json.loads((out / "summary.json").read_text())
    assert summary == {**json.loads((reference / "summary.json").read_text()), **_wall(summary)}
    # the match ran to the end, exactly as without a video
    assert (out / "events.jsonl").read_text() == (reference / "events.jsonl").read_text()
    with Image.open(video) as im:  # what was written before the failure is a valid, shorter video
        assert im.n_frames == 3


@pytest.mark.parametrize("where", ["finish", "render"])
def test_video_failing_at_the_end_or_in_rendering_keeps_the_summary(tmp_path, capsys, monkeypatch, where):
    if where == "finish":

        def finish(self: GifStream) -> None:
            raise OSError(errno.EIO, "Input/output error")

        monkeypatch.setattr(GifStream, "finish", finish)
        expected = "Input/output error"
    else:
        original = TopDownRenderer.render
        calls = [0]

        def render(self: TopDownRenderer, *args: object, **kwargs: object) -> np.ndarray:
            calls[0] += 1
            if calls[0] > 2:
                raise ValueError("Belief pose must be finite, got (nan, 0.0, 0.0)")
            return original(self, *args, **kwargs)

        monkeypatch.setattr(TopDownRenderer, "render", render)
        expected = "ValueError: Belief pose must be finite"
    video, out = tmp_path / "m.gif", tmp_path / "run"
    code = main([*TINY, "--video", str(video), "--out", str(out)])
    captured = capsys.readouterr()
    assert code == 1
    assert "final score" in captured.out
    assert (out / "summary.json").is_file()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and str(video) in lines[0] and expected in lines[0]


def test_video_on_a_full_disk_keeps_the_summary(tmp_path, capsys):
    if not Path("/dev/full").exists():
        pytest.skip("needs /dev/full to simulate a full disk")
    video, out = tmp_path / "full.gif", tmp_path / "run"
    video.symlink_to("/dev/full")
    code = main([*TINY, "--video", str(video), "--out", str(out)])
    captured = capsys.readouterr()
    assert code == 1
    assert "final score" in captured.out and (out / "summary.json").is_file()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and "full.gif" in lines[0] and "No space left on device" in lines[0]
