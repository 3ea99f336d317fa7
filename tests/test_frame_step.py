"""The particle filter's compiled frame (:mod:`cognition.localization.frame_step`) against its
Python steps: the same numbers to the bit for every built-in strategy, frame after frame.

Each filter runs once on the compiled frame and once on the Python steps (``_knobs = None``,
the path of any other strategy), on the frames of a recorded 1 v 1 match in which the robot
walks, scans and is kidnapped, with ``harsh`` percepts (false positives of every kind), so
that the strategies inject, the KLD count varies and the safety net relocalizes. The safety
net's window (a compiled ring buffer) is checked against a plain deque version of its rule.
"""

from __future__ import annotations

import dataclasses
from collections import deque

import numpy as np
import pytest

from cognition.localization import LocalizationParams
from cognition.localization.amcl import AMCLInjection
from cognition.localization.frame_step import (
    R_COUNT,
    R_OBSERVED,
    R_RELOCALIZE,
    R_UNEXPLAINED,
    WATCH_MIN_FRAMES,
    WATCH_MIN_SPAN,
    grow_ring,
    watch_nb,
)
from cognition.localization.particle_filter import ParticleFilter
from cognition.localization.strategy import Injection
from teamsim.events import Kidnap
from tests.test_localization import SPL, record


@pytest.fixture(scope="module")
def frames() -> list:
    """25 s of a walking, scanning robot, kidnapped twice, on harsh percepts; some frames with
    the robot picked up (no observations)."""
    got, _ = record(
        7, 25.0, walk=True, percepts="harsh", playing=True,
        events=[Kidnap(8.0, 0, 1, (2.0, 1.0, 2.0)), Kidnap(16.0, 0, 1, (-3.0, -1.5, -1.0))],
    )  # fmt: skip
    return [dataclasses.replace(f, picked_up=True) if 300 <= i < 306 else f for i, f in enumerate(got)]


def _filter(variant: str, params: LocalizationParams, injection: type[Injection] | None, compiled: bool):
    pf = ParticleFilter(variant, SPL, params, np.random.default_rng(11), 1, 1, injection=injection)
    assert pf._knobs is not None  # a built-in strategy
    if not compiled:
        pf._knobs = None
    return pf


def _state(pf: ParticleFilter) -> list:
    inj = pf.injection
    cand = [inj.cand[: inj.nc].copy(), inj.ages[: inj.nc].copy()] if hasattr(inj, "cand") else []
    return [
        pf.n, pf.parts[: pf.n].copy(), pf.w[: pf.n].copy(), pf.logw[: pf.n].copy(), pf.kernel_state.copy(),
        pf.rng.bit_generator.state, pf.injected, pf.relocalizations, inj.w_slow, inj.w_fast, pf.unexplained_share,
        pf._relocalize, pf.observation_evidence.copy(), *cand,
    ]  # fmt: skip


def _same(a, b) -> bool:
    if isinstance(a, np.ndarray):
        return a.dtype == b.dtype and np.array_equal(a, b)  # NaN-free: equality to the bit for floats
    return a == b and type(a) is type(b)


CASES = [
    ("mcl", {}, None),
    ("lowvar", {}, None),
    ("amcl", {}, None),
    ("reset", {}, None),
    ("maturing", {}, None),
    ("maturing", {"kld": True}, None),
    ("amcl", {"kld": True, "relocalize_seconds": 2.0, "relocalize_share": 0.3}, None),
    ("lowvar", {}, AMCLInjection),  # a combination: the low-variance draw with AMCL's random poses
    ("reset", {"resample_interval": 0.2, "adaptive": True}, None),
]


@pytest.mark.parametrize(("variant", "overrides", "injection"), CASES)
def test_the_compiled_frame_equals_the_python_steps(frames, variant, overrides, injection) -> None:
    params = LocalizationParams(**overrides)
    fast, steps = (_filter(variant, params, injection, c) for c in (True, False))
    injected = resampled = 0
    for f in frames:
        a, b = fast.update(f), steps.update(f)
        for field in dataclasses.fields(a):
            assert _same(getattr(a, field.name), getattr(b, field.name)), (f.time, field.name)
        sa, sb = _state(fast), _state(steps)
        assert len(sa) == len(sb) and all(_same(x, y) for x, y in zip(sa, sb, strict=True)), f.time
        injected += fast.injected > 0
        resampled += fast._last_resample[0] == f.time
    assert resampled > 50  # the frames exercised the resampling ...
    if variant not in ("mcl", "lowvar") or injection is not None:
        assert injected > 0  # ... and the strategy's injection


def test_the_frames_reach_the_safety_net(frames) -> None:
    """The recorded frames make the safety net fire, on both paths alike (checked above)."""
    pf = _filter("amcl", LocalizationParams(relocalize_seconds=2.0, relocalize_share=0.3), None, True)
    for f in frames:
        pf.update(f)
    assert pf.relocalizations > 0


def test_another_strategy_keeps_the_python_steps(frames) -> None:
    class Nothing(Injection):
        name = "nothing"

    pf = ParticleFilter("lowvar", SPL, LocalizationParams(), np.random.default_rng(0), 1, 1, injection=Nothing)
    assert pf._knobs is None
    reference = ParticleFilter("lowvar", SPL, LocalizationParams(), np.random.default_rng(0), 1, 1)
    for f in frames[:200]:
        a, b = pf.update(f), reference.update(f)
        assert (a.x, a.y, a.theta) == (b.x, b.y, b.theta)  # the same rule, another path


def _watch_reference(entries, window: float, share: float) -> list[tuple[bool, int, int]]:
    """The safety net's rule on a deque: (relocalize, unexplained, observed) after each frame."""
    w: deque[tuple[float, int, int]] = deque()
    bad = seen = 0
    out = []
    for t, u, o in entries:
        fired = False
        w.append((t, u, o))
        bad, seen = bad + u, seen + o
        while w[0][0] < t - window:
            _, du, do = w.popleft()
            bad, seen = bad - du, seen - do
        if len(w) >= WATCH_MIN_FRAMES and t - w[0][0] >= WATCH_MIN_SPAN * window and bad >= share * seen:
            fired = True
            w.clear()
            bad = seen = 0
        out.append((fired, bad, seen))
    return out


@pytest.mark.parametrize("seed", range(4))
def test_watch_ring_equals_a_deque(seed: int) -> None:
    rng = np.random.default_rng(seed)
    times = np.cumsum(rng.uniform(0.01, 0.1, 2000))
    entries = [(float(t), int(rng.integers(0, 4)), int(rng.integers(1, 5))) for t in times]
    window, share = 2.5, 0.6
    ring = (np.zeros(2), np.zeros(2, dtype=np.int64), np.zeros(2, dtype=np.int64))  # tiny: it must grow
    state = np.zeros(5, dtype=np.int64)
    fired = 0
    for (t, u, o), (want, bad, seen) in zip(entries, _watch_reference(entries, window, share), strict=True):
        ring = grow_ring(*ring, state)
        watch_nb(t, u, o, window, share, *ring, state)
        assert (bool(state[R_RELOCALIZE]), int(state[R_UNEXPLAINED]), int(state[R_OBSERVED])) == (want, bad, seen)
        fired += want
        state[R_RELOCALIZE] = 0
    assert fired > 5 and ring[0].shape[0] > 2 and state[R_COUNT] < ring[0].shape[0]
