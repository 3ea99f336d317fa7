"""The machinery under every teamsim environment: a match, policy-driven robots, rewards, rendering.

:class:`SoccerCore` runs one :class:`~teamsim.match.Match` in which some robots are driven by
:class:`~cognition.behaviors.actions.PolicyBrain` (the agents) and the rest by the scripted
players. One decision step applies every agent's action from the current cognition frame on,
then runs physics (``physics_hz``) and cognition (``cognition_hz``) until the next decision
(``decision_hz``): a continuous action is held, a macro-action is re-run on each new frame.

Observation modes (the belief provider of agents *and* scripted players):

==========  =================================================================================
mode        beliefs
==========  =================================================================================
truth       oracle providers (:class:`~cognition.worldmodel.beliefs.TruthBeliefs`); no camera
percepts    synthesized percepts through localization and the world model
            (:class:`~cognition.worldmodel.beliefs.CognitionBeliefs`)
images      rendered camera images (``images`` preset of the image effects) through each robot's
            vision (:mod:`cognition.vision`), then the same localization and world model
==========  =================================================================================

Reward terms (per agent and step; :class:`RewardWeights` scales them, read from ground truth,
which is fine for a training signal; the policy never sees it):

=============  ==============  ==============================================================================
term           weight range    value
=============  ==============  ==============================================================================
goal           [-1000, 1000]   +1 when the agent's team scores, -1 when it concedes
ball_progress  [-1000, 1000]   metres the ball moved toward the opponent goal (team frame x) while PLAYING
ball_approach  [-1000, 1000]   metres the agent came closer to the ball while PLAYING
penalty        [-1000, 1000]   -1 when the agent is penalised (left the field, pushing, ...)
=============  ==============  ==============================================================================

The weights and the numbers of :class:`EnvConfig` (ranges in the :mod:`envs.soccer_v0`
argument table) are checked when they are built (:func:`cognition.params.check_ranges`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any, ClassVar, Protocol

import numpy as np
from numpy.typing import NDArray

from cognition.behaviors.actions import ACTION_TYPES, ActionError, ActionParams, PolicyBrain, check_action
from cognition.brain import Brain
from cognition.field import make_colour_scheme
from cognition.gamestate import GameStateId, SetPlay
from cognition.localization import VARIANTS
from cognition.pipeline import TRUTH, CognitionConfig, providers
from cognition.positions import kickoff_position
from cognition.worldmodel.beliefs import CognitionBeliefs
from teamsim.match import MAX_PLAYERS_PER_TEAM, Match, MatchConfig
from teamsim.params import Range, Ranges, check_ranges, positive
from teamsim.placement import team_to_world
from teamsim.referee import RefereeParams
from teamsim.render import TopDownRenderer, VideoWriter

OBSERVATION_MODES: tuple[str, ...] = ("truth", "percepts", "images")
"""Observation modes by name."""
TEAM_NAMES = ("home", "away")
CONTROL = ("home", "away", "both")
OPPONENTS = ("scripted", "random")
STARTS = ("kickoff", "playing")


@dataclass(frozen=True)
class RewardWeights:
    """Weights of the reward terms (module table)."""

    goal: float = 1.0
    ball_progress: float = 0.05
    ball_approach: float = 0.0
    penalty: float = 0.2

    RANGES: ClassVar[Ranges] = {
        "goal": Range(-1000.0, 1000.0),
        "ball_progress": Range(-1000.0, 1000.0),
        "ball_approach": Range(-1000.0, 1000.0),
        "penalty": Range(-1000.0, 1000.0),
    }

    def __post_init__(self) -> None:
        check_ranges(self)

    @classmethod
    def from_any(cls, value: RewardWeights | Mapping[str, float] | None) -> RewardWeights:
        """Weights from an instance, a mapping of term -> weight (unknown terms are an error) or None."""
        if value is None:
            return cls()
        if isinstance(value, RewardWeights):
            return value
        if not isinstance(value, Mapping):
            raise TypeError(f"reward_weights must be a mapping of term -> weight, got {value!r}")
        known = [f.name for f in fields(cls)]
        for k in value:
            if k not in known:
                raise ValueError(f"unknown reward term {k!r}; valid: {known}")
        return cls(**value)


@dataclass(frozen=True)
class EnvConfig:
    """Arguments shared by the environments (see :mod:`envs.soccer_v0` for the table)."""

    players_per_team: int = 5
    control: str = "home"
    observation: str = "percepts"
    localization: str = "maturing"
    obstacle_model: str = "sectors"
    action_type: str = "continuous"
    decision_hz: float = 10.0
    cognition_hz: float | None = None
    half_seconds: float = 300.0
    max_cycles: int = 3000
    start: str = "kickoff"
    opponents: str = "scripted"
    reward_weights: RewardWeights | Mapping[str, float] | None = None
    render_mode: str | None = None
    render_path: str = "soccer_v0.mp4"
    percepts: str = "default"
    images: str = "default"
    cognition: Mapping[str, Any] | None = None
    """More of the robots' cognition frame outside ``truth`` mode: a ``CognitionConfig`` mapping of
    the other slots' providers and the modules' parameters (``localization`` and ``obstacle_model``
    have their own keys)."""

    RANGES: ClassVar[Ranges] = {
        "players_per_team": Range(1, MAX_PLAYERS_PER_TEAM),
        "decision_hz": positive(1000.0),
        "cognition_hz": positive(1000.0),
        "half_seconds": positive(86_400.0),
        "max_cycles": Range(1, 10**9),
    }

    def __post_init__(self) -> None:
        for name, value, valid in (
            ("control", self.control, CONTROL),
            ("observation", self.observation, OBSERVATION_MODES),
            ("localization", self.localization, VARIANTS),
            ("obstacle_model", self.obstacle_model, providers("obstacles")),
            ("action_type", self.action_type, ACTION_TYPES),
            ("start", self.start, STARTS),
            ("opponents", self.opponents, OPPONENTS),
            ("render_mode", self.render_mode, (None, "rgb_array", "human")),
        ):
            if value not in valid:
                raise ValueError(f"unknown {name} {value!r}; valid: {list(valid)}")
        if self.cognition_hz is None:
            # the filters of the cognition stack run at 30 Hz; the oracle needs no more than the decisions
            object.__setattr__(self, "cognition_hz", self.decision_hz if self.observation == "truth" else 30.0)
        check_ranges(self)
        ratio = self.cognition_hz / self.decision_hz  # type: ignore[operator]
        if abs(ratio - round(ratio)) > 1e-9 or round(ratio) < 1:
            raise ValueError(
                f"EnvConfig.cognition_hz ({self.cognition_hz}) must be a whole multiple of decision_hz "
                f"({self.decision_hz})"
            )
        object.__setattr__(self, "reward_weights", RewardWeights.from_any(self.reward_weights))
        if self.cognition is not None:
            if not isinstance(self.cognition, Mapping):
                raise TypeError(
                    f"EnvConfig.cognition must be a mapping of CognitionConfig keys, got {self.cognition!r}"
                )
            own = {"localization": "localization", "obstacles": "obstacle_model", "beliefs": "observation='truth'"}
            for key, instead in own.items():
                if key in self.cognition:
                    raise ValueError(f"EnvConfig.cognition: set {key!r} with the environment's {instead} instead")
            object.__setattr__(self, "cognition", dict(self.cognition))
        self.cognition_config()  # an unknown provider or parameter fails here, naming it

    def cognition_config(self) -> CognitionConfig:
        """The cognition frame of every robot outside ``truth`` mode."""
        extra = dict(self.cognition or {})
        return CognitionConfig.from_mapping(
            {"localization": self.localization, "obstacles": self.obstacle_model, **extra}, "EnvConfig.cognition"
        )

    @property
    def frames_per_decision(self) -> int:
        """Cognition frames per decision step."""
        return round(self.cognition_hz / self.decision_hz)  # type: ignore[operator]

    @property
    def controlled_teams(self) -> tuple[int, ...]:
        """Team indices whose robots are agents."""
        return {"home": (0,), "away": (1,), "both": (0, 1)}[self.control]


class Drill(Protocol):
    """A set-up situation instead of a kickoff (the Gymnasium tasks' episodes)."""

    def setup(self, match: Match, rng: np.random.Generator) -> None:
        """Place robots and ball on a fresh match and start play."""
        ...

    def finished(self, match: Match) -> bool:
        """Whether the episode is over (goal, ball out, task done)."""
        ...

    def brain(self, team: int, number: int, truth: bool) -> Brain | None:
        """A special brain for a robot that is not an agent (``None``: the usual scripted one)."""
        ...


class SoccerCore:
    """One episode's match and everything around it (see the module docstring).

    ``agents_filter`` keeps only some controlled robots as agents (the others of the
    controlled teams play scripted); ``drill`` replaces the kickoff with a set-up situation.
    """

    def __init__(
        self,
        config: EnvConfig,
        agents_filter: Callable[[int, int], bool] | None = None,
        drill: Drill | None = None,
    ):
        self.config = config
        self.drill = drill
        self.agents_filter = agents_filter or (lambda team, number: True)
        self.possible_agents: list[str] = [
            f"{TEAM_NAMES[t]}_{n}"
            for t in config.controlled_teams
            for n in range(1, config.players_per_team + 1)
            if self.agents_filter(t, n)
        ]
        if not self.possible_agents:
            raise ValueError("no robot is controlled by a policy: check control and the agents filter")
        self._index = {a: self._robot_index(a) for a in self.possible_agents}
        self.weights: RewardWeights = config.reward_weights  # type: ignore[assignment]
        self.match: Match | None = None
        self.policies: dict[str, PolicyBrain] = {}
        self.cycles = 0
        self.renderer: TopDownRenderer | None = None
        self.video: VideoWriter | None = None

    def _robot_index(self, agent: str) -> int:
        team, number = agent.split("_")
        return TEAM_NAMES.index(team) * self.config.players_per_team + int(number) - 1

    # -- episode ---------------------------------------------------------------------------
    def reset(self, seed: int) -> dict[str, NDArray[np.float32]]:
        """A new match from ``seed``; returns the first observations."""
        c = self.config
        truth = c.observation == "truth"
        self.policies = {}
        controlled = {(t, n) for t in c.controlled_teams for n in range(1, c.players_per_team + 1)}

        def brains(team: int, number: int) -> Brain:
            if (team, number) in controlled and self.agents_filter(team, number):
                brain = PolicyBrain(c.action_type, cognition=self._cognition(truth), params=ActionParams())
                self.policies[f"{TEAM_NAMES[team]}_{number}"] = brain
                return brain
            special = self.drill.brain(team, number, truth) if self.drill is not None else None
            return special if special is not None else self._scripted(team, number, truth)

        mc = MatchConfig(
            seed=int(seed),
            players_per_team=c.players_per_team,
            cognition_hz=float(c.cognition_hz),  # type: ignore[arg-type]
            observation="none" if truth else c.observation,
            percepts=c.percepts,
            images=c.images,
            cognition=None if truth else self._cognition(truth),
            referee=RefereeParams(half_seconds=c.half_seconds),
        )
        self.match = Match(mc, brains=brains)
        m = self.match
        if self.drill is not None:
            self.drill.setup(m, np.random.default_rng(np.random.SeedSequence(int(seed)).spawn(1)[0]))
        elif c.start == "playing":
            for r in m.world.robots:
                pose = kickoff_position(m.field, r.number, r.team == m.referee.kicking_team)
                r.teleport(*team_to_world(m.referee.sign(r.team), *pose))
            m.referee.play_now(0.0)
        if self.drill is not None or c.start == "playing":
            self._tell_placements(m)
        self.cycles = 0
        m.advance_frame()
        self._previous = self._measure()
        if c.render_mode == "human":
            self._write_frame()
        return self.observations()

    @staticmethod
    def _tell_placements(m: Match) -> None:
        """Robots placed for an episode start know where they were put (as after a manual placement):
        every localizer of the cognition stack starts around its robot's placed pose."""
        for robot, brain in zip(m.world.robots, m.brains, strict=True):
            provider = getattr(brain, "provider", None)
            if isinstance(provider, CognitionBeliefs) and provider.localizer is not None:
                provider.localizer.on_placement(np.array([m.referee.team_pose(robot)], dtype=np.float64))

    def _scripted(self, team: int, number: int, truth: bool) -> Brain:
        c = self.config
        controlled_team = team in c.controlled_teams
        if c.opponents == "random" and not controlled_team:
            from cognition.behaviors.random_walk import RandomWalkBrain

            return RandomWalkBrain()
        from cognition.behaviors.team_play import ScriptedBrain

        return ScriptedBrain(self._cognition(truth))

    def _cognition(self, truth: bool) -> CognitionConfig:
        """The cognition frame of every brain: the oracle providers, or the stack with the
        configured localization and obstacle model."""
        c = self.config
        return TRUTH if truth else c.cognition_config()

    def observations(self) -> dict[str, NDArray[np.float32]]:
        """Every agent's observation now."""
        return {a: p.observation() for a, p in self.policies.items()}

    def step(
        self, actions: Mapping[str, Any], agents: list[str]
    ) -> tuple[dict[str, NDArray[np.float32]], dict[str, float], bool, bool, dict[str, dict[str, Any]]]:
        """Apply ``actions`` of the live ``agents`` and run to the next decision.

        Returns observations, rewards, whether the match ended (termination), whether
        ``max_cycles`` was reached (truncation) and infos. Every action is checked before any
        is applied, so a bad action (:class:`~cognition.behaviors.actions.ActionError`, naming
        every agent whose action was refused and why) changes nothing.
        """
        m = self.match
        if m is None:
            raise RuntimeError("step() before reset()")
        extra = [a for a in actions if a not in self._index]
        if extra:
            raise ValueError(f"actions for unknown agents {extra}; agents are {self.possible_agents}")
        missing = [a for a in agents if a not in actions]
        if missing:
            raise ValueError(f"no action for live agents {missing}")
        checked: dict[str, NDArray[np.float64] | int] = {}
        refused: list[str] = []
        for a in agents:
            try:
                checked[a] = check_action(actions[a], self.config.action_type)
            except ActionError as e:
                refused.append(f"{a}: {e}")
        if refused:
            raise ActionError("bad action from " + "; ".join(refused))
        for a, act in checked.items():
            m.command(self._index[a], self.policies[a].act(act))
        for _ in range(self.config.frames_per_decision):
            m.advance_frame()
            if m.finished:
                break
        self.cycles += 1
        rewards, infos = self._rewards()
        if self.config.render_mode == "human":
            self._write_frame()
        ended = m.finished or (self.drill is not None and self.drill.finished(m))
        return self.observations(), rewards, ended, self.cycles >= self.config.max_cycles, infos

    # -- rewards ---------------------------------------------------------------------------
    def _measure(self) -> dict[str, Any]:
        m = self.match
        assert m is not None
        bx, by = m.world.ball.position
        dist = {}
        for a, i in self._index.items():
            rx, ry, _ = m.world.robots[i].pose
            dist[a] = math.hypot(bx - rx, by - ry)
        penalised = {a: m.world.robots[i].penalized for a, i in self._index.items()}
        return {
            "ball_x": bx,
            "score": tuple(m.referee.score),
            "playing": m.referee.state == GameStateId.PLAYING,
            "signs": (m.referee.sign(0), m.referee.sign(1)),
            "dist": dist,
            "penalised": penalised,
        }

    def _rewards(self) -> tuple[dict[str, float], dict[str, dict[str, Any]]]:
        m = self.match
        assert m is not None
        before, now = self._previous, self._measure()
        self._previous = now
        w = self.weights
        scored = (now["score"][0] - before["score"][0], now["score"][1] - before["score"][1])
        live = before["playing"] and now["playing"] and scored == (0, 0) and before["signs"] == now["signs"]
        rewards: dict[str, float] = {}
        infos: dict[str, dict[str, Any]] = {}
        state, set_play = GameStateId(m.referee.state).name, SetPlay(m.referee.set_play).name
        robots = m.world.robots
        for a, i in self._index.items():
            team = robots[i].team
            goal = float(scored[team] - scored[1 - team])
            progress = now["signs"][team] * (now["ball_x"] - before["ball_x"]) if live else 0.0
            approach = before["dist"][a] - now["dist"][a] if live else 0.0
            penalty = -1.0 if now["penalised"][a] and not before["penalised"][a] else 0.0
            terms = {"goal": goal, "ball_progress": progress, "ball_approach": approach, "penalty": penalty}
            # the weighted sum in the order of the terms, from 0 (what sum() over them gives)
            rewards[a] = float(
                0.0 + w.goal * goal + w.ball_progress * progress + w.ball_approach * approach + w.penalty * penalty
            )
            infos[a] = {
                "reward_terms": terms,
                "score": (now["score"][team], now["score"][1 - team]),
                "game_state": state,
                "set_play": set_play,
            }
        return rewards, infos

    # -- rendering -------------------------------------------------------------------------
    def render(self) -> NDArray[np.uint8]:
        """The top-down view now (RGB ``uint8``, H x W x 3)."""
        m = self.match
        if m is None:
            raise RuntimeError("render() before reset()")
        if self.renderer is None:
            self.renderer = TopDownRenderer(m.field, make_colour_scheme(m.config.colours), pixels_per_metre=40.0)
        return self.renderer.render(m.snapshot(), m.game_state())

    def _write_frame(self) -> None:
        if self.video is None:
            self.video = VideoWriter(Path(self.config.render_path), fps=self.config.decision_hz)
        self.video.write(self.render())

    def close(self) -> None:
        """Finish the human-mode video."""
        if self.video is not None:
            self.video.close()
            self.video = None
