"""How the suite shares its two cores: the longest test files start first.

The suite runs on two pytest-xdist workers, one test file at a time each (``-n 2 --dist
loadfile`` in ``pyproject.toml``), so a worker that starts a long file late runs alone at the
end. Tests that play long matches carry ``@pytest.mark.slow(seconds=S)``, S being roughly their
cost on the development machine (a ranking, not a limit), and the files are handed out in
decreasing order of their summed S, the rest in collection order. ``--no-loadscope-reorder``
keeps this order; xdist would otherwise sort the files by their number of tests, which puts the
few-test full-match files last.

S includes numba's first compilation where that dominates on a fresh clone, whose kernel cache
is empty: the vision quality file is the first to need the renderer and the vision, and it
compiles them (a few minutes) on one worker while the other plays the long matches of
``test_match.py``.
"""

from __future__ import annotations

from collections import defaultdict

import pytest


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Put the files with the most declared seconds first (a stable sort: ties keep their order)."""
    weight: defaultdict[str, float] = defaultdict(float)
    for item in items:
        mark = item.get_closest_marker("slow")
        if mark is not None:
            weight[item.nodeid.split("::")[0]] += float(mark.kwargs.get("seconds", 0.0))
    items.sort(key=lambda item: -weight[item.nodeid.split("::")[0]])
