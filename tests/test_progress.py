"""The live progress line of ``teamsim match`` (:mod:`teamsim.progress`): what it shows, that it
stays off the stream when that is not a terminal, and that it changes nothing in the match."""

from __future__ import annotations

import io
import itertools
import re

import pytest

from teamsim.cli import main
from teamsim.match import Match, MatchConfig
from teamsim.progress import MatchProgress
from teamsim.referee import RefereeParams


class _Terminal(io.StringIO):
    """A text stream that says it is a terminal (tqdm then draws on it)."""

    def isatty(self) -> bool:
        return True


def _config() -> MatchConfig:
    return MatchConfig(
        seed=3, players_per_team=2, referee=RefereeParams(half_seconds=4.0, ready_seconds=2.0, halftime_seconds=1.0)
    )


def test_line_on_a_terminal_follows_the_game_clock_and_is_removed_at_the_end() -> None:
    match = Match(_config())
    term = _Terminal()
    played: list[float] = []
    with MatchProgress(match, stream=term, refresh_seconds=0.0) as progress:
        assert progress.enabled

        def step(m: Match) -> None:
            progress.update(m)
            played.append(progress.played())

        summary = match.run(on_step=step)
        desc, speed = progress.line()
    assert summary.score == tuple(match.referee.score)
    # the game clock over both halves never runs backwards and ends at two halves
    assert all(b >= a for a, b in itertools.pairwise(played))
    assert played[0] == 0.0 and played[-1] == pytest.approx(8.0)
    assert desc.startswith("2nd  0:04") and re.fullmatch(r"\d+\.\dx real time", speed)
    text = term.getvalue()
    assert "1st  0:00 READY" in text and "2nd " in text and "x real time" in text
    assert text.endswith("\r")  # tqdm's leave=False wipes the line: the summary starts on a clean line


def test_not_a_terminal_or_quiet_draws_nothing_and_changes_nothing() -> None:
    quiet_stream = io.StringIO()  # isatty() is False
    a = Match(_config())
    with MatchProgress(a, stream=quiet_stream) as progress:
        assert not progress.enabled
        summary_a = a.run(on_step=progress.update)
    assert quiet_stream.getvalue() == ""
    b = Match(_config())
    with MatchProgress(b, stream=_Terminal(), enabled=False) as progress:
        summary_b = b.run(on_step=progress.update)
    c = Match(_config())
    with MatchProgress(c, stream=_Terminal()) as progress:
        summary_c = c.run(on_step=progress.update)
    for s in (summary_b, summary_c):  # drawing the line does not touch the simulation
        assert s.score == summary_a.score
        assert s.localization == summary_a.localization
        assert s.physics_steps == summary_a.physics_steps


def test_teamsim_match_piped_prints_only_the_summary(capsys: pytest.CaptureFixture[str]) -> None:
    out = io.StringIO()
    assert main(["match", "--half-seconds", "2", "--players-per-team", "1"], out=out) == 0
    assert capsys.readouterr().err == ""  # pytest's stderr is no terminal: no progress line
    assert out.getvalue().startswith("teamsim match")
