"""Frozen records with a fast constructor (:func:`cognition.records.fast_init`): the same
behaviour as the ``__init__`` that ``dataclass(frozen=True)`` writes, for every record it is
applied to and for the field forms a dataclass can declare."""

from __future__ import annotations

import dataclasses
import inspect
import pickle
from dataclasses import dataclass, field

import numpy as np
import pytest

import cognition.camera as camera
import cognition.gamestate as gamestate
import cognition.oracle as oracle
import cognition.representations as reps
import cognition.worldmodel.goal as goal
import cognition.worldmodel.hypotheses as hypotheses
import cognition.worldmodel.messages as messages
import cognition.worldmodel.obstacles as obstacles
import cognition.worldmodel.representations as wm_reps
import cognition.worldmodel.team as team
import teamsim.odometry as odometry
import teamsim.world as world
from cognition.records import dataclass_twin, fast_init

MODULES = (reps, wm_reps, oracle, odometry, gamestate, camera, world, goal, hypotheses, messages, obstacles, team)
RECORDS = [
    obj
    for module in MODULES
    for obj in vars(module).values()
    if isinstance(obj, type) and obj.__module__ == module.__name__ and obj.__init__.__module__ == module.__name__
    and dataclasses.is_dataclass(obj) and obj.__init__.__qualname__ == f"{obj.__qualname__}.__init__"
    and "_record_self_" in inspect.signature(obj.__init__).parameters
]  # fmt: skip


def test_the_hot_records_have_the_fast_constructor() -> None:
    names = {cls.__name__ for cls in RECORDS}
    hot = {"SensorFrame", "RobotPose", "BallModel", "MotionRequest", "Beliefs", "Teammate", "TrueOdometry"}
    hot |= {"GameControlData", "TeamInfo", "RobotInfo", "CollisionEvent", "CameraMatrix", "CameraImage"}
    assert hot | {"BallBelief", "GoalEstimate", "ObstacleModel", "TeamBallEstimate", "TeamMessage"} <= names


@pytest.mark.parametrize("cls", RECORDS, ids=lambda c: c.__name__)
def test_same_signature_as_the_dataclass_constructor(cls: type) -> None:
    ours = inspect.signature(cls)
    reference = inspect.signature(dataclass_twin(cls))
    assert list(ours.parameters) == list(reference.parameters)
    for name, p in ours.parameters.items():
        q = reference.parameters[name]
        assert p.kind == q.kind, name
        assert (p.default is inspect.Parameter.empty) == (q.default is inspect.Parameter.empty), name
        assert repr(p.default) == repr(q.default) or repr(q.default) == "<factory>", name


@dataclass
class _Mutable:
    value: int = 0


@fast_init
@dataclass(frozen=True)
class _AllForms:
    a: float
    b: int = 3
    items: list[int] = field(default_factory=list)
    box: _Mutable = field(default_factory=_Mutable)
    derived: float = field(default=0.5, init=False)
    made: list[int] = field(default_factory=lambda: [1], init=False)
    k: str = field(default="k", kw_only=True)

    def __post_init__(self) -> None:
        if self.a != self.a:
            raise ValueError("a must not be NaN")


def test_every_field_form_behaves_as_in_a_dataclass() -> None:
    r = _AllForms(1.0)
    assert (r.a, r.b, r.items, r.box, r.derived, r.made, r.k) == (1.0, 3, [], _Mutable(0), 0.5, [1], "k")
    assert _AllForms(1.0).items is not r.items and _AllForms(1.0).box is not r.box  # a fresh default each time
    assert _AllForms(2.0, 4, [7], k="z") == _AllForms(a=2.0, b=4, items=[7], k="z")
    assert _AllForms(2.0) != _AllForms(3.0)
    expected = "_AllForms(a=1.0, b=3, items=[], box=_Mutable(value=0), derived=0.5, made=[1], k='k')"
    assert repr(_AllForms(1.0)) == expected
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.a = 2.0  # type: ignore[misc]
    with pytest.raises(ValueError, match="NaN"):
        _AllForms(float("nan"))  # __post_init__ runs
    with pytest.raises(TypeError):
        _AllForms()  # type: ignore[call-arg]
    with pytest.raises(TypeError):
        _AllForms(1.0, 2, [], _Mutable(), "positional k")  # type: ignore[misc]
    with pytest.raises(TypeError):
        _AllForms(1.0, derived=2.0)  # type: ignore[call-arg]
    with pytest.raises(TypeError):
        _AllForms(1.0, unknown=2)  # type: ignore[call-arg]
    assert dataclasses.replace(r, b=9) == _AllForms(1.0, 9)
    assert pickle.loads(pickle.dumps(r)) == r
    assert [f.name for f in dataclasses.fields(r)] == ["a", "b", "items", "box", "derived", "made", "k"]


def test_records_equal_the_dataclass_construction() -> None:
    pose_args = (1.0, -2.0, 0.5, np.eye(3), True, 7, np.zeros((7, 3)), np.full(7, 1 / 7), "maturing")
    ours, reference = reps.RobotPose(*pose_args), dataclass_twin(reps.RobotPose)(*pose_args)
    assert dataclasses.asdict(ours).keys() == dataclasses.asdict(reference).keys()
    assert all(getattr(ours, n) is getattr(reference, n) for n in dataclasses.asdict(reference))
    assert reps.MotionRequest() == reps.MotionRequest(reps.WalkRequest(), None, reps.HeadRequest())
    assert hash(reps.WalkRequest(0.1, 0.2)) == hash(reps.WalkRequest(0.1, 0.2, 0.0))
    with pytest.raises(ValueError, match=r"WalkRequest\.forward"):
        reps.WalkRequest(float("nan"))  # the requests' checks still run
    with pytest.raises(ValueError, match=r"HeadRequest\.speed"):
        reps.HeadRequest(speed=0.0)


def test_refuses_what_it_cannot_speed_up() -> None:
    @dataclass
    class Plain:
        a: int

    @dataclass(frozen=True, slots=True)
    class Slotted:
        a: int

    @dataclass(frozen=True)
    class WithInitVar:
        a: int
        scale: dataclasses.InitVar[int] = 1

    for cls, words in ((Plain, "frozen dataclass"), (Slotted, "__slots__"), (WithInitVar, "InitVar"), (int, "frozen")):
        with pytest.raises(TypeError, match=words):
            fast_init(cls)


def test_a_sensor_frames_penalty_is_its_games_and_its_dictionary_holds_only_its_fields() -> None:
    """``SensorFrame.penalty`` answers for the frame's game and player (also for a frame made with
    another game by ``replace``), and asking it leaves nothing in the instance dictionary: a frame
    can be copied from its ``__dict__`` (as some tests and users do)."""
    pushing = gamestate.RobotInfo(penalty=gamestate.Penalty.PLAYER_PUSHING)
    rest = [gamestate.RobotInfo() for _ in range(gamestate.MAX_NUM_PLAYERS - 2)]
    players = (gamestate.RobotInfo(), pushing, *rest)
    game = gamestate.GameControlData(
        teams=(gamestate.TeamInfo(team_number=7, players=players), gamestate.TeamInfo(team_number=9))
    )
    odometry, head = reps.OdometryReading(0.0, 0.0, 0.0), reps.HeadState()
    frame = reps.SensorFrame(1.0, 0, 7, 2, odometry, head, game)
    assert frame.penalty == gamestate.Penalty.PLAYER_PUSHING
    assert set(frame.__dict__) == {f.name for f in dataclasses.fields(frame)}
    assert reps.SensorFrame(**frame.__dict__) == frame and pickle.loads(pickle.dumps(frame)) == frame
    assert dataclasses.replace(frame, player_number=1).penalty == 0
    playing = dataclasses.replace(game, teams=(gamestate.TeamInfo(team_number=7), gamestate.TeamInfo(team_number=9)))
    assert dataclasses.replace(frame, game=playing).penalty == 0
