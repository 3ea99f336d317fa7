"""Helpers for the frozen parameter dataclasses every module declares (brain and simulator).

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


def from_mapping(cls: type[T], data: Mapping[str, Any] | str, where: str = "", base: T | None = None) -> T:
    """Build the dataclass ``cls`` from ``data``; nested dataclass fields accept mappings.

    Keys missing from ``data`` keep the value of ``base`` (or the class default). A class
    with a ``PRESETS`` dict (name -> instance) also accepts a preset name instead of a
    mapping, and a mapping with a ``"preset"`` key starts from that preset.
    """
    if not dataclasses.is_dataclass(cls):
        raise TypeError(f"{cls!r} is not a dataclass")
    label = where or cls.__name__
    presets: Mapping[str, Any] | None = getattr(cls, "PRESETS", None)
    if isinstance(data, str):
        if presets is None:
            raise TypeError(f"{label}: expected a mapping, got the string {data!r}")
        data = {"preset": data}
    if not isinstance(data, Mapping):
        raise TypeError(f"{label}: expected a mapping, got {type(data).__name__}")
    data = dict(data)
    if presets is not None and "preset" in data:
        name = data.pop("preset")
        if name not in presets:
            raise ValueError(f"unknown {label} preset {name!r}; valid presets: {sorted(presets)}")
        base = presets[name]
    hints = typing.get_type_hints(cls)
    fields = {f.name: f for f in dataclasses.fields(cls) if f.init}
    unknown = sorted(set(data) - set(fields))
    if unknown:
        extra = " (or 'preset')" if presets is not None else ""
        raise ValueError(f"unknown {label} key(s) {unknown}; valid keys: {sorted(fields)}{extra}")
    kwargs: dict[str, Any] = {}
    for name, value in data.items():
        hint = hints.get(name)
        if isinstance(hint, type) and dataclasses.is_dataclass(hint) and isinstance(value, Mapping | str):
            sub_where = f"{label}.{name}"
            sub_base = getattr(base, name) if base is not None else _default_of(fields[name])
            value = from_mapping(hint, value, sub_where, sub_base)
        kwargs[name] = value
    if base is not None:
        return dataclasses.replace(base, **kwargs)  # type: ignore[type-var]
    return cls(**kwargs)


def _default_of(f: dataclasses.Field[Any]) -> Any:
    """A field's default value (``None`` if it has none)."""
    if f.default is not dataclasses.MISSING:
        return f.default
    if f.default_factory is not dataclasses.MISSING:
        return f.default_factory()
    return None


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
