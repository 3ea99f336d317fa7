"""The study report (scenarios.report): paired tests, Kaplan-Meier recovery, determinism, failures, figures.

Rows are synthetic, written with :class:`scenarios.store.RowWriter`; no simulation runs.
"""

from __future__ import annotations

import math
import random
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from scenarios.report import bootstrap_ci, holm, km_summary, paired_test, summary_tables, write_report
from scenarios.store import EVENT_COLUMNS, RUN_COLUMNS, RowWriter, read_rows

TIMING_HEADER = "## Timing (machine-dependent)"


def run_row(scenario: str, variant: str, seed: int, **values: Any) -> dict[str, Any]:
    """A complete ok run row (int columns 0, float metrics NaN) updated with ``values``."""
    row: dict[str, Any] = dict.fromkeys(RUN_COLUMNS, math.nan)
    row.update(scenario=scenario, variant=variant, seed=seed, status="ok", error="", sim_s=60.0, frames=600)
    row.update(mirror_flips=0, ball_frames=0, goals_for=0, goals_against=0, loc_cpu_us=120.0, wall_s=2.0)
    row.update(values)
    return row


def event_row(scenario: str, variant: str, seed: int, event: int, relocalize_s: float, relocalized: int,
              kind: str = "kidnap", horizon_s: float = 10.0, **values: Any) -> dict[str, Any]:  # fmt: skip
    """A complete event row; the mirror-aware time equals the plain one unless ``values`` say otherwise."""
    row: dict[str, Any] = dict.fromkeys(EVENT_COLUMNS, math.nan)
    row.update(scenario=scenario, variant=variant, seed=seed, event=event, kind=kind, team=1, number=2, detail="")
    row.update(time_s=5.0 + 20 * event, start_s=5.0 + 20 * event, horizon_s=horizon_s, relocalize_s=relocalize_s)
    row.update(relocalized=relocalized, relocalize_sym_s=relocalize_s, relocalized_sym=relocalized)
    row.update(error_before_m=0.1, error_after_m=2.0, goals_conceded_short=0)
    row.update(values)
    return row


def write_study(
    folder: Path, runs: list[dict[str, Any]], events: list[dict[str, Any]], shuffle: int | None = None
) -> None:
    """Store ``runs`` and their events (matched by key) in ``folder``, optionally in a shuffled order."""
    order = list(runs)
    if shuffle is not None:
        random.Random(shuffle).shuffle(order)
    with RowWriter(folder) as writer:
        for run in order:
            key = (run["scenario"], run["variant"], run["seed"])
            mine = [e for e in events if (e["scenario"], e["variant"], e["seed"]) == key]
            if shuffle is not None:
                random.Random(shuffle).shuffle(mine)
            writer.add(run, mine)


def paired_study() -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
    """12 paired seeds: "reset" is 0.1-0.15 m worse than "amcl" in every seed; "twin" differs from "amcl" by
    symmetric +-d perturbations (same distribution). Each run has one kidnap event; one "twin" run failed."""
    rng = np.random.default_rng(7)
    base = rng.uniform(0.2, 0.6, 12)
    worse = base + 0.1 + rng.uniform(0.0, 0.05, 12)
    twin = base + np.repeat([0.01, 0.02, 0.03, 0.04, 0.05, 0.06], 2) * np.tile([1.0, -1.0], 6)
    recover = rng.uniform(0.5, 4.0, 12)
    runs, events = [], []
    for variant, values in (("amcl", base), ("reset", worse), ("twin", twin)):
        for seed in range(12):
            if variant == "twin" and seed == 11:
                runs.append(run_row("kidnap", variant, seed, status="failed", error="RuntimeError: diverged | x"))
                continue
            v = float(values[seed])
            runs.append(run_row("kidnap", variant, seed, pos_rmse_m=v, pos_p90_m=2 * v, heading_rmse_deg=10 * v,
                                share_over_0_5m=v / 2, mirror_flips=seed % 3, loc_cpu_us=100.0 + seed))  # fmt: skip
            late = 3.0 if variant == "reset" else 0.0
            t = float(recover[seed]) + late
            events.append(event_row("kidnap", variant, seed, 0, t, 1))
    return runs, events


@pytest.fixture(scope="module")
def paired(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("paired")
    write_study(folder, *paired_study())
    write_report(folder, title="Paired")
    return folder


def test_holm_and_paired_test_by_hand() -> None:
    np.testing.assert_allclose(holm([0.01, 0.04, 0.03, math.nan]), [0.03, 0.06, 0.06, math.nan])
    same = paired_test([1.0, 2.0, 3.0], [1.0, 2.0, 3.0])
    assert same == {"n": 3.0, "median_diff": 0.0, "rank_biserial": 0.0, "p": 1.0, "n_nonzero": 0.0}
    lower = paired_test([1.0, 2.0, 3.0, 4.0, 5.0, math.nan], [2.0, 4.0, 6.0, 8.0, 10.0, 1.0])
    assert lower["n"] == 5 and lower["median_diff"] == -3.0 and lower["rank_biserial"] == -1.0
    assert lower["p"] == pytest.approx(2 / 2**5)  # exact two-sided: only all-negative or all-positive as extreme
    assert math.isnan(paired_test([math.nan], [1.0])["p"])
    assert all(map(math.isnan, bootstrap_ci([1.0])))
    assert all(map(math.isnan, bootstrap_ci([2.0, 2.0, 2.0])))
    low, high = bootstrap_ci(np.arange(12.0))
    assert low < 5.5 < high


def test_clearly_better_variant_is_holm_significant_and_twin_is_not(paired: Path) -> None:
    tables = summary_tables(read_rows(paired))
    pt = tables["paired"].set_index(["metric", "variant_a", "variant_b"])
    better = pt.loc[("pos_rmse_m", "amcl", "reset")]
    assert better.n == 12 and better.significant and better.p_holm < 0.05
    assert better.median_diff < -0.1 and better.rank_biserial == -1.0  # amcl - reset < 0 in every seed
    twin = pt.loc[("pos_rmse_m", "amcl", "twin")]
    assert twin.n == 11 and not twin.significant and twin.p > 0.5  # the failed seed has no pair
    reloc = pt.loc[("relocalize_s (kidnap)", "amcl", "reset")]
    assert reloc.significant and reloc.median_diff == pytest.approx(-3.0)
    # Holm: each p_holm is at least the raw p and the scenario's tests are corrected together
    assert (pt.p_holm >= pt.p - 1e-15).all() and pt.p_holm.max() <= 1.0
    # pairs with identical results everywhere are no tests: they stay out of the Holm family
    tested = pt[pt.n_nonzero > 0]
    assert len(tested) < len(pt) and (pt[pt.n_nonzero == 0].p_holm == 1.0).all()
    np.testing.assert_allclose(tested.p_holm.to_numpy(), holm(tested.p.to_numpy()))
    metrics = tables["metrics"].set_index(["metric", "variant"])
    assert metrics.loc[("mirror_flips", "amcl")].statistic == "median"
    assert metrics.loc[("pos_rmse_m", "twin")].n == 11
    assert "goals_for" in set(tables["metrics"].metric) and "ball_rmse_m" not in set(tables["metrics"].metric)
    text = (paired / "report.md").read_text()
    assert "| pos_rmse_m | amcl | reset | 12 |" in text and "**" in text.split("| pos_rmse_m | amcl | reset |")[1][:80]


def test_kaplan_meier_matches_hand_computation(tmp_path: Path) -> None:
    # A recovers at 1, 2, 3, 4 s; B at 2 s twice and is censored at 10 s twice; C recovers once at 3 s of four
    times = {"A": [(1.0, 1), (2.0, 1), (3.0, 1), (4.0, 1)], "B": [(2.0, 1), (2.0, 1), (10.0, 0), (10.0, 0)],
             "C": [(3.0, 1), (10.0, 0), (10.0, 0), (10.0, 0)]}  # fmt: skip
    runs, events = [], []
    for variant, pairs in times.items():
        for seed, (t, seen) in enumerate(pairs):
            runs.append(run_row("penalties", variant, seed, pos_rmse_m=0.3))
            extra = {
                "penalty_s": 45.0,
                "back_in_play_s": 45.0 + t,
                "relocalize_sym_s": min(t, 1.5),
                "relocalized_sym": 1,
            }
            events.append(event_row("penalties", variant, seed, 0, t, seen, kind="penalty", **extra))
    write_study(tmp_path, runs, events)
    report = write_report(tmp_path)
    rec = summary_tables(read_rows(tmp_path))["recovery"].set_index(["measure", "variant"])
    a, b, c = (rec.loc[("relocalize_s", v)] for v in "ABC")
    assert (a.n, a.recovered, a.share_recovered, a.km_median_s) == (4, 4, 1.0, 2.0)  # S: .75, .5 at 2 s
    assert (b.n, b.recovered, b.share_recovered, b.km_median_s) == (4, 2, 0.5, 2.0)  # not the naive mean 6 s
    assert b.longest_horizon_s == 10.0 and b.ci_high_s == math.inf
    assert c.recovered == 1 and c.km_median_s == math.inf  # S(3) = .75 then censored: median not reached
    assert a.ci_low_s <= a.km_median_s <= a.ci_high_s < math.inf
    assert rec.loc[("relocalize_sym_s", "B")].km_median_s == 1.5
    assert rec.loc[("back_in_play_s", "B")].km_median_s == 47.0
    # the same numbers from the function directly; an uncensored sample has no "longest censored horizon"
    direct = km_summary([2.0, 10.0, 2.0, 10.0, math.nan], [1, 0, 1, 0, 1])
    assert (direct["n"], direct["recovered"], direct["km_median_s"]) == (4, 2, 2.0)
    assert math.isnan(km_summary([1.0, 2.0], [1, 1])["longest_horizon_s"])
    assert km_summary([], [])["n"] == 0
    text = report.read_text()
    assert "| penalty | relocalize_s | B | 4 | 2 | 0.5 | 2 |" in text
    assert "| penalty | relocalize_s | C | 4 | 1 | 0.25 | not reached |" in text
    assert "penalty_s" in text and "![survival survival_penalties_penalty.png](survival_penalties_penalty.png)" in text


def test_report_is_deterministic_order_free_and_timing_only_moves_the_timing_section(tmp_path: Path) -> None:
    runs, events = paired_study()
    first, shuffled, timed = tmp_path / "first", tmp_path / "shuffled", tmp_path / "timed"
    write_study(first, runs, events)
    write_study(shuffled, runs, events, shuffle=3)
    retimed = [{**r, "loc_cpu_us": 3 * r["loc_cpu_us"], "wall_s": r["wall_s"] + 7.5} for r in runs]
    write_study(timed, retimed, events)
    assert (first / "runs.csv").read_bytes() != (shuffled / "runs.csv").read_bytes()
    text = write_report(first).read_bytes()
    pngs = {p.name: p.read_bytes() for p in first.glob("*.png")}
    assert write_report(first).read_bytes() == text
    assert {p.name: p.read_bytes() for p in first.glob("*.png")} == pngs
    assert write_report(shuffled).read_bytes() == text
    assert {p.name: p.read_bytes() for p in shuffled.glob("*.png")} == pngs
    other = write_report(timed).read_text()
    assert other != text.decode()
    assert other.split(TIMING_HEADER)[0] == text.decode().split(TIMING_HEADER)[0]
    assert text.decode().rstrip().endswith("|") and TIMING_HEADER in other
    assert {p.name: p.read_bytes() for p in timed.glob("*.png")} == pngs


def test_failed_runs_are_listed_with_their_error(paired: Path) -> None:
    text = (paired / "report.md").read_text()
    failures = text.split("## Failures")[1].split(TIMING_HEADER)[0]
    assert "| kidnap | twin | 11 | RuntimeError: diverged \\| x |" in failures
    assert "Runs: 35 ok, 1 failed." in text
    assert text.index("## Failures") < text.index(TIMING_HEADER)


def test_figures_exist_and_are_linked(paired: Path) -> None:
    text = (paired / "report.md").read_text()
    for name in ("box_kidnap_pos_rmse_m.png", "box_kidnap_kidnap_relocalize_s.png", "survival_kidnap_kidnap.png"):
        data = (paired / name).read_bytes()
        assert data.startswith(b"\x89PNG") and len(data) > 1000
        assert f"({name})" in text
        assert b"Software" not in data and b"matplotlib" not in data


def test_report_without_events_or_pairs(tmp_path: Path) -> None:
    write_study(tmp_path, [run_row("solo", "amcl", 0, pos_rmse_m=0.4)], [])
    text = write_report(tmp_path).read_text()
    assert "| pos_rmse_m | mean | 0.4 n/a (n=1) |" in text
    assert "No pairs of variants to compare." in text and TIMING_HEADER in text
