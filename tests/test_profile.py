"""``teamsim match --profile`` (:mod:`teamsim.profile`, :mod:`cognition.profiling`): the table
accounts for the whole run, names the cognition modules, and profiling changes no result."""

from __future__ import annotations

import io

import pytest

from cognition.pipeline import CognitionConfig
from teamsim.cli import main
from teamsim.match import Match, MatchConfig
from teamsim.referee import RefereeParams

MODULES = [
    "frame start", "input check", "localization", "team messages", "ball model", "ball hypotheses",
    "team ball", "obstacles", "goal model", "beliefs", "behaviour",
]  # fmt: skip
"""The rows of a frame on percepts, in order (no vision module: the frames carry the percepts)."""


def _config(observation: str = "percepts") -> MatchConfig:
    return MatchConfig(
        seed=2, players_per_team=2, observation=observation, cognition=CognitionConfig(),  # type: ignore[arg-type]
        referee=RefereeParams(half_seconds=3.0, ready_seconds=2.0, halftime_seconds=1.0),
    )  # fmt: skip


def test_profiled_match_is_the_same_match_and_its_rows_add_up_to_the_wall_time() -> None:
    plain = Match(_config())
    s_plain = plain.run()
    m = Match(_config(), profile=True)
    s = m.run()
    assert repr(m.snapshot()) == repr(plain.snapshot()) and s.localization == s_plain.localization
    prof = m.profile
    assert prof is not None and plain.profile is None
    assert prof.robot_frames == m.frames * 4  # every brain call of every cognition frame
    rows = dict(prof.rows(m.wall_seconds))
    assert list(prof.modules.seconds)[: len(MODULES)] == MODULES  # the cognition frame's order
    assert "vision" not in prof.modules.seconds
    assert all(v >= 0.0 for v in rows.values())
    assert sum(rows.values()) == pytest.approx(m.wall_seconds, rel=1e-9)
    # the world's stages and the brains hold the run's time, not the leftover
    assert rows["other"] < 0.2 * m.wall_seconds and rows["cognition: localization"] > 0.0
    assert rows["physics"] > 0.0 and rows["camera"] > 0.0
    text = prof.format(m.wall_seconds, m.time)
    assert "cognition: localization" in text and text.splitlines()[-1].split()[-1] == "100.0%"


def test_on_images_the_vision_module_is_timed() -> None:
    m = Match(_config("images"), profile=True)
    m.run(until=4.0)
    assert m.profile is not None
    seconds = m.profile.modules.seconds
    assert list(seconds)[1:4] == ["input check", "vision", "localization"]  # the planned order on images
    assert seconds["vision"] > 0.3 * seconds["localization"]  # on images the vision stage does the work


def test_teamsim_match_profile_prints_the_table() -> None:
    out = io.StringIO()
    argv = ["match", "--half-seconds", "2", "--players-per-team", "1", "--profile", "--quiet"]
    assert main(argv, out=out) == 0
    text = out.getvalue()
    assert "us per robot-frame" in text and "cognition: localization" in text and "match glue" in text
