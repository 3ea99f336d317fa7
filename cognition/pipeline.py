"""The cognition frame as declared modules, and the configuration that picks their providers.

A cognition frame is a pipeline of modules (DESIGN principle 1; B-Human's split of modules and
representations is the model). Every module declares the representations it **requires** (it
cannot run without them), those it **uses** when something provides them, and the one it
**provides**. A *slot* is a representation with a choice of providers; which provider fills each
slot is configuration (:class:`CognitionConfig`, loadable from a ``--config`` file), never a
code edit. :func:`plan` turns a configuration and the contents of the sensor frames into the
ordered modules of one frame, and refuses a configuration whose requirements nothing provides.

==============  ===============================  ===================================  ==================
slot            providers (default first)        requires (uses)                      provides
==============  ===============================  ===================================  ==================
(input check)   check                            sensor frame                         odometry
vision          dnt, hough                       image                                percepts
localization    maturing, mcl, lowvar, amcl,     odometry, percepts                   robot pose
                reset
                odometry                         odometry                             robot pose
                oracle                           ground truth                         robot pose
(team messages) messages                         sensor frame                         teammates
ball            kalman                           odometry, robot pose (percepts,      ball
                                                 teammates)
hypotheses      cmu, none                        robot pose (percepts, teammates)     look at
team_ball       fusion, none                     ball, robot pose, teammates          team ball
obstacles       sectors, grid, none              odometry (percepts)                  obstacles
goal            posts, none                      odometry (percepts)                  goal
beliefs         cognition                        robot pose, ball, teammates (team    beliefs
                                                 ball, goal, obstacles, look at)
                truth                            ground truth                         beliefs
==============  ===============================  ===================================  ==================

Sources: the particle filters are DNT 4 and CMU III (``reset``) and Darmstadt VI (``maturing``);
the Kalman ball Darmstadt V; the ball hypotheses CMU IV.A; the goal model CMU IV.B; the obstacle
models Darmstadt VII; the vision DNT 3 (``dnt``) and NimbRo 5 (``hough``).

What the sensor frames carry is the match's ``observation``: ``percepts`` (synthesized
percepts), ``images`` (a camera image; the vision module makes the percepts) or ``none``. Every
frame carries the ``sensor frame`` itself (odometry, head, game state, team messages, body
signals); ``ground truth`` is what only a declared oracle provider (``localization="oracle"``,
``beliefs="truth"``) may read, and a simulator hands it to exactly those brains.

A module runs only when something downstream needs what it provides (the ``beliefs``
representation is what a behaviour reads), and a provider named ``none`` leaves its slot empty:
``beliefs="truth"`` is a one-module frame, and ``goal="none"`` drops the goal model. Modules run
in an order that respects every declaration (ties in the order of the table).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any, ClassVar

from cognition.localization import VARIANTS, LocalizationParams
from cognition.params import Ranges, check_choice, check_ranges, from_mapping
from cognition.vision import VisionParams
from cognition.worldmodel.goal import GoalModelParams
from cognition.worldmodel.hypotheses import HypothesisParams
from cognition.worldmodel.kalman_ball import KalmanBallParams
from cognition.worldmodel.obstacles import ObstacleGridParams

OBSERVATIONS: dict[str, tuple[str, ...]] = {
    "percepts": ("sensor frame", "percepts"),
    "images": ("sensor frame", "image"),
    "none": ("sensor frame",),
}
"""What the sensor frames carry for each observation mode (besides ``ground truth``, which a
simulator offers to declared oracle providers)."""

TARGET = "beliefs"
"""The representation a behaviour reads: the pipeline is what it takes to provide it."""


@dataclass(frozen=True)
class Declaration:
    """What one module of the frame needs and gives (representation names of the module table)."""

    stage: str
    """The module's name in the frame (a profile row; :attr:`cognition.brain.StagedBrain.stages`)."""
    requires: tuple[str, ...]
    """Representations the module cannot run without."""
    provides: str
    """The representation it writes."""
    uses: tuple[str, ...] = ()
    """Representations it reads when something provides them."""


_PARTICLE = Declaration("localization", ("odometry", "percepts"), "robot pose")

DECLARATIONS: dict[str, dict[str, Declaration]] = {
    "input check": {"check": Declaration("input check", ("sensor frame",), "odometry")},
    "vision": {m: Declaration("vision", ("image",), "percepts") for m in ("dnt", "hough")},
    "localization": {
        **{v: _PARTICLE for v in VARIANTS if v not in ("odometry", "oracle")},
        "odometry": Declaration("localization", ("odometry",), "robot pose"),
        "oracle": Declaration("localization", ("ground truth",), "robot pose"),
    },
    "team messages": {"messages": Declaration("team messages", ("sensor frame",), "teammates")},
    "ball": {
        "kalman": Declaration("ball model", ("odometry", "robot pose"), "ball", ("percepts", "teammates")),
    },
    "hypotheses": {
        "cmu": Declaration("ball hypotheses", ("robot pose",), "look at", ("percepts", "teammates")),
    },
    "team_ball": {"fusion": Declaration("team ball", ("ball", "robot pose", "teammates"), "team ball")},
    "obstacles": {m: Declaration("obstacles", ("odometry",), "obstacles", ("percepts",)) for m in ("sectors", "grid")},
    "goal": {"posts": Declaration("goal model", ("odometry",), "goal", ("percepts",))},
    "beliefs": {
        "cognition": Declaration(
            "beliefs", ("robot pose", "ball", "teammates"), "beliefs", ("team ball", "goal", "obstacles", "look at")
        ),
        "truth": Declaration("truth beliefs", ("ground truth",), "beliefs"),
    },
}
"""Every provider of every slot with its declaration, slots in the order of the module table
(the order ties are broken in). The slots in parentheses in the table (``input check``, ``team
messages``) have one provider and no configuration key."""

OPTIONAL_SLOTS: tuple[str, ...] = ("hypotheses", "team_ball", "obstacles", "goal")
"""Slots that also accept the provider ``none`` (the representation stays empty)."""

FIXED_SLOTS: dict[str, str] = {"input check": "check", "team messages": "messages"}
"""Slots with a single provider and no configuration key."""


@dataclass(frozen=True)
class CognitionConfig:
    """Which provider fills each slot of a robot's cognition frame, and the modules' parameters
    (one frozen parameters class per module, DESIGN principle 3).

    Every field is checked when the configuration is built: an unknown provider or parameter is
    an error that names it (:func:`from_mapping` for plain mappings). ``vision`` is also the
    line method of ``vision_params`` (:attr:`cognition.vision.VisionParams.method`).
    """

    beliefs: str = "cognition"
    """``cognition`` (the modules below) or ``truth`` (read the ground truth; a baseline)."""
    vision: str = "dnt"
    """Vision on camera images (frames with ``observation="images"``): ``dnt`` or ``hough``."""
    localization: str = "maturing"
    """The localization variant (:data:`cognition.localization.VARIANTS`)."""
    ball: str = "kalman"
    """The ball model: ``kalman`` (Darmstadt V)."""
    hypotheses: str = "cmu"
    """Ball hypotheses for active gaze (CMU IV.A), or ``none``."""
    team_ball: str = "fusion"
    """The team ball fused from teammates' messages, or ``none``."""
    obstacles: str = "sectors"
    """The obstacle model: ``sectors``, ``grid`` (Darmstadt VII) or ``none``."""
    goal: str = "posts"
    """The goal model from post pairs (CMU IV.B), or ``none``."""
    localization_params: LocalizationParams = field(default_factory=LocalizationParams)
    """Parameters of the particle filters (:mod:`cognition.localization.params`)."""
    vision_params: VisionParams = field(default_factory=VisionParams)
    """Parameters of the vision (:mod:`cognition.vision.params`)."""
    ball_params: KalmanBallParams = field(default_factory=KalmanBallParams)
    """Parameters of the Kalman ball (:mod:`cognition.worldmodel.kalman_ball`)."""
    hypotheses_params: HypothesisParams = field(default_factory=HypothesisParams)
    """Parameters of the ball hypotheses (:mod:`cognition.worldmodel.hypotheses`)."""
    goal_params: GoalModelParams = field(default_factory=GoalModelParams)
    """Parameters of the goal model (:mod:`cognition.worldmodel.goal`)."""
    obstacle_grid_params: ObstacleGridParams = field(default_factory=ObstacleGridParams)
    """Parameters of the ``grid`` obstacle model (:mod:`cognition.worldmodel.obstacles`)."""

    RANGES: ClassVar[Ranges] = {}
    """No numeric fields: the providers are names, the parameters are checked by their own classes."""
    SLOTS: ClassVar[tuple[str, ...]] = (
        "beliefs", "vision", "localization", "ball", "hypotheses", "team_ball", "obstacles", "goal",
    )  # fmt: skip
    """The fields that name a provider."""

    def __post_init__(self) -> None:
        check_ranges(self)  # provider names are strings, every parameters section is its class
        for slot in self.SLOTS:
            check_choice("CognitionConfig", slot, getattr(self, slot), providers(slot))
        method = self.vision_params.method
        if method != self.vision:
            if method != VisionParams().method:
                raise ValueError(
                    f"CognitionConfig: vision={self.vision!r} but vision_params.method={method!r}; "
                    "choose the line method with 'vision' alone"
                )
            object.__setattr__(self, "vision_params", dataclasses.replace(self.vision_params, method=self.vision))

    @classmethod
    def from_mapping(cls, data: Any, where: str = "CognitionConfig") -> CognitionConfig:
        """Build from a plain mapping (a ``--config`` file's ``cognition`` section); unknown keys,
        providers and parameters are errors that name them."""
        return from_mapping(cls, data, where)

    @property
    def reads_ground_truth(self) -> bool:
        """Whether a declared oracle provider of this configuration reads the ground truth."""
        return any("ground truth" in d.requires for d in plan(self, "percepts", ground_truth=True))

    def provider(self, slot: str) -> str:
        """The provider name of ``slot`` (the fixed slots included)."""
        return FIXED_SLOTS[slot] if slot in FIXED_SLOTS else getattr(self, slot)

    def summary(self) -> str:
        """One line naming every provider, e.g. for a report."""
        if self.beliefs == "truth":
            return "beliefs=truth"
        return ", ".join(f"{s}={getattr(self, s)}" for s in self.SLOTS if s != "beliefs")


def providers(slot: str) -> tuple[str, ...]:
    """The provider names of ``slot`` in the order of :data:`DECLARATIONS` (``none`` last for optional slots)."""
    names = tuple(DECLARATIONS[slot])
    return (*names, "none") if slot in OPTIONAL_SLOTS else names


TRUTH = CognitionConfig(beliefs="truth")
"""The oracle providers: beliefs read from the ground truth."""


class PipelineError(ValueError):
    """A configuration whose modules need a representation that nothing provides."""


def plan(config: CognitionConfig, observation: str = "percepts", ground_truth: bool = True) -> tuple[Declaration, ...]:
    """The modules of one frame in the order they run, for frames of ``observation``.

    A module is in the plan when its representation is needed downstream of :data:`TARGET`; a
    ``none`` provider leaves its slot out. ``ground_truth``: whether the frames' owner may be
    given the ground truth (a simulator: yes; a real robot: no). Raises :class:`PipelineError`
    naming the module and the representation nothing provides.
    """
    check_choice("plan", "observation", observation, OBSERVATIONS)
    inputs = set(OBSERVATIONS[observation]) | ({"ground truth"} if ground_truth else set())
    chosen: dict[str, tuple[str, Declaration]] = {}  # representation -> (slot, declaration)
    for slot, options in DECLARATIONS.items():
        name = config.provider(slot)
        if name != "none":
            decl = options[name]
            chosen[decl.provides] = (slot, decl)
    needed: dict[str, Declaration] = {}
    can: dict[str, bool] = {}

    def providable(rep: str) -> bool:
        if rep not in can:
            can[rep] = False  # a cycle provides nothing
            can[rep] = rep in inputs or (rep in chosen and all(providable(r) for r in chosen[rep][1].requires))
        return can[rep]

    def fail(rep: str, by: Declaration | None) -> None:
        """Raise naming the module that misses an input: the user of an observable representation
        (percepts, image), else the provider that lacks its own requirement."""
        if rep in chosen:
            decl = chosen[rep][1]
            blocker = next(r for r in decl.requires if not providable(r))
            if blocker in chosen:
                fail(blocker, decl)
            if by is None or not any(rep in carried for carried in OBSERVATIONS.values()):
                raise PipelineError(_missing(config, observation, decl, blocker))
        assert by is not None
        raise PipelineError(_missing(config, observation, by, rep))

    def need(rep: str, by: Declaration | None) -> None:
        if rep in needed or rep in inputs:
            return
        if not providable(rep):
            fail(rep, by)
        decl = chosen[rep][1]
        needed[rep] = decl
        for r in decl.requires:
            need(r, decl)
        for r in decl.uses:
            if providable(r):
                need(r, decl)

    need(TARGET, None)
    order = list(chosen)  # table order breaks ties
    done: set[str] = set(inputs)
    out: list[Declaration] = []
    pending = [r for r in order if r in needed]
    while pending:
        for rep in pending:
            d = needed[rep]
            if all(r in done for r in d.requires) and all(r in done or r not in needed for r in d.uses):
                out.append(d)
                done.add(rep)
                pending.remove(rep)
                break
        else:  # pragma: no cover - the table has no cycles (a test checks every configuration)
            raise PipelineError(f"cognition pipeline: a cycle among {pending}")
    return tuple(out)


def _missing(config: CognitionConfig, observation: str, by: Declaration, rep: str) -> str:
    """The error text of a requirement nothing provides."""
    user = next(f"{s}={config.provider(s)!r}" for s, opts in DECLARATIONS.items() if opts.get(config.provider(s)) is by)
    carried = ", ".join(OBSERVATIONS[observation])
    hint = ""
    if rep == "percepts":
        hint = (
            "; percepts come with the frames (observation='percepts') or from the vision module on "
            "camera images (observation='images')"
        )
    elif rep == "image":
        hint = "; only observation='images' carries camera images"
    elif rep == "ground truth":
        hint = "; only a simulator can give the ground truth"
    else:
        slots = [s for s, opts in DECLARATIONS.items() if any(d.provides == rep for d in opts.values())]
        hint = "".join(f"; {s}={config.provider(s)!r} provides nothing" for s in slots)
    return (
        f"cognition pipeline: the module {by.stage!r} ({user}) requires {rep!r}, which nothing provides: "
        f"observation={observation!r} frames carry {carried}{hint}"
    )


__all__ = [
    "DECLARATIONS",
    "OBSERVATIONS",
    "TRUTH",
    "CognitionConfig",
    "Declaration",
    "PipelineError",
    "plan",
    "providers",
]
