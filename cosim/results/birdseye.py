"""The bird's-eye plot of a run (PNG): the road, the ego's path coloured by speed, the objects, the collision.

Two panels, both in metres: above, the whole run (the road, every path; across the road the
scale is stretched when the run is long and the road narrow, and the panel says by how much);
below, true to scale, the moment that matters: the collision, or else the closest approach
between the ego and an object, with the boxes of the ego and the objects then and every 0.5 s
before it, the contact point and normal, and the impact speed. Matplotlib's Agg backend; the
drawing helpers here are shared with the video (:mod:`cosim.results.birdseye_video`).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ..world.road import Road
from .plots import _pyplot
from .run_view import RunView, StrategyTrack, body_box, load_run_view
from .scene_file import Body

ROAD_COLOR, MARKING_COLOR, EDGE_COLOR = "#d9d9d9", "white", "#555555"
EGO_COLOR, STOPPING_COLOR, COLLISION_COLOR = "tab:blue", "tab:orange", "crimson"
#: an object's class -> its colour (other classes: grey)
OBJECT_COLORS = {"EPTa": "tab:purple", "EPTc": "tab:pink", "EBTa": "tab:green", "EMT": "tab:olive",
                 "GVT": "tab:brown", "object": "tab:green"}
SPEED_CMAP = "viridis"
GHOST_PERIOD_S = 0.5
ZOOM_SPAN_M = 40.0


def object_color(body: Body) -> str:
    return OBJECT_COLORS.get(body.kind, "tab:gray")


def road_lines(road: Road, step_m: float = 1.0) -> tuple[np.ndarray, np.ndarray, list[np.ndarray]]:
    """The road's left and right edges and its markings (the lane borders within it, and the centre line between
    its two directions), each an (n, 2) polyline."""
    left, right = road.edges(step_m)
    s = np.linspace(0.0, road.length_m, max(2, int(road.length_m / step_m) + 1))
    inner = [lane for lane in road.lane_ids() if lane not in (max(road.lane_ids()), min(road.lane_ids()))]
    lines = [road.lane_border_line(lane, step_m) for lane in inner]
    if any(lane > 0 for lane in road.lane_ids()) and any(lane < 0 for lane in road.lane_ids()):
        x, y, _ = road.pose(s, 0.0)
        lines.append(np.column_stack([x, y]))
    return left, right, lines


def draw_road_lines(ax, left: np.ndarray, right: np.ndarray, markings: Sequence[np.ndarray]) -> None:
    """A road's surface between its edges, the edges (solid) and the markings (dashed)."""
    surface = np.vstack([left, right[::-1]])
    ax.fill(surface[:, 0], surface[:, 1], color=ROAD_COLOR, zorder=0, lw=0)
    for edge in (left, right):
        ax.plot(edge[:, 0], edge[:, 1], color=EDGE_COLOR, lw=1.2, zorder=1)
    for line in markings:
        ax.plot(line[:, 0], line[:, 1], color=MARKING_COLOR, lw=1.2, ls=(0, (6, 6)), zorder=1)


def draw_road(ax, road: Road | None, step_m: float = 1.0) -> None:
    """The road surface, its edges (solid) and the lane borders within it (dashed)."""
    if road is not None:
        draw_road_lines(ax, *road_lines(road, step_m))


def box_patch(ax, body: Body, color: str, **style):
    """A polygon patch for ``body`` (placed later with ``set_xy``)."""
    from matplotlib.patches import Polygon

    patch = Polygon(np.zeros((4, 2)), closed=True, facecolor=color, edgecolor="black", lw=0.8, **style)
    ax.add_patch(patch)
    return patch


def speed_line(ax, xy: np.ndarray, speed: np.ndarray, vmax: float, max_segments: int = 2000):
    """The path ``xy`` coloured by ``speed`` (a LineCollection of at most ``max_segments``: each segment is a path
    of its own to draw)."""
    from matplotlib.collections import LineCollection

    keep = np.unique(np.linspace(0, len(xy) - 1, min(len(xy), max_segments + 1)).round().astype(int))
    xy, speed = xy[keep], speed[keep]
    segments = np.stack([xy[:-1], xy[1:]], axis=1)
    line = LineCollection(segments, cmap=SPEED_CMAP, lw=2.5, zorder=3)
    line.set_array(0.5 * (speed[:-1] + speed[1:]))
    line.set_clim(0.0, vmax)
    ax.add_collection(line)
    return line


def ego_boxes_xy(view: RunView, track: StrategyTrack) -> np.ndarray:
    """The centres of the ego's box over time, shape (n, 2)."""
    shift = view.ego.front_m - view.ego.length_m / 2.0
    return track.ego[:, :2] + shift * np.column_stack([np.cos(track.ego[:, 2]), np.sin(track.ego[:, 2])])


def focus_index(view: RunView, track: StrategyTrack) -> int:
    """The time index the zoom shows: the collision (last sample), else the closest approach, else the end."""
    if track.collision is not None or not len(view.objects):
        return len(track.t_s) - 1
    centres = ego_boxes_xy(view, track)
    gaps = np.hypot(track.objects[:, :, 0] - centres[:, 0], track.objects[:, :, 1] - centres[:, 1]).min(axis=0)
    return int(np.argmin(gaps))


def set_view(ax, x_m: float, y_m: float, span_m: float) -> None:
    """Centre the axes on (x, y) at ``span_m`` metres across, true to scale (the height follows the axes' shape)."""
    pos = ax.get_position()
    ratio = (pos.height * ax.figure.get_figheight()) / (pos.width * ax.figure.get_figwidth())
    ax.set_xlim(x_m - span_m / 2.0, x_m + span_m / 2.0)
    ax.set_ylim(y_m - span_m * ratio / 2.0, y_m + span_m * ratio / 2.0)


def _overview(ax, view: RunView, track: StrategyTrack, vmax: float):
    draw_road(ax, view.road, step_m=2.0)
    line = speed_line(ax, track.ego[:, :2], track.speed_mps, vmax)
    for body, poses in zip(view.objects, track.objects):
        ax.plot(poses[:, 0], poses[:, 1], color=object_color(body), lw=1.5, ls=":", zorder=2)
        ax.plot(*poses[-1, :2], marker="s", color=object_color(body), ms=5, zorder=4, label=f"{body.name} ({body.kind})")
    if track.collision is not None:
        ax.plot(track.collision.x_m, track.collision.y_m, marker="X", ms=11, color=COLLISION_COLOR, ls="none", zorder=6,
                label="collision")
    xy = np.vstack([track.ego[:, :2], *(p[:, :2] for p in track.objects)])
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    if view.road is not None:
        edges = np.vstack(view.road.edges(5.0))
        lo, hi = np.minimum(lo, np.nanmin(edges, axis=0)), np.maximum(hi, np.nanmax(edges, axis=0))
    pad = 0.03 * max(hi - lo) + 1.0
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - 2.0, hi[1] + 2.0)
    width_in, height_in = ax.get_position().width * ax.figure.get_figwidth(), ax.get_position().height * ax.figure.get_figheight()
    stretch = ((hi[0] - lo[0] + 2 * pad) / width_in) / ((hi[1] - lo[1] + 4.0) / height_in)
    if stretch > 1.05:
        ax.set_title(f"whole run (across the road stretched {stretch:.0f}x)", fontsize=10, loc="left")
    else:
        ax.set_aspect("equal")
        ax.set_title("whole run", fontsize=10, loc="left")
    return line


def _zoom(ax, view: RunView, track: StrategyTrack, k: int, vmax: float) -> None:
    draw_road(ax, view.road, step_m=0.5)
    speed_line(ax, track.ego[:, :2], track.speed_mps, vmax)
    dt = float(np.median(np.diff(track.t_s))) if len(track.t_s) > 1 else 1.0
    ghosts = range(k, -1, -max(1, int(round(GHOST_PERIOD_S / dt))))
    for n, j in enumerate(ghosts):
        alpha = 0.9 if n == 0 else 0.25
        box_patch(ax, view.ego, EGO_COLOR, alpha=alpha, zorder=4).set_xy(body_box(view.ego, *track.ego[j]).corners())
        for body, poses in zip(view.objects, track.objects):
            box_patch(ax, body, object_color(body), alpha=alpha, zorder=4).set_xy(body_box(body, *poses[j]).corners())
    centre = ego_boxes_xy(view, track)[k]
    hit = track.collision
    if hit is not None:
        centre = np.array([hit.x_m, hit.y_m])
        ax.plot(hit.x_m, hit.y_m, marker="X", ms=13, color=COLLISION_COLOR, ls="none", zorder=7)
        ax.annotate("", xy=(hit.x_m + 2.0 * hit.normal[0], hit.y_m + 2.0 * hit.normal[1]), xytext=(hit.x_m, hit.y_m),
                    arrowprops=dict(arrowstyle="->", color=COLLISION_COLOR, lw=1.5), zorder=7)
        speed = "" if hit.impact_speed_mps is None else f", {hit.impact_speed_mps:.2f} m/s"
        ax.set_title(f"collision at t = {hit.t_s:.2f} s{speed} (contact point and normal)", fontsize=10, loc="left")
    else:
        ax.set_title(f"closest approach, t = {track.t_s[k]:.2f} s (boxes every {GHOST_PERIOD_S:g} s before it)",
                     fontsize=10, loc="left")
    set_view(ax, centre[0], centre[1], ZOOM_SPAN_M)


def plot_birdseye(view: RunView, strategy: str, path: Path) -> Path:
    """Write the bird's-eye PNG of one strategy's run to ``path``."""
    plt = _pyplot()
    track = view.tracks[strategy]
    vmax = max(1.0, float(np.nanmax(track.speed_mps)))
    fig = plt.figure(figsize=(12.0, 7.5), dpi=100)
    top = fig.add_axes((0.06, 0.60, 0.80, 0.33))
    bottom = fig.add_axes((0.06, 0.07, 0.80, 0.44))
    line = _overview(top, view, track, vmax)
    _zoom(bottom, view, track, focus_index(view, track), vmax)
    for ax in (top, bottom):
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
    bar = fig.colorbar(line, cax=fig.add_axes((0.88, 0.07, 0.015, 0.86)))
    bar.set_label("ego speed (m/s)")
    from matplotlib.patches import Patch

    handles, _ = top.get_legend_handles_labels()
    handles.insert(0, Patch(facecolor=EGO_COLOR, edgecolor="black", label="ego (below: every 0.5 s)"))
    top.legend(handles=handles, loc="upper right", fontsize=8, framealpha=0.9)
    fig.suptitle(f"{view.path.name}: {strategy} (bird's-eye view)", x=0.06, ha="left", fontsize=12)
    fig.savefig(path)
    plt.close(fig)
    return path


def plot_run(run_dir: Path, strategies: Sequence[str]) -> list[tuple[str, str]]:
    """``<strategy>/birdseye.png`` of each strategy of the run written to ``run_dir`` (every planar run gets
    them); the report's (title, path relative to ``run_dir``) of each."""
    view = load_run_view(run_dir, list(strategies))
    return [(f"{s}: bird's-eye view", str(plot_birdseye(view, s, run_dir / s / "birdseye.png").relative_to(run_dir)))
            for s in strategies]
