"""The team-message channel: SPL-style UDP broadcast inside a team, with delay, loss, budget.

A robot broadcasts a message of at most 128 bytes to its teammates (in the real league on
UDP port 10000 + team number). Each receiver gets its copy after ``delay`` plus a uniform
jitter, unless that copy is lost (independently per receiver, probability ``loss``). Every
team has a budget of messages for the whole game (1200 by default, as the SPL rules set);
a message sent with an exhausted budget is not delivered and is counted as refused.

=============  =======  ============  ======================================================
parameter      default  range         meaning
=============  =======  ============  ======================================================
delay          0.05 s   [0, 60]       fixed part of the delivery delay
jitter         0.05 s   [0, 60]       extra delay drawn uniformly from [0, jitter]
loss           0.05     [0, 1]        probability that one receiver's copy is lost
budget         1200     [0, 1000000]  messages per team per game
=============  =======  ============  ======================================================

Every value is checked against its range when the parameters are built
(:func:`cognition.params.check_ranges`).
"""

from __future__ import annotations

import heapq
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from cognition.gamestate import TEAM_MESSAGE_BUDGET, TEAM_MESSAGE_MAX_BYTES
from cognition.representations import TeamMessageIn
from teamsim.params import PROBABILITY, Range, Ranges, check_ranges, non_negative


@dataclass(frozen=True)
class ChannelParams:
    """Delivery model of the team channel (see module table)."""

    delay: float = 0.05
    jitter: float = 0.05
    loss: float = 0.05
    budget: int = TEAM_MESSAGE_BUDGET

    RANGES: ClassVar[Ranges] = {
        "delay": non_negative(60.0),
        "jitter": non_negative(60.0),
        "loss": PROBABILITY,
        "budget": Range(0, 1_000_000),
    }

    def __post_init__(self) -> None:
        check_ranges(self)


@dataclass
class ChannelStats:
    """Counters of one team's traffic."""

    sent: int = 0
    """Messages accepted within the budget."""
    refused: int = 0
    """Messages refused because the budget was exhausted."""
    lost: int = 0
    """Receiver copies lost in transit."""
    delivered: int = 0
    """Receiver copies delivered."""


@dataclass(order=True)
class _Pending:
    deliver_at: float
    seq: int
    receiver: int = field(compare=False)
    message: TeamMessageIn = field(compare=False)


class TeamChannel:
    """Broadcast channel for two teams of ``players_per_team`` robots."""

    def __init__(self, params: ChannelParams, players_per_team: int, rng: np.random.Generator):
        self.params = params
        self.players_per_team = players_per_team
        self.rng = rng
        self._queues: list[list[_Pending]] = [[], []]
        self._seq = 0
        self.budget_left = [params.budget, params.budget]
        self.stats = [ChannelStats(), ChannelStats()]
        self.taps: list[Callable[[int, int, bytes, float], None]] = []
        """Called as ``tap(team, sender, payload, now)`` for every message accepted within the
        budget, before delivery (the GameController bridge mirrors them onto UDP)."""

    def send(self, team: int, sender: int, payload: bytes, now: float) -> bool:
        """Broadcast ``payload`` from player ``sender`` of ``team``; False if refused."""
        if not isinstance(payload, bytes | bytearray):
            raise TypeError(f"team message must be bytes, got {type(payload).__name__}")
        if len(payload) > TEAM_MESSAGE_MAX_BYTES:
            raise ValueError(f"team message has {len(payload)} bytes; at most {TEAM_MESSAGE_MAX_BYTES} allowed")
        if not 1 <= sender <= self.players_per_team:
            raise ValueError(f"sender must be a player number 1..{self.players_per_team}")
        stats = self.stats[team]
        if self.budget_left[team] <= 0:
            stats.refused += 1
            return False
        self.budget_left[team] -= 1
        stats.sent += 1
        msg = TeamMessageIn(sender=sender, payload=bytes(payload), sent_at=now)
        for tap in self.taps:
            tap(team, sender, msg.payload, now)
        p = self.params
        for receiver in range(1, self.players_per_team + 1):
            if receiver == sender:
                continue
            lost = self.rng.random() < p.loss
            jitter = self.rng.random() * p.jitter
            if lost:
                stats.lost += 1
                continue
            self._seq += 1
            heapq.heappush(self._queues[team], _Pending(now + p.delay + jitter, self._seq, receiver, msg))
        return True

    def receive(self, team: int, now: float) -> dict[int, list[TeamMessageIn]]:
        """Pop every copy due by ``now`` for ``team``, grouped by receiving player number."""
        out: dict[int, list[TeamMessageIn]] = {}
        q = self._queues[team]
        while q and q[0].deliver_at <= now:
            item = heapq.heappop(q)
            out.setdefault(item.receiver, []).append(item.message)
            self.stats[team].delivered += 1
        return out
