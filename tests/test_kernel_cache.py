"""Kernel caches go stale with the modules a kernel depends on (cognition.kernel_cache).

A throwaway package in a temporary directory: ``a`` holds a kernel and a constant, ``b`` a
kernel calling ``a``'s, ``c`` a kernel of its own. Each run is a fresh process that loads
what the previous one cached, as a user's next ``teamsim match`` would.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from cognition import kernel_cache

_A = "import numba\n\nSCALE = {scale}\n\n\n@numba.njit(cache=True)\ndef f(x):\n    return SCALE * x\n"
_B = "import numba\n\nfrom kcdemo.a import f\n\n\n@numba.njit(cache=True)\ndef g():\n    return f(10) + 1\n"
_C = "import numba\n\n\n@numba.njit(cache=True)\ndef h():\n    return 7\n"
_RUN = "import cognition.kernel_cache as k; k.install(['kcdemo']); from kcdemo import b, c; print(b.g(), c.h())"


def _package(tmp_path: Path, scale: int) -> Path:
    pkg = tmp_path / "kcdemo"
    pkg.mkdir(exist_ok=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text(_A.format(scale=scale))
    (pkg / "b.py").write_text(_B)
    (pkg / "c.py").write_text(_C)
    return pkg


def _run(tmp_path: Path) -> tuple[int, int]:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(tmp_path), os.environ.get("PYTHONPATH", "")])}
    env.pop("NUMBA_CACHE_DIR", None)  # the caches live next to the sources
    out = subprocess.run([sys.executable, "-c", _RUN], cwd=tmp_path, env=env, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    g, h = out.stdout.split()
    return int(g), int(h)


def test_a_kernel_recompiles_when_a_module_it_calls_changes(tmp_path: Path) -> None:
    pkg = _package(tmp_path, scale=1)
    assert _run(tmp_path) == (11, 7)
    cached = {p.name: p.stat().st_mtime_ns for p in (pkg / "__pycache__").glob("*.nbc")}
    assert any(n.startswith("b.g-") for n in cached) and any(n.startswith("c.h-") for n in cached), cached
    assert _run(tmp_path) == (11, 7)  # loaded from the cache, nothing written again
    assert {p.name: p.stat().st_mtime_ns for p in (pkg / "__pycache__").glob("*.nbc")} == cached
    (pkg / "a.py").write_text(_A.format(scale=2))  # only a changes; b's file stays as it was
    assert _run(tmp_path) == (21, 7)  # numba alone would run b's cached copy of the old f: 11
    after = {p.name: p.stat().st_mtime_ns for p in (pkg / "__pycache__").glob("*.nbc")}
    c_files = [n for n in cached if n.startswith("c.h-")]
    assert all(after[n] == cached[n] for n in c_files), "c imports nothing of a: its cache must be kept"
    assert any(after[n] != cached[n] for n in cached if n.startswith("b.g-"))


def test_the_stamp_covers_imported_modules_but_not_the_packages_imports() -> None:
    root = Path(kernel_cache.__file__).resolve().parent
    deps = {
        p.relative_to(root.parent).as_posix() for p in kernel_cache._closure((root / "vision" / "dnt.py").resolve())
    }
    # dnt.py calls kernels of these modules: an edit of any of them must invalidate its cache
    assert {"cognition/vision/scanlines.py", "cognition/vision/segments.py", "cognition/vision/circle.py"} <= deps
    # the vision package's __init__ imports every stage, but dnt.py takes nothing from them
    assert "cognition/vision/robots.py" not in deps and "cognition/vision/vision.py" not in deps
