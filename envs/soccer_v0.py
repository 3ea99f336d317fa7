# ruff: noqa: E501  (the docstring holds the PettingZoo-style markdown tables)
"""# Soccer (teamsim) — multi-agent RoboCup SPL soccer on beliefs

```python
from envs import soccer_v0
env = soccer_v0.parallel_env(players_per_team=5, control="home", observation="percepts")
observations, infos = env.reset(seed=0)
```

Two teams of simulated NAO robots play SPL soccer under a referee (kickoffs, goals, half time
with side switch, penalties). The agents are the robots of the team(s) named by ``control``;
every other robot runs the scripted team play (:mod:`cognition.behaviors.team_play`) or
random walking. Each agent's observation is built from its own robot's beliefs: the full
cognition stack on synthesized camera percepts (``percepts``), on its own vision of rendered
camera images (``images``) or the oracle providers
(``truth``). Physics runs at 100 Hz, cognition at ``cognition_hz`` and decisions at
``decision_hz``; between decisions a continuous action is held and a macro-action keeps
running on fresh beliefs. Machinery: :mod:`envs.core`.

Bad actions: the parallel ``step`` checks every action before it applies any and raises
:class:`~cognition.behaviors.actions.ActionError` naming each agent whose action was refused;
nothing changes. The AEC ``step`` checks an action at its sender's own turn and raises there,
naming that agent, without storing it: the same agent may then act validly and the cycle goes
on. A finished agent's AEC step takes ``None``; anything else is a ``ValueError``.

| | |
|---|---|
| Actions | continuous or discrete (``action_type``) |
| Parallel API | yes (``parallel_env``); AEC through ``env`` |
| Agents | ``home_1`` ... ``home_N`` and/or ``away_1`` ... ``away_N`` (``_1`` is the goalkeeper) |
| Action space | continuous: ``Box(-1, 1, (7,), float32)``: forward, sideways, turn, kick (> 0 kicks with that strength), kick direction, head yaw, head pitch; values outside [-1, 1] are clipped, NaN/inf or a wrong shape raises ``ActionError`` and changes nothing. discrete: ``Discrete(7)``: stand, go_to_ball, kick_to_goal, pass, defend, support, scan (:mod:`cognition.behaviors.actions`) |
| Observation space | ``Box(-1, 1, (41 + 5 (N - 1) + 15,), float32)``: own pose estimate and its uncertainty, the ball model (relative position, velocity, level, age), team ball, goal directions and the goal model, game state and clocks, own penalty, teammates (by number) and the 5 nearest obstacles (:mod:`cognition.behaviors.observation`) |
| State space | ``Box(-1, 1, (A (41 + 5 (N - 1) + 15),), float32)``: ``state()`` is the observations of all A agents (``possible_agents``, in that order) side by side, for centralised critics |
| Rewards | weighted terms ``goal``, ``ball_progress``, ``ball_approach``, ``penalty`` (:mod:`envs.core`); per-term values in ``infos[agent]["reward_terms"]`` |
| Episode end | termination when the match is over (two halves of ``half_seconds``); truncation after ``max_cycles`` decisions |

## Arguments

| argument | default | meaning |
|---|---|---|
| ``players_per_team`` | 5 | robots per team, in [1, 7] |
| ``control`` | ``home`` | agents: ``home``, ``away`` or ``both`` teams |
| ``observation`` | ``percepts`` | ``percepts`` (synthesized percepts), ``images`` (rendered camera images through each robot's vision, :mod:`cognition.vision`) or ``truth`` |
| ``localization`` | ``maturing`` | localization variant in ``percepts`` mode (``cognition.localization.VARIANTS``) |
| ``obstacle_model`` | ``sectors`` | world-model obstacle variant (``sectors``, ``grid`` or ``none``) |
| ``action_type`` | ``continuous`` | ``continuous`` or ``discrete`` |
| ``decision_hz`` | 10 | decisions per simulated second, in (0, 1000] |
| ``cognition_hz`` | None | cognition frames per second, in (0, 1000] and a whole multiple of ``decision_hz``; None: 30 with ``percepts`` (the filters' rate), ``decision_hz`` with ``truth`` |
| ``half_seconds`` | 300 | length of a half (s), in (0, 86400] |
| ``max_cycles`` | 3000 | decisions before truncation, in [1, 1000000000] |
| ``start`` | ``kickoff`` | ``kickoff`` (INITIAL, READY, SET as in a game) or ``playing`` (robots at kickoff positions, play starts at once) |
| ``opponents`` | ``scripted`` | robots of uncontrolled teams: ``scripted`` or ``random`` (random walkers) |
| ``reward_weights`` | goal 1, ball_progress 0.05, ball_approach 0, penalty 0.2 | mapping term -> weight, each in [-1000, 1000]; unknown terms are an error |
| ``render_mode`` | None | ``rgb_array`` (``render()`` returns the top-down view) or ``human`` (every step writes a frame to ``render_path``; no display needed) |
| ``render_path`` | ``soccer_v0.mp4`` | video file of ``human`` mode (``.mp4`` or ``.gif``) |
| ``percepts`` | ``default`` | percept noise preset (``ideal``, ``default``, ``harsh``) |
| ``images`` | ``default`` | image-effects preset in ``images`` mode (``ideal``, ``default``, ``harsh``) |
| ``cognition`` | None | the other modules of the robots' cognition frame outside ``truth`` mode, by name, and their parameters: a mapping of :class:`cognition.pipeline.CognitionConfig` keys, e.g. ``{"goal": "none", "hypotheses": "none"}`` (fewer modules, faster steps) |

## Version history

* v0: first release.
"""

from __future__ import annotations

from typing import Any, ClassVar

import gymnasium
import numpy as np
from numpy.typing import NDArray
from pettingzoo import ParallelEnv
from pettingzoo.utils import wrappers
from pettingzoo.utils.conversions import parallel_to_aec_wrapper

from cognition.behaviors.actions import CONTINUOUS_SIZE, MACROS, ActionError, check_action
from cognition.behaviors.observation import observation_size
from envs.core import EnvConfig, SoccerCore

__all__ = ["SoccerAECEnv", "SoccerParallelEnv", "env", "parallel_env", "raw_env"]


def action_space_of(action_type: str) -> gymnasium.spaces.Space:
    """The action space of every agent for this action type."""
    if action_type == "discrete":
        return gymnasium.spaces.Discrete(len(MACROS))
    return gymnasium.spaces.Box(-1.0, 1.0, (CONTINUOUS_SIZE,), dtype=np.float32)


def observation_space_of(players_per_team: int) -> gymnasium.spaces.Box:
    """The observation space of every agent for this team size."""
    return gymnasium.spaces.Box(-1.0, 1.0, (observation_size(players_per_team),), dtype=np.float32)


class SoccerParallelEnv(ParallelEnv):
    """The soccer environment, parallel API (module docstring)."""

    metadata: ClassVar[dict[str, Any]] = {
        "name": "soccer_v0",
        "render_modes": ["rgb_array", "human"],
        "is_parallelizable": True,
        "render_fps": 10,
    }

    def __init__(self, **kwargs: Any):
        self.config = EnvConfig(**kwargs)
        self.render_mode = self.config.render_mode
        self.core = SoccerCore(self.config)
        self.possible_agents = list(self.core.possible_agents)
        self.agents: list[str] = []
        obs_space = observation_space_of(self.config.players_per_team)
        act_space = action_space_of(self.config.action_type)
        self._observation_spaces = {a: obs_space for a in self.possible_agents}
        self.state_space = gymnasium.spaces.Box(
            -1.0, 1.0, (len(self.possible_agents) * obs_space.shape[0],), dtype=np.float32
        )
        """Space of :meth:`state`: every agent's observation, in ``possible_agents`` order."""
        self._action_spaces = {a: act_space for a in self.possible_agents}
        self._seeds: np.random.Generator | None = None

    def observation_space(self, agent: str) -> gymnasium.spaces.Space:
        """Every agent shares one space (parameter sharing works)."""
        return self._observation_spaces[agent]

    def action_space(self, agent: str) -> gymnasium.spaces.Space:
        """Every agent shares one space."""
        return self._action_spaces[agent]

    def reset(
        self, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, NDArray[np.float32]], dict[str, dict[str, Any]]]:
        """A new match. ``seed`` fixes this episode and the ones after it that get no seed."""
        if seed is not None or self._seeds is None:
            self._seeds = np.random.default_rng(seed)
        episode_seed = int(self._seeds.integers(0, 2**31 - 1))
        obs = self.core.reset(episode_seed)
        self.agents = list(self.possible_agents)
        return obs, {a: {"episode_seed": episode_seed} for a in self.agents}

    def step(
        self, actions: dict[str, Any]
    ) -> tuple[
        dict[str, NDArray[np.float32]], dict[str, float], dict[str, bool], dict[str, bool], dict[str, dict[str, Any]]
    ]:
        """One decision for every live agent."""
        if not self.agents:
            raise RuntimeError("step() called with no live agents: call reset() first")
        obs, rewards, terminated, truncated, infos = self.core.step(actions, self.agents)
        terms = dict.fromkeys(self.agents, terminated)
        truncs = dict.fromkeys(self.agents, truncated and not terminated)
        if terminated or truncated:
            self.agents = []
        return obs, rewards, terms, truncs, infos

    def render(self) -> NDArray[np.uint8] | None:
        """``rgb_array``: the top-down view; ``human``: frames are written by ``step`` (returns None)."""
        if self.render_mode is None:
            gymnasium.logger.warn("render() called without a render_mode; pass render_mode='rgb_array' or 'human'")
            return None
        if self.render_mode == "human":
            return None
        return self.core.render()

    def close(self) -> None:
        """Finish the ``human`` video."""
        self.core.close()

    def state(self) -> NDArray[np.float32]:
        """All agents' observations side by side (a global state for centralised critics; ``state_space``)."""
        if not self.core.policies:
            raise RuntimeError("state() before reset(): there is no match yet")
        return np.concatenate([self.core.policies[a].observation() for a in self.possible_agents])


class SoccerAECEnv(parallel_to_aec_wrapper):
    """The AEC API of :class:`SoccerParallelEnv`: PettingZoo's converter, with each action checked
    at its sender's own ``step`` (module docstring) instead of at the last agent's, where the
    converter would run the parallel step with the bad action stored and fail at every later
    step until ``reset``."""

    env: SoccerParallelEnv

    def step(self, action: Any) -> None:
        """Store the selected agent's action (one parallel step after the last live agent).

        Raises :class:`~cognition.behaviors.actions.ActionError` naming the agent for an action
        that cannot be carried out, and ``ValueError`` for an action other than ``None`` from an
        agent that is done; in both cases nothing is stored and the same agent is still selected.
        """
        agent = self.agent_selection
        if self.terminations[agent] or self.truncations[agent]:
            if action is not None:
                raise ValueError(f"{agent} is done (terminated or truncated): its step takes None, got {action!r}")
        else:
            try:
                check_action(action, self.env.config.action_type)
            except ActionError as e:
                raise ActionError(f"bad action from {agent}: {e}") from e
        super().step(action)


def parallel_env(**kwargs: Any) -> SoccerParallelEnv:
    """The parallel environment (arguments in the module docstring)."""
    return SoccerParallelEnv(**kwargs)


def raw_env(**kwargs: Any) -> SoccerAECEnv:
    """The AEC environment without wrappers."""
    return SoccerAECEnv(parallel_env(**kwargs))


def env(**kwargs: Any) -> Any:
    """The AEC environment (agents act in turn; one decision step after the last agent)."""
    e = raw_env(**kwargs)
    e = wrappers.OrderEnforcingWrapper(e)
    return e
