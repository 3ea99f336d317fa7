"""The particle filter's strategies, one file per paper algorithm: the multinomial and low-variance
draws, AMCL's share, sensor resetting's count and share, maturing's candidates, and a filter
composed of strategies no variant of the papers combines."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import chisquare, kstest

from cognition.field import make_field
from cognition.localization import LocalizationParams
from cognition.localization.amcl import AMCLInjection, augmented_share
from cognition.localization.low_variance import LOW_VARIANCE
from cognition.localization.maturing import Maturing
from cognition.localization.multinomial import MULTINOMIAL, multinomial_draws_nb
from cognition.localization.particle_filter import VARIANT_STRATEGIES, ParticleFilter
from cognition.localization.resample import resample_nb
from cognition.localization.resetting import SensorResetting
from cognition.localization.strategy import Injection
from teamsim.events import Kidnap
from tests.test_localization import SPL, record

PARAMS = LocalizationParams()


def _resample(w: np.ndarray, m: int, low_variance: bool, seed: int) -> np.ndarray:
    """How often each of the len(w) particles is drawn in one resampling of m (no jitter)."""
    n = w.shape[0]
    cap = max(n, m)  # the weight buffers hold the filter's capacity (the new weights are written there)
    parts = np.zeros((n, 3))
    parts[:, 0] = np.arange(n)  # the x coordinate names the particle
    out = np.zeros((m, 3))
    state = np.array([seed * 7919 + 1], dtype=np.uint64)
    weights = np.zeros(cap)
    weights[:n] = w
    resample_nb(parts, n, weights, np.zeros(cap), out, m, low_variance, 0.0, 0.0, 0, np.zeros(cap, np.int64), state)
    return np.bincount(out[:, 0].astype(np.int64), minlength=n)


def test_low_variance_draws_every_particle_floor_or_ceil_of_m_w_times() -> None:
    rng = np.random.default_rng(0)
    for seed in range(20):
        n, m = 120, 300
        w = rng.dirichlet(np.full(n, 0.5))
        copies = _resample(w, m, True, seed)
        assert copies.sum() == m
        assert np.all(copies >= np.floor(m * w) - 1e-9) and np.all(copies <= np.ceil(m * w) + 1e-9), seed
    equal = _resample(np.full(300, 1 / 300), 300, True, 3)
    assert np.all(equal == 1)  # equal weights: every particle survives once


def test_multinomial_draws_are_independent_draws_from_the_weights() -> None:
    equal = _resample(np.full(300, 1 / 300), 300, False, 3)
    assert (equal > 0).sum() < 230  # independent draws lose about 1/e of equally weighted particles
    rng = np.random.default_rng(1)
    w = rng.dirichlet(np.full(40, 2.0))
    total = sum(_resample(w, 500, False, seed) for seed in range(200))
    assert chisquare(total, 100_000 * w).pvalue > 1e-3
    u = np.empty(5000)
    multinomial_draws_nb(u, 5000, np.array([12345], dtype=np.uint64))
    assert np.all(np.diff(u) >= 0.0) and u[0] >= 0.0 and u[-1] < 1.0
    # sorted uniforms: their spacings are what a sorted uniform sample has (KS on u itself)
    assert kstest(u, "uniform").pvalue > 1e-3


def test_amcl_share_follows_the_drop_of_the_fast_average_below_the_slow_one() -> None:
    assert augmented_share(0.0, 0.5, 0.3) == 0.0
    assert augmented_share(1.0, 1.2, 0.3) == 0.0
    assert augmented_share(1.0, 0.9, 0.3) == pytest.approx(0.1)
    assert augmented_share(1.0, 0.1, 0.3) == 0.3  # capped at injection_max
    amcl = AMCLInjection(PARAMS)
    shares = [amcl.share(0.8, False) for _ in range(300)]  # steady evidence: no injection once settled
    assert shares[-1] == 0.0
    assert amcl.w_slow == pytest.approx(0.8 * (1 - (1 - PARAMS.alpha_slow) ** 300))
    drop = [amcl.share(0.05, False) for _ in range(10)]  # the evidence collapses: the share rises
    # w_fast needs a few frames to fall below w_slow (0.62 after 300 frames at 0.8), then the share
    # grows with the gap up to injection_max
    assert drop[0] == 0.0 and 0.0 < drop[3] < PARAMS.injection_max and drop[-1] == PARAMS.injection_max
    assert drop == sorted(drop)
    amcl.restart()
    assert amcl.w_slow == amcl.w_fast == 0.0


def test_sensor_resetting_count_adapts_and_a_lost_robot_resets_at_least_reset_probability() -> None:
    reset = SensorResetting(PARAMS)
    lo, hi = PARAMS.floor_particles, PARAMS.particles
    counts = [reset.count(hi, w) for w in (1.0, 0.9, 0.7, 0.5, 0.3, 1e-6)]
    assert counts[0] == lo and counts[-1] == hi
    assert counts == sorted(counts)  # falling evidence: more particles
    assert reset.share(0.8, lost=True) >= PARAMS.reset_probability
    plain = SensorResetting(PARAMS)
    assert plain.share(0.8, lost=False) == 0.0  # first frame: no averages to compare yet
    assert Injection(PARAMS).count(123, 0.01) == 123 and Injection(PARAMS).share(0.0, True) == 0.0


def test_maturing_candidates_mirror_with_the_sides_and_are_forgotten() -> None:
    mat = Maturing(PARAMS)
    mat.cand[:2] = [(1.0, 2.0, 0.5), (-3.0, 0.5, -2.0)]
    mat.ages[:2] = (3, 9)
    mat.nc = 2
    mat.side_switch()
    assert mat.cand[0] == pytest.approx((-1.0, -2.0, 0.5 - math.pi))
    assert mat.cand[1] == pytest.approx((3.0, -0.5, -2.0 + math.pi))
    mat.forget()
    assert mat.nc == 0 and mat.w_slow == 0.0


def test_each_variant_is_its_draw_and_injection() -> None:
    field = make_field("spl2025")
    expected = {
        "mcl": ("multinomial", "none"),
        "lowvar": ("low variance", "none"),
        "amcl": ("multinomial", "amcl"),
        "reset": ("multinomial", "reset"),
        "maturing": ("low variance", "maturing"),
    }
    assert set(VARIANT_STRATEGIES) == set(expected)
    for variant, (draw, injection) in expected.items():
        pf = ParticleFilter(variant, field)
        assert (pf.resampling.name, pf.injection.name, pf.name) == (draw, injection, variant)
    with pytest.raises(TypeError, match="injection must be an Injection subclass"):
        ParticleFilter("mcl", field, injection=AMCLInjection(PARAMS))  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="resampling must be a Resampling"):
        ParticleFilter("mcl", field, resampling="low variance")  # type: ignore[arg-type]


@pytest.mark.slow(seconds=4)
def test_a_new_combination_low_variance_with_amcl_injects_where_plain_lowvar_cannot() -> None:
    """The strategies compose: low-variance resampling with AMCL's random poses (no variant of
    the papers) injects after a kidnapping and finds the robot again in most recordings,
    while the plain low-variance filter never injects anything (safety net off in both)."""
    params = LocalizationParams(relocalize_seconds=0.0)
    injected_new, injected_plain, found = 0, 0, 0
    for seed in range(4):
        rng = np.random.default_rng(200 + seed)
        target = (float(rng.uniform(-3.5, 3.5)), float(rng.uniform(-2.5, 2.5)), float(rng.uniform(-math.pi, math.pi)))
        frames, truth = record(seed, 30.0, playing=True, events=[Kidnap(6.0, 0, 1, target)])
        new = ParticleFilter("lowvar", SPL, params, np.random.default_rng(seed), 1, 1, injection=AMCLInjection)
        plain = ParticleFilter("lowvar", SPL, params, np.random.default_rng(seed), 1, 1, resampling=LOW_VARIANCE)
        assert new.name == "lowvar:low variance+amcl" and plain.name == "lowvar"
        for f in frames:
            pose = new.update(f)
            plain.update(f)
            injected_new += new.injected
            injected_plain += plain.injected
        d = min(
            math.hypot(pose.x - truth[-1, 0], pose.y - truth[-1, 1]),
            math.hypot(pose.x + truth[-1, 0], pose.y + truth[-1, 1]),
        )
        found += d < 0.5
    assert injected_plain == 0 and injected_new > 0
    assert found >= 3, found
    assert MULTINOMIAL != LOW_VARIANCE


def _resample_reference(
    parts: np.ndarray, n: int, w: np.ndarray, m: int, low_variance: bool, jit_xy: float, jit_th: float, m_inj: int,
    state: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """Plain numpy resampling with the kernel's random stream: the draws, one search per draw in
    the cumulative weights, the jitter (x, y, theta per particle) and the injection slots."""
    from cognition.localization.kernels import choose_nb, rand_n
    from cognition.localization.low_variance import low_variance_draws_nb

    cdf = np.cumsum(w[:n])
    cdf[-1] = 1.0 + 1e-12
    u = np.empty(m)
    (low_variance_draws_nb if low_variance else multinomial_draws_nb)(u, m, state)
    drawn = np.minimum(np.searchsorted(cdf, u, side="left"), n - 1)
    out = parts[drawn].copy()
    for k in range(m):
        out[k, 0] += jit_xy * rand_n(state)
        out[k, 1] += jit_xy * rand_n(state)
        out[k, 2] += jit_th * rand_n(state)
    out[:, 2] = out[:, 2] - 2 * math.pi * np.floor((out[:, 2] + math.pi) / (2 * math.pi))
    slots = choose_nb(m, m_inj, state) if m_inj else np.zeros(0, np.int64)
    return out, slots


@pytest.mark.parametrize("low_variance", [True, False])
def test_the_compiled_resampling_equals_a_plain_reference(low_variance: bool) -> None:
    rng = np.random.default_rng(5)
    for n, m, m_inj in [(300, 300, 0), (300, 120, 17), (80, 250, 40), (1, 5, 1)]:
        parts = np.column_stack([rng.uniform(-4.5, 4.5, n), rng.uniform(-3, 3, n), rng.uniform(-math.pi, math.pi, n)])
        cap = max(n, m)
        w = np.zeros(cap)
        w[:n] = rng.dirichlet(np.full(n, 0.3))
        seed = np.array([int(rng.integers(1, 2**62))], dtype=np.uint64)
        out, logw, slots, state = np.zeros((cap, 3)), np.full(cap, 7.0), np.zeros(cap, np.int64), seed.copy()
        weights = w.copy()
        resample_nb(parts, n, weights, logw, out, m, low_variance, 0.03, 0.05, m_inj, slots, state)
        ref_state = seed.copy()
        ref_out, ref_slots = _resample_reference(parts, n, w, m, low_variance, 0.03, 0.05, m_inj, ref_state)
        assert np.array_equal(out[:m], ref_out) and np.array_equal(slots[:m_inj], ref_slots), (n, m)
        assert state[0] == ref_state[0]  # the same random numbers, no more, no fewer
        assert np.all(logw[:m] == 0.0) and np.allclose(weights[:m], 1.0 / m)
