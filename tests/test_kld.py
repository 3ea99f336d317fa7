"""KLD-sampling (:mod:`cognition.localization.kld`): Fox's bound, the bins, and the count a
particle filter draws (few particles when converged, all of them when lost)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from cognition.field import make_field
from cognition.localization import LocalizationParams
from cognition.localization.kld import bin_masses_nb, kld_bound, kld_count
from cognition.localization.particle_filter import ParticleFilter

FIELD = make_field("spl2025")
P = LocalizationParams()


@pytest.mark.parametrize("k", [2, 5, 10, 50, 300])
def test_bound_is_the_chi_square_quantile_over_two_epsilon(k: int) -> None:
    """Fox's n(k) is the Wilson-Hilferty form of chi2_{k-1, 1-delta} / (2 epsilon)."""
    exact = stats.chi2.ppf(0.99, k - 1) / (2 * 0.1)
    assert kld_bound(k, 0.1, float(stats.norm.ppf(0.99))) == pytest.approx(exact, rel=0.05 if k < 5 else 0.01)
    assert kld_bound(1, 0.1, 2.326) == 0.0 and kld_bound(k + 1, 0.1, 2.326) > kld_bound(k, 0.1, 2.326)


def _cloud(rng: np.random.Generator, n: int, sd_xy: float, sd_th: float) -> np.ndarray:
    parts = np.column_stack([rng.normal(1.0, sd_xy, n), rng.normal(-0.5, sd_xy, n), rng.normal(0.3, sd_th, n)])
    parts[:, 2] = np.remainder(parts[:, 2] + math.pi, 2 * math.pi) - math.pi
    return parts


def test_bin_masses_match_a_numpy_histogram() -> None:
    rng = np.random.default_rng(1)
    parts = _cloud(rng, 300, 0.4, 0.5)
    w = rng.random(300)
    w /= w.sum()
    masses = bin_masses_nb(parts, w, 300, P.kld_bin_xy, P.kld_bin_theta)
    keys = np.column_stack(
        [
            np.floor(parts[:, 0] / P.kld_bin_xy),
            np.floor(parts[:, 1] / P.kld_bin_xy),
            np.floor((parts[:, 2] + math.pi) / P.kld_bin_theta),
        ]
    )
    _, inverse = np.unique(keys, axis=0, return_inverse=True)
    reference = np.bincount(inverse.ravel(), weights=w)
    assert np.allclose(np.sort(masses), np.sort(reference)) and masses.sum() == pytest.approx(1.0)


def test_bin_masses_of_thousands_of_bins_and_of_a_non_finite_particle() -> None:
    """The bins are counted in a hash table (linear probing): a cloud over the whole field puts
    nearly every particle in its own bin, so many keys share a probe sequence; the masses must
    still be numpy's histogram, in the order the bins are first met. A NaN particle (a broken
    estimate, before the filter repairs it) gets some bin of its own, never an error."""
    rng = np.random.default_rng(5)
    n = 5000
    parts = np.column_stack([rng.uniform(-5, 5, n), rng.uniform(-3.5, 3.5, n), rng.uniform(-math.pi, math.pi, n)])
    w = rng.random(n)
    w /= w.sum()
    masses = bin_masses_nb(parts, w, n, P.kld_bin_xy, P.kld_bin_theta)
    keys = np.column_stack(
        [
            np.floor(parts[:, 0] / P.kld_bin_xy),
            np.floor(parts[:, 1] / P.kld_bin_xy),
            np.floor((parts[:, 2] + math.pi) / P.kld_bin_theta),
        ]
    )
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    reference = np.bincount(inverse.ravel(), weights=w)[np.argsort(first)]  # in order of first appearance
    assert masses.shape[0] > 0.9 * n and np.allclose(masses, reference)
    parts[17] = np.nan
    masses = bin_masses_nb(parts, w, n, P.kld_bin_xy, P.kld_bin_theta)
    assert masses.sum() == pytest.approx(1.0)


def test_the_count_grows_with_the_spread_from_the_floor_to_the_cap() -> None:
    rng = np.random.default_rng(2)
    counts = []
    for sd_xy, sd_th in [(0.01, 0.005), (0.05, 0.03), (0.1, 0.05), (0.2, 0.1), (3.0, 3.0)]:
        parts = _cloud(rng, 300, sd_xy, sd_th)
        w = np.full(300, 1 / 300)
        counts.append(kld_count(parts, w, 300, 60, 300, P.kld_epsilon, P.kld_z, P.kld_bin_xy, P.kld_bin_theta))
    assert counts[0] == 60 and counts[-1] == 300  # one bin: the floor; spread over the field: the cap
    assert counts == sorted(counts) and len(set(counts)) >= 4, counts
    # weights count, not positions: the same spread cloud with all weight on one particle needs the floor
    w = np.zeros(300)
    w[7] = 1.0
    assert kld_count(parts, w, 300, 60, 300, P.kld_epsilon, P.kld_z, P.kld_bin_xy, P.kld_bin_theta) == 60


def test_a_filter_shrinks_when_it_knows_where_it_is_and_grows_when_it_does_not() -> None:
    params = LocalizationParams(kld=True, placement_sigma_theta=0.03)
    pf = ParticleFilter("lowvar", FIELD, params, np.random.default_rng(3))
    pf.set_particles_around(np.array([[-2.0, 1.0, 0.5]]), sigma_xy=0.05)
    pf.w[: pf.n] = 1.0 / pf.n
    p = pf.params
    n_known = kld_count(pf.parts, pf.w, pf.n, 60, 300, p.kld_epsilon, p.kld_z, p.kld_bin_xy, p.kld_bin_theta)
    pf.set_uniform()
    pf.w[: pf.n] = 1.0 / pf.n
    n_lost = kld_count(pf.parts, pf.w, pf.n, 60, 300, p.kld_epsilon, p.kld_z, p.kld_bin_xy, p.kld_bin_theta)
    assert n_known < 100 and n_lost == 300


def test_a_search_keeps_every_particle_and_tracking_shrinks() -> None:
    """KLD counts only while tracking: lost (or injecting, or relocalizing) the filter resamples
    at the full count, so that fresh poses have room."""
    from cognition.localization.sensor import NO_OBSERVATIONS

    params = LocalizationParams(kld=True, placement_sigma_theta=0.03)
    pf = ParticleFilter("lowvar", FIELD, params, np.random.default_rng(4))
    pf.set_particles_around(np.array([[1.0, 0.5, 0.0]]), sigma_xy=0.05)
    pf._resample(NO_OBSERVATIONS, 1.0, 1.0, False, None)  # type: ignore[arg-type]
    tracking = pf.n
    pf._resample(NO_OBSERVATIONS, 1.0, 1.0, True, None)  # type: ignore[arg-type]
    assert tracking < 100 and pf.n == params.particles
    pf._resample(NO_OBSERVATIONS, 1.0, 1.0, False, None)  # type: ignore[arg-type]
    assert pf.n < 100  # tracking again: the count shrinks back
