"""The parameter helpers, re-exported: they live in :mod:`cognition.params` so that brain
modules (which must not import ``teamsim``) validate their parameters the same way."""

from cognition.params import (
    check_choice,
    check_non_negative,
    check_positive,
    check_probability,
    from_mapping,
)

__all__ = ["check_choice", "check_non_negative", "check_positive", "check_probability", "from_mapping"]
