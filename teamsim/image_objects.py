"""Compiled ray-casting primitives for the objects in a rendered camera image.

Each function intersects one viewing ray with one solid and returns the pixel's coverage
(anti-aliased at the silhouette) and what the shading needs. A ray is
``origin + t * d`` in the **world frame** (m) where ``d`` has a camera-frame x component of 1,
so ``t`` is the depth along the optical axis and ``t / fx`` the width of a pixel there (m).
Used by :mod:`teamsim.image_kernel`; see that module for the conventions of the packed
inputs.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray


@nb.njit(cache=True, inline="always")
def axis_cylinder(o1, o2, oa, d1, d2, da, c1, c2, r, a0, a1, inv_f):  # pragma: no cover - compiled
    """Ray against a cylinder whose axis is parallel to a coordinate axis.

    ``o1, o2`` / ``d1, d2``: the ray origin and direction in the two coordinates across the
    axis, ``oa`` / ``da`` along it; the axis passes through (``c1``, ``c2``), radius ``r``,
    extent [``a0``, ``a1``]. Returns (coverage, t, n1, n2, a): coverage in [0, 1] (0 is a
    miss), depth ``t``, the outward surface normal across the axis and the axial coordinate
    of the hit point. The end caps are not included.
    """
    p1, p2 = o1 - c1, o2 - c2
    aa = d1 * d1 + d2 * d2
    if aa < 1e-18:
        return 0.0, 0.0, 0.0, 0.0, 0.0
    b = p1 * d1 + p2 * d2
    tc = -b / aa
    if tc <= 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0
    dist2 = max(p1 * p1 + p2 * p2 - b * b / aa, 0.0)
    dist = math.sqrt(dist2)
    foot = tc * math.sqrt(aa) * inv_f
    cov = (r - dist) / max(foot, 1e-9) + 0.5
    if cov <= 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0
    cov = min(cov, 1.0)
    t = tc
    if dist < r:
        t = tc - math.sqrt((r * r - dist2) / aa)
    a = oa + t * da
    if a < a0 or a > a1:
        return 0.0, 0.0, 0.0, 0.0, 0.0
    h1, h2 = p1 + t * d1, p2 + t * d2
    n = math.sqrt(h1 * h1 + h2 * h2)
    if n < 1e-12:
        return cov, t, 0.0, 0.0, a
    return cov, t, h1 / n, h2 / n, a


@nb.njit(cache=True, inline="always")
def sphere(ox, oy, oz, dx, dy, dz, sx, sy, sz, r, inv_f):  # pragma: no cover - compiled
    """Ray against a sphere at (sx, sy, sz) of radius ``r``: (coverage, t, nx, ny, nz)."""
    px, py, pz = ox - sx, oy - sy, oz - sz
    aa = dx * dx + dy * dy + dz * dz
    b = px * dx + py * dy + pz * dz
    tc = -b / aa
    if tc <= 0.0:
        return 0.0, 0.0, 0.0, 0.0, 1.0
    dist2 = max(px * px + py * py + pz * pz - b * b / aa, 0.0)
    dist = math.sqrt(dist2)
    foot = tc * math.sqrt(aa) * inv_f
    cov = (r - dist) / max(foot, 1e-9) + 0.5
    if cov <= 0.0:
        return 0.0, 0.0, 0.0, 0.0, 1.0
    cov = min(cov, 1.0)
    t = tc
    if dist < r:
        t = tc - math.sqrt((r * r - dist2) / aa)
    hx, hy, hz = px + t * dx, py + t * dy, pz + t * dz
    n = max(math.sqrt(hx * hx + hy * hy + hz * hz), 1e-12)
    return cov, t, hx / n, hy / n, hz / n


@nb.njit(cache=True, inline="always")
def plane_panel(o_n, d_n, plane, o1, d1, lo1, hi1, o2, d2, lo2, hi2):  # pragma: no cover - compiled
    """Ray against an axis-aligned rectangle: (hit, t, coordinate 1, coordinate 2).

    The rectangle lies in the plane where the normal coordinate equals ``plane`` and spans
    [``lo1``, ``hi1``] x [``lo2``, ``hi2``] in the two other coordinates.
    """
    if abs(d_n) < 1e-12:
        return False, 0.0, 0.0, 0.0
    t = (plane - o_n) / d_n
    if t <= 0.0:
        return False, 0.0, 0.0, 0.0
    a, b = o1 + t * d1, o2 + t * d2
    if a < lo1 or a > hi1 or b < lo2 or b > hi2:
        return False, 0.0, 0.0, 0.0
    return True, t, a, b


@nb.njit(cache=True, inline="always")
def mesh_alpha(a, b, spacing, t, inv_f):  # pragma: no cover - compiled
    """Opacity of a net at mesh coordinates (a, b) (m) seen at depth ``t``."""
    half = max(0.006, 0.5 * t * inv_f)
    fa = a / spacing - math.floor(a / spacing)
    fb = b / spacing - math.floor(b / spacing)
    da = min(fa, 1.0 - fa) * spacing
    db = min(fb, 1.0 - fb) * spacing
    if da < half or db < half:
        return 0.7
    return 0.12


@nb.njit(cache=True, inline="always")
def blend(img: NDArray[np.uint8], j, i, alpha, r, g, b):  # pragma: no cover - compiled
    """Blend colour (r, g, b) (0..255) over pixel (j, i) with opacity ``alpha``."""
    old = float(img[j, i, 0])
    img[j, i, 0] = np.uint8(min(255.0, max(0.0, old + alpha * (r - old) + 0.5)))
    old = float(img[j, i, 1])
    img[j, i, 1] = np.uint8(min(255.0, max(0.0, old + alpha * (g - old) + 0.5)))
    old = float(img[j, i, 2])
    img[j, i, 2] = np.uint8(min(255.0, max(0.0, old + alpha * (b - old) + 0.5)))


def icosahedron() -> NDArray[np.float64]:
    """The 12 unit vertex directions of an icosahedron (centres of a football's pentagons)."""
    g = (1.0 + math.sqrt(5.0)) / 2.0
    v = []
    for a in (-1.0, 1.0):
        for b in (-g, g):
            v += [(0.0, a, b), (a, b, 0.0), (b, 0.0, a)]
    arr = np.array(v, dtype=np.float64)
    return arr / np.linalg.norm(arr, axis=1, keepdims=True)
