"""Plots of stored traces: localization error over time with the events marked (matplotlib, Agg).

``error_plot(folder, scenario)`` reads every trace of ``scenario`` under ``folder/traces`` and
draws one panel per variant: the position error (m) of each traced robot and seed against the
match time (s), with the scripted events as vertical lines (kidnaps red, penalties orange,
returns green, falls grey). The PNG carries no time stamp, so equal traces give equal bytes.
"""

from __future__ import annotations

from pathlib import Path

from scenarios.trace import Trace

_EVENT_STYLE = {"kidnap": "tab:red", "penalty": "tab:orange", "unpenalized": "tab:green", "forced_fall": "0.5"}


def error_plot(folder: Path, scenario: str, max_lines: int = 40) -> Path:
    """Write ``folder/error_<scenario>.png`` (module docstring); returns its path."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    root = folder / "traces" / scenario
    variants = sorted(p.name for p in root.iterdir() if p.is_dir()) if root.exists() else []
    fig, axes = plt.subplots(max(1, len(variants)), 1, figsize=(9, 2.2 * max(1, len(variants))), squeeze=False)
    for ax, variant in zip(axes[:, 0], variants, strict=False):
        files = sorted((root / variant).glob("seed-*.parquet"))
        lines = 0
        marked: set[tuple[str, float]] = set()
        for path in files:
            tr = Trace.read(path)
            d, _, _, _ = tr.errors()
            for number in tr.meta["traced"]:
                if lines >= max_lines:
                    break
                sel = tr.column("number") == number
                ax.plot(tr.column("time")[sel], d[sel], lw=0.7, alpha=0.6)
                lines += 1
            for kind, colour in _EVENT_STYLE.items():
                for e in tr.log(kind):
                    if e.get("team", 0) == 0 and (kind, e["time"]) not in marked:
                        marked.add((kind, e["time"]))
                        ax.axvline(e["time"], color=colour, lw=0.8, ls="--")
        ax.set_title(f"{scenario}: {variant} ({len(files)} seed(s))", fontsize=9)
        ax.set_ylabel("position error (m)")
        ax.set_ylim(bottom=0)
    axes[-1, 0].set_xlabel("match time (s); dashed: kidnap red, penalty orange, return green, fall grey")
    fig.tight_layout()
    out = folder / f"error_{scenario}.png"
    fig.savefig(out, dpi=90, metadata={"Software": None})
    plt.close(fig)
    return out
