"""Localization against bad input and repeated construction: what the audit of issue 14 found.

Each test here failed before its fix: the compiled-map cache grew by one entry per match.
"""

from __future__ import annotations

from cognition.field import make_field
from cognition.localization import make_localizer
from cognition.localization import particle_filter as pf


def test_field_model_cache_is_shared_and_bounded_across_matches() -> None:
    """Every match builds its own Field; the compiled map (about 1 MB) must be shared by geometry
    and the cache must not grow with the number of matches (it leaked 1 MB per env reset)."""
    pf._MODELS.clear()
    first = make_localizer("mcl", make_field("spl2025"))
    for _ in range(50):
        again = make_localizer("mcl", make_field("spl2025"))
        assert again.model is first.model
    assert len(pf._MODELS) == 1
    for name in ("spl2013", "kidsize"):
        make_localizer("amcl", make_field(name))
    assert len(pf._MODELS) == 3
    assert len(pf._MODELS) <= pf._MODELS_KEPT
