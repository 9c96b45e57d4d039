"""Aggregates and heat maps of a sweep's results (numpy and matplotlib's Agg backend).

Per strategy, over two axes ``x`` and ``y``, marginalising every other axis:
each cell holds the runs (``status = ok``) whose ``x`` and ``y`` fall in it;
``collision rate = collided runs / runs``, and ``mean impact speed`` is the mean
relative impact speed (m/s) over the cell's *collided* runs (blank when none
collided). An axis with at most :data:`MAX_LEVELS` distinct values keeps them;
a continuous one (Monte Carlo) is cut into :data:`BINS` equal-width bins.
"""

from __future__ import annotations

import itertools
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 - the backend must be chosen first
import numpy as np  # noqa: E402

MAX_LEVELS = 12
BINS = 8
METRICS = {"collision_rate": "collision rate", "mean_impact_speed_mps": "mean impact speed (m/s), collided runs"}


@dataclass(frozen=True)
class Levels:
    """How an axis is cut: ``labels`` per level and each row's level index (-1: no value)."""

    labels: tuple[str, ...]
    index: np.ndarray


def _fmt(v: Any) -> str:
    return f"{v:g}" if isinstance(v, float) else str(v)


def levels(values: Sequence[Any]) -> Levels:
    distinct = sorted({v for v in values if v is not None})
    if len(distinct) <= MAX_LEVELS or not all(isinstance(v, (int, float)) for v in distinct):
        pos = {v: i for i, v in enumerate(distinct)}
        return Levels(tuple(_fmt(v) for v in distinct), np.array([pos.get(v, -1) for v in values]))
    lo, hi = float(distinct[0]), float(distinct[-1])
    edges = np.linspace(lo, hi, BINS + 1)
    idx = np.clip(np.searchsorted(edges, np.asarray(values, dtype=float), side="right") - 1, 0, BINS - 1)
    return Levels(tuple(f"{edges[i]:.3g}–{edges[i + 1]:.3g}" for i in range(BINS)), idx)


def numeric_axes(rows: list[dict], axes: Sequence[str]) -> list[str]:
    """The axes that can be a map's x or y: numeric, with at least two distinct values."""
    out = []
    for path in axes:
        vals = {r.get(path) for r in rows} - {None}
        if len(vals) >= 2 and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in vals):
            out.append(path)
    return out


def strategies(rows: list[dict]) -> list[str]:
    return list(dict.fromkeys(r["strategy"] for r in rows))


def cell_grid(rows: list[dict], strategy: str, x: Levels, y: Levels, metric: str) -> np.ndarray:
    """``len(y) × len(x)`` array of ``metric`` for one strategy (NaN: no runs, or no collision)."""
    total = np.zeros((len(y.labels), len(x.labels)))
    hits = np.zeros_like(total)
    impact = np.zeros_like(total)
    for i, r in enumerate(rows):
        if r["strategy"] != strategy or r["status"] != "ok" or x.index[i] < 0 or y.index[i] < 0:
            continue
        cell = (y.index[i], x.index[i])
        total[cell] += 1
        if r["collided"]:
            hits[cell] += 1
            impact[cell] += r["impact_speed_mps"] or 0.0
    with np.errstate(invalid="ignore", divide="ignore"):
        return hits / total if metric == "collision_rate" else np.where(hits > 0, impact / hits, np.nan)


def _safe(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", name)


def heatmap(path: Path, rows: list[dict], x_axis: str, y_axis: str, metric: str) -> Path:
    """One PNG: a panel per strategy of ``metric`` over ``x_axis`` × ``y_axis``."""
    x, y = levels([r.get(x_axis) for r in rows]), levels([r.get(y_axis) for r in rows])
    names = strategies(rows)
    grids = [cell_grid(rows, s, x, y, metric) for s in names]
    finite = [g[np.isfinite(g)] for g in grids]
    vmax = 1.0 if metric == "collision_rate" else max([float(f.max()) for f in finite if f.size] + [1.0])
    fig, axes = plt.subplots(1, len(names), figsize=(1.2 + 3.6 * len(names), 3.9), dpi=100, squeeze=False)
    for ax, name, grid in zip(axes[0], names, grids):
        image = ax.imshow(grid, origin="lower", aspect="auto", cmap="magma_r", vmin=0.0, vmax=vmax)
        ax.set_xticks(range(len(x.labels)), x.labels, rotation=45, fontsize=7)
        ax.set_yticks(range(len(y.labels)), y.labels, fontsize=7)
        ax.set_xlabel(x_axis, fontsize=8)
        ax.set_title(name, fontsize=9)
        if grid.size <= 144:
            for (j, i), v in np.ndenumerate(grid):
                if np.isfinite(v):
                    ax.text(i, j, f"{v:.2f}" if metric == "collision_rate" else f"{v:.1f}", ha="center",
                            va="center", fontsize=6, color="white" if v > 0.6 * vmax else "black")
    axes[0][0].set_ylabel(y_axis, fontsize=8)
    fig.colorbar(image, ax=axes[0].tolist(), shrink=0.85, label=METRICS[metric])
    fig.suptitle(f"{METRICS[metric]} over {x_axis} × {y_axis} (other axes marginalised)", fontsize=9)
    fig.savefig(path, bbox_inches="tight")
    plt.close(fig)
    return path


def draw_maps(out_dir: Path, rows: list[dict], axes: Sequence[str],
              pairs: Sequence[tuple[str, str]] | None = None) -> list[tuple[str, str, str, Path]]:
    """Heat maps for every pair of numeric axes (or the given pairs); returns (metric, x, y, file)."""
    pairs = list(pairs) if pairs else list(itertools.combinations(numeric_axes(rows, axes), 2))
    out_dir.mkdir(parents=True, exist_ok=True)
    drawn = []
    for (x_axis, y_axis), metric in itertools.product(pairs, METRICS):
        file = out_dir / f"{metric}__{_safe(x_axis)}__{_safe(y_axis)}.png"
        drawn.append((metric, x_axis, y_axis, heatmap(file, rows, x_axis, y_axis, metric)))
    return drawn
