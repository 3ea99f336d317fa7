"""Policy actions and how a robot carries them out, and the brain that a policy drives.

Two action types, shared by every agent of an environment:

**continuous** (7 real numbers in [-1, 1], a float or integer array or a list of numbers;
values outside are clipped; NaN, infinity, bool, str or complex entries are an error):

=====  ====================================================================================
index  meaning
=====  ====================================================================================
0      forward speed, times ``max_forward`` (m/s; the walking engine limits backward speed)
1      sideways speed, times ``max_sideways`` (m/s, positive to the left)
2      turn rate, times ``max_turn`` (rad/s, counter-clockwise)
3      kick: above 0 the robot kicks now with this strength (the kick misses without a ball)
4      kick direction, times ``kick_angle`` (rad, robot frame)
5      head yaw target, times ``head_yaw`` (rad)
6      head pitch target, mapped from [-1, 1] to [``pitch_min``, ``pitch_max``] (rad)
=====  ====================================================================================

**discrete** (an integer in ``0..len(MACROS)-1``: ``int``, numpy integer or 0-d integer array,
as ``gymnasium.spaces.Discrete`` accepts; no bool, no float such as ``2.0``): macro-actions that run a scripted skill
(:mod:`cognition.behaviors.skills`) closed-loop on the latest beliefs until the next decision,
with the head control of the scripted players (``scan`` forces a landmark scan):

=====  ==============  ====================================================================
index  name            skill
=====  ==============  ====================================================================
0      stand           stand still
1      go_to_ball      walk to the line-up spot behind the ball, facing the aim; no kick
2      kick_to_goal    approach, align and kick toward the opponent goal
3      pass            kick toward the best-placed field teammate ahead of the ball
                       (:meth:`Skills.pass_receiver`); with none, or no free kick line, as
                       kick_to_goal (so in Striker-v0, whose only teammate is the keeper,
                       pass and kick_to_goal coincide)
4      defend          stand between the ball and the own goal
5      support         hold a supporting spot relative to the ball
6      scan            stand and sweep the head for landmarks
=====  ==============  ====================================================================

The continuous scales (:class:`ActionParams`; every value is checked against its range when
the parameters are built, :func:`cognition.params.check_ranges`):

============  =======  ==============  ==========================================================
ActionParams  default  range           meaning
============  =======  ==============  ==========================================================
max_forward   0.25     (0, 10]         forward speed of action 1.0 (m/s)
max_sideways  0.15     (0, 10]         sideways speed of action 1.0 (m/s)
max_turn      1.0      (0, 20]         turn rate of action 1.0 (rad/s)
kick_angle    1.05     (0, pi]         kick direction of action 1.0 (rad)
head_yaw      2.0      (0, pi]         head yaw of action 1.0 (rad)
pitch_min     -0.3     [-pi/2, pi/2]   head pitch of action -1.0 (rad; below pitch_max)
pitch_max     0.5      [-pi/2, pi/2]   head pitch of action 1.0 (rad)
============  =======  ==============  ==========================================================
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import ClassVar, Literal

import numpy as np
from numpy.typing import NDArray

from cognition.behaviors.message_budget import message_due
from cognition.behaviors.observation import ObservationBuilder
from cognition.brain import BrainContext, think_by_stages
from cognition.oracle import OracleInput
from cognition.params import Range, Ranges, check_ranges, positive
from cognition.pipeline import TRUTH, CognitionConfig, plan
from cognition.representations import BrainOutput, HeadRequest, KickRequest, MotionRequest, SensorFrame, WalkRequest
from cognition.worldmodel.beliefs import Beliefs, CognitionBeliefs, TruthBeliefs

ActionType = Literal["continuous", "discrete"]
ACTION_TYPES: tuple[str, ...] = ("continuous", "discrete")
CONTINUOUS_SIZE = 7
"""Length of a continuous action."""
MACROS: tuple[str, ...] = ("stand", "go_to_ball", "kick_to_goal", "pass", "defend", "support", "scan")
"""The discrete macro-actions, by index."""


class ActionError(ValueError):
    """An action that cannot be carried out (wrong shape, not finite, not a valid index)."""


@dataclass(frozen=True)
class ActionParams:
    """Scales of the continuous action (NAO-like limits; the walking engine clips further)."""

    max_forward: float = 0.25
    max_sideways: float = 0.15
    max_turn: float = 1.0
    kick_angle: float = 1.05
    head_yaw: float = 2.0
    pitch_min: float = -0.3
    pitch_max: float = 0.5

    RANGES: ClassVar[Ranges] = {
        "max_forward": positive(10.0),
        "max_sideways": positive(10.0),
        "max_turn": positive(20.0),
        "kick_angle": positive(math.pi),
        "head_yaw": positive(math.pi),
        "pitch_min": Range(-math.pi / 2, math.pi / 2),
        "pitch_max": Range(-math.pi / 2, math.pi / 2),
    }

    def __post_init__(self) -> None:
        check_ranges(self)
        if not self.pitch_min < self.pitch_max:
            raise ValueError(f"ActionParams.pitch_min ({self.pitch_min}) must be below pitch_max ({self.pitch_max})")


def check_action(action: object, action_type: str) -> NDArray[np.float64] | int:
    """The action as the robot will use it: a clipped float vector or a macro index.

    What is accepted follows the Gymnasium spaces' ``contains``:

    * **discrete**: one integer in ``0..len(MACROS)-1``: a Python ``int``, a numpy integer
      scalar or a 0-d integer array (what Stable-Baselines3 passes). ``bool``, floats (even
      ``2.0``), strings and arrays of any other shape are refused;
    * **continuous**: ``CONTINUOUS_SIZE`` finite real numbers, as a numpy array of a float or
      integer dtype or a list or tuple of real numbers. ``bool``, ``str``, ``complex`` or
      ``None`` entries (or arrays of those dtypes) are refused; values outside [-1, 1] are
      clipped (documented behaviour).

    Raises :class:`ActionError` naming the problem (wrong type, shape, a non-finite value, an
    index out of range).
    """
    if action_type == "discrete":
        return _macro_index(action)
    if action_type != "continuous":
        raise ValueError(f"unknown action type {action_type!r}; valid: {list(ACTION_TYPES)}")
    want = f"a continuous action must be {CONTINUOUS_SIZE} real numbers"
    if isinstance(action, np.ndarray):
        if action.dtype.kind not in "fiu":
            raise ActionError(f"{want}, got an array of dtype {action.dtype}")
        v = action.astype(np.float64)
    elif isinstance(action, list | tuple):
        for i, x in enumerate(action):
            if isinstance(x, bool | np.bool_) or not isinstance(x, int | float | np.integer | np.floating):
                raise ActionError(f"{want}; entry {i} is {x!r} ({type(x).__name__})")
        v = np.asarray(action, dtype=np.float64)
    else:
        raise ActionError(f"{want} (an array, list or tuple), got {action!r} ({type(action).__name__})")
    if v.shape != (CONTINUOUS_SIZE,):
        raise ActionError(f"a continuous action must have shape ({CONTINUOUS_SIZE},), got shape {v.shape}")
    if not np.isfinite(v).all():
        raise ActionError(f"a continuous action must be finite, got {v.tolist()}")
    np.minimum(v, 1.0, out=v)  # v is a copy: clip it in place ([-1, 1]; np.clip costs more on 7 values)
    np.maximum(v, -1.0, out=v)
    return v


def _macro_index(action: object) -> int:
    """The macro index of a discrete action (see :func:`check_action`)."""
    zero_d = isinstance(action, np.ndarray) and action.shape == () and action.dtype.kind in "iu"
    integer = isinstance(action, int | np.integer) and not isinstance(action, bool | np.bool_)
    if not (integer or zero_d):
        raise ActionError(
            f"a discrete action must be one integer in 0..{len(MACROS) - 1} (an int, a numpy integer or a 0-d "
            f"integer array), got {action!r} ({type(action).__name__})"
        )
    k = int(action)  # type: ignore[call-overload]
    if not 0 <= k < len(MACROS):
        raise ActionError(f"discrete action {k} is out of range 0..{len(MACROS) - 1} ({', '.join(MACROS)})")
    return k


def continuous_motion(a: NDArray[np.float64], p: ActionParams) -> MotionRequest:
    """The motion request of a checked continuous action (module table)."""
    forward, left, turn, kick, direction, yaw, pitch = a.tolist()  # Python floats (a float64 array)
    head = HeadRequest(yaw * p.head_yaw, p.pitch_min + 0.5 * (pitch + 1.0) * (p.pitch_max - p.pitch_min))
    if kick > 0.0:
        return MotionRequest(kick=KickRequest(direction * p.kick_angle, kick), head=head)
    walk = WalkRequest(forward * p.max_forward, left * p.max_sideways, turn * p.max_turn)
    return MotionRequest(walk=walk, head=head)


class PolicyBrain:
    """A robot whose decisions come from outside (an RL policy) and whose inputs are beliefs.

    ``cognition`` picks the providers of its cognition frame (:class:`~cognition.pipeline.CognitionConfig`;
    the default :data:`~cognition.pipeline.TRUTH` reads the ground truth, and then only when the
    policy needs the beliefs). Each frame :meth:`think` updates the beliefs and carries out the
    current action: a continuous action is held, a macro-action re-runs its skill on the new
    beliefs. :meth:`observation` gives the policy's view, :meth:`act` sets a new action and
    returns the motion it means now.
    """

    def __init__(
        self,
        action_type: str = "continuous",
        cognition: CognitionConfig = TRUTH,
        params: ActionParams | None = None,
    ):
        if action_type not in ACTION_TYPES:
            raise ValueError(f"unknown action type {action_type!r}; valid: {list(ACTION_TYPES)}")
        if not isinstance(cognition, CognitionConfig):
            raise TypeError(f"PolicyBrain: cognition must be a CognitionConfig, got {cognition!r}")
        self.action_type = action_type
        self.cognition = cognition
        self.params = params or ActionParams()
        self.uses_oracle = cognition.reads_ground_truth
        self.context: BrainContext | None = None
        self.provider: TruthBeliefs | CognitionBeliefs | None = None
        self.beliefs: Beliefs | None = None
        """The latest beliefs (``None`` before the first frame)."""
        self.pose = None
        self.action: NDArray[np.float64] | int = np.zeros(CONTINUOUS_SIZE) if action_type == "continuous" else 0
        self._motion_key = b""
        self._motion_of_action = MotionRequest()
        self.kicks = 0
        """Kick requests issued so far."""
        self._pending: tuple[SensorFrame, OracleInput | None] | None = None
        self._frame: tuple[SensorFrame, OracleInput | None] | None = None
        self._output = BrainOutput(motion=MotionRequest())
        self._stage_runs: dict[str, Callable[[], None]] = {"policy action": self._act_stage}
        self._stages: tuple[str, ...] = ("policy action",)

    def reset(self, context: BrainContext) -> None:
        """Build the cognition frame, the skills and the observation builder."""
        self.context = context
        if self.cognition.beliefs == "truth":
            # the oracle provider of the ``beliefs`` slot, run only when the policy needs beliefs
            plan(self.cognition, context.observation)
            self.provider = TruthBeliefs(context)
        else:
            self.provider = CognitionBeliefs(context, self.cognition)
        if self.action_type == "discrete":
            from cognition.behaviors.head_control import HeadControl
            from cognition.behaviors.skills import Skills

            self.skills = Skills(context)
            self.head = HeadControl(context)
        self.observer = ObservationBuilder(context.field, context.players_per_team, context.team_number)
        self.beliefs = None
        self._pending: tuple[SensorFrame, OracleInput | None] | None = None
        self.pose = None
        self.action = np.zeros(CONTINUOUS_SIZE) if self.action_type == "continuous" else 0
        self._motion_key = b""
        """The bytes of the action :attr:`_motion_of_action` belongs to (none yet)."""
        self._motion_of_action = MotionRequest()
        self._last_message = -1e9
        self._stage_runs = {"policy action": self._act_stage}
        """What each stage calls: the cognition stack's modules on its blackboard, then the action."""
        if isinstance(self.provider, CognitionBeliefs):
            self._stage_runs = {**self.provider.stage_calls(), "policy action": self._act_stage}
        self._stages = tuple(self._stage_runs)
        self._runs = tuple(self._stage_runs.values())

    def rejected_inputs(self) -> dict[str, int]:
        """Sensor inputs the cognition stack could not use, by kind (none on truth beliefs)."""
        return self.provider.rejected_inputs() if isinstance(self.provider, CognitionBeliefs) else {}

    # -- the frame, stage by stage (:class:`cognition.brain.StagedBrain`) ----------------------
    @property
    def stages(self) -> tuple[str, ...]:
        """The modules of one frame: the cognition stack's (none on truth beliefs), then the action."""
        return self._stages

    def think(self, frame: SensorFrame, oracle: OracleInput | None) -> BrainOutput:
        """Update the beliefs, then carry out the current action (every stage in order)."""
        return think_by_stages(self, frame, oracle)

    def begin(self, frame: SensorFrame, oracle: OracleInput | None) -> None:
        """Start a frame."""
        if self.provider is None or self.context is None:
            raise RuntimeError("PolicyBrain.think called before reset()")
        self._frame = (frame, oracle)
        if isinstance(self.provider, CognitionBeliefs):
            self.provider.begin(frame, oracle)

    def run_stage(self, stage: str) -> None:
        """Run one stage of :attr:`stages`: a module of the cognition stack, or the action."""
        self._stage_runs[stage]()

    def stage_runs(self) -> tuple[Callable[[], None], ...]:
        """The stages of :attr:`stages` as calls without arguments, in order (:func:`~cognition.brain.stage_runs`)."""
        return self._runs

    def _act_stage(self) -> None:
        self._output = self._carry_out()

    def finish(self) -> BrainOutput:
        """The motion (and team message) of the frame."""
        return self._output

    def _carry_out(self) -> BrainOutput:
        frame, oracle = self._frame
        if isinstance(self.provider, TruthBeliefs):
            # the oracle providers hold no state: read the truth only when it is needed
            self._pending = (frame, oracle)
            self.beliefs = None
            if frame.penalty or frame.picked_up or frame.fallen:
                return BrainOutput(motion=MotionRequest())
            if self.action_type == "continuous":
                return BrainOutput(motion=self._count(self._continuous()))
            self.beliefs = self.provider.update(frame, oracle)
        else:
            assert self.provider is not None
            self.beliefs = self.provider.finish()
            self.pose = self.beliefs.pose
        return BrainOutput(motion=self.motion(), message=self._message(frame))

    def observation(self) -> NDArray[np.float32]:
        """The policy's observation of the latest beliefs (:mod:`cognition.behaviors.observation`)."""
        return self.observer.build(self.latest_beliefs())

    def latest_beliefs(self) -> Beliefs:
        """The beliefs of the latest frame (computed now if the truth provider deferred them)."""
        if self.beliefs is None:
            if self._pending is None or not isinstance(self.provider, TruthBeliefs):
                raise RuntimeError("PolicyBrain has no beliefs before its first frame")
            self.beliefs = self.provider.update(*self._pending)
        return self.beliefs

    def act(self, action: NDArray[np.float64] | int) -> MotionRequest:
        """Take a checked action (:func:`check_action`); returns the motion it means now."""
        self.action = action
        return self.motion()

    def motion(self) -> MotionRequest:
        """The motion of the current action on the latest beliefs (standing while not playing)."""
        if self.beliefs is None and self._pending is None:
            return MotionRequest()
        b = self.latest_beliefs()
        if b.penalty or b.picked_up or b.fallen:
            return MotionRequest()
        if self.action_type == "continuous":
            m = self._continuous()
        else:
            m = self._macro(int(self.action), b)  # type: ignore[arg-type]
        return self._count(m)

    def _continuous(self) -> MotionRequest:
        """:func:`continuous_motion` of the current action, computed once per action value (the
        environment asks for it when the action arrives and again in every cognition frame)."""
        action: NDArray[np.float64] = self.action  # type: ignore[assignment]
        key = action.tobytes()
        if key != self._motion_key:
            self._motion_key = key
            self._motion_of_action = continuous_motion(action, self.params)
        return self._motion_of_action

    def _count(self, m: MotionRequest) -> MotionRequest:
        self.kicks += m.kick is not None
        return m

    def _macro(self, k: int, b: Beliefs) -> MotionRequest:
        sk = self.skills
        name = MACROS[k]
        if name == "stand":
            m = sk.stand(b)
        elif name == "go_to_ball":
            m = sk.go_to_ball(b)
        elif name == "kick_to_goal":
            m = sk.kick_to_goal(b)
        elif name == "pass":
            m = sk.pass_to(b)
        elif name == "defend":
            m = sk.defend(b)
        elif name == "support":
            m = sk.support(b, b.player_number)
        else:
            m = sk.stand(b)
        head = self.head.request(b) if name != "scan" else self.head.scan(b)
        return MotionRequest(m.walk, m.kick, head)  # dataclasses.replace(m, head=head), without its field walk

    def _message(self, frame: SensorFrame) -> bytes | None:
        """Team messages in cognition mode (teammates' team ball), spreading the team's budget."""
        if not isinstance(self.provider, CognitionBeliefs):
            return None
        assert self.context is not None
        c = self.context
        if not message_due(frame.game, c.team_number, c.players_per_team, frame.time, self._last_message, 1.0):
            return None
        self._last_message = frame.time
        return self.provider.message()
