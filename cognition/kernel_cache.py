"""numba's on-disk kernel cache, invalidated by edits of the modules a kernel depends on.

numba keeps a compiled function next to its source (``__pycache__/*.nbi``, ``*.nbc``) and
reuses it as long as *that file* is unchanged (numba hashes the file's contents). A compiled
function also carries what it took from other modules when it was compiled, though: the
compiled functions it calls are linked into it, and module-level constants are frozen into
its code. An edit of such a module leaves the caller's file, and so its cache, unchanged, and
the caller goes on running the old code without a word: after an edit of
``cognition/vision/segments.py`` the cached ``dnt_lines_nb`` (in ``dnt.py``) kept chaining
segments the old way until its cache was deleted by hand. Anyone who updates the project in
place (``git pull`` in an editable install, a reinstall over an old ``__pycache__``) meets
the same trap.

The locators here stamp the cache of a project file with a hash over the contents of that
file **and of every project module it imports**, directly or through other project modules
(the ``import`` statements, read with :mod:`ast`; a module counts whether it holds kernels or
only constants). An edit anywhere in that closure recompiles the file's kernels at their next
use; files outside it keep their caches. They are numba's own locators otherwise, tried in
numba's order: ``NUMBA_CACHE_DIR`` when set, else ``__pycache__`` next to the source, else the
user's cache directory; files of other packages are left to numba.

:func:`install` registers the locators for packages by name; ``cognition`` and ``teamsim``
each register themselves when imported, before any of their kernels is defined (numba picks
a function's cache locator, and takes the stamp, when the function is decorated).
"""

from __future__ import annotations

import ast
import hashlib
import importlib.util
from collections.abc import Iterable
from functools import cache
from pathlib import Path

from numba.core import caching

_PACKAGES: dict[str, Path] = {}
"""Registered top-level package names and the directory each one lives in."""


def install(packages: Iterable[str]) -> None:
    """Stamp the kernel caches of the modules of ``packages`` (top-level package names) with
    their dependencies' contents (module docstring). Idempotent; affects functions decorated
    after the call."""
    for name in packages:
        if name in _PACKAGES:
            continue
        spec = importlib.util.find_spec(name)
        if spec is None or spec.origin is None:
            raise ValueError(f"kernel_cache.install: no importable package named {name!r}")
        _PACKAGES[name] = Path(spec.origin).resolve().parent.parent
    _closure.cache_clear()
    classes = caching.CacheImpl._locator_classes
    if _LOCATORS[0] not in classes:
        classes[:0] = _LOCATORS


def _package_of(path: Path) -> str | None:
    """The registered top-level package whose tree holds ``path``, or ``None``."""
    for name, root in _PACKAGES.items():
        if path.is_relative_to(root / name):
            return name
    return None


def _module_file(module: str) -> Path | None:
    """The source file of the project module ``module`` (a dotted name), or ``None``."""
    top = module.split(".", 1)[0]
    root = _PACKAGES.get(top)
    if root is None:
        return None
    base = root.joinpath(*module.split("."))
    for candidate in (base.with_suffix(".py"), base / "__init__.py"):
        if candidate.is_file():
            return candidate
    return None


def _imports(path: Path) -> tuple[set[Path], set[Path]]:
    """The project modules ``path`` imports, as (modules whose own imports count too, package
    ``__init__`` files passed on the way). A module whose names the file takes counts with its
    imports (``from package import name`` takes the submodule ``package.name`` if there is one,
    else a name of the package itself); the packages above it run first but lend the file
    nothing, so only their own text counts."""
    tree = ast.parse(path.read_bytes(), filename=str(path))
    root = next((r for n, r in _PACKAGES.items() if path.is_relative_to(r / n)), None)
    names: list[str] = []  # the modules whose names the file takes
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.extend(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            module = node.module or ""
            if node.level and root is not None:  # relative: from the file's package upwards
                base = path.parent
                for _ in range(node.level - 1):
                    base = base.parent
                prefix = ".".join(base.relative_to(root).parts)
                module = f"{prefix}.{module}" if module else prefix
            for alias in node.names:  # a submodule, else a name the module itself holds
                sub = f"{module}.{alias.name}"
                names.append(sub if _module_file(sub) is not None else module)
    followed: set[Path] = set()
    passed: set[Path] = set()
    for name in names:
        parts = name.split(".")
        target = _module_file(name)
        if target is not None:
            followed.add(target.resolve())
        for i in range(1, len(parts)):
            parent = _module_file(".".join(parts[:i]))
            if parent is not None:
                passed.add(parent.resolve())
    return followed, passed - followed


@cache
def _closure(path: Path) -> tuple[Path, ...]:
    """``path`` and the project modules it depends on (:func:`_imports`, transitively), sorted."""
    seen = {path}
    passed: set[Path] = set()
    todo = [path]
    while todo:
        followed, on_the_way = _imports(todo.pop())
        passed |= on_the_way
        for dep in followed:
            if dep not in seen:
                seen.add(dep)
                todo.append(dep)
    return tuple(sorted(seen | passed))


def dependency_stamp(path: str | Path) -> bytes:
    """SHA-256 over the contents of ``path`` and of the project modules it imports
    (transitively), in a fixed order: what a kernel cache of that file is valid for."""
    h = hashlib.sha256()
    for dep in _closure(Path(path).resolve()):
        h.update(str(dep).encode())
        h.update(hashlib.sha256(dep.read_bytes()).digest())
    return h.digest()


class _Stamped:
    """Mixin for numba's cache locators: only functions of the registered packages, stamped
    with :func:`dependency_stamp` instead of their file's own hash."""

    _py_file: str

    @classmethod
    def from_function(cls, py_func, py_file):  # type: ignore[no-untyped-def]
        """A locator for functions defined in a registered package, else ``None`` (numba's
        own locators take over)."""
        if _package_of(Path(py_file).resolve()) is None:
            return None
        return super().from_function(py_func, py_file)  # type: ignore[misc]

    def get_source_stamp(self) -> bytes:
        return dependency_stamp(self._py_file)


class ProjectUserProvidedLocator(_Stamped, caching.UserProvidedCacheLocator):
    """Caches under ``NUMBA_CACHE_DIR`` when it is set (numba's first choice)."""


class ProjectCacheLocator(_Stamped, caching.InTreeCacheLocator):
    """Caches in ``__pycache__`` next to the source (numba's usual place)."""


class ProjectUserWideLocator(_Stamped, caching.UserWideCacheLocator):
    """Caches in the user's cache directory when the source tree is not writable."""


_LOCATORS = (ProjectUserProvidedLocator, ProjectCacheLocator, ProjectUserWideLocator)
"""Tried in this order, before numba's own locators (the same order as numba's)."""
