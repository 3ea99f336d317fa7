"""The fast-math flags of every compiled kernel: all of LLVM's but ``reassoc``.

Numba links a compiled function that other compiled functions call into each caller as a
weak copy, optimized again in the caller's module; which copy runs depends on the process: a
caller compiled in the process calls the callee's own build, a caller loaded from numba's
on-disk cache its embedded copy. With reassociation the two copies may sum in different
orders and round differently in the last bits, so a run's results would depend on the state
of the cache (a fresh CI machine compiles, the next run loads). Without it both copies compute
the same numbers and one seed gives one result; the other flags (no NaN or infinity
assumptions, signed zeros, reciprocals, contraction, approximate functions) still let LLVM
vectorize the kernels' arithmetic.

A kernel that does not name its flags takes them from the compiled function that first calls
it (numba compiles the callee with the caller's flags, and caches that build): the renderer
(``fastmath=FASTMATH``) compiling :func:`cognition.camera.camera_pose_nb` first gave its sines
approximate last bits, a Python call first gave exact ones, and the same image match diverged
with the history of the cache. So every kernel that is not ``inline="always"`` names both
``fastmath`` (this set, or ``False``) and ``error_model``; ``tests/test_kernel_cache.py``
checks it.
"""

from __future__ import annotations

FASTMATH = {"nnan", "ninf", "nsz", "arcp", "contract", "afn"}
"""Pass as ``fastmath=FASTMATH`` to ``numba.njit`` instead of ``fastmath=True`` (a set: numba takes
no frozenset; never change it at run time)."""
