"""The policy observation: a fixed-size vector built from one robot's :class:`Beliefs`.

Everything a learned policy sees comes from its robot's beliefs (the world model, or the oracle
providers in ``truth`` mode), never from the simulator. Every entry is scaled to [-1, 1] and
clipped there; distances are divided by the field length ``L`` (9 m on the SPL 2025 field),
field positions by the half length ``HL`` and half width ``HW``.

=====  ==========================================================================================
index  entry
=====  ==========================================================================================
0-3    own pose (team frame): x / HL, y / HW, cos theta, sin theta
4-6    pose uncertainty: position std / 2 m, heading std / pi, ``lost`` flag
7-8    own ball, robot frame: x / L, y / L
9-10   own ball velocity, robot frame: vx / 3, vy / 3 (m/s)
11-13  ball level one-hot: valid, suspicious, invalid
14     ball age: min(age, 10 s) / 10
15-16  own ball, team frame: x / HL, y / HW (0 when unknown)
17-19  team ball known flag; team ball in the robot frame: x / L, y / L
20-23  opponent goal centre and own goal centre in the robot frame (from the pose): x / L, y / L
24-26  goal model: confidence; the seen goal's centre in the robot frame: x / L, y / L
27-31  game state one-hot: INITIAL (and STANDBY), READY, SET, PLAYING, FINISHED
32-36  own team kicks off / has the set play; a set play is on; secondary clock / 30 s;
       half time remaining / 600 s; goal difference / 5
37-40  own penalty flag; seconds till return / 45; fallen; is the goalkeeper (player 1)
41-    per teammate slot (``players_per_team - 1`` slots, by player number): present, x / L,
       y / L (robot frame), active (not fallen, not penalised), age / 3 s
then   the ``OBSTACLE_SLOTS`` nearest obstacles, nearest first: present, x / 3 m, y / 3 m
=====  ==========================================================================================
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np
from numpy.typing import NDArray

from cognition.field import Field
from cognition.gamestate import GameStateId
from cognition.worldmodel.beliefs import Beliefs

OBSTACLE_SLOTS = 5
"""Obstacles in the observation."""
_BASE = 41
_MATE = 5
_OBSTACLE = 3
_STATES = {
    GameStateId.INITIAL: 27,
    GameStateId.STANDBY: 27,
    GameStateId.READY: 28,
    GameStateId.SET: 29,
    GameStateId.PLAYING: 30,
    GameStateId.FINISHED: 31,
}
_LEVELS = {"valid": 11, "suspicious": 12, "invalid": 13}


def observation_size(players_per_team: int) -> int:
    """Length of the observation vector for teams of ``players_per_team``."""
    return _BASE + _MATE * (players_per_team - 1) + _OBSTACLE * OBSTACLE_SLOTS


class ObservationBuilder:
    """Fills observation vectors (table in the module docstring) for one field and team size."""

    def __init__(self, field: Field, players_per_team: int, team_number: int):
        self.size = observation_size(players_per_team)
        self.players_per_team = players_per_team
        self.team_number = team_number
        self._hl = field.half_length
        self._hw = field.half_width
        self._inv_l = 1.0 / field.dims.length

    def build(self, b: Beliefs) -> NDArray[np.float32]:
        """The observation of beliefs ``b`` (float32, every entry in [-1, 1])."""
        o = [0.0] * self.size
        p = b.pose
        inv_l, hl, hw = self._inv_l, self._hl, self._hw
        px, py = p.x, p.y
        c, s = math.cos(p.theta), math.sin(p.theta)  # team -> robot frame: Beliefs.to_robot, inlined
        o[0], o[1], o[2], o[3] = px / hl, py / hw, c, s
        cov = p.covariance
        o[4] = p.position_std / 2.0
        o[5] = math.sqrt(max(0.0, float(cov[2, 2]))) / math.pi
        o[6] = float(p.lost)
        ball = b.ball
        level = ball.level
        if level != "invalid":
            o[7], o[8], o[9], o[10] = ball.x * inv_l, ball.y * inv_l, ball.vx / 3.0, ball.vy / 3.0
        o[_LEVELS[level]] = 1.0
        o[14] = min(ball.age, 10.0) / 10.0
        if level != "invalid" and math.isfinite(ball.field_x):
            o[15], o[16] = ball.field_x / hl, ball.field_y / hw
        tb = b.team_ball
        if tb is not None:
            dx, dy = tb.x - px, tb.y - py
            o[17], o[18], o[19] = 1.0, (c * dx + s * dy) * inv_l, (-s * dx + c * dy) * inv_l
        dx, dy = hl - px, 0.0 - py  # the opponent goal centre
        o[20], o[21] = (c * dx + s * dy) * inv_l, (-s * dx + c * dy) * inv_l
        dx = -hl - px  # the own goal centre
        o[22], o[23] = (c * dx + s * dy) * inv_l, (-s * dx + c * dy) * inv_l
        if b.goal is not None:
            o[24], o[25], o[26] = b.goal.confidence, b.goal.centre_x * inv_l, b.goal.centre_y * inv_l
        g = b.game
        o[_STATES.get(g.state, 27)] = 1.0  # IntEnum keys: a plain int state finds them
        o[32] = float(g.kicking_team == self.team_number)
        o[33] = float(g.set_play != 0)
        o[34] = g.secondary_time / 30.0
        o[35] = g.secs_remaining / 600.0
        first, second = g.teams[0], g.teams[1]
        own, other = (first, second) if first.team_number == self.team_number else (second, first)
        if own.team_number != self.team_number:
            own = g.team(self.team_number)  # not in this game: the lookup's KeyError names it
        o[36] = (own.score - other.score) / 5.0
        o[37] = float(b.penalty != 0)
        o[38] = own.players[b.player_number - 1].secs_till_unpenalised / 45.0
        o[39] = float(b.fallen)
        number = b.player_number
        o[40] = float(number == 1)
        slots = self.players_per_team - 1
        for m in b.teammates:
            slot = m.number - 1 if m.number < number else m.number - 2
            if not 0 <= slot < slots:
                continue
            i = _BASE + _MATE * slot
            dx, dy = m.x - px, m.y - py
            o[i], o[i + 1], o[i + 2] = 1.0, (c * dx + s * dy) * inv_l, (-s * dx + c * dy) * inv_l
            o[i + 3], o[i + 4] = float(m.active), m.age / 3.0
        obs = b.obstacles
        if len(obs):
            i = _BASE + _MATE * slots
            rows = obs.tolist()
            d = [x * x + y * y for x, y in rows]
            total = sum(d)  # NaN exactly when a distance is NaN (they are sums of squares: no -inf)
            if obs.dtype == np.float64 and total == total:  # nearest first, ties in order (stable)
                nearest: Iterable[int] = sorted(range(len(d)), key=d.__getitem__)[:OBSTACLE_SLOTS]
            else:  # NaN distances: numpy's order (NaN last)
                nearest = np.argsort(obs[:, 0] ** 2 + obs[:, 1] ** 2, kind="stable")[:OBSTACLE_SLOTS].tolist()
            for k in nearest:
                x, y = rows[k]
                o[i], o[i + 1], o[i + 2] = 1.0, x / 3.0, y / 3.0
                i += _OBSTACLE
        out = np.array(o, dtype=np.float32)
        if not math.isfinite(sum(o)):  # rare: a belief without a value reads as 0 (NaN in o makes the sum NaN)
            np.nan_to_num(out, copy=False, nan=0.0, posinf=1.0, neginf=-1.0)
        np.minimum(out, 1.0, out=out)  # clip to [-1, 1] (np.clip costs several times more on a short vector)
        np.maximum(out, -1.0, out=out)
        return out
