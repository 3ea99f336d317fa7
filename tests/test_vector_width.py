"""The kernels' vector width (cognition.vector_width): 512-bit vectors on AVX-512 hosts, unless
the environment or the user's numba settings say otherwise. Each case is a fresh process, as
the setting must be made before numba generates any code."""

from __future__ import annotations

import functools
import os
import subprocess
import sys

import pytest
from numba.core.codegen import get_host_cpu_features

AVX512 = "+avx512f" in get_host_cpu_features().split(",")

_PROBE = """
import sys, warnings
warnings.simplefilter("error" if "--strict" in sys.argv else "default")
if "--compile-first" in sys.argv:
    import numba
    numba.njit(lambda x: x + 1)(1)
import numpy as np
import numba
import cognition
from numba.core import config

@numba.njit(fastmath=True)
def axpy(a, x, y):
    for i in range(x.shape[0]):
        y[i] += a * x[i]

x = np.ones(1000, dtype=np.float32)
axpy(np.float32(2.0), x, x.copy())
asm = next(iter(axpy.inspect_asm().values()))
print(config.CPU_FEATURES is not None and config.CPU_FEATURES.endswith(",-prefer-256-bit"), "zmm" in asm)
"""


def _run(code: str, *args: str, **env: str) -> subprocess.CompletedProcess[str]:
    """``code`` in a fresh Python process, with ``env`` over the environment cleared of the width settings."""
    clean = {
        k: v for k, v in os.environ.items() if k not in ("TEAMSIM_VECTOR_BITS", "NUMBA_CPU_FEATURES", "NUMBA_CPU_NAME")
    }
    return subprocess.run(
        [sys.executable, "-c", code, *args], env={**clean, **env}, capture_output=True, text=True, timeout=300
    )


def _probe(*args: str, code: str = _PROBE, **env: str) -> tuple[bool, bool]:
    """(numba's features drop the 256-bit preference, a float32 loop uses zmm registers) in a fresh process."""
    out = _run(code, *args, **env)
    assert out.returncode == 0, out.stderr
    dropped, zmm = out.stdout.split()
    return dropped == "True", zmm == "True"


@functools.cache
def _numba_default() -> tuple[bool, bool]:
    """The probe without cognition: numba's own choice on this host. LLVM tunes Intel's AVX-512
    cores to prefer 256-bit vectors (no zmm), AMD's Zen 4 and later not (zmm already)."""
    return _probe(code=_PROBE.replace("import cognition\n", ""))


def test_avx512_hosts_compile_with_512_bit_vectors_by_default() -> None:
    dropped, zmm = _probe("--strict")  # and no warning
    assert dropped == AVX512
    assert zmm == AVX512


@pytest.mark.skipif(not AVX512, reason="the host has no AVX-512")
def test_the_environment_keeps_llvm_s_256_bit_preference() -> None:
    assert _numba_default()[0] is False
    assert _probe(TEAMSIM_VECTOR_BITS="256") == _numba_default()
    assert _probe(TEAMSIM_VECTOR_BITS="512") == (True, True)


@pytest.mark.skipif(not AVX512, reason="the host has no AVX-512")
def test_numba_targets_chosen_by_the_user_are_left_alone() -> None:
    features = get_host_cpu_features()  # the host's own features: numba's default width
    assert _probe(NUMBA_CPU_FEATURES=features) == _numba_default()


@pytest.mark.skipif(not AVX512, reason="the host has no AVX-512")
def test_code_generated_before_the_import_keeps_the_default_width_and_says_so() -> None:
    assert _probe("--compile-first") == _numba_default()
    out = _run(_PROBE, "--compile-first", "--strict")
    assert out.returncode != 0 and "RuntimeWarning" in out.stderr and "import cognition first" in out.stderr


def test_a_bad_setting_names_the_variable() -> None:
    out = _run("import cognition", TEAMSIM_VECTOR_BITS="128")
    assert out.returncode != 0
    assert "TEAMSIM_VECTOR_BITS must be 256 or 512, got '128'" in out.stderr
