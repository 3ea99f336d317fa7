"""The robot's brain: field map, vision, localization, world model and behaviors."""

from cognition.kernel_cache import install as _install_kernel_cache

_install_kernel_cache(["cognition"])  # before any kernel is defined (cognition.kernel_cache)
