"""What ``crd matrix`` writes: matrix.csv, matrix.json, report.md with tables and plots, and a summary.

One row per cell and strategy (the worst radar phase). Plots: relative impact
speed against test speed, one line per strategy, one panel per group
(``impact_<catalogue>.png``, not for false positives, which count
interventions); the Euro NCAP colour bands as a grid of cells
by strategy (``bands_<catalogue>.png``); a bird's-eye thumbnail of every
failing planar cell, a panel per failing strategy (``thumbs/``,
:mod:`cosim.matrix.thumbnails`). The planar rows' traces feed the thumbnails
and are left out of ``matrix.json``.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path
from typing import Any, Mapping, Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from .catalogue import Catalogue  # noqa: E402
from .scoring import Scoring  # noqa: E402
from .scorings import scoring_named  # noqa: E402
from .scorings.ncap import NCAP_BANDS, RED  # noqa: E402
from .thumbnails import thumbnails  # noqa: E402

CSV_COLUMNS = ("catalogue", "scoring", "cell", "group", "test_speed_kmh", "target_speed_kmh", "road_friction",
               "strategy", "phases", "collided", "impact_kmh", "max_impact_kmh", "colour", "score", "interventions",
               "min_speed_intervening_mps", "min_gap_m", "end_reason", "passed", "verdict",
               "impact_kmh_by_phase", "sim_time_s", "wall_time_s", "error")
COLOURS = {"green": "#2e9e44", "yellow": "#f2d024", "orange": "#f28c28", "brown": "#8b5a2b", "red": "#d62728"}


def write_outputs(out: Path, catalogues: Sequence[Catalogue], rows: Sequence[Mapping[str, Any]],
                  meta: Mapping[str, Any]) -> Path:
    """Write everything under ``out``; returns the report's path."""
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "matrix.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=CSV_COLUMNS, extrasaction="ignore")
        writer.writeheader()
        for r in rows:
            writer.writerow({k: r.get(k) for k in CSV_COLUMNS})
    plain = [{k: v for k, v in r.items() if k != "trace"} for r in rows]
    (out / "matrix.json").write_text(json.dumps({"meta": dict(meta), "rows": plain}, indent=1))
    figures, thumbs = {}, {}
    for cat in catalogues:
        cat_rows = [r for r in rows if r["catalogue"] == cat.name]
        figures[cat.name] = [PLOTS[name](out / f"{name}_{cat.name}.png", cat, cat_rows)
                             for name in scoring_named(cat.scoring).plots]
        thumbs[cat.name] = thumbnails(out, cat, cat_rows, int(meta.get("workers", 1)))
    path = out / "report.md"
    path.write_text(report_text(catalogues, plain, meta, figures, thumbs))
    return path


def impact_plot(path: Path, cat: Catalogue, rows: Sequence[Mapping[str, Any]]) -> str:
    """Relative impact speed against test speed: one panel per group, one line per strategy."""
    groups = list(dict.fromkeys(r["group"] for r in rows))
    strategies = list(dict.fromkeys(r["strategy"] for r in rows))
    fig, axes = plt.subplots(1, len(groups), figsize=(3.6 * len(groups), 3.2), squeeze=False)
    for ax, group in zip(axes[0], groups):
        for s in strategies:
            pts = [(r["test_speed_kmh"], r["impact_kmh"]) for r in rows if r["group"] == group and r["strategy"] == s]
            ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", label=s)
        limits = [(r["test_speed_kmh"], r["max_impact_kmh"]) for r in rows
                  if r["group"] == group and r["strategy"] == strategies[0] and "max_impact_kmh" in r]
        if limits:
            ax.step([p[0] for p in limits], [p[1] for p in limits], "k--", where="mid", label="limit")
        ax.set_title(group, fontsize=9)
        ax.set_xlabel("test speed (km/h)")
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("relative impact speed (km/h)")
    axes[0][0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path.name


def band_grid(path: Path, cat: Catalogue, rows: Sequence[Mapping[str, Any]]) -> str:
    """Euro NCAP colour of every cell (columns) for every strategy (rows)."""
    cells = list(dict.fromkeys(r["cell"] for r in rows))
    strategies = list(dict.fromkeys(r["strategy"] for r in rows))
    colour = {(r["strategy"], r["cell"]): r.get("colour", "red") for r in rows}
    fig, ax = plt.subplots(figsize=(max(6.0, 0.32 * len(cells)), 0.5 * len(strategies) + 1.6))
    for i, s in enumerate(strategies):
        for j, c in enumerate(cells):
            ax.add_patch(plt.Rectangle((j, i), 0.95, 0.9, color=COLOURS[colour[(s, c)]]))
    ax.set_xlim(0, len(cells))
    ax.set_ylim(0, len(strategies))
    ax.set_xticks([j + 0.5 for j in range(len(cells))], cells, rotation=90, fontsize=7)
    ax.set_yticks([i + 0.45 for i in range(len(strategies))], strategies)
    ax.set_title(f"{cat.title}: colour bands", fontsize=9)
    ax.legend(handles=band_legend(), loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=7,
              title="relative impact", title_fontsize=7, frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path.name


def band_legend() -> list:
    """One patch per Euro NCAP colour band, labelled with its range of relative impact speed."""
    from matplotlib.patches import Patch

    labels, low = [], 0.0
    for edge, colour, _ in NCAP_BANDS:
        labels.append((colour, "no contact" if edge == 0.0 else f"{low:g}-{edge:g} km/h"))
        low = edge
    labels.append((RED[0], f"> {low:g} km/h"))
    return [Patch(color=COLOURS[colour], label=f"{colour}: {text}") for colour, text in labels]


#: report figure name (a scoring's ``plots``) -> the function that draws it
PLOTS = {"impact": impact_plot, "bands": band_grid}


def _fmt(r: Mapping[str, Any], scoring: Scoring) -> str:
    return "error" if r.get("error") else scoring.cell_text(r)


def cell_table(cat: Catalogue, rows: Sequence[Mapping[str, Any]]) -> list[str]:
    """Markdown table: one line per cell, one column per strategy (and the scoring's limit column, if any)."""
    scoring = scoring_named(cat.scoring)
    strategies = list(dict.fromkeys(r["strategy"] for r in rows))
    by = {(r["cell"], r["strategy"]): r for r in rows}
    extra = f" {scoring.limit_header} |" if scoring.limit_header else ""
    lines = [f"| cell |{extra} " + " | ".join(strategies) + " |",
             "|---|" + ("---|" if extra else "") + "---|" * len(strategies)]
    for cell in dict.fromkeys(r["cell"] for r in rows):
        lim = f" {scoring.limit_text(by[(cell, strategies[0])])} |" if extra else ""
        lines.append(f"| {cell} |{lim} " + " | ".join(_fmt(by[(cell, s)], scoring) for s in strategies) + " |")
    return lines


def summary_lines(catalogues: Sequence[Catalogue], rows: Sequence[Mapping[str, Any]]) -> list[str]:
    """Per catalogue and strategy: the cells whose requirement is met, what the scoring adds (the NCAP
    bands and points, the interventions), and the failed cells."""
    lines = []
    for cat in catalogues:
        cat_rows = [r for r in rows if r["catalogue"] == cat.name]
        scoring = scoring_named(cat.scoring)
        for s in dict.fromkeys(r["strategy"] for r in cat_rows):
            mine = [r for r in cat_rows if r["strategy"] == s]
            failed = [r["cell"] for r in mine if not r["passed"]]
            text = f"{cat.name:<16} {s:<13} {len(mine) - len(failed):>3}/{len(mine):<3} requirements met"
            text += scoring.summary(mine, cat.scoring_table)
            if failed:
                text += "  FAIL: " + ", ".join(failed[:6]) + (" ..." if len(failed) > 6 else "")
            lines.append(text)
    return lines


def report_text(catalogues: Sequence[Catalogue], rows: Sequence[Mapping[str, Any]], meta: Mapping[str, Any],
                figures: Mapping[str, list[str]], thumbs: Mapping[str, list[tuple[str, str]]] | None = None) -> str:
    lines = ["# crd matrix report", "",
             f"Strategies {', '.join(meta['strategies'])}; {meta['phases']} radar phase(s) per cell, worst "
             f"scored; {meta['runs']} runs in {meta['wall_s']:.1f} s on {meta['workers']} worker(s); "
             f"crd {meta['version']}.", "", "## Summary", "", "```", *summary_lines(catalogues, rows), "```", ""]
    for cat in catalogues:
        cat_rows = [r for r in rows if r["catalogue"] == cat.name]
        lines += [f"## {cat.title} (`{cat.name}`, scoring `{cat.scoring}`)", "",
                  f"How to read a cell: {scoring_named(cat.scoring).rule}", ""]
        lines += cell_table(cat, cat_rows) + [""]
        lines += [f"![{name}]({name})" for name in figures.get(cat.name, [])] + [""]
        made = (thumbs or {}).get(cat.name, [])
        if made:
            lines += [f"Failing cells, bird's-eye ({len(made)}, a panel per failing strategy: the collision or the "
                      "closest approach, the boxes then and 1 s before):", ""] + [f"![{caption}]({rel})" for caption, rel in made] + [""]
        lines += ["Sources:", ""] + [f"- `{k}`: {v}" for k, v in cat.sources.items()] + [""]
    return "\n".join(lines)
