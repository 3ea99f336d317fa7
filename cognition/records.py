"""Frozen records that are cheap to build: :func:`fast_init` for frozen dataclasses.

The representations a cognition frame hands from module to module (sensor frame, pose, ball,
beliefs, motion request, ...) are frozen dataclasses, so that no module can change what
another one reads. The ``__init__`` that ``dataclass(frozen=True)`` writes stores every field
through ``object.__setattr__`` (the class's own ``__setattr__`` refuses), which makes a frozen
record five times as expensive to build as a plain one: 1.6 us for ten fields on the
development machine, against 0.3 us (``python -m benchmarks.bench_records``). A default match
builds about twenty of them per robot and cognition frame, so that alone cost close to a
tenth of the frame; with this constructor a pose, ball, sensor frame or beliefs record takes
about 0.5 us instead of 1.5 to 2.2.

:func:`fast_init` replaces that ``__init__`` by one with the same parameters (names, order,
defaults, default factories, keyword-only fields) that writes the fields into the instance
dictionary directly and then calls ``__post_init__`` like the original. Nothing else of the
class changes: assignment still raises :class:`dataclasses.FrozenInstanceError`; equality,
hashing, ``repr``, :func:`dataclasses.replace`, :func:`dataclasses.fields` and pickling work
as before (they read the same instance dictionary).
"""

from __future__ import annotations

import dataclasses
from typing import Any, TypeVar

T = TypeVar("T")


class _Factory:
    """Stands for "call the default factory" in a generated ``__init__`` signature."""

    def __repr__(self) -> str:
        return "<factory>"


_FACTORY = _Factory()


def fast_init(cls: type[T]) -> type[T]:
    """Give the frozen dataclass ``cls`` a faster ``__init__`` with the same behaviour
    (module docstring). Apply it above ``@dataclass(frozen=True)``.

    Refused (``TypeError``): a class that is not a frozen dataclass, one with ``__slots__``
    (no instance dictionary) and one with ``InitVar`` pseudo-fields.
    """
    params = getattr(cls, "__dataclass_params__", None)
    if params is None or not params.frozen:
        raise TypeError(f"fast_init needs a frozen dataclass, got {cls!r}")
    if "__slots__" in cls.__dict__:
        raise TypeError(f"fast_init: {cls.__name__} has __slots__ (no instance dictionary)")
    declared = cls.__dataclass_fields__  # type: ignore[attr-defined]
    if any(f._field_type is dataclasses._FIELD_INITVAR for f in declared.values()):  # type: ignore[attr-defined]
        raise TypeError(f"fast_init: {cls.__name__} has InitVar fields")
    names: dict[str, Any] = {"_FACTORY": _FACTORY}
    positional: list[str] = []
    keyword: list[str] = []
    body: list[str] = []
    for f in dataclasses.fields(cls):  # type: ignore[arg-type]
        name = f.name
        has_default = f.default is not dataclasses.MISSING
        has_factory = f.default_factory is not dataclasses.MISSING
        if has_default:
            names[f"_default_{name}"] = f.default
        if has_factory:
            names[f"_factory_{name}"] = f.default_factory
        if not f.init:  # not a parameter: the default, if any, as dataclass does
            if has_factory:
                body.append(f"_record_dict_[{name!r}] = _factory_{name}()")
            elif has_default:
                body.append(f"_record_dict_[{name!r}] = _default_{name}")
            continue
        if has_default:
            param = f"{name}=_default_{name}"
        elif has_factory:
            param = f"{name}=_FACTORY"
            body.append(f"if {name} is _FACTORY:\n        {name} = _factory_{name}()")
        else:
            param = name
        (keyword if f.kw_only else positional).append(param)
        body.append(f"_record_dict_[{name!r}] = {name}")
    if hasattr(cls, "__post_init__"):
        body.append("_record_self_.__post_init__()")
    signature = ", ".join(["_record_self_", *positional, *(["*", *keyword] if keyword else [])])
    lines = "\n    ".join(["_record_dict_ = _record_self_.__dict__", *body])
    source = f"def __init__({signature}):\n    {lines}\n"
    namespace: dict[str, Any] = {}
    exec(source, names, namespace)
    init = namespace["__init__"]
    original = cls.__init__  # type: ignore[misc]
    init.__qualname__ = f"{cls.__qualname__}.__init__"
    init.__module__ = cls.__module__
    init.__annotations__ = dict(getattr(original, "__annotations__", {}))
    init.__doc__ = original.__doc__
    cls.__init__ = init  # type: ignore[misc]
    return cls


def dataclass_twin(cls: type) -> type:
    """A class with the fields (defaults, factories, ``init``, ``kw_only``) and ``__post_init__``
    of the dataclass ``cls`` but the ``__init__`` that ``dataclass(frozen=True)`` writes: the
    reference :func:`fast_init` is tested and timed against."""
    namespace: dict[str, Any] = {"__annotations__": {f.name: f.type for f in dataclasses.fields(cls)}}
    for f in dataclasses.fields(cls):
        namespace[f.name] = dataclasses.field(
            default=f.default, default_factory=f.default_factory, init=f.init, kw_only=f.kw_only
        )  # type: ignore[call-overload]
    if hasattr(cls, "__post_init__"):
        namespace["__post_init__"] = cls.__post_init__
    return dataclasses.dataclass(frozen=True)(type(cls.__name__, (), namespace))
