"""Helpers for the frozen parameter dataclasses every module declares (brain and simulator).

``from_mapping(cls, data)`` builds a (possibly nested) parameters dataclass from a plain
mapping, as read from a scenario file or the command line. Unknown keys are an error that
names the key and the valid ones; nothing is silently ignored.

``check_ranges(self)``, called from every parameters dataclass's ``__post_init__``, checks
each field against its annotation and, for numbers, against the class's declared table
``RANGES: ClassVar[Ranges]`` (field name -> :class:`Range`, e.g. ``positive(100)`` for
(0, 100]). A ``float`` field takes real numbers only (no bool, str, complex or None), an
``int`` field only integers, a ``bool`` field only booleans, a nested dataclass field only
instances of its class. A numeric field without a declared range is an error when the class
is first built, so every numeric parameter has a documented range. Errors are ``TypeError``
(wrong type) or ``ValueError`` (outside the range; NaN and infinity always are), and name
``Class.field``, the range in interval notation and the bad value. :func:`check_number` is the
same check for one value (function arguments), :func:`check_finite` its cheap form for the
requests a brain builds every frame.
"""

from __future__ import annotations

import dataclasses
import math
import reprlib
import types
import typing
from collections.abc import Mapping
from typing import Any, TypeVar

import numpy as np

T = TypeVar("T")


def from_mapping(cls: type[T], data: Mapping[str, Any] | str, where: str = "", base: T | None = None) -> T:
    """Build the dataclass ``cls`` from ``data``; nested dataclass fields accept mappings.

    Keys missing from ``data`` keep the value of ``base`` (or the class default). A class
    with a ``PRESETS`` dict (name -> instance) also accepts a preset name instead of a
    mapping, and a mapping with a ``"preset"`` key starts from that preset.

    Errors name the key path, e.g. ``MatchConfig.physics.robot.radius`` (``where`` is the
    path of ``data`` itself; it defaults to the class name):

    - ``ValueError``: an unknown key (the message lists the valid ones) or preset, a value
      outside a ``Literal``, or a value the dataclass rejects (its own message, with the class
      name replaced by the path);
    - ``TypeError``: a value of the wrong type for its annotation (``str``, ``int``,
      ``float``, ``bool``, ``Literal``, a union of these with ``None``, fixed-length
      ``tuple``), a nested dataclass field given anything but a mapping, a preset name or an
      instance, or a missing key that has no default. JSON lists are accepted (and stored as
      tuples) where the annotation is a tuple.
    """
    if not dataclasses.is_dataclass(cls):
        raise TypeError(f"{cls!r} is not a dataclass")
    label = where or cls.__name__
    presets: Mapping[str, Any] | None = getattr(cls, "PRESETS", None)
    if isinstance(data, str):
        if presets is None:
            raise TypeError(f"{label}: expected a mapping, got the string {_short(data)}")
        data = {"preset": data}
    if not isinstance(data, Mapping):
        raise TypeError(f"{label}: expected a mapping, got {type(data).__name__}")
    data = dict(data)
    if presets is not None and "preset" in data:
        name = data.pop("preset")
        if not isinstance(name, str) or name not in presets:
            raise ValueError(f"unknown {label} preset {_short(name)}; valid presets: {sorted(presets)}")
        base = presets[name]
    hints = typing.get_type_hints(cls)
    fields = {f.name: f for f in dataclasses.fields(cls) if f.init}
    unknown = sorted(set(data) - set(fields), key=str)
    if unknown:
        extra = " (or 'preset')" if presets is not None else ""
        raise ValueError(f"unknown {label} key(s) {unknown}; valid keys: {sorted(fields)}{extra}")
    if base is None:
        missing = sorted(n for n, f in fields.items() if n not in data and _has_no_default(f))
        if missing:
            raise TypeError(f"{label}: missing key(s) {missing} (they have no default)")
    kwargs: dict[str, Any] = {}
    for name, value in data.items():
        hint = hints.get(name)
        path = f"{label}.{name}"
        if isinstance(hint, type) and dataclasses.is_dataclass(hint):
            if isinstance(value, Mapping | str):
                sub_base = getattr(base, name) if base is not None else _default_of(fields[name])
                value = from_mapping(hint, value, path, sub_base)
            elif not isinstance(value, hint):
                kinds = "a mapping, a preset name" if getattr(hint, "PRESETS", None) is not None else "a mapping"
                raise TypeError(f"{path}: expected {kinds} or {hint.__name__}, got {_kind(value)}")
        else:
            value = _checked(hint, value, path)
        kwargs[name] = value
    try:
        if base is not None:
            return dataclasses.replace(base, **kwargs)  # type: ignore[type-var]
        return cls(**kwargs)
    except (ValueError, TypeError) as exc:
        located = _at_path(exc, cls.__name__, label)
        if located is exc:
            raise
        raise located from exc


_SCALARS: dict[type, str] = {bool: "true or false", int: "an integer", float: "a number", str: "a string"}


def _checked(hint: Any, value: Any, path: str) -> Any:
    """``value`` if it fits the annotation ``hint`` (lists become tuples); ``TypeError`` otherwise.

    Annotations this does not understand (callables, arrays, unions of classes) pass the
    value through: the dataclass checks it.
    """
    wanted = _describe(hint)
    if wanted is None:
        return value
    if typing.get_origin(hint) in (typing.Union, types.UnionType) and isinstance(value, list | tuple):
        arms = [a for a in typing.get_args(hint) if typing.get_origin(a) is tuple]
        if arms:  # e.g. ``tuple[float, float, float] | None`` given a list
            return _checked(arms[0], value, path)
    if isinstance(hint, type) or typing.get_origin(hint) in (typing.Literal, typing.Union, types.UnionType):
        if _fits(hint, value):
            return value
        choices = typing.get_args(hint) if typing.get_origin(hint) is typing.Literal else ()
        error = ValueError if any(type(value) is type(c) for c in choices) else TypeError  # a value outside the set
        raise error(f"{path}: expected {wanted}, got {_kind(value)}")
    # a tuple annotation
    if not isinstance(value, list | tuple):
        raise TypeError(f"{path}: expected {wanted}, got {_kind(value)}")
    args = typing.get_args(hint)
    items = args[:1] * len(value) if len(args) == 2 and args[1] is Ellipsis else args
    if len(items) != len(value):
        raise TypeError(f"{path}: expected {wanted}, got {len(value)} item(s)")
    return tuple(_checked(h, v, f"{path}[{i}]") for i, (h, v) in enumerate(zip(items, value, strict=True)))


def _describe(hint: Any) -> str | None:
    """Words for the values ``hint`` allows, or ``None`` if :func:`_checked` does not check it."""
    if hint in _SCALARS:
        return _SCALARS[hint]
    if hint is type(None):
        return "null"
    origin = typing.get_origin(hint)
    args = typing.get_args(hint)
    if origin is typing.Literal:
        return "one of " + ", ".join(repr(a) for a in args)
    if origin in (typing.Union, types.UnionType):
        parts = [_describe(a) for a in args]
        return None if any(p is None for p in parts) else " or ".join(p for p in parts if p is not None)
    if origin is tuple and args:
        if len(args) == 2 and args[1] is Ellipsis:
            inner = _describe(args[0])
            return None if inner is None else f"a list of {inner.removeprefix('a ').removeprefix('an ')} values"
        parts = [_describe(a) for a in args]
        if any(p is None for p in parts):
            return None
        return f"a list of {len(args)} items ({', '.join(p for p in parts if p is not None)})"
    return None


def _fits(hint: Any, value: Any) -> bool:
    """Whether ``value`` is allowed by the scalar, ``Literal`` or union annotation ``hint``."""
    if hint is type(None):
        return value is None
    if hint is bool:
        return isinstance(value, bool)
    if hint is int:
        return isinstance(value, int) and not isinstance(value, bool)
    if hint is float:
        return isinstance(value, int | float) and not isinstance(value, bool)
    if hint is str:
        return isinstance(value, str)
    origin = typing.get_origin(hint)
    if origin is typing.Literal:
        return any(type(value) is type(a) and value == a for a in typing.get_args(hint))
    return any(_fits(a, value) for a in typing.get_args(hint))


def _at_path(exc: ValueError | TypeError, owner: str, label: str) -> ValueError | TypeError:
    """``exc`` with its message naming the key path ``label`` instead of the class ``owner``.

    The checks of the parameters dataclasses write ``Owner.field must ...``; that prefix
    becomes ``label.field``. Any other message gets ``label: `` in front.
    """
    message = str(exc)
    if message.startswith(f"{owner}."):
        located = label + message[len(owner) :]
    elif message.startswith(f"{label}.") or message.startswith(f"{label}:"):
        return exc
    else:
        located = f"{label}: {message}"
    if len(exc.args) <= 1:
        exc.args = (located,)
        if str(exc) == located:
            return exc
    return (TypeError if isinstance(exc, TypeError) else ValueError)(located)


def _kind(value: Any) -> str:
    """``type value`` for an error message, the value shortened."""
    return f"{type(value).__name__} {_short(value)}"


def _short(value: Any, limit: int = 60) -> str:
    """``repr(value)``, cut to about ``limit`` characters."""
    shortener = reprlib.Repr()
    shortener.maxstring = shortener.maxother = limit
    shortener.maxlist, shortener.maxdict, shortener.maxlevel = 6, 4, 2
    text = shortener.repr(value)
    return text if len(text) <= limit + 20 else text[:limit] + "..."


def _has_no_default(f: dataclasses.Field[Any]) -> bool:
    """Whether the field needs a value (no default and no default factory)."""
    return f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING


def _default_of(f: dataclasses.Field[Any]) -> Any:
    """A field's default value (``None`` if it has none)."""
    if f.default is not dataclasses.MISSING:
        return f.default
    if f.default_factory is not dataclasses.MISSING:
        return f.default_factory()
    return None


# -- ranges of numeric parameters ---------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class Range:
    """The values a numeric parameter may take: from ``low`` to ``high``, each end open or closed.

    Both ends are finite, so a value inside a range is finite as well; ``str()`` gives interval
    notation (``"(0, 100]"``), the form the module tables and the error messages use.
    """

    low: float
    high: float
    low_open: bool = False
    """Whether ``low`` itself is excluded."""
    high_open: bool = False
    """Whether ``high`` itself is excluded."""

    def __post_init__(self) -> None:
        for end in (self.low, self.high):
            if isinstance(end, bool) or not isinstance(end, int | float) or not math.isfinite(end):
                raise ValueError(f"a Range needs finite ends, got {self.low!r} and {self.high!r}")
        empty = self.low > self.high or (self.low == self.high and (self.low_open or self.high_open))
        if empty:
            raise ValueError(f"the range {self} is empty")

    def __contains__(self, value: float) -> bool:
        above = value > self.low if self.low_open else value >= self.low
        below = value < self.high if self.high_open else value <= self.high
        return above and below

    def __str__(self) -> str:
        left = "(" if self.low_open else "["
        right = ")" if self.high_open else "]"
        return f"{left}{_number_text(self.low)}, {_number_text(self.high)}{right}"


def positive(high: float) -> Range:
    """The range (0, ``high``]: quantities that must not vanish (lengths, rates, masses)."""
    return Range(0.0, high, low_open=True)


def non_negative(high: float) -> Range:
    """The range [0, ``high``]: quantities that may be 0 (sigmas, delays, allowances)."""
    return Range(0.0, high)


PROBABILITY = Range(0.0, 1.0)
"""The range [0, 1] of probabilities, shares and fractions."""

RangeSpec = Range | tuple[Range, ...]
"""What ``RANGES`` maps a field to: one range (a number, or every entry of a tuple) or one
range per entry of a fixed-length tuple (e.g. a pose's x, y and theta)."""
Ranges = dict[str, RangeSpec]
"""The type of a parameters dataclass's ``RANGES: ClassVar[Ranges]`` table."""


def _number_text(x: float) -> str:
    """``x`` for a message or a table: whole numbers exactly (``2^63-1`` for the largest seeds),
    quarter multiples of pi as ``pi/2``."""
    if isinstance(x, int) and x >= 2**20 and (x + 1) & x == 0:
        return f"2^{x.bit_length()}-1"
    if float(x).is_integer() and abs(x) < 1e16:
        return str(int(x))
    quarters = x / math.pi * 4.0
    k = round(quarters)
    if k != 0 and abs(quarters - k) < 1e-9:
        sign, k = ("-" if k < 0 else ""), abs(k)
        for div, suffix in ((4, ""), (2, "/2"), (1, "/4")):
            if k % div == 0:
                n = k // div
                return f"{sign}{'' if n == 1 else n}pi{suffix}"
    return f"{x:g}"


def check_number(owner: str, name: str, value: object, allowed: Range, integer: bool = False) -> Any:
    """``value`` if it is a number inside ``allowed``; numpy scalars come back as Python numbers.

    A real parameter (``integer`` false) accepts ``int``, ``float`` and numpy integer or
    floating scalars; an integer parameter accepts only integers (``int`` and its subclasses
    such as ``IntEnum``, numpy integer scalars). ``bool``, ``str``, ``complex`` and ``None``
    are never numbers here. Raises ``TypeError`` for a wrong type and ``ValueError`` for a value
    outside the range (NaN and infinity are always outside), both naming ``owner.name``, the
    range and the bad value.
    """
    cls = value.__class__
    if cls is int or (cls is float and not integer):
        number: Any = value
    elif isinstance(value, bool | np.bool_):
        number = None
    elif isinstance(value, int):
        number = value
    elif isinstance(value, np.integer):
        number = int(value)
    elif isinstance(value, float | np.floating) and not integer:
        number = float(value)
    else:
        number = None
    what = "an integer" if integer else "a real number"
    if number is None:
        raise TypeError(f"{owner}.{name} must be {what} in {allowed}, got {value!r} ({cls.__name__})")
    if number not in allowed:
        raise ValueError(f"{owner}.{name} must be {what} in {allowed}, got {value!r}")
    return number


def check_finite(owner: str, **values: object) -> None:
    """Raise unless every value is a finite real number (the per-frame requests' cheap check).

    Plain finite floats pass on a fast path. Otherwise the types are those of
    :func:`check_number` (``TypeError`` for bool, str, complex, None) and NaN or infinity is a
    ``ValueError``; both messages name ``owner.name`` and the bad value.
    """
    for name, v in values.items():
        if v.__class__ is float and v - v == 0.0:  # type: ignore[operator]
            continue
        if isinstance(v, bool | np.bool_) or not isinstance(v, int | float | np.integer | np.floating):
            raise TypeError(f"{owner}.{name} must be a finite number, got {v!r} ({type(v).__name__})")
        if not math.isfinite(v):
            raise ValueError(f"{owner}.{name} must be a finite number, got {v!r}")


@dataclasses.dataclass(frozen=True)
class _FieldCheck:
    """How :func:`check_ranges` checks one field, compiled once per class from its annotation."""

    name: str
    kind: str
    """``real``, ``int`` (numbers or tuples of them), ``bool`` or ``instance`` (a nested dataclass)."""
    optional: bool
    """``None`` is allowed (annotation ``X | None``)."""
    allowed: RangeSpec | None = None
    tuple_length: int | None = None
    """For a tuple field: the fixed length, or -1 for ``tuple[X, ...]``; ``None``: not a tuple."""
    cls: type | None = None

    def check(self, owner: str, value: Any) -> Any:
        """``value`` (normalised: numpy scalars to Python numbers, lists to tuples) or raise."""
        if value is None and self.optional:
            return None
        if self.kind == "bool":
            if value.__class__ is bool:
                return value
            if isinstance(value, np.bool_):
                return bool(value)
            raise TypeError(f"{owner}.{self.name} must be true or false, got {value!r} ({type(value).__name__})")
        if self.kind == "instance":
            assert self.cls is not None
            if not isinstance(value, self.cls):
                raise TypeError(
                    f"{owner}.{self.name} must be a {self.cls.__name__}, got {value!r} ({type(value).__name__})"
                )
            return value
        integer = self.kind == "int"
        if self.tuple_length is None:
            assert isinstance(self.allowed, Range)
            return check_number(owner, self.name, value, self.allowed, integer)
        if isinstance(value, list):
            value = tuple(value)
        n = self.tuple_length
        if not isinstance(value, tuple):
            size = f"{n} numbers" if n >= 0 else "numbers"
            raise TypeError(f"{owner}.{self.name} must be a tuple of {size}, got {value!r} ({type(value).__name__})")
        if n >= 0 and len(value) != n:
            raise ValueError(f"{owner}.{self.name} must have {n} entries, got {len(value)}: {value!r}")
        per_entry = self.allowed if isinstance(self.allowed, tuple) else (self.allowed,) * len(value)
        checked = tuple(
            check_number(owner, f"{self.name}[{i}]", v, r, integer)
            for i, (v, r) in enumerate(zip(value, per_entry, strict=True))
        )
        return value if all(a is b for a, b in zip(checked, value, strict=True)) else checked


_COMPILED: dict[type, tuple[_FieldCheck, ...]] = {}


def _field_check(owner: str, name: str, hint: Any, ranges: Mapping[str, RangeSpec]) -> _FieldCheck | None:
    """The check of one field from its type annotation, or ``None`` for fields this mechanism
    does not cover (strings, mappings, unions of several types, ...)."""
    optional = False
    if typing.get_origin(hint) in (typing.Union, types.UnionType):
        rest = [a for a in typing.get_args(hint) if a is not type(None)]
        if len(rest) != 1:
            return None
        hint, optional = rest[0], True
    if hint is bool:
        return _FieldCheck(name, "bool", optional)
    if isinstance(hint, type) and dataclasses.is_dataclass(hint):
        return _FieldCheck(name, "instance", optional, cls=hint)
    length: int | None = None
    if typing.get_origin(hint) is tuple:
        args = typing.get_args(hint)
        if len(args) == 2 and args[1] is Ellipsis:
            length = -1
        elif args and all(a is args[0] for a in args):
            length = len(args)
        else:
            return None
        hint = args[0]
    if hint not in (int, float):
        return None
    allowed = ranges.get(name)
    if allowed is None:
        raise TypeError(f"{owner}.{name} is numeric but {owner}.RANGES declares no range for it")
    if isinstance(allowed, tuple) and (length is None or len(allowed) != length):
        raise TypeError(f"{owner}.RANGES[{name!r}] has one range per entry but the field is not a tuple of that length")
    if not isinstance(allowed, Range | tuple):
        raise TypeError(f"{owner}.RANGES[{name!r}] must be a Range or a tuple of them, got {allowed!r}")
    return _FieldCheck(name, "int" if hint is int else "real", optional, allowed, length)


def _compile(cls: type) -> tuple[_FieldCheck, ...]:
    owner = cls.__name__
    ranges: Mapping[str, RangeSpec] = getattr(cls, "RANGES", {})
    names = [f.name for f in dataclasses.fields(cls)]
    unknown = sorted(set(ranges) - set(names))
    if unknown:
        raise TypeError(f"{owner}.RANGES names {unknown}, which are not fields of {owner}")
    hints = typing.get_type_hints(cls)
    checks = [_field_check(owner, name, hints[name], ranges) for name in names]
    compiled = tuple(c for c in checks if c is not None)
    _COMPILED[cls] = compiled
    return compiled


def check_ranges(params: Any) -> None:
    """Check every field of the dataclass instance ``params`` against its annotation and range.

    Call it from ``__post_init__`` (after any conversion of convenience inputs). By the field's
    annotation: ``float`` accepts real numbers (not bool, str, complex or None), ``int`` only
    integers, ``bool`` only booleans, a dataclass type only its instances; ``X | None`` also
    accepts ``None``; ``tuple[float, ...]`` and ``tuple[int, int]`` accept tuples (or lists,
    stored as tuples) whose entries are checked one by one. Every numeric field must have an
    entry in the class's ``RANGES: ClassVar[Ranges]`` table (a missing one is a ``TypeError``
    when the class is first built); the value must lie inside it. Errors are ``TypeError``
    (wrong type) or ``ValueError`` (out of range, not finite), naming ``Class.field``, the
    range and the bad value. Numpy scalars are stored back as Python numbers.

    Fields of other types (strings, mappings, sequences of events) are left to the class.
    """
    cls = type(params)
    checks = _COMPILED.get(cls) or _compile(cls)
    owner = cls.__name__
    for c in checks:
        value = getattr(params, c.name)
        checked = c.check(owner, value)
        if checked is not value:
            object.__setattr__(params, c.name, checked)


def numeric_fields(cls: type) -> dict[str, RangeSpec]:
    """The numeric fields of the parameters dataclass ``cls`` and their declared ranges."""
    checks = _COMPILED.get(cls) or _compile(cls)
    return {c.name: c.allowed for c in checks if c.allowed is not None}


def check_choice(owner: str, name: str, value: str, choices: typing.Iterable[str]) -> None:
    """Raise ``ValueError`` unless ``value`` is one of ``choices``."""
    options = tuple(choices)
    if value not in options:
        raise ValueError(f"{owner}.{name} must be one of {list(options)}, got {value!r}")
