"""Aggregates and heat maps of a sweep's results (numpy and matplotlib's Agg backend).

One panel per strategy (and per value of any other axis whose values are not
numbers, such as a fleet's ``vehicle.ecu.way_out``: :func:`panel`), over two
numeric axes ``x`` and ``y``, marginalising every other axis: each cell holds
the runs (``status = ok``) whose ``x`` and ``y`` fall in it, and a metric of
:data:`METRICS` is computed over them: ``collision rate = collided runs /
runs``; ``mean impact speed``, the mean relative impact speed (m/s) over the
cell's *collided* runs (blank when none collided); ``mean deadlock time``, the
mean of a fleet run's time in deadlock (s). An axis with at most
:data:`MAX_LEVELS` distinct values keeps them; a continuous one (Monte Carlo) is
cut into :data:`BINS` equal-width bins.
"""

from __future__ import annotations

import itertools
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 - the backend must be chosen first
import numpy as np  # noqa: E402

MAX_LEVELS = 12
BINS = 8


@dataclass(frozen=True)
class MapMetric:
    """A heat map's figure: ``value`` of a cell's runs (NaN: nothing to show), printed with ``fmt``; colours from
    0 to ``vmax`` (None: the largest value, at least 1)."""

    label: str
    value: Callable[[list[dict]], float]
    fmt: str
    vmax: float | None = None


def _mean(xs: list[float]) -> float:
    return float(np.mean(xs)) if xs else float("nan")


METRICS = {
    "collision_rate": MapMetric("collision rate", lambda runs: _mean([float(bool(r["collided"])) for r in runs]),
                                ".2f", 1.0),
    "mean_impact_speed_mps": MapMetric("mean impact speed (m/s), collided runs",
                                       lambda runs: _mean([r["impact_speed_mps"] or 0.0 for r in runs if r["collided"]]),
                                       ".1f"),
    "mean_deadlock_s": MapMetric("mean time in deadlock (s)", lambda runs: _mean([r["deadlock_s"] for r in runs]),
                                 ".1f"),
}
#: draw_maps' default: a scenario sweep's maps (a subject names its own, cosim.sweep.subject)
DEFAULT_METRICS = ("collision_rate", "mean_impact_speed_mps")


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


def panel_axes(rows: list[dict], axes: Sequence[str]) -> list[str]:
    """The axes whose values are not all numbers (strings, booleans): each value gets its own panel."""
    def number(v: Any) -> bool:
        return v is None or (isinstance(v, (int, float)) and not isinstance(v, bool))
    return [a for a in axes if not all(number(r.get(a)) for r in rows)]


def panel(row: dict, by: Sequence[str] = ()) -> str:
    """A row's panel: its strategy, then its value of each of ``by`` (:func:`panel_axes`)."""
    return ", ".join([str(row["strategy"])] + [_fmt(row.get(a)) for a in by])


def panels(rows: list[dict], by: Sequence[str] = ()) -> list[str]:
    return list(dict.fromkeys(panel(r, by) for r in rows))


def cell_grid(rows: list[dict], name: str, x: Levels, y: Levels, metric: str, by: Sequence[str] = ()) -> np.ndarray:
    """``len(y) × len(x)`` array of ``metric`` for one panel (NaN: no runs, or nothing to show)."""
    cells: dict[tuple[int, int], list[dict]] = {}
    for i, r in enumerate(rows):
        if r["status"] == "ok" and x.index[i] >= 0 and y.index[i] >= 0 and panel(r, by) == name:
            cells.setdefault((int(y.index[i]), int(x.index[i])), []).append(r)
    grid = np.full((len(y.labels), len(x.labels)), np.nan)
    for cell, runs in cells.items():
        grid[cell] = METRICS[metric].value(runs)
    return grid


def _safe(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", name)


def heatmap(path: Path, rows: list[dict], x_axis: str, y_axis: str, metric: str, by: Sequence[str] = ()) -> Path:
    """One PNG: a panel per strategy (and value of each ``by`` axis) of ``metric`` over ``x_axis`` × ``y_axis``."""
    x, y = levels([r.get(x_axis) for r in rows]), levels([r.get(y_axis) for r in rows])
    names, m = panels(rows, by), METRICS[metric]
    grids = [cell_grid(rows, s, x, y, metric, by) for s in names]
    finite = [g[np.isfinite(g)] for g in grids]
    vmax = m.vmax if m.vmax is not None else max([float(f.max()) for f in finite if f.size] + [1.0])
    cols = min(len(names), 4)
    rows_n = -(-len(names) // cols)
    fig, axes = plt.subplots(rows_n, cols, figsize=(1.2 + 3.6 * cols, 0.4 + 3.5 * rows_n), dpi=100, squeeze=False)
    for k, (ax, name, grid) in enumerate(zip(axes.flat, names, grids)):
        image = ax.imshow(grid, origin="lower", aspect="auto", cmap="magma_r", vmin=0.0, vmax=vmax)
        ax.set_xticks(range(len(x.labels)), x.labels, rotation=45, fontsize=7)
        ax.set_yticks(range(len(y.labels)), y.labels, fontsize=7)
        ax.set_xlabel(x_axis, fontsize=8)
        if k % cols == 0:
            ax.set_ylabel(y_axis, fontsize=8)
        ax.set_title(name, fontsize=9)
        if grid.size <= 144:
            for (j, i), v in np.ndenumerate(grid):
                if np.isfinite(v):
                    ax.text(i, j, format(v, m.fmt), ha="center", va="center", fontsize=6,
                            color="white" if v > 0.6 * vmax else "black")
    for ax in list(axes.flat)[len(names):]:
        ax.set_visible(False)
    fig.colorbar(image, ax=axes.ravel().tolist(), shrink=0.85, label=m.label)
    panes = ", ".join(["strategy", *by])
    fig.suptitle(f"{m.label} over {x_axis} × {y_axis} (a panel per {panes}; other axes marginalised)", fontsize=9)
    fig.savefig(path, bbox_inches="tight")
    plt.close(fig)
    return path


def draw_maps(out_dir: Path, rows: list[dict], axes: Sequence[str], pairs: Sequence[tuple[str, str]] | None = None,
              metrics: Sequence[str] = DEFAULT_METRICS) -> list[tuple[str, str, str, Path]]:
    """Heat maps for every pair of numeric axes (or the given pairs); returns (metric, x, y, file)."""
    pairs = list(pairs) if pairs else list(itertools.combinations(numeric_axes(rows, axes), 2))
    by = panel_axes(rows, axes)
    out_dir.mkdir(parents=True, exist_ok=True)
    drawn = []
    for (x_axis, y_axis), metric in itertools.product(pairs, metrics):
        file = out_dir / f"{metric}__{_safe(x_axis)}__{_safe(y_axis)}.png"
        drawn.append((metric, x_axis, y_axis, heatmap(file, rows, x_axis, y_axis, metric, by)))
    return drawn
