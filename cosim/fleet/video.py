"""The bird's-eye video of a fleet run (``crd animate`` on a ``crd fleet --out`` directory): ``fleet.mp4``
(``--gif``: ``fleet.gif``) and the still ``fleet.png``.

The whole scene is in view, fixed: every car's box in its colour with its name, outlined in the colour of its
ECU's mode (:data:`cosim.results.birdseye_video.MODE_COLORS`), its stopping region as its ECU reports it
(:mod:`cosim.fleet.run_view`), the roads, the standing objects, the conflict zone, each car's path (dotted),
the time, and a strip of every car's speed with a moving cursor. The machinery is the one-car video's
(:func:`cosim.results.birdseye_video.encode_frames`): the figure is built once; as the view does not move,
everything but the cars, their regions and labels, the time and the cursor is drawn once and kept, and each
frame restores it and draws only those.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from matplotlib.lines import Line2D
from matplotlib.patches import Circle, Patch

from ..results.birdseye import COLLISION_COLOR, box_patch, draw_road_lines, object_color, set_view
from ..results.birdseye_video import (
    FAST_TEXT, FIGURE_IN, MODE_COLORS, VideoOptions, encode_frames, frame_indices, scale_bar, video_params,
)
from ..results.plots import _pyplot
from ..results.region_view import stopping_band
from ..results.scene_file import Body
from ..world.geometry import Box
from .run_view import CarTrack, FleetView, load_fleet_view

#: margin around everything the cars and the scene cover (m): room for the stopping regions
VIEW_MARGIN_M = 12.0
MAP_AXES = (0.01, 0.06, 0.56, 0.86)
STILL_FILE = "fleet.png"
STILL_WIDTH_PX = 1280
#: from a car's side to the centre of its name (m)
LABEL_GAP_M = 2.0


#: the cars' colours, clear of the mode colours of their outlines (green, orange, red, grey)
CAR_COLORS = ("tab:blue", "tab:purple", "tab:brown", "tab:pink", "tab:olive", "tab:cyan", "navy", "teal",
              "darkmagenta", "black")


def car_color(index: int) -> str:
    return CAR_COLORS[index % len(CAR_COLORS)]


def _extent(view: FleetView, height_per_width: float) -> tuple[float, float, float]:
    """The view's centre and width (m): every box over time, the objects and the conflict zone, with a margin,
    in axes ``height_per_width`` as high as wide."""
    x0, y0, r = view.scene.conflict
    xy = [np.array([[x0 - r, y0 - r], [x0 + r, y0 + r]])]
    xy += [track.box[:, :2] for track in view.tracks]
    xy += [np.array([[o.x_m, o.y_m]]) for o in view.scene.objects]
    points = np.vstack(xy)
    lo, hi = points.min(axis=0) - VIEW_MARGIN_M, points.max(axis=0) + VIEW_MARGIN_M
    (dx, dy), (cx, cy) = hi - lo, (lo + hi) / 2
    return float(cx), float(cy), float(max(dx, dy / height_per_width))


@dataclass
class _Car:
    """The artists one car moves: its box, its stopping region, its name; its box about its centre."""

    body: Body
    box: object
    region: object
    label: object


class FleetFrame:
    """The figure and the artists a frame moves (module docstring)."""

    def __init__(self, view: FleetView, options: VideoOptions) -> None:
        plt = _pyplot()
        self.view = view
        self.fig = plt.figure(figsize=FIGURE_IN, dpi=options.width_px / FIGURE_IN[0])
        self.ax = self.fig.add_axes(MAP_AXES)
        self._map()
        self.cars = [self._car(i) for i in range(len(view.tracks))]
        hits = [t.collision for t in view.tracks if t.collision is not None]
        self.hits = self.ax.plot([h[1] for h in hits], [h[2] for h in hits], marker="X", ms=14, color=COLLISION_COLOR,
                                 ls="none", zorder=7)[0]
        self.time = self.fig.text(0.60, 0.885, "", fontsize=13, family="monospace")
        self._panel()
        self.moving = [self.hits, self.time, self.cursor, *(a for c in self.cars for a in (c.region, c.box, c.label))]
        self._background = self._keep_background()

    def _map(self) -> None:
        scene, ax = self.view.scene, self.ax
        for car in scene.cars:
            if car.road is not None:
                draw_road_lines(ax, car.road.left, car.road.right, car.road.markings)
        for obj in scene.objects:
            patch = box_patch(ax, obj.body, object_color(obj.body), zorder=3)
            patch.set_xy(Box(obj.x_m, obj.y_m, obj.heading_rad, obj.body.length_m, obj.body.width_m).corners())
        x0, y0, r = scene.conflict
        ax.add_patch(Circle((x0, y0), r, fill=False, ls="--", lw=1.2, color="0.35", zorder=2))
        for i, track in enumerate(self.view.tracks):
            ax.plot(track.box[:, 0], track.box[:, 1], color=car_color(i), lw=1.0, ls=":", zorder=2)
        cx, cy, span = _extent(self.view, (MAP_AXES[3] * FIGURE_IN[1]) / (MAP_AXES[2] * FIGURE_IN[0]))
        set_view(ax, cx, cy, span)
        ax.set_xticks([])
        ax.set_yticks([])
        scale_bar(self.fig, ax, span)

    def _car(self, i: int) -> _Car:
        own, color = self.view.scene.cars[i].body, car_color(i)
        body = Body(own.name, own.kind, own.length_m, own.width_m, own.length_m / 2.0)  # world.csv: box centres
        box = box_patch(self.ax, body, color, zorder=5)
        box.set_linewidth(2.0)
        region = box_patch(self.ax, body, color, alpha=0.3, zorder=4)
        region.set_visible(False)
        label = self.ax.text(0.0, 0.0, body.name, fontsize=9, ha="center", va="center", zorder=6)
        return _Car(body, box, region, label)

    def _panel(self) -> None:
        view, fig = self.view, self.fig
        fig.text(0.01, 0.95, f"{view.scene.name}: every car's box (outline: its ECU's mode) and its ECU's stopping "
                             "region, world frame (x right, y up; dashed: the conflict zone)", fontsize=11)
        names = [c.name for c in view.scene.cars]
        cars = [Patch(facecolor=car_color(i), edgecolor="black", label=n) for i, n in enumerate(names)]
        modes = [Patch(facecolor="white", edgecolor=c, lw=2.0, label=m) for m, c in MODE_COLORS.items()]
        modes.append(Line2D([], [], marker="X", ms=10, color=COLLISION_COLOR, ls="none", label="collision"))
        fig.legend(handles=cars, loc="upper left", bbox_to_anchor=(0.59, 0.86), fontsize=9, frameon=False, ncol=2,
                   title="car")
        fig.legend(handles=modes, loc="upper left", bbox_to_anchor=(0.80, 0.86), fontsize=9, frameon=False,
                   title="ECU mode (outline)")
        strip = fig.add_axes((0.63, 0.08, 0.35, 0.46))
        for i, track in enumerate(view.tracks):
            strip.plot(view.t_s, track.speed_mps * 3.6, color=car_color(i), lw=1.2)
        top = max(float(np.nanmax(t.speed_mps)) for t in view.tracks) * 3.6
        strip.set_xlim(view.t_s[0], max(view.t_s[-1], view.t_s[0] + 1e-3))
        strip.set_ylim(0.0, max(10.0, top * 1.1))
        strip.set_xlabel("time (s)")
        strip.set_ylabel("speed (km/h)")
        strip.set_title("every car's speed", fontsize=9, loc="left")
        self.strip = strip
        self.cursor = strip.axvline(view.t_s[0], color="black", lw=1.0)

    def _keep_background(self):
        """Draw everything that stays (the moving artists hidden) and keep its pixels."""
        shown = [a.get_visible() for a in self.moving]
        for artist in self.moving:
            artist.set_visible(False)
        self.fig.canvas.draw()
        background = self.fig.canvas.copy_from_bbox(self.fig.bbox)
        for artist, visible in zip(self.moving, shown):
            artist.set_visible(visible)
        return background

    def draw(self, j: int) -> memoryview:
        """Draw sample ``j`` of the world's times; the canvas's RGBA buffer."""
        t = float(self.view.t_s[j])
        for car, track in zip(self.cars, self.view.tracks):
            _place(car, track, j)
        self.hits.set_visible(j == len(self.view.t_s) - 1)
        self.time.set_text(f"t {t:6.2f} s")
        self.cursor.set_xdata([t, t])
        self.fig.canvas.restore_region(self._background)
        for artist in self.moving:
            self.fig.draw_artist(artist)
        return self.fig.canvas.buffer_rgba()

def _place(car: _Car, track: CarTrack, j: int) -> None:
    """Move a car's artists to sample ``j``: its box, outline (its ECU's mode), name and stopping path."""
    x, y, yaw = (float(v) for v in track.box[j])
    body = car.body
    car.box.set_xy(Box(x, y, yaw, body.length_m, body.width_m).corners())
    car.box.set_edgecolor(MODE_COLORS.get(track.mode[j], "black") if track.mode is not None else "black")
    beside = 0.5 * body.width_m + LABEL_GAP_M  # on its left, clear of its path ahead
    car.label.set_position((x - beside * math.sin(yaw), y + beside * math.cos(yaw)))
    curvature, length = track.paths[j] if track.paths is not None else (math.nan, math.nan)
    show = math.isfinite(length) and length > 0.0
    if show:
        car.region.set_xy(stopping_band((x, y, yaw), body, curvature, length))
    car.region.set_visible(show)


def still_index(view: FleetView, at_s: float | None) -> int:
    """The sample the still shows: the last at or before ``at_s`` (None: the end)."""
    if at_s is None:
        return len(view.t_s) - 1
    return max(0, int(np.searchsorted(view.t_s, at_s + 1e-9, side="right")) - 1)


def write_still(view: FleetView, path: Path, at_s: float | None = None, width_px: int = STILL_WIDTH_PX) -> float:
    """``fleet.png``: the video's frame at ``at_s`` (None: the end), ``width_px`` wide; the time it shows."""
    j = still_index(view, at_s)
    with _pyplot().rc_context(FAST_TEXT):
        frame = FleetFrame(view, VideoOptions(width_px=width_px))
        try:
            _pyplot().imsave(path, np.asarray(frame.draw(j)))
        finally:
            _pyplot().close(frame.fig)
    return float(view.t_s[j])


def write_video(view: FleetView, path: Path, options: VideoOptions) -> int:
    """The video of the fleet run at ``path`` (its suffix picks the format); the number of frames."""
    params = video_params(path, options)
    path.parent.mkdir(parents=True, exist_ok=True)
    with _pyplot().rc_context(FAST_TEXT):
        frame = FleetFrame(view, options)
        return encode_frames(frame, frame_indices(view.t_s, options.fps, options.playback), path, options, params)


def animate_fleet(run_dir: Path, video: Path | None, options: VideoOptions, png: bool = True,
                  at_s: float | None = None) -> list[str]:
    """The video ``video`` (None: none) and, with ``png``, ``fleet.png`` at ``at_s`` of a fleet run; the lines
    saying what was written."""
    view = load_fleet_view(run_dir)
    lines = []
    if video is not None:
        count = write_video(view, Path(video), options)
        lines.append(f"{video} ({count} frames, {options.width_px}x{options.height_px}, {options.fps:g} fps)")
    if png:
        still = view.path / STILL_FILE
        lines.append(f"{still} (t = {write_still(view, still, at_s):.2f} s)")
    return lines
