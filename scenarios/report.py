"""The statistical report of a study: ``report.md`` and PNG figures, computed from the stored rows alone.

:func:`write_report` reads ``runs.csv`` and ``events.csv`` (:func:`scenarios.store.read_rows`), sorts them by
(scenario, variant, seed, event) and writes, into the same folder:

==============  =========================================================================================
section         what, and with which ``scipy.stats`` function
==============  =========================================================================================
Runs            scenarios, variants, seeds, runs ok / failed
Run metrics     per scenario, variant and metric: mean (median for the skewed count ``mirror_flips``) with
                a 95 % CI from ``bootstrap`` (BCa for means, percentile for medians, ``rng=default_rng(0)``)
Recovery        per scenario, event kind, measure and variant: the right-censored recovery times as a
                Kaplan-Meier survival curve (``ecdf`` of ``CensoredData``); its median (smallest time with
                S(t) <= 0.5) and a 95 % CI read where the pointwise log-log bands
                (``sf.confidence_interval``) cross 0.5; uncensored event metrics as bootstrap means
Paired tests    every pair of variants, per scenario and metric: ``wilcoxon`` on the differences paired by
                seed (events: by seed and event; a censored time counts as its horizon, which is
                conservative), Holm-corrected across the scenario's tests, median difference and the
                matched-pairs rank-biserial correlation (``rankdata``)
Figures         ``box_<scenario>_<metric>.png`` and ``survival_<scenario>_<kind>.png`` (matplotlib, Agg)
Failures        failed runs with their error
Timing          the machine-dependent columns (:data:`~scenarios.store.TIMING_COLUMNS`), last
==============  =========================================================================================

Units follow the column names: seconds (``*_s``), metres (``*_m``), degrees (``*_deg``), microseconds (``*_us``),
shares in [0, 1], counts. The output is byte-identical for the same rows in any order, and everything above
the Timing section is unaffected by the timing columns.
"""

from __future__ import annotations

import math
import re
import warnings
from collections.abc import Sequence
from itertools import combinations
from pathlib import Path
from typing import Any

import matplotlib.style
import numpy as np
import pandas as pd
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from scipy import stats

from scenarios.store import EVENT_COLUMNS, RUN_COLUMNS, Rows, read_rows

RUN_METRICS = ("pos_rmse_m", "pos_p90_m", "heading_rmse_deg", "share_over_0_5m", "share_over_30deg", "mirror_flips",
               "lost_share", "ball_rmse_m", "goals_for", "goals_against")  # fmt: skip
"""Per-run metrics summarised and tested (units in their names; shares in [0, 1]; the rest counts)."""
MEDIAN_METRICS = frozenset({"mirror_flips"})
"""Skewed counts summarised by their median instead of their mean."""
CENSORED = {"relocalize_s": "relocalized", "relocalize_sym_s": "relocalized_sym", "back_in_play_s": "relocalized"}
"""Right-censored event times (s) and the 0/1 column that says whether each was observed."""
EVENT_METRICS = ("error_before_m", "error_after_m", "penalty_s", "goals_conceded_short")
"""Uncensored per-event metrics (m, s, goals); the last two only for penalties."""
PENALTY_ONLY = frozenset({"back_in_play_s", "penalty_s", "goals_conceded_short"})
BOX_METRICS = ("pos_rmse_m", "heading_rmse_deg")
ALPHA = 0.05


def run_frame(rows: Rows) -> pd.DataFrame:
    """All run rows, sorted by (scenario, variant, seed)."""
    df = pd.DataFrame(rows.runs, columns=list(RUN_COLUMNS))
    return df.sort_values(["scenario", "variant", "seed"], kind="stable").reset_index(drop=True)


def event_frame(rows: Rows) -> pd.DataFrame:
    """Event rows of the runs that finished ok, sorted by (scenario, variant, seed, event)."""
    ok = {(r["scenario"], r["variant"], int(r["seed"])) for r in rows.runs if r["status"] == "ok"}
    events = [e for e in rows.events if (e["scenario"], e["variant"], int(e["seed"])) in ok]
    df = pd.DataFrame(events, columns=list(EVENT_COLUMNS))
    return df.sort_values(["scenario", "variant", "seed", "event"], kind="stable").reset_index(drop=True)


def _finite(values: Any) -> np.ndarray:
    x = np.asarray(values, dtype=float)
    return x[np.isfinite(x)]


def bootstrap_ci(values: Sequence[float] | np.ndarray, statistic: str = "mean") -> tuple[float, float]:
    """95 % bootstrap CI (``scipy.stats.bootstrap``, 9999 resamples, ``rng=default_rng(0)``) of the mean (BCa) or
    median (percentile) of the finite values, in their unit; (nan, nan) for fewer than two or constant values."""
    x = _finite(values)
    if x.size < 2 or np.ptp(x) == 0:
        return (math.nan, math.nan)
    func, method = (np.mean, "BCa") if statistic == "mean" else (np.median, "percentile")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ci = stats.bootstrap((x,), func, method=method, n_resamples=9999, rng=np.random.default_rng(0))
    return (float(ci.confidence_interval.low), float(ci.confidence_interval.high))


def _first_at_or_below_half(times: np.ndarray, surv: np.ndarray) -> float:
    below = np.flatnonzero(surv <= 0.5 + 1e-12)
    return float(times[below[0]]) if below.size else math.inf


def km_summary(times: Sequence[float] | np.ndarray, observed: Sequence[int] | np.ndarray) -> dict[str, float]:
    """Kaplan-Meier summary of right-censored recovery times (s): ``observed`` is 1 where the time was seen, 0 where
    the run stopped watching then (the time is the horizon). Pairs with a non-finite time are dropped.

    Returns n, recovered (count), share_recovered (within each event's horizon), km_median_s (smallest t with
    S(t) <= 0.5; inf if the curve never gets there), ci_low_s / ci_high_s (where the pointwise 95 % log-log band's
    lower / upper edge first reaches 0.5; a band undefined at S = 0 or 1 is taken as S there), longest_horizon_s.
    """
    t = np.asarray(times, dtype=float)
    seen = np.asarray(observed, dtype=float)
    keep = np.isfinite(t) & np.isfinite(seen)
    t, seen = t[keep], seen[keep] > 0
    out = {
        "n": float(t.size),
        "recovered": float(seen.sum()),
        "share_recovered": math.nan,
        "km_median_s": math.nan,
        "ci_low_s": math.nan,
        "ci_high_s": math.nan,
        "longest_horizon_s": math.nan,
    }
    if t.size == 0:
        return out
    out["share_recovered"] = float(seen.mean())
    out["longest_horizon_s"] = float(t[~seen].max()) if (~seen).any() else math.nan
    res = stats.ecdf(stats.CensoredData(uncensored=t[seen], right=t[~seen]))
    q, s = res.sf.quantiles, res.sf.probabilities
    out["km_median_s"] = _first_at_or_below_half(q, s)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ci = res.sf.confidence_interval(0.95, method="log-log")
    low, high = (np.where(np.isfinite(b.probabilities), b.probabilities, s) for b in (ci.low, ci.high))
    out["ci_low_s"], out["ci_high_s"] = _first_at_or_below_half(q, low), _first_at_or_below_half(q, high)
    return out


def km_curve(times: np.ndarray, observed: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Kaplan-Meier step points (x = s since the clock started, y = share not yet recovered), starting at (0, 1)."""
    t, seen = np.asarray(times, dtype=float), np.asarray(observed, dtype=float) > 0
    if t.size == 0:
        return np.zeros(1), np.ones(1)
    res = stats.ecdf(stats.CensoredData(uncensored=t[seen], right=t[~seen]))
    return np.r_[0.0, res.sf.quantiles], np.r_[1.0, res.sf.probabilities]


def paired_test(a: Sequence[float] | np.ndarray, b: Sequence[float] | np.ndarray) -> dict[str, float]:
    """Wilcoxon signed-rank test of the paired differences a - b (pairs where both are finite; units of a and b).

    Returns n (pairs), median_diff, rank_biserial (matched-pairs: (R+ - R-) / (R+ + R-) over the non-zero
    differences, in [-1, 1], positive when a tends to be larger) and p (two-sided; 1.0 when all differences are 0,
    nan without pairs). Zero differences are dropped before ranking (``zero_method="wilcox"``); p is exact when the
    remaining absolute differences have no ties, else the tie-corrected normal approximation (as R's wilcox.test).
    """
    d = np.asarray(a, dtype=float) - np.asarray(b, dtype=float)
    d = d[np.isfinite(d)]
    if d.size == 0:
        return {"n": 0.0, "median_diff": math.nan, "rank_biserial": math.nan, "p": math.nan}
    nz = d[d != 0]
    out = {"n": float(d.size), "median_diff": float(np.median(d)) + 0.0, "rank_biserial": 0.0, "p": 1.0,
           "n_nonzero": float(nz.size)}  # fmt: skip
    if nz.size:
        ranks = stats.rankdata(np.abs(nz))
        out["rank_biserial"] = float((ranks[nz > 0].sum() - ranks[nz < 0].sum()) / ranks.sum())
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            exact = np.unique(ranks).size == ranks.size  # with ties scipy's "auto" enumerates 2**n slowly
            out["p"] = float(stats.wilcoxon(nz, method="exact" if exact else "asymptotic").pvalue)
    return out


def holm(pvalues: Sequence[float] | np.ndarray) -> np.ndarray:
    """Holm step-down adjusted p-values over the finite entries (nan stays nan)."""
    p = np.asarray(pvalues, dtype=float)
    out = np.full(p.shape, math.nan)
    ok = np.flatnonzero(np.isfinite(p))
    order = ok[np.argsort(p[ok], kind="stable")]
    m = order.size
    out[order] = np.minimum(1.0, np.maximum.accumulate((m - np.arange(m)) * p[order]))
    return out


def _seeds_text(seeds: Sequence[int]) -> str:
    """Seeds as "first–last (count)" when consecutive, else listed."""
    s = sorted({int(x) for x in seeds})
    if not s:
        return "none"
    if s == list(range(s[0], s[-1] + 1)) and len(s) > 2:
        return f"{s[0]}–{s[-1]} ({len(s)})"
    return ", ".join(map(str, s))


def _summaries(groups: pd.DataFrame, keys: list[str], metrics: Sequence[str]) -> list[dict[str, Any]]:
    """Mean or median with its bootstrap CI per ``keys`` group and metric (penalty-only metrics only for penalties)."""
    out: list[dict[str, Any]] = []
    for key, g in groups.groupby(keys, sort=True):
        for metric in metrics:
            row = dict(zip(keys, key, strict=True))
            if metric in PENALTY_ONLY and row.get("kind") != "penalty":
                continue
            x = _finite(g[metric])
            stat = "median" if metric in MEDIAN_METRICS else "mean"
            value = float(np.median(x) if stat == "median" else np.mean(x)) if x.size else math.nan
            low, high = bootstrap_ci(x, stat)
            out.append({**row, "metric": metric, "statistic": stat, "n": x.size, "value": value, "ci_low": low})
            out[-1]["ci_high"] = high
    return out


def _paired_rows(runs: pd.DataFrame, events: pd.DataFrame, scenario: str) -> list[dict[str, Any]]:
    """:func:`paired_test` for every variant pair and metric of one scenario, Holm-corrected together."""
    tests: list[tuple[str, pd.DataFrame]] = []
    r = runs[(runs.scenario == scenario) & (runs.status == "ok")]
    for metric in RUN_METRICS:
        if np.isfinite(r[metric].to_numpy(float)).any():
            tests.append((metric, r.pivot(index="seed", columns="variant", values=metric)))
    e = events[events.scenario == scenario]
    for kind in sorted(e.kind.unique()):
        k = e[e.kind == kind]
        for metric in ("relocalize_s", "relocalize_sym_s"):
            if np.isfinite(k[metric].to_numpy(float)).any():
                tests.append((f"{metric} ({kind})", k.pivot(index=["seed", "event"], columns="variant", values=metric)))
    out = []
    for metric, table in tests:
        for a, b in combinations(sorted(table.columns), 2):
            res = paired_test(table[a].to_numpy(float), table[b].to_numpy(float))
            if res["n"]:
                out.append({"scenario": scenario, "metric": metric, "variant_a": a, "variant_b": b, **res})
    tested = [row for row in out if row["n_nonzero"] > 0]  # identical results everywhere: nothing was tested
    for row in out:
        row["p_holm"], row["significant"] = 1.0, False
    for row, p in zip(tested, holm([row["p"] for row in tested]), strict=True):
        row["p_holm"], row["significant"] = float(p), bool(p < ALPHA)
    return out


def summary_tables(rows: Rows) -> dict[str, pd.DataFrame]:
    """The report's numbers as DataFrames (units as in the column and metric names):

    ``overview`` (per scenario: variants, seeds, ok, failed), ``metrics`` (run metrics per scenario and variant:
    statistic, n, value, ci_low, ci_high), ``event_metrics`` (the same per event kind for :data:`EVENT_METRICS`),
    ``recovery`` (Kaplan-Meier per scenario, kind, measure, variant: :func:`km_summary` columns), ``paired``
    (per scenario, metric and variant pair: :func:`paired_test` columns, p_holm, significant), ``failures``
    (scenario, variant, seed, error) and ``timing`` (runs, mean loc_cpu_us, total wall_s per scenario and variant).
    """
    runs, events = run_frame(rows), event_frame(rows)
    ok = runs[runs.status == "ok"]
    overview = [
        (
            s,
            ", ".join(sorted(g.variant.unique())),
            _seeds_text(g.seed),
            (g.status == "ok").sum(),
            (g.status != "ok").sum(),
        )
        for s, g in runs.groupby("scenario", sort=True)
    ]
    metrics = []
    for _, g in ok.groupby("scenario", sort=True):
        metrics += _summaries(g, ["scenario", "variant"], [m for m in RUN_METRICS if g[m].notna().any()])
    event_metrics = _summaries(events, ["scenario", "kind", "variant"], EVENT_METRICS)
    recovery = []
    for (scenario, kind), g in events.groupby(["scenario", "kind"], sort=True):
        for measure, flag in CENSORED.items():
            for variant, h in (
                g.groupby("variant", sort=True) if kind == "penalty" or measure not in PENALTY_ONLY else []
            ):
                km = km_summary(h[measure].to_numpy(float), h[flag].to_numpy(float))
                if km["n"]:
                    recovery.append({"scenario": scenario, "kind": kind, "measure": measure, "variant": variant, **km})
    paired = [row for s in sorted(ok.scenario.unique()) for row in _paired_rows(runs, events, s)]
    failed = runs[runs.status != "ok"][["scenario", "variant", "seed", "error"]]
    timing = runs.groupby(["scenario", "variant"], sort=True).agg(
        runs=("seed", "size"), mean_loc_cpu_us=("loc_cpu_us", "mean"), total_wall_s=("wall_s", "sum")
    )
    frames = dict(metrics=metrics, event_metrics=event_metrics, recovery=recovery, paired=paired)
    out = {"overview": pd.DataFrame(overview, columns=["scenario", "variants", "seeds", "ok", "failed"])}
    out |= {name: pd.DataFrame(value) for name, value in frames.items()}
    return out | {"failures": failed.reset_index(drop=True), "timing": timing.reset_index()}


RECOVERY_HEADERS = {"kind": "kind", "measure": "measure", "variant": "variant", "n": "n", "recovered": "recovered",
                    "share_recovered": "share recovered", "km_median_s": "KM median (s)", "ci": "95 % CI (s)",
                    "longest_horizon_s": "longest censored horizon (s)"}  # fmt: skip
PAIRED_HEADERS = {"metric": "metric", "variant_a": "A", "variant_b": "B", "n": "pairs", "median_diff": "median(A − B)",
                  "rank_biserial": "rank-biserial r", "p": "p", "holm": "Holm p"}  # fmt: skip
TIMING_HEADERS = {"scenario": "scenario", "variant": "variant", "runs": "runs", "mean_loc_cpu_us": "mean loc_cpu_us",
                  "total_wall_s": "total wall_s"}  # fmt: skip


def _by_scenario(df: pd.DataFrame) -> Any:
    return df.groupby("scenario", sort=True) if not df.empty else []


def _num(x: Any) -> str:
    if isinstance(x, str | int | np.integer):
        return str(x)
    x = float(x)
    if math.isnan(x):
        return "n/a"
    return "not reached" if math.isinf(x) else f"{x + 0.0:.4g}"


def _ci(low: float, high: float) -> str:
    return "n/a" if math.isnan(low) else f"[{_num(low)}, {_num(high)}]"


def _md(df: pd.DataFrame, columns: dict[str, str]) -> str:
    """Pipe table of ``df``'s columns (the keys) under the headers (the values); numbers through :func:`_num`."""
    cells = [
        [_num(v).replace("|", "\\|").replace("\n", " ") for v in r] for r in df[list(columns)].itertuples(index=False)
    ]
    lines = ["| " + " | ".join(columns.values()) + " |", "|" + "---|" * len(columns)]
    return "\n".join([*lines, *("| " + " | ".join(r) + " |" for r in cells)]) + "\n"


def _wide(df: pd.DataFrame, keys: list[str]) -> str:
    """One row per ``keys`` and one column per variant: "value [CI] (n=...)"."""
    cell = df.apply(lambda r: f"{_num(r.value)} {_ci(r.ci_low, r.ci_high)} (n={r.n})", axis=1)
    wide = df.assign(cell=cell).pivot(index=[*keys, "statistic"], columns="variant", values="cell").fillna("")
    wide = wide.reindex(df[[*keys, "statistic"]].drop_duplicates().itertuples(index=False, name=None))
    return _md(wide.reset_index(), {c: c for c in [*keys, "statistic", *wide.columns]})


def _safe(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "-", str(name))


def _save(fig: Figure, path: Path) -> None:
    FigureCanvasAgg(fig)
    fig.savefig(path, format="png", dpi=80, metadata={"Software": None})


def _box_figure(values: dict[str, np.ndarray], censored: dict[str, np.ndarray] | None, title: str) -> Figure:
    """Box plot per variant with the points over it; censored points (recovery times at the horizon) hollow red."""
    fig = Figure(figsize=(max(3.5, 1.2 + 1.1 * len(values)), 3.6), layout="constrained")
    ax = fig.add_subplot(title=title)
    names = list(values)
    ax.boxplot([values[v] for v in names], tick_labels=names, showfliers=censored is None)
    for i, v in enumerate(names, start=1):
        x = i + np.linspace(-0.12, 0.12, len(values[v])) if len(values[v]) > 1 else np.full(len(values[v]), i)
        cens = censored[v] if censored is not None else np.zeros(len(values[v]), dtype=bool)
        ax.plot(x[~cens], values[v][~cens], "o", color="C0", ms=4, alpha=0.6)
        ax.plot(x[cens], values[v][cens], "o", mfc="none", color="C3", ms=5, label="_" if i > 1 else "censored")
    if censored is not None and any(c.any() for c in censored.values()):
        ax.legend(loc="best", fontsize="small")
    ax.set_ylabel(f"{title.split()[0]} ({title.split()[0].rsplit('_', 1)[-1]})")
    return fig


def _figures(folder: Path, runs: pd.DataFrame, events: pd.DataFrame) -> dict[str, list[str]]:
    """Write the PNGs; return the file names per scenario (box plots first, then survival curves)."""
    made: dict[str, list[str]] = {}
    ok = runs[runs.status == "ok"]
    for scenario, g in ok.groupby("scenario", sort=True):
        for metric in BOX_METRICS:
            vals = {v: _finite(h[metric]) for v, h in g.groupby("variant", sort=True)}
            if any(x.size for x in vals.values()):
                name = f"box_{_safe(scenario)}_{metric}.png"
                _save(_box_figure(vals, None, f"{metric} per run"), folder / name)
                made.setdefault(scenario, []).append(name)
        e = events[(events.scenario == scenario) & np.isfinite(events.relocalize_s.to_numpy(float))]
        for kind, k in e.groupby("kind", sort=True):
            groups = dict(list(k.groupby("variant", sort=True)))
            vals = {v: h.relocalize_s.to_numpy(float) for v, h in groups.items()}
            cens = {v: h.relocalized.to_numpy(int) == 0 for v, h in groups.items()}
            name = f"box_{_safe(scenario)}_{_safe(kind)}_relocalize_s.png"
            _save(_box_figure(vals, cens, f"relocalize_s after {kind}"), folder / name)
            fig = Figure(figsize=(9, 3.6), layout="constrained")
            fig.suptitle(f"{scenario}: Kaplan-Meier, + = censored")
            for i, (measure, title) in enumerate((("relocalize_s", "plain"), ("relocalize_sym_s", "mirror-aware"))):
                ax = fig.add_subplot(1, 2, i + 1)
                for v, h in groups.items():
                    t, seen = h[measure].to_numpy(float), h[CENSORED[measure]].to_numpy(float)
                    t, seen = t[np.isfinite(t)], seen[np.isfinite(t)]
                    x, y = km_curve(t, seen)
                    line = ax.step(x, y, where="post", label=v)[0]
                    ax.plot(t[seen == 0], y[np.searchsorted(x, t[seen == 0])], "+", color=line.get_color(), ms=8)
                ax.set(
                    title=f"{kind}: {title}",
                    xlabel="s since the clock started",
                    ylim=(-0.02, 1.02),
                    ylabel="share not yet relocalized",
                )
                ax.legend(fontsize="small")
            sname = f"survival_{_safe(scenario)}_{_safe(kind)}.png"
            _save(fig, folder / sname)
            made.setdefault(scenario, []).extend([name, sname])
    return made


def _sections(tables: dict[str, pd.DataFrame], figures: dict[str, list[str]], title: str) -> list[str]:
    ov, out = tables["overview"], [f"# {title}\n"]
    if ov.empty:
        return [*out, "No runs.\n"]
    variants = ", ".join(sorted({v for s in ov.variants for v in s.split(", ")}))
    runs = f"Runs: {ov.ok.sum()} ok, {ov.failed.sum()} failed."
    out.append(f"Scenarios: {', '.join(ov.scenario)}. Variants: {variants}. {runs}\n")
    out.append(_md(ov, {c: c for c in ov.columns}))
    out.append(
        "## Run metrics\n\nMean with a 95 % bootstrap CI (BCa); `mirror_flips` is a skewed count and shows the "
        "median (percentile bootstrap). n = runs with a finite value. Units: `_m` metres, `_deg` degrees, "
        "`share_` in [0, 1], goals and flips counts. CI n/a: fewer than two or constant values.\n"
    )
    for scenario, g in _by_scenario(tables["metrics"]):
        out.append(f"### {scenario}\n\n" + _wide(g, ["metric"]))
    out.append(
        "## Recovery after events\n\nNo scripted robot events in these scenarios.\n"
        if tables["recovery"].empty
        else "## Recovery after events\n\nRecovery times (s from the clock start: the event, or a penalised "
        "robot's return) are right-censored at the event's horizon. Kaplan-Meier (`scipy.stats.ecdf`); "
        "median = first time the share not yet relocalized is <= 0.5, CI where the pointwise 95 % log-log "
        "band crosses 0.5. `back_in_play_s` = penalty_s + relocalize_s, censored like relocalize_s.\n"
    )
    em = tables["event_metrics"]
    for scenario, r in _by_scenario(tables["recovery"]):
        r = r.assign(ci=[_ci(a, b) for a, b in zip(r.ci_low_s, r.ci_high_s, strict=True)])
        out.append(f"### {scenario}\n\n" + _md(r.astype({"n": int, "recovered": int}), RECOVERY_HEADERS))
        e = em[em.scenario == scenario]
        if not e.empty:
            out.append("Other event metrics (mean, 95 % bootstrap CI):\n\n" + _wide(e, ["kind", "metric"]))
        out += [f"![survival {n}]({n})\n" for n in figures.get(scenario, []) if n.startswith("survival_")]
    out.append(
        "## Paired tests\n\nWilcoxon signed-rank on A − B paired by seed (events by seed and event; a censored "
        "recovery time counts as its horizon, which is conservative), two-sided (exact without tied "
        "|differences|, else normal approximation; zero differences dropped); Holm correction across all "
        f"tests of a scenario; **bold** = Holm p < {ALPHA}. Rank-biserial r > 0: A tends to be larger. "
        "p = 1 with median 0 and r = 0: identical results in every pair, which is no test and stays out of the "
        "Holm family.\n"
    )
    for scenario, g in _by_scenario(tables["paired"]):
        holm_text = [f"**{_num(p)}**" if sig else _num(p) for p, sig in zip(g.p_holm, g.significant, strict=True)]
        out.append(f"### {scenario}\n\n" + _md(g.assign(holm=holm_text, n=g.n.astype(int)), PAIRED_HEADERS))
    if tables["paired"].empty:
        out.append("No pairs of variants to compare.\n")
    out.append("## Figures\n\nBox plots per variant (points: runs or events; hollow red: censored at the horizon).\n")
    for scenario, names in figures.items():
        out.append(f"### {scenario}\n\n" + "".join(f"![{n}]({n})\n" for n in names if n.startswith("box_")))
    fl = tables["failures"]
    out.append("## Failures\n\n" + (_md(fl, {c: c for c in fl.columns}) if not fl.empty else "None.\n"))
    out.append(
        "## Timing (machine-dependent)\n\nCPU and wall-clock times measured on the machine that ran the "
        "sweep; they differ between identical sweeps.\n\n" + _md(tables["timing"], TIMING_HEADERS)
    )
    return out


def write_report(folder: Path, title: str | None = None) -> Path:
    """Write ``folder/report.md`` and its PNG figures from the rows stored in ``folder``; return the report's path."""
    folder = Path(folder)
    rows = read_rows(folder)
    tables = summary_tables(rows)
    with matplotlib.style.context("default"):
        figures = _figures(folder, run_frame(rows), event_frame(rows))
    text = "\n".join(_sections(tables, figures, title or "Study report"))
    path = folder / "report.md"
    path.write_text(text, encoding="utf-8", newline="\n")
    return path
