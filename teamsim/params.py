"""The parameter helpers, re-exported: they live in :mod:`cognition.params` so that brain
modules (which must not import ``teamsim``) validate their parameters the same way.

Every parameters dataclass declares ``RANGES: ClassVar[Ranges]`` (field -> :class:`Range`)
and calls :func:`check_ranges` in ``__post_init__``; see :mod:`cognition.params`.
"""

from cognition.params import (
    PROBABILITY,
    Range,
    Ranges,
    check_choice,
    check_finite,
    check_number,
    check_ranges,
    from_mapping,
    non_negative,
    positive,
)

__all__ = [
    "PROBABILITY",
    "Range",
    "Ranges",
    "check_choice",
    "check_finite",
    "check_number",
    "check_ranges",
    "from_mapping",
    "non_negative",
    "positive",
]
