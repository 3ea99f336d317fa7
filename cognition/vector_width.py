"""The vector width of the compiled kernels: all 16 float32 lanes on CPUs with AVX-512.

numba compiles for the host CPU, but LLVM tunes the Intel cores with AVX-512 (Skylake-SP
to Emerald Rapids) to *prefer* 256-bit vectors, a tuning kept from the first of them, whose
clock dropped while 512-bit code ran. Its loop vectorizer then fills 8 float32 lanes of
registers that hold 16, in every loop over pixels, particles or rows. This project's kernels
are such loops (the image kernels pad their spans to 16 lanes, :data:`teamsim.image_objects.VEC`),
(AMD's Zen 4 and later are not tuned so: there numba uses 512-bit vectors already, and
dropping the preference changes nothing), and on the machine of the README's figures (Emerald
Rapids) the wider vectors are faster:
the renderer took 156 instead of 209 us per 320 x 240 image, and the default 5 v 5 match on
images (render, image effects, vision) ran at 3.5x to 3.6x real time instead of 3.2x, with
the match on synthesized percepts, whose kernels are small, as fast as before.

:func:`configure` turns the preference off (LLVM's ``-prefer-256-bit`` feature) before
numba creates its code generator; :mod:`cognition` calls it on import, before any kernel
exists. It changes nothing when

* the CPU has no AVX-512 (``avx512f``), or the environment sets ``TEAMSIM_VECTOR_BITS=256``;
* the user chose numba's target (``NUMBA_CPU_NAME`` or ``NUMBA_CPU_FEATURES``);
* numba already generated code in this process (something compiled a kernel before
  :mod:`cognition` was imported): the kernels then keep numba's default width, and a
  ``RuntimeWarning`` says so.

The width changes which elements of a loop run in its vector body and which in its scalar
remainder, and vector and scalar code may round a division differently (a reciprocal
estimate refined once, against a correctly rounded division), so images and percepts from
them can differ in the last bits between the two widths, and between machines with and
without AVX-512. One width in one process gives one result, run after run; numba's on-disk
cache keeps the kernels of each width apart (its index is keyed by the target's features).
"""

from __future__ import annotations

import os
import warnings

from numba.core import config, registry
from numba.core.codegen import get_host_cpu_features

ENV = "TEAMSIM_VECTOR_BITS"
"""Environment variable: ``256`` keeps LLVM's preference for 256-bit vectors, ``512`` (or unset) drops it."""
_FEATURE = "-prefer-256-bit"


def configure() -> bool:
    """Let numba's kernels use 512-bit vectors on AVX-512 hosts (module docstring); True when
    this process compiles with them. Idempotent."""
    bits = os.environ.get(ENV, "512").strip()
    if bits not in ("256", "512"):
        raise ValueError(f"{ENV} must be 256 or 512, got {bits!r}")
    if config.CPU_FEATURES is not None:  # set by the user, or by an earlier call
        return config.CPU_FEATURES.endswith("," + _FEATURE)
    if bits == "256" or config.CPU_NAME is not None:
        return False
    features = get_host_cpu_features()
    if "+avx512f" not in features.split(","):
        return False
    if "_toplevel_target_context" in registry.cpu_target.__dict__:  # numba's code generator exists
        warnings.warn(
            "numba compiled code before cognition was imported, so its kernels keep numba's default "
            "vector width (256 bits on Intel's AVX-512 cores); import cognition first for 512-bit vectors "
            f"({__name__})",
            RuntimeWarning,
            stacklevel=2,
        )
        return False
    config.CPU_FEATURES = features + "," + _FEATURE
    return True
