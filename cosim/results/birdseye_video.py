"""The bird's-eye video of a run (``crd animate``): MP4 or GIF through the ffmpeg of ``imageio-ffmpeg``.

One figure is built once: the road, the paths, the ego's and the objects' boxes, the ECU's
stopping path (1-D: a rectangle of the ego's width ahead of the front bumper, ``stopping_m``
long; planar: the reported polygon), the time, speed and ECU mode, and a strip of the speed
over time. Each frame only moves these artists (``set_xy``, ``set_data``, the camera's limits)
and draws the canvas; its RGBA buffer goes straight into ffmpeg's pipe, with no copy to disk.
Frames are taken at the video's rate from the time series (the sample at or before each frame
time), and the last frame is held ``hold_s`` so that the end, a collision, can be seen.

The writer is chosen by the output's suffix (:data:`VIDEO_FORMATS`): ``.mp4`` is H.264
(yuv420p, plays everywhere), ``.gif`` a palette GIF (``palettegen``/``paletteuse`` in one pass).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from ..errors import ConfigError
from .birdseye import (
    COLLISION_COLOR, EGO_COLOR, STOPPING_COLOR, box_patch, draw_road, object_color, set_view, speed_line,
)
from .plots import _pyplot
from .run_view import RunView, StrategyTrack, body_box

#: ECU mode (DBC names) -> colour of its label
MODE_COLORS = {"STANDBY": "tab:green", "TIGHTENING": "tab:orange", "CONTINGENCY": "crimson", "FAULT": "tab:gray"}


#: the figure's size in inches; the pixel width sets its dpi, so every size has the same layout
FIGURE_IN = (12.8, 7.2)


@dataclass(frozen=True)
class VideoOptions:
    """Frame rate (1/s), width (px; the height is 9/16 of it), width of the view that follows the ego (m),
    end hold (s), playback speed (simulated seconds per video second)."""

    fps: float = 25.0
    width_px: int = 1280
    view_m: float = 60.0
    hold_s: float = 1.0
    playback: float = 1.0

    def __post_init__(self) -> None:
        if not (self.fps > 0 and self.view_m > 0 and self.hold_s >= 0 and self.playback > 0):
            raise ConfigError(f"video: expected fps, view_m, playback > 0 and hold_s >= 0, got {self}")
        if self.width_px % 32 or not 320 <= self.width_px <= 3840:
            raise ConfigError(f"video: expected a width of 320..3840 px in steps of 32, got {self.width_px}")

    @property
    def height_px(self) -> int:
        return self.width_px * 9 // 16


def _mp4(fps: float) -> dict:
    # x264's ultrafast preset: 8 instead of 12.8 ms of CPU a 720p frame (veryfast), files 3.5x larger (about
    # 1 MB for 15 s of these flat drawings); so ffmpeg, in its own process, keeps ahead of the drawing
    return {"codec": "libx264", "pix_fmt_out": "yuv420p", "quality": 6, "fps": fps,
            "output_params": ["-preset", "ultrafast"]}


def _gif(fps: float) -> dict:
    return {"codec": "gif", "pix_fmt_out": "pal8", "quality": None, "fps": fps,
            "output_params": ["-filter_complex", "split[a][b];[a]palettegen=stats_mode=diff[p];[b][p]paletteuse"]}


#: output suffix -> ffmpeg writer parameters for imageio_ffmpeg.write_frames
VIDEO_FORMATS = {".mp4": _mp4, ".gif": _gif}


def frame_indices(t_s: np.ndarray, fps: float, playback: float = 1.0) -> np.ndarray:
    """The sample index shown in each frame: frame ``j`` shows time ``t0 + j * playback / fps`` (the sample at or
    before it), up to the last sample."""
    count = int(math.floor((t_s[-1] - t_s[0]) * fps / playback + 1e-9)) + 1
    times = t_s[0] + np.arange(count) * (playback / fps)
    return np.clip(np.searchsorted(t_s, times + 1e-9, side="right") - 1, 0, len(t_s) - 1)


class _Frame:
    """The figure and the artists a frame moves.

    Drawing every text of a figure costs most of a frame (ticks, labels, legend: ~90 texts, ~0.3 s). So
    the figure is drawn once without the view that follows the ego and without the changing texts, and
    kept (``copy_from_bbox``); each frame restores it and draws only the view (ticks hidden: a scale bar
    gives the metres) and the few changing artists.
    """

    def __init__(self, view: RunView, track: StrategyTrack, options: VideoOptions) -> None:
        plt = _pyplot()
        self.view, self.track, self.options = view, track, options
        self.fig = plt.figure(figsize=FIGURE_IN, dpi=options.width_px / FIGURE_IN[0])
        self.ax = self.fig.add_axes((0.02, 0.31, 0.66, 0.60))
        self._static()
        self.ego = box_patch(self.ax, view.ego, EGO_COLOR, zorder=5, label="ego")
        self.objects = [box_patch(self.ax, b, object_color(b), zorder=5, label=f"{b.name} ({b.kind})")
                        for b in view.objects]
        self.stopping = box_patch(self.ax, view.ego, STOPPING_COLOR, alpha=0.35, zorder=4, label="ECU stopping path")
        self.stopping.set_visible(False)
        hit = track.collision
        self.hit = self.ax.plot([] if hit is None else [hit.x_m], [] if hit is None else [hit.y_m], marker="X", ms=14,
                                color=COLLISION_COLOR, ls="none", zorder=7, label="collision")[0]
        self.hit.set_visible(False)
        self._panel()
        self._background = self._keep_background()

    def _static(self) -> None:
        view, track, ax = self.view, self.track, self.ax
        draw_road(ax, view.road, step_m=1.0)
        vmax = max(1.0, float(np.nanmax(track.speed_mps)))
        bar = self.fig.colorbar(speed_line(ax, track.ego[:, :2], track.speed_mps, vmax, max_segments=150),
                                cax=self.fig.add_axes((0.69, 0.31, 0.010, 0.60)))
        bar.set_label("ego speed (m/s)")
        for body, poses in zip(view.objects, track.objects):
            ax.plot(poses[:, 0], poses[:, 1], color=object_color(body), lw=1.2, ls=":", zorder=2)
        ax.set_xticks([])
        ax.set_yticks([])
        ax.set_aspect("auto")
        scale_bar(self.fig, ax, self.options.view_m)
        self.fig.text(0.02, 0.94, f"{view.path.name}: {track.strategy} (bird's-eye view, x right, y up)", fontsize=12)
        strip = self.fig.add_axes((0.06, 0.07, 0.62, 0.16))
        strip.plot(track.t_s, track.speed_mps * 3.6, color=EGO_COLOR, lw=1.2)
        strip.set_xlim(track.t_s[0], track.t_s[-1])
        strip.set_ylim(0.0, max(10.0, float(np.nanmax(track.speed_mps)) * 3.6 * 1.1))
        strip.set_xlabel("time (s)")
        strip.set_ylabel("speed (km/h)")
        strip.set_title("ego speed; shaded where the ECU is not in STANDBY, in its mode's colour", fontsize=9, loc="left")
        _shade_modes(strip, track)
        self.strip = strip
        self.cursor = strip.axvline(track.t_s[0], color="black", lw=1.0)

    def _panel(self) -> None:
        fig = self.fig
        # few changing texts: each costs 2-3 ms a frame to lay out and render, whatever its length
        self.state = fig.text(0.765, 0.86, "", fontsize=12, family="monospace")
        self.mode = fig.text(0.765, 0.80, "", fontsize=12, family="monospace", weight="bold")
        self.stop_text = fig.text(0.765, 0.74, "", fontsize=11, family="monospace")
        handles = [Patch(facecolor=p.get_facecolor(), edgecolor="black", label=p.get_label())
                   for p in (self.ego, *self.objects, self.stopping)]
        handles.append(Line2D([], [], marker="X", ms=10, color=COLLISION_COLOR, ls="none", label="collision"))
        fig.legend(handles=handles, loc="upper left", bbox_to_anchor=(0.76, 0.68), fontsize=9, frameon=False)

    def _changing(self) -> list:
        return [self.state, self.mode, self.stop_text, self.cursor]

    def _keep_background(self):
        """Draw everything that stays (the view hidden, the changing artists left out) and keep its pixels."""
        for artist in (self.ax, *self._changing()):
            artist.set_visible(False)
        self.fig.canvas.draw()
        background = self.fig.canvas.copy_from_bbox(self.fig.bbox)
        for artist in (self.ax, *self._changing()):
            artist.set_visible(True)
        return background

    def draw(self, j: int) -> memoryview:
        """Draw sample ``j``; the canvas's RGBA buffer."""
        view, track = self.view, self.track
        x, y, yaw = track.ego[j]
        ego_box = body_box(view.ego, x, y, yaw)
        self.ego.set_xy(ego_box.corners())
        for patch, body, poses in zip(self.objects, view.objects, track.objects):
            patch.set_xy(body_box(body, *poses[j]).corners())
        self._stopping(j, ego_box)
        t = track.t_s[j]
        self.hit.set_visible(track.collision is not None and j == len(track.t_s) - 1)
        ahead = 0.25 * self.options.view_m
        set_view(self.ax, x + ahead * math.cos(yaw), y + ahead * math.sin(yaw), self.options.view_m)
        self.cursor.set_xdata([t, t])
        self.state.set_text(f"t {t:6.2f} s  v {track.speed_mps[j] * 3.6:5.1f} km/h")
        mode = track.mode[j] if track.mode is not None else "n/a"
        self.mode.set_text(f"ECU {mode}")
        self.mode.set_color(MODE_COLORS.get(mode, "black"))
        canvas = self.fig.canvas
        canvas.restore_region(self._background)
        self.fig.draw_artist(self.ax)
        for artist in self._changing()[:-1]:
            self.fig.draw_artist(artist)
        self.strip.draw_artist(self.cursor)
        return canvas.buffer_rgba()

    def _stopping(self, j: int, ego_box) -> None:
        track = self.track
        if track.regions is not None:
            times, polygons = track.regions
            i = int(np.searchsorted(times, track.t_s[j] + 1e-9, side="right")) - 1
            show = i >= 0 and len(polygons[i]) >= 3
            if show:
                self.stopping.set_xy(polygons[i])
            self.stopping.set_visible(show)
            label = track.region_labels[i] if show and track.region_labels is not None else "stopping region"
            self.stop_text.set_text(label if show else "")
            return
        d = np.nan if track.stopping_m is None else float(track.stopping_m[j])
        show = math.isfinite(d) and d > 0.0
        if show:
            (ux, uy), (nx, ny) = ego_box.axes()
            fx, fy = ego_box.x_m + ux * ego_box.length_m / 2, ego_box.y_m + uy * ego_box.length_m / 2
            hw = ego_box.width_m / 2
            self.stopping.set_xy([(fx + nx * hw, fy + ny * hw), (fx - nx * hw, fy - ny * hw),
                                  (fx + ux * d - nx * hw, fy + uy * d - ny * hw), (fx + ux * d + nx * hw, fy + uy * d + ny * hw)])
        self.stopping.set_visible(show)
        self.stop_text.set_text(f"stop path {d:5.1f} m" if math.isfinite(d) else "")


def _shade_modes(ax, track: StrategyTrack) -> None:
    """Shade the strip where the ECU was in a mode other than STANDBY, in the mode's colour."""
    if track.mode is None:
        return
    modes, start = track.mode, 0
    for j in range(1, len(modes) + 1):
        if j == len(modes) or modes[j] != modes[start]:
            if modes[start] != "STANDBY":
                ax.axvspan(track.t_s[start], track.t_s[min(j, len(modes) - 1)], color=MODE_COLORS.get(modes[start],
                           "tab:gray"), alpha=0.15, lw=0)
            start = j


def scale_bar(fig, ax, view_m: float) -> None:
    """A bar of a round number of metres (about a sixth of the view) under the view's lower left corner.

    Drawn once with the figure: the view is always ``view_m`` wide (:func:`set_view`), so a metre is always
    as many pixels."""
    length = min((1, 2, 5, 10, 20, 50, 100), key=lambda m: abs(m - view_m / 6.0))
    pos = ax.get_position()
    x0, y = pos.x0 + 0.01, pos.y0 - 0.025
    x1 = x0 + pos.width * length / view_m
    fig.add_artist(Line2D([x0, x1], [y, y], transform=fig.transFigure, color="black", lw=3, solid_capstyle="butt"))
    fig.text(x1 + 0.008, y, f"{length} m", va="center", fontsize=10)


def video_params(path: Path, options: VideoOptions) -> dict:
    """The ffmpeg writer parameters of the format ``path``'s suffix picks (:data:`VIDEO_FORMATS`)."""
    make = VIDEO_FORMATS.get(Path(path).suffix.lower())
    if make is None:
        raise ConfigError(f"{path}: expected a video suffix in {sorted(VIDEO_FORMATS)}, got {path.suffix or 'none'!r}")
    return make(options.fps)


def render_video(view: RunView, strategy: str, path: Path, options: VideoOptions = VideoOptions()) -> int:
    """Write the video of one strategy's run to ``path`` (its suffix picks the format); the number of frames."""
    path = Path(path)
    params = video_params(path, options)
    track = view.tracks[strategy]
    with _pyplot().rc_context(FAST_TEXT):
        frame = _Frame(view, track, options)
        return encode_frames(frame, frame_indices(track.t_s, options.fps, options.playback), path, options, params)


#: text without hinting: half the cost of each changing text, which is most of a frame (a video needs no hinting)
FAST_TEXT = {"text.hinting": "none"}


class FrameDrawer(Protocol):
    """A figure built once whose ``draw(j)`` moves its artists to sample ``j`` and gives the canvas's RGBA buffer."""

    fig: Figure

    def draw(self, j: int) -> memoryview: ...


def encode_frames(frame: FrameDrawer, indices: np.ndarray, path: Path, options: VideoOptions, params: dict) -> int:
    """Draw the samples ``indices`` into ffmpeg's pipe, then hold the last ``options.hold_s``; the number of frames.
    Closes the figure."""
    import imageio_ffmpeg

    writer = imageio_ffmpeg.write_frames(str(path), (options.width_px, options.height_px), pix_fmt_in="rgba",
                                         macro_block_size=2, ffmpeg_log_level="error", **params)
    writer.send(None)  # start ffmpeg
    count = 0
    try:
        for j in indices.tolist():
            last = frame.draw(j)
            writer.send(last)
            count += 1
        for _ in range(int(round(options.hold_s * options.fps))):
            writer.send(last)
            count += 1
    finally:
        writer.close()
        _pyplot().close(frame.fig)
    return count
