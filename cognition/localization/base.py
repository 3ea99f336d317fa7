"""What every localization variant shares: the interface, game-controller events, the simple variants.

A localizer is built once per robot and fed every cognition frame:

``update(frame, truth=None) -> RobotPose``
    ``frame`` is the robot's :class:`~cognition.representations.SensorFrame` (odometry,
    percepts, game state, pickup flag); ``truth`` is the true team-frame pose and is read
    only by the ``oracle`` variant (the brain passes it only when it runs that variant).

Game-controller events (CMU paper, Sec. III.A) are detected here from consecutive frames
and handed to the variant as calls of :meth:`Localizer.on_side_switch`,
:meth:`Localizer.on_placement` and :meth:`Localizer.on_penalty`:

===============  ===========================================================================
event            detected when
===============  ===========================================================================
side switch      ``game.first_half`` goes from 1 to 0 (teams change ends at half time)
placement        the robot is picked up (both feet off the ground) while the game state is
                 INITIAL, READY or SET: it will be put down at a legal position
penalty          the robot's penalty code becomes non-zero, and again when it returns to 0;
                 a penalty cleared in INITIAL (the referee ends every penalty when a half
                 starts and lines the robots up on their touchline spots) is a placement
                 at the touchline spot instead
===============  ===========================================================================

Input that cannot be trusted (non-finite or implausible odometry) is replaced by no motion
and counted (:class:`cognition.inputs.InputCheck`, :meth:`Localizer.rejected_inputs`). A
variant whose estimate still becomes non-finite is repaired: :meth:`Localizer.repair`
restarts it from the robot's possible positions, counted in :attr:`Localizer.repairs`, so
no filter is ever left in a broken state.

Frames: everything is in the robot's **team frame** (m, rad; own goal at -x).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from numpy.typing import NDArray

from cognition.field import Field
from cognition.gamestate import GameStateId
from cognition.geometry import wrap_angle
from cognition.inputs import InputCheck
from cognition.localization.params import LocalizationParams
from cognition.localization.places import placement_poses, return_poses
from cognition.representations import RobotPose, SensorFrame

_EMPTY3 = np.zeros((0, 3))
_EMPTY3.setflags(write=False)
_EMPTY1 = np.zeros(0)
_EMPTY1.setflags(write=False)
_PLACEMENT_STATES = (GameStateId.INITIAL, GameStateId.READY, GameStateId.SET)


class Localizer:
    """Base class: tracks game-controller events and dispatches to the variant's hooks."""

    name = "base"

    def __init__(
        self,
        field: Field,
        params: LocalizationParams | None = None,
        rng: np.random.Generator | None = None,
        player_number: int = 1,
        players_per_team: int = 5,
    ):
        if not isinstance(field, Field):
            raise TypeError(f"field must be a Field, got {type(field).__name__}")
        self.field = field
        self.params = params or LocalizationParams()
        if not isinstance(self.params, LocalizationParams):
            raise TypeError(f"params must be LocalizationParams, got {type(self.params).__name__}")
        self.rng = rng if rng is not None else np.random.default_rng(0)
        self.player_number = int(player_number)
        self.players_per_team = int(players_per_team)
        self._first_half: int | None = None
        self._penalty = 0
        self._picked = False
        self.frames = 0
        self.pose = RobotPose(0.0, 0.0, 0.0, np.diag([1e2, 1e2, 10.0]), True, 0, _EMPTY3, _EMPTY1, self.name)
        self.inputs = InputCheck("localization")
        """Counts the odometry this localizer replaced by no motion."""
        self.repairs = 0
        """Times the estimate became non-finite and the variant was restarted (:meth:`repair`)."""

    # -- the per-frame entry point ---------------------------------------------------------
    def update(
        self, frame: SensorFrame, truth: tuple[float, float, float] | None = None, *, checked: bool = False
    ) -> RobotPose:
        """Process one frame: input checks, game-controller events, then the variant's own update.
        ``checked``: the frame's odometry has passed an :class:`~cognition.inputs.InputCheck`
        already (the cognition pipeline's input check), so this localizer does not check it again."""
        if not isinstance(frame, SensorFrame):
            raise TypeError(f"expected a SensorFrame, got {type(frame).__name__}")
        if not checked:
            frame = self.inputs.frame(frame)
        self._game_events(frame)
        pose = self._update(frame, truth)
        if not (math.isfinite(pose.x) and math.isfinite(pose.y) and math.isfinite(pose.theta)):
            self.repairs += 1
            warnings.warn(
                f"{self.name} localization of player {frame.player_number} produced a non-finite pose at "
                f"t={frame.time:.2f} s; restarted from the robot's possible positions",
                RuntimeWarning,
                stacklevel=2,
            )
            self.repair(frame)
            pose = self._update(frame, truth)
        self.pose = pose
        self.frames += 1
        return self.pose

    def rejected_inputs(self) -> dict[str, int]:
        """Inputs this localizer could not use, by kind (:mod:`cognition.inputs`)."""
        return dict(self.inputs.rejected)

    def _game_events(self, frame: SensorFrame) -> None:
        game = frame.game
        if self._first_half is not None and self._first_half and not game.first_half:
            self.on_side_switch()
        self._first_half = int(game.first_half)
        penalty = frame.penalty
        if penalty != self._penalty:
            if not penalty and game.state == GameStateId.INITIAL:
                # a penalty cleared at the start of a half: the referee lines every robot up on its
                # touchline spot, not at a return spot (the return prior put robots penalised at
                # half time on the far touchline's return spot, 6 m and 180 degrees off)
                self.on_placement(
                    placement_poses(self.field, self.player_number, self.players_per_team, game.state, False)
                )
            else:
                self.on_penalty(bool(penalty), game.state)
        self._penalty = penalty
        picked = bool(frame.picked_up)
        if picked and not self._picked and not penalty and game.state in _PLACEMENT_STATES:
            kicking = game.kicking_team == frame.team_number
            self.on_placement(
                placement_poses(self.field, self.player_number, self.players_per_team, game.state, kicking)
            )
        self._picked = picked

    # -- hooks for the variants ------------------------------------------------------------
    def _update(self, frame: SensorFrame, truth: tuple[float, float, float] | None) -> RobotPose:
        raise NotImplementedError

    def on_side_switch(self) -> None:
        """Teams changed ends: mirror the belief (CMU III.A.1)."""

    def on_placement(self, poses: NDArray[np.float64]) -> None:
        """The robot is carried to one of ``poses`` (K x 3, team frame) (CMU III.A.2)."""

    def on_penalty(self, penalized: bool, state: int) -> None:
        """Penalty starts (``penalized``) or ends; the robot comes back at a return position (III.A.3)."""

    def return_poses(self) -> NDArray[np.float64]:
        """Where a penalised robot may come back (K x 3, team frame), for the active rule set."""
        return return_poses(self.field, self.params.return_rule)

    def repair(self, frame: SensorFrame) -> None:
        """Restart after a non-finite estimate: the variant forgets its state and believes the
        robot stands where the game state says it can be (the initial touchline spots before
        the game, else anywhere on the field)."""
        raise NotImplementedError


def _pose(x: float, y: float, th: float, cov: NDArray[np.float64], lost: bool, name: str) -> RobotPose:
    return RobotPose(x, y, wrap_angle(th), cov, lost, 0, _EMPTY3, _EMPTY1, name)


class DeadReckoning(Localizer):
    """``odometry``: integrates odometry from the last known placement; never looks at percepts.

    Starts at the robot's initial touchline position. Placements and penalty returns reset it
    to the first candidate pose (the one nearest to the current estimate). Its covariance
    grows with the distance walked (CMU Alg. 2 sigmas) and it never claims to be lost.
    """

    name = "odometry"

    def __init__(
        self, field: Field, params: LocalizationParams | None = None, rng=None, player_number=1, players_per_team=5
    ):  # type: ignore[no-untyped-def]
        super().__init__(field, params, rng, player_number, players_per_team)
        start = placement_poses(field, self.player_number, self.players_per_team, GameStateId.INITIAL, False)[0]
        self._x, self._y, self._th = float(start[0]), float(start[1]), float(start[2])
        self._var = np.diag([0.01, 0.01, 0.01])
        self.pose = _pose(self._x, self._y, self._th, self._var.copy(), False, self.name)

    def _update(self, frame: SensorFrame, truth: tuple[float, float, float] | None) -> RobotPose:
        o = frame.odometry
        c, s = math.cos(self._th), math.sin(self._th)
        self._x += float(c * o.dx - s * o.dy)
        self._y += float(s * o.dx + c * o.dy)
        self._th = wrap_angle(self._th + o.dtheta)
        p = self.params
        step = math.hypot(o.dx, o.dy)
        self._var[0, 0] += (p.sigma_mx * step) ** 2
        self._var[1, 1] += (p.sigma_mx * step) ** 2
        self._var[2, 2] += (p.sigma_mtheta * o.dtheta) ** 2 + (p.sigma_mytheta * o.dy) ** 2
        return _pose(self._x, self._y, self._th, self._var.copy(), False, self.name)

    def _jump(self, poses: NDArray[np.float64]) -> None:
        d = np.hypot(poses[:, 0] - self._x, poses[:, 1] - self._y)
        best = poses[int(np.argmin(d))]
        self._x, self._y, self._th = float(best[0]), float(best[1]), float(best[2])
        self._var = np.diag([0.01, 0.01, 0.01])

    def on_side_switch(self) -> None:
        self._x, self._y, self._th = -self._x, -self._y, wrap_angle(self._th + math.pi)

    def on_placement(self, poses: NDArray[np.float64]) -> None:
        self._jump(poses)

    def on_penalty(self, penalized: bool, state: int) -> None:
        if not penalized and self.params.penalty_prior:
            self._jump(self.return_poses())

    def repair(self, frame: SensorFrame) -> None:
        start = placement_poses(self.field, self.player_number, self.players_per_team, GameStateId.INITIAL, False)[0]
        self._x, self._y, self._th = float(start[0]), float(start[1]), float(start[2])
        self._var = np.diag([0.01, 0.01, 0.01])


class Oracle(Localizer):
    """``oracle``: reports the true pose it is handed (a baseline; needs ``truth`` every frame)."""

    name = "oracle"

    def _update(self, frame: SensorFrame, truth: tuple[float, float, float] | None) -> RobotPose:
        if truth is None:
            raise ValueError("the 'oracle' localization needs the true pose (truth=...) every frame")
        x, y, th = (float(v) for v in truth)
        if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(th)):
            raise ValueError(f"the 'oracle' localization was given a non-finite true pose {truth!r}")
        return _pose(x, y, th, np.zeros((3, 3)), False, self.name)

    def repair(self, frame: SensorFrame) -> None:
        """Never needed: the oracle keeps no state and refuses non-finite truth."""
