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


# -- compile order ------------------------------------------------------------------------
# numba compiles a kernel that states no fastmath or error model, when a caller compiles it
# first, with the *caller's* flags, and caches that code: the kernel's results then depend on
# which caller ran first on this machine (camera_pose_nb, first compiled by the fastmath
# renderer, gave other last bits of its sines than when first called from Python, and a match
# on images diverged). Kernels that state both flags compile the same code from any caller.
_CALLEE = (
    "import math\n\nimport numba\n\n\n@numba.njit(cache=True{flags})\ndef callee(a):\n"
    "    return math.cos(a) * math.sin(a) + 0.1 * a\n"
)
_CALLER = (
    "import numba\n\nfrom kcorder.callee import callee\n\n\n"
    "@numba.njit(cache=True, fastmath=True, error_model='numpy')\ndef caller(a):\n    return callee(a)\n"
)
_ORDER = (
    "import numpy as np\nfrom kcorder import callee, caller\nxs = np.linspace(0.1, 3.0, 200)\n"
    "if {caller_first}:\n    caller.caller(0.5)\nprint(repr([callee.callee(x) for x in xs]))"
)


def _callee_values(tmp_path: Path, flags: str, caller_first: bool) -> str:
    """The callee's values (from Python) in a fresh package after the first compile was by
    the fastmath caller or by the callee itself."""
    root = tmp_path / f"{caller_first}{len(flags)}"
    pkg = root / "kcorder"
    pkg.mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "callee.py").write_text(_CALLEE.format(flags=flags))
    (pkg / "caller.py").write_text(_CALLER)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(root), os.environ.get("PYTHONPATH", "")])}
    env.pop("NUMBA_CACHE_DIR", None)
    code = _ORDER.format(caller_first=caller_first)
    first = subprocess.run([sys.executable, "-c", code], cwd=root, env=env, capture_output=True, text=True)
    assert first.returncode == 0, first.stderr
    again = subprocess.run([sys.executable, "-c", code.replace(f"if {caller_first}", "if False")], cwd=root, env=env,
                           capture_output=True, text=True)  # fmt: skip
    assert again.returncode == 0, again.stderr
    assert again.stdout == first.stdout  # the cache serves the code compiled first
    return first.stdout


def test_kernels_with_explicit_flags_compile_the_same_code_from_any_caller(tmp_path: Path) -> None:
    flags = ", fastmath=False, error_model='python'"
    assert _callee_values(tmp_path, flags, caller_first=True) == _callee_values(tmp_path, flags, caller_first=False)
    # the hazard the rule guards against is numba's: without flags the first caller decides
    assert _callee_values(tmp_path, "", caller_first=True) != _callee_values(tmp_path, "", caller_first=False)


def test_every_project_kernel_states_its_fastmath_and_error_model() -> None:
    """Every compiled function of cognition and teamsim that is not inlined into its callers
    names both flags, so that its cached code does not depend on which caller compiled it."""
    import importlib
    import pkgutil

    from numba.core.registry import CPUDispatcher

    import cognition
    import teamsim

    kernels, missing = 0, []
    for pkg in (cognition, teamsim):
        for info in pkgutil.walk_packages(pkg.__path__, pkg.__name__ + "."):
            if info.name.endswith(".__main__"):
                continue
            module = importlib.import_module(info.name)
            for name, obj in vars(module).items():
                if not isinstance(obj, CPUDispatcher) or obj.py_func.__module__ != module.__name__:
                    continue
                kernels += 1
                opts = obj.targetoptions
                if opts.get("inline", "never") != "always" and not {"fastmath", "error_model"} <= opts.keys():
                    missing.append(f"{module.__name__}.{name}")
    assert kernels > 200
    assert not missing, f"kernels without explicit fastmath and error_model: {missing}"
