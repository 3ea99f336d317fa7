"""Single-agent Gymnasium tasks on the soccer machinery, registered under ``teamsim/``.

```python
import gymnasium, envs  # importing envs registers the tasks
env = gymnasium.make("teamsim/Striker-v0", observation="truth", action_type="discrete")
```

Both tasks are 2 v 2 drills of :class:`~envs.core.SoccerCore` that start in PLAYING from a
random situation drawn from the episode seed; spaces, observation modes, action types and
reward terms are those of :mod:`envs.soccer_v0` (observation length 61 for 2 players a team).

=====================  ===================================================================================
task                   episode
=====================  ===================================================================================
teamsim/Striker-v0     the agent (``home_2``) starts 0.4-1.4 m from a ball placed in the opponent half; a
                       defender (the ``defend`` skill) and the scripted keeper oppose it; the own keeper
                       stays home.
                       Ends on a goal (either side), when the ball leaves the field or after
                       ``max_cycles`` decisions (default 300 = 30 s). Rewards: goal 10, ball progress
                       1 per metre, ball approach 0.5 per metre, penalty 1.
teamsim/Keeper-v0      the agent is the goalkeeper (``home_1``); a scripted striker starts at a ball in the
                       own half and attacks, the own field player is off the field (penalised).
                       Ends on a goal, when the ball leaves the field or reaches the opponent half
                       (cleared), or after ``max_cycles`` (default 300). Rewards: goal 10 (so -10 for a
                       goal conceded), ball progress 1 per metre (away from the own goal), penalty 1.
=====================  ===================================================================================

``info["outcome"]`` at the end says ``scored``, ``conceded``, ``out`` (the ball left the field),
``cleared`` (Keeper-v0), ``penalised``, ``time`` (``max_cycles``) or ``full_time`` (the match
clock ran out, possible only with ``max_cycles`` beyond a half). ``penalised`` ends the episode when the
referee removes the agent, e.g. for LOCAL_GAME_STUCK: the ball has stayed within 0.3 m for 20 s
with the agent the nearest robot (:mod:`teamsim.fouls`), so a striker that stands at the ball
without kicking it is stopped there.
Keyword arguments of ``gymnasium.make`` are those of :class:`~envs.core.EnvConfig` (minus
``players_per_team`` and ``control``).
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

import gymnasium
import numpy as np
from numpy.typing import NDArray

from cognition.behaviors.actions import MACROS, PolicyBrain
from cognition.brain import Brain, BrainContext
from cognition.gamestate import GameStateId, Penalty, SetPlay
from cognition.pipeline import TRUTH, CognitionConfig
from envs.core import EnvConfig, SoccerCore
from envs.soccer_v0 import action_space_of, observation_space_of
from teamsim.match import Match
from teamsim.placement import team_to_world


def _place(match: Match, team: int, number: int, x: float, y: float, theta: float) -> None:
    """Teleport a robot to a pose given in the **home** team frame."""
    match.world.robot(team, number).teleport(*team_to_world(match.referee.sign(0), x, y, theta))


class _Drill:
    """Shared end of a drill: the agent is robot ``(0, agent_number)`` of the home team."""

    agent_number = 0
    outcome: str | None = None
    """How the episode ended so far (module docstring), ``None`` while it goes on."""

    def start(self, m: Match) -> None:
        """Begin PLAYING now and remember the score."""
        m.referee.play_now(0.0)
        self.start_score = (m.referee.score[0], m.referee.score[1])
        self.outcome = None

    def finished(self, m: Match) -> bool:
        """A goal, the ball out of play, a drill-specific end (:meth:`extra_outcome`), or the
        agent penalised."""
        ref = m.referee
        if ref.score[0] > self.start_score[0]:
            self.outcome = "scored"
        elif ref.score[1] > self.start_score[1]:
            self.outcome = "conceded"
        elif ref.state != GameStateId.PLAYING or ref.set_play != SetPlay.NONE:
            self.outcome = "out"
        elif m.world.robot(0, self.agent_number).penalized:
            self.outcome = "penalised"
        else:
            self.outcome = self.extra_outcome(m)
        return self.outcome is not None

    def extra_outcome(self, m: Match) -> str | None:
        """A further way the drill ends (none by default)."""
        return None


class DefenderBrain(PolicyBrain):
    """A scripted defender: the ``defend`` macro-action, held for the whole episode."""

    def __init__(self, truth: bool):
        super().__init__("discrete", cognition=TRUTH if truth else CognitionConfig())

    def reset(self, context: BrainContext) -> None:
        """Fresh beliefs; the action is ``defend``."""
        super().reset(context)
        self.action = MACROS.index("defend")


class StrikerDrill(_Drill):
    """Set-up and end of a Striker-v0 episode (module table)."""

    agent_number = 2

    def brain(self, team: int, number: int, truth: bool) -> Brain | None:
        """The opponent field player defends instead of attacking."""
        return DefenderBrain(truth) if (team, number) == (1, 2) else None

    def setup(self, m: Match, rng: np.random.Generator) -> None:
        """Ball in the opponent half, the agent near it, a defender and a keeper in the way."""
        hl = m.field.half_length
        bx, by = float(rng.uniform(0.5, 3.0)), float(rng.uniform(-2.0, 2.0))
        d, a = float(rng.uniform(0.4, 1.4)), float(rng.uniform(math.pi / 2, 3 * math.pi / 2))
        ax, ay = bx + d * math.cos(a), by + d * math.sin(a)
        _place(m, 0, 2, ax, ay, math.atan2(by - ay, bx - ax) + float(rng.uniform(-0.5, 0.5)))
        _place(m, 0, 1, -hl + 0.3, 0.0, 0.0)
        _place(m, 1, 1, hl - 0.3, 0.0, math.pi)
        gx, gy = 0.5 * (bx + hl), 0.5 * by
        _place(m, 1, 2, gx + float(rng.uniform(-0.3, 0.3)), gy + float(rng.uniform(-0.5, 0.5)), math.pi)
        m.world.place_ball(bx * m.referee.sign(0), by * m.referee.sign(0))
        self.start(m)


class KeeperDrill(_Drill):
    """Set-up and end of a Keeper-v0 episode (module table)."""

    agent_number = 1

    def brain(self, team: int, number: int, truth: bool) -> Brain | None:
        """Everyone plays the usual scripted game."""
        return None

    def setup(self, m: Match, rng: np.random.Generator) -> None:
        """Ball in the own half with an attacker at it; the agent in its goal."""
        hl = m.field.half_length
        bx, by = float(rng.uniform(-3.0, -1.5)), float(rng.uniform(-1.5, 1.5))
        ang = math.atan2(-by, -hl - bx)  # ball toward the own goal centre
        _place(m, 1, 2, bx - 0.35 * math.cos(ang), by - 0.35 * math.sin(ang), ang)
        _place(m, 0, 1, -hl + 0.3, float(rng.uniform(-0.5, 0.5)), 0.0)
        _place(m, 1, 1, hl - 0.3, 0.0, math.pi)
        _place(m, 0, 2, 2.0, 0.0, 0.0)
        m.world.place_ball(bx * m.referee.sign(0), by * m.referee.sign(0))
        self.start(m)
        m.referee.penalize(0, 2, Penalty.SUBSTITUTE, 0.0, reason="drill")

    def extra_outcome(self, m: Match) -> str | None:
        """``cleared`` once the ball is in the opponent half."""
        return "cleared" if m.world.ball.position.x * m.referee.sign(0) > 0.0 else None


class _DrillEnv(gymnasium.Env):
    """A one-agent drill (see the module docstring)."""

    metadata: ClassVar[dict[str, Any]] = {"render_modes": ["rgb_array", "human"], "render_fps": 10}
    drill_class: ClassVar[type[StrikerDrill | KeeperDrill]]
    default_weights: ClassVar[dict[str, float]] = {
        "goal": 10.0,
        "ball_progress": 1.0,
        "ball_approach": 0.0,
        "penalty": 1.0,
    }

    def __init__(self, **kwargs: Any):
        for bad in ("players_per_team", "control"):
            if bad in kwargs:
                raise ValueError(f"{type(self).__name__} fixes {bad}; it cannot be set")
        kwargs.setdefault("observation", "truth")
        kwargs.setdefault("max_cycles", 300)
        kwargs.setdefault("reward_weights", dict(self.default_weights))
        kwargs.setdefault("render_path", f"{type(self).__name__}.mp4")
        self.config = EnvConfig(players_per_team=2, control="home", **kwargs)
        self.render_mode = self.config.render_mode
        self.drill = self.drill_class()
        self.agent = f"home_{self.drill.agent_number}"
        self.core = SoccerCore(self.config, agents_filter=lambda t, n: f"home_{n}" == self.agent, drill=self.drill)
        self.observation_space = observation_space_of(2)
        self.action_space = action_space_of(self.config.action_type)

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[NDArray[np.float32], dict[str, Any]]:
        """A new drill situation drawn from the environment's generator (seeded by ``seed``)."""
        super().reset(seed=seed)
        episode_seed = int(self.np_random.integers(0, 2**31 - 1))
        obs = self.core.reset(episode_seed)
        return obs[self.agent], {"episode_seed": episode_seed}

    def step(self, action: Any) -> tuple[NDArray[np.float32], float, bool, bool, dict[str, Any]]:
        """One decision of the agent."""
        obs, rewards, terminated, truncated, infos = self.core.step({self.agent: action}, [self.agent])
        info = dict(infos[self.agent])
        if terminated or truncated:
            info["outcome"] = self.drill.outcome or ("time" if truncated else "full_time")
        return obs[self.agent], rewards[self.agent], bool(terminated), bool(truncated and not terminated), info

    def render(self) -> NDArray[np.uint8] | None:
        """``rgb_array``: the top-down view; ``human`` writes frames during ``step``."""
        if self.render_mode == "rgb_array":
            return self.core.render()
        return None

    def close(self) -> None:
        """Finish the ``human`` video."""
        self.core.close()


class StrikerEnv(_DrillEnv):
    """``teamsim/Striker-v0`` (module table): the drill's weights plus a ball-approach term."""

    drill_class = StrikerDrill
    default_weights: ClassVar[dict[str, float]] = {**_DrillEnv.default_weights, "ball_approach": 0.5}


class KeeperEnv(_DrillEnv):
    """``teamsim/Keeper-v0`` (module table)."""

    drill_class = KeeperDrill
