"""teamsim: the simulated world (ground truth) of teams of SPL-style soccer robots.

Physics (pymunk), robots, ball, referee and game controller, scripted events, the team
channel and the match loop live here. The robots' brains live in :mod:`cognition`.
"""

from cognition.kernel_cache import install as _install_kernel_cache

_install_kernel_cache(["teamsim"])  # before any kernel is defined (cognition.kernel_cache)

from teamsim.match import Match, MatchConfig, MatchSummary  # noqa: E402

__all__ = ["Match", "MatchConfig", "MatchSummary"]
__version__ = "0.1.0"
