"""The one-way dependency rules of DESIGN.md, checked on the source: ``cognition`` imports nothing
above it, and ``teamsim`` never imports ``envs`` or ``scenarios``, not even inside a function
(commands from above register through the ``teamsim.commands`` entry points)."""

from __future__ import annotations

import ast
from importlib.metadata import entry_points
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
FORBIDDEN = {"cognition": {"teamsim", "envs", "scenarios"}, "teamsim": {"envs", "scenarios"}}


def _imports(path: Path) -> list[tuple[int, str]]:
    """Every module an ``import`` or ``from ... import`` in the file names (anywhere in it)."""
    out = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            out.extend((node.lineno, a.name) for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            out.append((node.lineno, node.module))
    return out


@pytest.mark.parametrize("package", sorted(FORBIDDEN))
def test_no_module_imports_a_package_above_it(package):
    bad = [
        f"{path.relative_to(ROOT)}:{line} imports {name}"
        for path in sorted((ROOT / package).rglob("*.py"))
        for line, name in _imports(path)
        if name.split(".")[0] in FORBIDDEN[package]
    ]
    assert not bad, bad
    assert len(list((ROOT / package).rglob("*.py"))) > 5  # the scan saw the package


def test_commands_from_above_are_registered_as_entry_points():
    names = {e.name: e.value for e in entry_points(group="teamsim.commands")}
    assert names.get("studies") == "scenarios.cli:register" and names.get("rl") == "envs.cli:register"
