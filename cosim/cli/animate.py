"""``crd animate RUN_DIR``: the bird's-eye video and plot of a written run.

For each strategy of the run (or those named with ``--strategy``) it writes
``<strategy>/birdseye.mp4`` (``--gif``: ``birdseye.gif``) and ``<strategy>/birdseye.png``
in the run directory; ``--out FILE`` names the video when one strategy is drawn, and its
suffix (``.mp4``, ``.gif``) picks the format. What the view reads from the run directory
is documented in ``docs/run-format.md``; runs of today's 1-D world work as they are.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from ..errors import ConfigError

#: defaults per format: frame rate (1/s) and width (px); a GIF is made smaller, as GIFs are large
FORMAT_DEFAULTS = {".mp4": (25.0, 1280), ".gif": (12.5, 640)}


def add_subparser(subparsers: argparse._SubParsersAction) -> None:
    p = subparsers.add_parser("animate", help="bird's-eye video (MP4/GIF) and plot of a run directory")
    p.add_argument("run_dir", type=Path, help="output directory of crd run/paper (--out)")
    p.add_argument("--strategy", action="append", default=None, help="only this strategy (repeatable)")
    p.add_argument("--out", type=Path, default=None, help="the video file (one strategy); .mp4 or .gif")
    p.add_argument("--gif", action="store_true", help="write a GIF instead of an MP4")
    p.add_argument("--fps", type=float, default=None, help="frame rate (default 25 for MP4, 12.5 for GIF)")
    p.add_argument("--width", type=int, default=None, help="width in px, a multiple of 32 (default 1280 MP4, 640 GIF)")
    p.add_argument("--view-m", type=float, default=60.0, help="width of the view that follows the ego (m)")
    p.add_argument("--playback", type=float, default=1.0, help="simulated seconds per video second")
    p.add_argument("--hold-s", type=float, default=1.0, help="hold the last frame this long (s)")
    p.add_argument("--no-png", action="store_true", help="do not write birdseye.png")
    p.set_defaults(func=_do_animate)


def _targets(args: argparse.Namespace, strategies: list[str]) -> dict[str, Path]:
    """strategy -> video path."""
    suffix = ".gif" if args.gif else ".mp4"
    if args.out is None:
        return {s: args.run_dir / s / f"birdseye{suffix}" for s in strategies}
    if len(strategies) != 1:
        raise ConfigError(f"--out: names one video, but {len(strategies)} strategies are drawn ({strategies});"
                          " choose one with --strategy")
    return {strategies[0]: args.out}


def _do_animate(args: argparse.Namespace) -> int:
    from ..results.birdseye_video import VideoOptions
    from ..results.run_view import load_run_view

    start = time.perf_counter()
    view = load_run_view(args.run_dir, args.strategy)
    for strategy, video in _targets(args, list(view.tracks)).items():
        fps, width = FORMAT_DEFAULTS.get(video.suffix.lower(), FORMAT_DEFAULTS[".mp4"])
        options = VideoOptions(args.fps or fps, args.width or width, args.view_m, args.hold_s, args.playback)
        for line in _draw(view, strategy, video, options, png=not args.no_png):
            print(line)
    print(f"done in {time.perf_counter() - start:.1f} s")
    return 0


def _draw(view, strategy: str, video: Path | None, options, png: bool) -> list[str]:
    """One strategy's video (None: none) and plot; the lines saying what was written."""
    from ..results.birdseye import plot_birdseye
    from ..results.birdseye_video import render_video

    lines = []
    if video is not None:
        video.parent.mkdir(parents=True, exist_ok=True)
        frames = render_video(view, strategy, video, options)
        lines.append(f"{strategy}: {video} ({frames} frames, {options.width_px}x{options.height_px}, "
                     f"{options.fps:g} fps)")
    if png:
        lines.append(f"{strategy}: {plot_birdseye(view, strategy, view.path / strategy / 'birdseye.png')}")
    return lines


def write_video(run_dir: Path, strategies: list[str]) -> list[str]:
    """``crd run --video``: each strategy's ``birdseye.mp4`` as ``crd animate`` makes it by default, and its
    ``birdseye.png`` where the run has none yet (a planar run has drawn it already; a 1-D run has not)."""
    from ..results.birdseye_video import VideoOptions
    from ..results.run_view import load_run_view

    view = load_run_view(run_dir, strategies)
    options = VideoOptions(*FORMAT_DEFAULTS[".mp4"])
    return [line for s in strategies for line in
            _draw(view, s, run_dir / s / "birdseye.mp4", options, png=not (run_dir / s / "birdseye.png").is_file())]
