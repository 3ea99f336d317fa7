"""Helpers for the frozen parameter dataclasses every module declares.

``from_mapping(cls, data)`` builds a (possibly nested) parameters dataclass from a plain
mapping, as read from a scenario file or the command line. Unknown keys are an error that
names the key and the valid ones; nothing is silently ignored.
"""

from __future__ import annotations

import dataclasses
import math
import typing
from collections.abc import Mapping
from typing import Any, TypeVar

T = TypeVar("T")


def from_mapping(cls: type[T], data: Mapping[str, Any], where: str = "") -> T:
    """Build the dataclass ``cls`` from ``data``; nested dataclass fields accept mappings."""
    if not dataclasses.is_dataclass(cls):
        raise TypeError(f"{cls!r} is not a dataclass")
    if not isinstance(data, Mapping):
        raise TypeError(f"{where or cls.__name__}: expected a mapping, got {type(data).__name__}")
    hints = typing.get_type_hints(cls)
    fields = {f.name: f for f in dataclasses.fields(cls) if f.init}
    unknown = sorted(set(data) - set(fields))
    if unknown:
        raise ValueError(f"unknown {where or cls.__name__} key(s) {unknown}; valid keys: {sorted(fields)}")
    kwargs: dict[str, Any] = {}
    for name, value in data.items():
        hint = hints.get(name)
        if isinstance(hint, type) and dataclasses.is_dataclass(hint) and isinstance(value, Mapping):
            sub_where = f"{where}.{name}" if where else f"{cls.__name__}.{name}"
            value = from_mapping(hint, value, sub_where)
        kwargs[name] = value
    return cls(**kwargs)


def check_positive(owner: str, **values: float) -> None:
    """Raise ``ValueError`` unless every value is finite and strictly positive."""
    for name, v in values.items():
        if not isinstance(v, int | float) or not math.isfinite(v) or v <= 0:
            raise ValueError(f"{owner}.{name} must be a finite number > 0, got {v!r}")


def check_non_negative(owner: str, **values: float) -> None:
    """Raise ``ValueError`` unless every value is finite and >= 0."""
    for name, v in values.items():
        if not isinstance(v, int | float) or not math.isfinite(v) or v < 0:
            raise ValueError(f"{owner}.{name} must be a finite number >= 0, got {v!r}")


def check_probability(owner: str, **values: float) -> None:
    """Raise ``ValueError`` unless every value lies in [0, 1]."""
    for name, v in values.items():
        if not isinstance(v, int | float) or not 0.0 <= v <= 1.0:
            raise ValueError(f"{owner}.{name} must be a probability in [0, 1], got {v!r}")


def check_choice(owner: str, name: str, value: str, choices: typing.Iterable[str]) -> None:
    """Raise ``ValueError`` unless ``value`` is one of ``choices``."""
    options = tuple(choices)
    if value not in options:
        raise ValueError(f"{owner}.{name} must be one of {list(options)}, got {value!r}")
