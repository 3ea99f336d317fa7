"""The robot's brain: field map, vision, localization, world model and behaviors."""

from cognition.kernel_cache import install as _install_kernel_cache
from cognition.vector_width import configure as _configure_vector_width

_configure_vector_width()  # before numba generates any code (cognition.vector_width)
_install_kernel_cache(["cognition"])  # before any kernel is defined (cognition.kernel_cache)
