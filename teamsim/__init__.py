"""teamsim: the simulated world (ground truth) of teams of SPL-style soccer robots.

Physics (pymunk), robots, ball, referee and game controller, scripted events, the team
channel and the match loop live here. The robots' brains live in :mod:`cognition`.
"""

from teamsim.match import Match, MatchConfig, MatchSummary

__all__ = ["Match", "MatchConfig", "MatchSummary"]
__version__ = "0.1.0"
