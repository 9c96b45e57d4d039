"""Bird's-eye thumbnails of a matrix's failing planar cells, drawn with the run plot's own pieces.

A planar cell's row carries a thinned trace of its worst phase (:mod:`cosim.matrix.planar_outcome`);
the scene (road and boxes) is the cell's at phase 0 (:func:`cosim.results.scene_file.scene_of`). Each
thumbnail is the zoom of :func:`cosim.results.birdseye.plot_birdseye` made small: the road, the ego's
path coloured by speed, the boxes at the collision (or the closest approach) and 1 s before it, the
contact point.
"""

from __future__ import annotations

from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np

from ..results.birdseye import (
    COLLISION_COLOR, EGO_COLOR, box_patch, draw_road, ego_boxes_xy, focus_index, object_color, set_view, speed_line,
)
from ..results.plots import _pyplot
from ..results.run_view import RunView, StrategyTrack, body_box, with_collision
from ..results.scene_file import scene_of
from ..scenarios.loader import scenario_from_dict
from .catalogue import Catalogue

THUMB_SIZE_IN, THUMB_DPI, THUMB_SPAN_M = (3.6, 2.4), 70, 30.0
GHOSTS_S = (0.0, 1.0)


def failing(row: Mapping[str, Any]) -> bool:
    """A row whose requirement is not met (for a grid scoring: not green), with a trace to draw."""
    return "trace" in row and not row["passed"]


def _view(scene, row: Mapping[str, Any]) -> RunView:
    tr = row["trace"]
    k = len(tr["t_s"])
    objects = np.array(tr["objects"], dtype=float).reshape(len(scene.objects), k, 3)
    track = StrategyTrack(row["strategy"], np.array(tr["t_s"], dtype=float), np.array(tr["ego"], dtype=float),
                          np.array(tr["speed_mps"], dtype=float), objects, None, None, None, None)
    impact = tr["contact"].get("impact_speed_mps") if tr["contact"] else None
    track = with_collision(track, scene.ego, scene.objects, tr["contact"], impact)
    return RunView(Path(row["cell"]), scene.road, scene.ego, scene.objects, {row["strategy"]: track})


def _panel(ax, scene, row: Mapping[str, Any]) -> None:
    """One row's zoom: road, path, the boxes at the focus and 1 s before, the contact point, the verdict."""
    view = _view(scene, row)
    track = view.tracks[row["strategy"]]
    draw_road(ax, view.road, step_m=1.0)
    speed_line(ax, track.ego[:, :2], track.speed_mps, max(1.0, float(np.nanmax(track.speed_mps))), 400)
    k = focus_index(view, track)
    dt = float(np.median(np.diff(track.t_s))) if len(track.t_s) > 1 else 1.0
    for back in GHOSTS_S:
        j = max(0, k - int(round(back / dt)))
        alpha = 0.9 if back == 0.0 else 0.3
        box_patch(ax, view.ego, EGO_COLOR, alpha=alpha, zorder=4).set_xy(body_box(view.ego, *track.ego[j]).corners())
        for body, poses in zip(view.objects, track.objects):
            box_patch(ax, body, object_color(body), alpha=alpha, zorder=4).set_xy(body_box(body, *poses[j]).corners())
    centre = ego_boxes_xy(view, track)[k]
    if track.collision is not None:
        centre = np.array([track.collision.x_m, track.collision.y_m])
        ax.plot(*centre, marker="X", ms=9, color=COLLISION_COLOR, ls="none", zorder=7)
    ax.set_title(f"{row['strategy']}: {row['verdict']}", fontsize=7, loc="left")
    ax.tick_params(labelsize=6)
    set_view(ax, float(centre[0]), float(centre[1]), THUMB_SPAN_M)


def draw_thumbnail(job: tuple[Path, Any, Sequence[Mapping[str, Any]]]) -> str:
    """One failing cell's thumbnail: a panel per failing strategy, side by side (PNG); returns its file name."""
    path, scene, rows = job
    plt = _pyplot()
    w, h = THUMB_SIZE_IN
    fig, axes = plt.subplots(1, len(rows), figsize=(w * len(rows), h), dpi=THUMB_DPI, squeeze=False)
    fig.subplots_adjust(left=0.06, right=0.99, top=0.82, bottom=0.12, wspace=0.25)
    for ax, row in zip(axes[0], rows):
        _panel(ax, scene, row)
    fig.suptitle(rows[0]["cell"], x=0.01, ha="left", fontsize=8)
    fig.savefig(path)
    plt.close(fig)
    return path.name


def thumbnails(out: Path, cat: Catalogue, rows: Sequence[Mapping[str, Any]], workers: int = 1) -> list[tuple[str, str]]:
    """A thumbnail of every failing cell of ``cat`` (a panel per failing strategy) under ``out/thumbs``, drawn by
    ``workers`` processes: (caption, relative path) each."""
    cells = {c.cell_id: c for c in cat.cells}
    failed: dict[str, list[Mapping[str, Any]]] = {}
    for row in rows:
        if failing(row):
            failed.setdefault(row["cell"], []).append(row)
    if not failed:
        return []
    (out / "thumbs").mkdir(parents=True, exist_ok=True)
    jobs = [(out / "thumbs" / f"{cat.name}_{cell}.png", scene_of(scenario_from_dict(cells[cell].scenario_dict())), mine)
            for cell, mine in failed.items()]
    if workers > 1 and len(jobs) > 1:
        with ProcessPoolExecutor(max_workers=workers) as pool:
            names = list(pool.map(draw_thumbnail, jobs, chunksize=8))
    else:
        names = [draw_thumbnail(job) for job in jobs]
    return [(f"{cell}: " + "; ".join(f"{r['strategy']} {r['verdict']}" for r in mine), f"thumbs/{name}")
            for (cell, mine), name in zip(failed.items(), names)]
