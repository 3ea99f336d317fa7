"""Live progress line of a running match: game clock, score and real-time factor.

``teamsim match`` plays for minutes; on a terminal this draws one line on stderr (tqdm), kept
up to date while the match runs and removed when it ends, so the summary that follows stands
alone. When stderr is not a terminal (piped, redirected, a CI log) nothing is drawn.

======================  ========================================================================
shown                   meaning
======================  ========================================================================
``1st``/``2nd`` mm:ss   the half being played and its game clock, and the game state when it is
                        not PLAYING
score                   goals of team 0 : team 1
``x real time``         simulated seconds per wall-clock second since the match started
bar                     game clock played of both halves (it stops in READY, SET, at half time
                        and in stoppages)
played, left            wall-clock time so far and tqdm's estimate of the wall time left (from
                        the rate of game clock so far)
======================  ========================================================================

The line is refreshed at most every :data:`REFRESH_SECONDS` of wall time and looked at every
:data:`CHECK_STEPS` physics steps, which costs well under a microsecond per step.
"""

from __future__ import annotations

import sys
import time
from typing import TextIO

from tqdm import tqdm

from teamsim.match import Match

REFRESH_SECONDS = 0.5
"""Wall-clock seconds between two redraws of the line."""
CHECK_STEPS = 50
"""Physics steps between two looks at the match (0.5 s of simulated time at 100 Hz)."""
_STATES = ("INITIAL", "READY", "SET", "PLAYING", "FINISHED", "STANDBY")


class MatchProgress:
    """The progress line of one match; call :meth:`update` after every physics step (it is an
    ``on_step`` callback of :meth:`Match.run`) and :meth:`close` at the end (or use ``with``).

    ``enabled``: draw the line (default: only when ``stream`` is a terminal); ``stream``:
    where to draw (default stderr); ``refresh_seconds``: least wall time between two redraws."""

    def __init__(
        self,
        match: Match,
        stream: TextIO | None = None,
        enabled: bool | None = None,
        refresh_seconds: float = REFRESH_SECONDS,
    ) -> None:
        self.match = match
        self.refresh_seconds = refresh_seconds
        self.stream = stream if stream is not None else sys.stderr
        if enabled is None:
            isatty = getattr(self.stream, "isatty", None)
            enabled = bool(isatty is not None and isatty())
        self.enabled = enabled
        self.half_seconds = match.config.referee.half_seconds
        self._start_wall = time.perf_counter()
        self._start_sim = match.time
        self._last_draw = -1e300
        self._bar: tqdm | None = None
        if enabled:
            self._bar = tqdm(
                total=round(2 * self.half_seconds),
                file=self.stream,
                leave=False,
                dynamic_ncols=True,
                mininterval=refresh_seconds,
                bar_format="{desc} |{bar}| {elapsed} played, ~{remaining} left",
            )
            self._draw()

    def played(self) -> float:
        """Game-clock seconds played so far over both halves (s)."""
        ref = self.match.referee
        half = 0 if ref.first_half else 1
        return half * self.half_seconds + max(0.0, self.half_seconds - ref.secs_remaining)

    def line(self) -> tuple[str, str]:
        """The line's text before the bar (half, clock, state, score) and after it (speed)."""
        m = self.match
        ref = m.referee
        played = self.played()
        clock = played - (0.0 if ref.first_half else self.half_seconds)
        minutes, seconds = divmod(int(clock), 60)
        state = int(ref.state)
        name = _STATES[state] if 0 <= state < len(_STATES) else str(state)
        half = "1st" if ref.first_half else "2nd"
        status = "" if name == "PLAYING" else f" {name}"
        wall = time.perf_counter() - self._start_wall
        factor = (m.time - self._start_sim) / wall if wall > 0.0 else 0.0
        return (
            f"{half} {minutes:2d}:{seconds:02d}{status}  {ref.score[0]}:{ref.score[1]}",
            f"{factor:.1f}x real time",
        )

    def update(self, match: Match | None = None) -> None:
        """Look at the match (every :data:`CHECK_STEPS` physics steps) and redraw when due."""
        if self._bar is None or self.match.steps % CHECK_STEPS != 0:
            return
        now = time.perf_counter()
        if now - self._last_draw >= self.refresh_seconds:
            self._draw()

    def _draw(self) -> None:
        bar = self._bar
        if bar is None:
            return
        self._last_draw = time.perf_counter()
        bar.set_description_str("  ".join(self.line()), refresh=False)
        bar.n = min(round(self.played()), bar.total)
        bar.refresh()

    def close(self) -> None:
        """Remove the line (the terminal is left as it was before the match)."""
        if self._bar is not None:
            self._bar.close()
            self._bar = None

    def __enter__(self) -> MatchProgress:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
