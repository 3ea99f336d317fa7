"""Every numeric parameter has a documented range, checked when its dataclass is built.

Covers :func:`cognition.params.check_ranges` on every parameters dataclass (values below and
above the range, NaN, infinity, bool, str and complex each refused with an error naming
``Class.field``), that every numeric field declares a range and the module table documents
it, the audit cases of issue 14, the per-frame requests and :func:`check_action`.
"""

from __future__ import annotations

import dataclasses
import importlib
import math
import pkgutil
import re
import sys
import types
import typing
from typing import Any

import hypothesis.strategies as st
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings

import cognition
import envs
import teamsim
from cognition.behaviors.actions import CONTINUOUS_SIZE, ActionError, ActionParams, check_action
from cognition.behaviors.head_control import HeadParams
from cognition.behaviors.skills import SkillParams
from cognition.camera import NAO_LOWER, NAO_UPPER, CameraRig, CameraSpec
from cognition.field import FIELD_PRESETS, FieldDimensions
from cognition.localization import LocalizationParams
from cognition.params import PROBABILITY, Range, check_number, positive
from cognition.pipeline import CognitionConfig
from cognition.representations import HeadRequest, KickRequest, WalkRequest
from cognition.vision import ColourParams, VisionParams
from cognition.vision.ball import BallParams
from cognition.vision.hough import HoughParams
from cognition.vision.posts import PostParams
from cognition.vision.robots import ObstacleParams
from cognition.worldmodel.goal import GoalModel, GoalModelParams
from cognition.worldmodel.hypotheses import HypothesisParams
from cognition.worldmodel.kalman_ball import KalmanBallParams
from cognition.worldmodel.obstacles import ObstacleGridParams, ObstacleSectors
from envs.core import EnvConfig, RewardWeights
from teamsim.channel import ChannelParams
from teamsim.events import ForceFall, ForcePenalty, Kidnap, PlaceBall
from teamsim.fouls import FoulParams
from teamsim.gc_bridge import BridgeParams
from teamsim.image_params import ImageParams
from teamsim.match import MatchConfig
from teamsim.odometry import OdometryParams
from teamsim.percept_params import Detection, PerceptParams
from teamsim.referee import RefereeParams
from teamsim.robot import RobotParams
from teamsim.world import PhysicsParams

BASES: dict[type, Any] = {
    BridgeParams: BridgeParams("listen"),
    PhysicsParams: PhysicsParams(),
    RobotParams: RobotParams(),
    RefereeParams: RefereeParams(),
    FoulParams: FoulParams(),
    OdometryParams: OdometryParams(),
    ChannelParams: ChannelParams(),
    Detection: Detection(),
    PerceptParams: PerceptParams(),
    ImageParams: ImageParams(),
    CameraSpec: NAO_UPPER,
    CameraRig: CameraRig(),
    FieldDimensions: FIELD_PRESETS["spl2025"],
    LocalizationParams: LocalizationParams(),
    CognitionConfig: CognitionConfig(),
    ObstacleGridParams: ObstacleGridParams(),
    HypothesisParams: HypothesisParams(),
    GoalModelParams: GoalModelParams(),
    KalmanBallParams: KalmanBallParams(),
    HeadParams: HeadParams(),
    ActionParams: ActionParams(),
    SkillParams: SkillParams(),
    EnvConfig: EnvConfig(),
    VisionParams: VisionParams(),
    ColourParams: ColourParams(),
    HoughParams: HoughParams(),
    PostParams: PostParams(),
    BallParams: BallParams(),
    ObstacleParams: ObstacleParams(),
    RewardWeights: RewardWeights(),
    MatchConfig: MatchConfig(),
    Kidnap: Kidnap(1.0, 0, 1, (0.5, -0.5, 1.0)),
    PlaceBall: PlaceBall(1.0, 0.5, 0.5),
    ForcePenalty: ForcePenalty(1.0, 0, 1),
    ForceFall: ForceFall(1.0, 0, 1),
}
"""A valid instance of every parameters dataclass (the class default where there is one)."""

DOC_MODULES: dict[type, str] = {EnvConfig: "envs.soccer_v0"}
"""Where a class's parameter table lives when it is not its own module's docstring."""


def _numeric(hint: Any) -> tuple[bool, bool] | None:
    """(integer, tuple) for a numeric annotation (``float``, ``int``, ``X | None``, tuples of
    them), ``None`` otherwise. Written independently of :mod:`cognition.params`."""
    if typing.get_origin(hint) in (typing.Union, types.UnionType):
        rest = [a for a in typing.get_args(hint) if a is not type(None)]
        if len(rest) != 1:
            return None
        hint = rest[0]
    is_tuple = typing.get_origin(hint) is tuple
    if is_tuple:
        hint = typing.get_args(hint)[0]
    if hint is bool or hint not in (int, float):
        return None
    return hint is int, is_tuple


def _numeric_fields(cls: type) -> dict[str, tuple[bool, bool]]:
    hints = typing.get_type_hints(cls)
    found = {f.name: _numeric(hints[f.name]) for f in dataclasses.fields(cls)}
    return {name: kind for name, kind in found.items() if kind is not None}


def _ranges(cls: type, name: str) -> tuple[Range, ...]:
    spec = cls.RANGES[name]  # type: ignore[attr-defined]
    return spec if isinstance(spec, tuple) else (spec,)


def _with(cls: type, name: str, value: Any) -> Any:
    """The base instance of ``cls`` with ``value`` in field ``name`` (entry 0 of a tuple field)."""
    base = BASES[cls]
    if _numeric_fields(cls)[name][1]:
        old = getattr(base, name)
        value = (value, *old[1:]) if old is not None else (value, *_inside_all(cls, name)[1:])
    return dataclasses.replace(base, **{name: value})


def _inside_all(cls: type, name: str) -> tuple[float, ...]:
    """Values inside the ranges of a tuple field whose base value is ``None`` (Kidnap's pose)."""
    return tuple(r.low if not r.low_open else (r.low + r.high) / 2 for r in _ranges(cls, name))


def _outside(r: Range, integer: bool) -> tuple[float, float]:
    """The nearest values below and above ``r``."""
    if integer:
        return (r.low if r.low_open else r.low - 1), (r.high if r.high_open else r.high + 1)
    below = r.low if r.low_open else math.nextafter(r.low, -math.inf)
    above = r.high if r.high_open else math.nextafter(r.high, math.inf)
    return below, above


CASES = [(cls, name) for cls in BASES for name in _numeric_fields(cls)]
BAD = ["below", "above", "nan", "inf", "true", "string", "complex"]


def test_every_numeric_field_has_a_declared_range() -> None:
    for cls in BASES:
        declared = getattr(cls, "RANGES", None)
        assert declared is not None, f"{cls.__name__} declares no RANGES"
        missing = sorted(set(_numeric_fields(cls)) - set(declared))
        assert not missing, f"{cls.__name__}: numeric fields without a range: {missing}"
        for name in _numeric_fields(cls):
            for r in _ranges(cls, name):
                assert math.isfinite(r.low) and math.isfinite(r.high)


def _all_modules() -> list[str]:
    names = []
    for pkg in (cognition, teamsim, envs):
        for info in pkgutil.walk_packages(pkg.__path__, pkg.__name__ + "."):
            if not info.name.endswith("__main__"):
                names.append(info.name)
    return names


def test_every_parameters_dataclass_is_covered_here() -> None:
    """A new parameters dataclass (``*Params``, ``*Config``, ``*Weights`` or one with ``RANGES``)
    must be added to ``BASES``, so that the tests below check its fields."""
    found = set()
    for name in _all_modules():
        module = importlib.import_module(name)
        for obj in vars(module).values():
            if not (isinstance(obj, type) and dataclasses.is_dataclass(obj) and obj.__module__ == name):
                continue
            if "RANGES" in vars(obj) or obj.__name__.endswith(("Params", "Config", "Weights")):
                found.add(obj)
    assert found - set(BASES) == set(), f"not covered: {sorted(c.__name__ for c in found - set(BASES))}"


@pytest.mark.parametrize("cls", list(BASES), ids=lambda c: c.__name__)
def test_defaults_and_presets_construct(cls: type) -> None:
    base = BASES[cls]
    assert dataclasses.replace(base) == base  # re-validates
    for preset in getattr(cls, "PRESETS", {}).values():
        assert dataclasses.replace(preset) == preset
    for name in _numeric_fields(cls):
        value = getattr(base, name)
        values = value if isinstance(value, tuple) else (value,)
        for v, r in zip(values, _ranges(cls, name) * len(values), strict=False):
            assert v is None or v in r, f"{cls.__name__}.{name} default {v!r} outside {r}"


def test_field_presets_and_cameras_validate() -> None:
    for dims in FIELD_PRESETS.values():
        assert dataclasses.replace(dims) == dims
    for spec in (NAO_UPPER, NAO_LOWER):
        assert dataclasses.replace(spec) == spec


@pytest.mark.parametrize("bad", BAD)
@pytest.mark.parametrize(("cls", "name"), CASES, ids=[f"{c.__name__}.{n}" for c, n in CASES])
def test_bad_values_are_refused_naming_the_field(cls: type, name: str, bad: str) -> None:
    integer = _numeric_fields(cls)[name][0]
    below, above = _outside(_ranges(cls, name)[0], integer)
    value: Any = {
        "below": below,
        "above": above,
        "nan": math.nan,
        "inf": math.inf,
        "true": True,
        "string": "1",
        "complex": 1 + 0j,
    }[bad]
    expected = TypeError if bad in ("true", "string", "complex") else ValueError
    if integer and bad in ("nan", "inf"):
        expected = TypeError  # a float is not an integer
    with pytest.raises(expected) as info:
        _with(cls, name, value)
    message = str(info.value)
    assert f"{cls.__name__}.{name}" in message
    assert repr(value) in message
    if expected is ValueError:
        assert str(_ranges(cls, name)[0]) in message


def _table_rows(doc: str, name: str) -> list[str]:
    """The lines of ``doc`` whose first cell is ``name``: RST simple table rows (the name then
    at least two spaces) or Markdown rows (``| ``name`` |``)."""
    pattern = rf"^(\| ``{re.escape(name)}`` \||{re.escape(name)}  )"
    return [line for line in doc.splitlines() if re.match(pattern, line)]


@pytest.mark.parametrize(("cls", "name"), CASES, ids=[f"{c.__name__}.{n}" for c, n in CASES])
def test_module_table_documents_the_range(cls: type, name: str) -> None:
    module = sys.modules[DOC_MODULES.get(cls, cls.__module__)]
    rows = _table_rows(module.__doc__ or "", name)
    assert rows, f"{module.__name__} has no table row for {cls.__name__}.{name}"
    wanted = [str(r) for r in _ranges(cls, name)]
    assert any(all(w in row for w in wanted) for row in rows), f"{module.__name__}: no row of {name} gives {wanted}"


# -- the audit cases -----------------------------------------------------------------------


@pytest.mark.parametrize(
    "name",
    [
        "kick_reach",
        "kick_half_angle",
        "kick_direction_sigma",
        "kick_strength_sigma",
        "kick_max_angle",
        "fall_speed_threshold",
        "fall_probability_slope",
        "getup_sigma",
        "head_yaw_limit",
    ],
)
def test_negative_robot_fields_are_refused(name: str) -> None:
    """These nine were not checked: a negative sigma aborted a match in ``rng.normal`` when the
    first robot fell or kicked; a negative reach or angle silently broke kicks."""
    with pytest.raises(ValueError, match=rf"RobotParams\.{name} must be a real number in [\[(]0, .*\], got -0\.5"):
        RobotParams(**{name: -0.5})


def test_head_pitch_limits_must_be_finite_and_ordered() -> None:
    with pytest.raises(ValueError, match=r"RobotParams\.head_pitch_max .*got nan"):
        RobotParams(head_pitch_max=math.nan)
    with pytest.raises(ValueError, match=r"RobotParams\.head_pitch_min \(0\.5\) must not exceed head_pitch_max"):
        RobotParams(head_pitch_min=0.5, head_pitch_max=0.2)


def test_huge_field_length_and_physics_rate_are_refused() -> None:
    """Both made a run that never ends (a 1e308 m field, a 1e-308 s time step)."""
    with pytest.raises(ValueError, match=r"FieldDimensions\.length must be a real number in \(0, 100\], got 1e\+308"):
        dataclasses.replace(FIELD_PRESETS["spl2025"], length=1e308)
    with pytest.raises(ValueError, match=r"PhysicsParams\.physics_hz must be a real number in \[10, 10000\]"):
        PhysicsParams(physics_hz=1e308)


def test_huge_size_parameters_are_refused() -> None:
    """``maturing_candidates=10**10`` ended in MemoryError; every size is bounded."""
    with pytest.raises(ValueError, match=r"LocalizationParams\.maturing_candidates .*\[1, 10000\], got 10000000000"):
        LocalizationParams(maturing_candidates=10**10)
    with pytest.raises(ValueError, match=r"LocalizationParams\.particles .*\[1, 100000\]"):
        LocalizationParams(particles=10**6)
    with pytest.raises(ValueError, match=r"CameraSpec\.width .*\[8, 2048\], got 100000"):
        dataclasses.replace(NAO_UPPER, width=100_000)
    with pytest.raises(ValueError, match=r"ChannelParams\.budget .*\[0, 1000000\]"):
        ChannelParams(budget=10**12)


def test_obstacle_grid_size_is_bounded() -> None:
    """``extent`` and ``cell`` are each in range but together asked for 10,000 x 10,000 cells."""
    with pytest.raises(ValueError, match=r"ObstacleGridParams\.extent and cell give a grid of 10000 x 10000"):
        ObstacleGridParams(extent=50.0, cell=0.01)
    with pytest.raises(ValueError, match="grid of 0 x 0"):
        ObstacleGridParams(extent=0.01, cell=1.0)
    assert ObstacleGridParams(extent=5.0, cell=0.02).cells_per_side == 500


def test_sections_of_a_match_config_must_be_their_dataclass() -> None:
    with pytest.raises(TypeError, match=r"MatchConfig\.physics must be a PhysicsParams, got 5"):
        MatchConfig(physics=5)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=r"MatchConfig\.referee must be a RefereeParams, got None"):
        MatchConfig(referee=None)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=r"PhysicsParams\.robot must be a RobotParams"):
        PhysicsParams(robot={"radius": 0.1})  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=r"PerceptParams\.ball must be a Detection"):
        PerceptParams(ball=0.9)  # type: ignore[arg-type]
    assert MatchConfig(percepts="harsh").percepts == PerceptParams.PRESETS["harsh"]  # names still work


def test_bools_strings_and_complex_numbers_are_not_numbers() -> None:
    with pytest.raises(TypeError, match=r"MatchConfig\.seed must be an integer .*got True \(bool\)"):
        MatchConfig(seed=True)
    with pytest.raises(TypeError, match=r"LocalizationParams\.particles must be an integer .*got 300\.0 \(float\)"):
        LocalizationParams(particles=300.0)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=r"RewardWeights\.goal must be a real number .*got '1' \(str\)"):
        RewardWeights.from_any({"goal": "1"})  # was float("1"), silently
    with pytest.raises(TypeError, match=r"RewardWeights\.penalty .*got True"):
        EnvConfig(reward_weights={"penalty": True})
    with pytest.raises(TypeError, match=r"LocalizationParams\.adaptive must be true or false, got 1"):
        LocalizationParams(adaptive=1)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=r"FieldDimensions\.centre_mark must be true or false"):
        dataclasses.replace(FIELD_PRESETS["spl2025"], centre_mark="yes")


def test_numpy_scalars_and_lists_are_stored_as_python_values() -> None:
    p = PhysicsParams(physics_hz=np.float32(200.0), substeps=np.int64(3))
    assert type(p.physics_hz) is float and p.physics_hz == 200.0
    assert type(p.substeps) is int and p.substeps == 3
    assert ImageParams(white_balance=[1.1, 1.0, 0.9]).white_balance == (1.1, 1.0, 0.9)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"ImageParams\.white_balance must have 3 entries"):
        ImageParams(white_balance=(1.0, 1.0))  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"ImageParams\.white_balance\[2\] .*\(0, 10\], got -1"):
        ImageParams(white_balance=(1.0, 1.0, -1.0))
    with pytest.raises(TypeError, match=r"RefereeParams\.team_numbers must be a tuple of 2 numbers"):
        RefereeParams(team_numbers=3)  # type: ignore[arg-type]


def test_scripted_events_are_checked() -> None:
    with pytest.raises(ValueError, match=r"Kidnap\.time .*got -1\.0"):
        Kidnap(-1.0, 0, 1)
    with pytest.raises(ValueError, match=r"Kidnap\.team must be an integer in \[0, 1\], got 2"):
        Kidnap(1.0, 2, 1)
    with pytest.raises(ValueError, match=r"ForceFall\.number must be an integer in \[1, 20\], got 0"):
        ForceFall(1.0, 0, 0)
    with pytest.raises(ValueError, match=r"Kidnap\.pose\[2\] .*\[-2pi, 2pi\], got 10\.0"):
        Kidnap(1.0, 0, 1, (0.0, 0.0, 10.0))
    with pytest.raises(ValueError, match=r"PlaceBall\.x .*\[-60, 60\], got 1000\.0"):
        PlaceBall(1.0, 1000.0, 0.0)
    with pytest.raises(ValueError, match=r"ForcePenalty\.code must be an SPL penalty code .*got 12"):
        ForcePenalty(1.0, 0, 1, code=12)
    with pytest.raises(ValueError, match=r"ForceFall\.duration .*\(0, 3600\], got 0\.0"):
        ForceFall(1.0, 0, 1, duration=0.0)


def test_match_config_puts_events_on_its_own_carpet_and_teams() -> None:
    """The spl2025 carpet reaches 4.5 + 0.7 m along x and 3 + 0.7 m along y."""
    assert MatchConfig(events=(PlaceBall(1.0, 5.2, 3.7), Kidnap(1.0, 0, 1, (-5.2, 0.0, 0.0))))
    with pytest.raises(ValueError, match=r"MatchConfig\.events\[1\]: PlaceBall at \(5\.3, 0\.0\) is off the carpet"):
        MatchConfig(events=(PlaceBall(1.0, 0.0, 0.0), PlaceBall(1.0, 5.3, 0.0)))
    with pytest.raises(ValueError, match=r"MatchConfig\.events\[0\]: Kidnap at \(0\.0, -4\.0\) is off the carpet"):
        MatchConfig(events=(Kidnap(1.0, 0, 1, (0.0, -4.0, 0.0)),))
    with pytest.raises(ValueError, match=r"MatchConfig\.events\[0\]: ForceFall names player 3 but teams have 2"):
        MatchConfig(players_per_team=2, events=(ForceFall(1.0, 1, 3),))
    with pytest.raises(TypeError, match=r"MatchConfig\.events\[0\]: unknown scripted event"):
        MatchConfig(events=("kidnap",))  # type: ignore[arg-type]


def test_function_arguments_use_the_same_check() -> None:
    with pytest.raises(ValueError, match=r"GoalModel\.separation .*\(0, 100\], got -1\.5"):
        GoalModel(-1.5)
    with pytest.raises(TypeError, match=r"ObstacleSectors\.memory .*got '3' \(str\)"):
        ObstacleSectors("3")  # type: ignore[arg-type]
    assert check_number("X", "y", np.float64(0.5), PROBABILITY) == 0.5
    with pytest.raises(TypeError, match=r"X\.y must be an integer in \[0, 1\], got np\.float64\(1\.0\)"):
        check_number("X", "y", np.float64(1.0), PROBABILITY, integer=True)


def test_range_notation() -> None:
    assert str(positive(100.0)) == "(0, 100]"
    assert str(Range(-math.pi / 2, math.pi / 2)) == "[-pi/2, pi/2]"
    assert str(Range(0.0, 1.0, high_open=True)) == "[0, 1)"
    assert str(Range(0, 2**63 - 1)) == "[0, 2^63-1]"
    assert 1.0 not in Range(0.0, 1.0, high_open=True) and 0.0 in Range(0.0, 1.0)
    assert math.nan not in Range(-1.0, 1.0)
    with pytest.raises(ValueError, match="finite ends"):
        Range(0.0, math.inf)
    with pytest.raises(ValueError, match="empty"):
        Range(1.0, 1.0, low_open=True)


# -- fuzzing: any value is either accepted or refused with the documented error -------------

_VALUES = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(min_value=-(10**20), max_value=10**20),
    st.booleans(),
    st.text(max_size=3),
    st.complex_numbers(max_magnitude=10.0),
    st.none(),
)


@settings(max_examples=400, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(case=st.sampled_from(CASES), value=_VALUES)
def test_any_value_is_accepted_or_refused_naming_the_field(case: tuple[type, str], value: object) -> None:
    cls, name = case
    integer, is_tuple = _numeric_fields(cls)[name]
    optional = type(None) in typing.get_args(typing.get_type_hints(cls)[name]) and not is_tuple  # None as entry 0
    right_type = isinstance(value, int) and not isinstance(value, bool)
    right_type = right_type or (isinstance(value, float) and not integer) or (value is None and optional)
    inside = value is None or (right_type and value in _ranges(cls, name)[0])  # type: ignore[operator]
    try:
        built = _with(cls, name, value)
    except TypeError as e:
        assert not right_type, f"{cls.__name__}.{name}={value!r} refused: {e}"
        assert f"{cls.__name__}.{name}" in str(e)
    except ValueError as e:
        assert str(e).startswith(cls.__name__), str(e)  # in range, only a rule between fields may refuse it
        if not inside:
            assert f"{cls.__name__}.{name}" in str(e)
    else:
        assert right_type and inside, f"{cls.__name__}.{name}={value!r} was accepted"
        stored = getattr(built, name)
        assert value is None or (stored[0] if isinstance(stored, tuple) else stored) == value


# -- per-frame requests and policy actions --------------------------------------------------


@pytest.mark.parametrize("bad", [True, "0.1", 1 + 0j, None])
@pytest.mark.parametrize(
    ("cls", "name"),
    [(WalkRequest, "forward"), (WalkRequest, "turn"), (KickRequest, "direction"), (HeadRequest, "yaw")],
)
def test_requests_refuse_non_numbers(cls: type, name: str, bad: object) -> None:
    with pytest.raises(TypeError, match=rf"{cls.__name__}\.{name} must be a finite number, got "):
        cls(**{name: bad})


def test_requests_take_ints_and_numpy_floats() -> None:
    assert WalkRequest(forward=np.float64(0.1), left=1, turn=np.float32(0.5)).left == 1
    with pytest.raises(ValueError, match=r"HeadRequest\.pitch must be a finite number, got nan"):
        HeadRequest(pitch=math.nan)


@pytest.mark.parametrize("good", [3, np.int64(3), np.uint8(3), np.array(3), np.array(3, dtype=np.int32)])
def test_discrete_actions_accept_what_gymnasium_discrete_accepts(good: object) -> None:
    assert check_action(good, "discrete") == 3


@pytest.mark.parametrize("bad", [True, np.bool_(True), 2.0, np.float64(2.0), "2", 2 + 0j, None, np.array([2])])
def test_discrete_actions_refuse_other_types(bad: object) -> None:
    with pytest.raises(ActionError, match=r"a discrete action must be one integer in 0\.\.6.*got"):
        check_action(bad, "discrete")


@pytest.mark.parametrize(
    ("bad", "problem"),
    [
        ([True] + [0.0] * 6, r"entry 0 is True \(bool\)"),
        ([0.0, "1"] + [0.0] * 5, r"entry 1 is '1' \(str\)"),
        ([0.0] * 6 + [1j], r"entry 6 is 1j \(complex\)"),
        (np.zeros(CONTINUOUS_SIZE, dtype=complex), "dtype complex128"),
        (np.zeros(CONTINUOUS_SIZE, dtype=bool), "dtype bool"),
        (np.array(["0"] * CONTINUOUS_SIZE), "dtype <U1"),
        ("0000000", r"got '0000000' \(str\)"),
        (0.5, r"got 0\.5 \(float\)"),
    ],
)
def test_continuous_actions_refuse_non_real_values(bad: object, problem: str) -> None:
    with pytest.raises(ActionError, match=rf"a continuous action must be 7 real numbers.*{problem}"):
        check_action(bad, "continuous")


def test_continuous_actions_take_real_arrays_and_lists() -> None:
    for good in (np.zeros(7, dtype=np.float32), np.zeros(7, dtype=np.int64), [0, 0.5, 1, -1, 0, 0, 2], (0.0,) * 7):
        out = check_action(good, "continuous")
        assert isinstance(out, np.ndarray) and out.dtype == np.float64 and out.shape == (7,)
    assert check_action([0, 0.5, 1, -1, 0, 0, 2], "continuous")[6] == 1.0  # clipped
