"""When a player may send its next team message: the team's budget spread over the game.

SPL teams may send at most 1200 messages per game (:data:`cognition.gamestate.TEAM_MESSAGE_BUDGET`),
and the GameController counts down what is left (``TeamInfo.message_budget``). A player
sends only while PLAYING, at an interval that spreads the team's remaining budget over
the remaining game time, each player taking its share, and never faster than a minimum
interval:

    interval = max(min_interval, remaining game seconds * players per team / remaining budget)

The remaining game time counts the second half during the first half (``secs_remaining``
doubled). Used by :class:`~cognition.behaviors.team_play.ScriptedBrain` and
:class:`~cognition.behaviors.actions.PolicyBrain`.
"""

from __future__ import annotations

from cognition.gamestate import GameControlData, GameStateId


def message_due(
    game: GameControlData,
    team_number: int,
    players_per_team: int,
    now: float,
    last_sent: float,
    min_interval: float = 1.0,
) -> bool:
    """Whether a player that last sent at ``last_sent`` (s) should send at ``now`` (s)."""
    if game.state != GameStateId.PLAYING:
        return False
    budget = game.team(team_number).message_budget
    if budget <= 0:
        return False
    remaining = max(1.0, float(game.secs_remaining) * (2.0 if game.first_half else 1.0))
    interval = max(min_interval, remaining * players_per_team / budget)
    return now - last_sent >= interval
