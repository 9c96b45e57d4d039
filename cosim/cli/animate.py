"""``crd animate RUN_DIR``: the bird's-eye video and plot of a written run.

For each strategy of the run (or those named with ``--strategy``) it writes
``<strategy>/birdseye.mp4`` (``--gif``: ``birdseye.gif``) and ``<strategy>/birdseye.png``
in the run directory; ``--out FILE`` names the video when one strategy is drawn, and its
suffix (``.mp4``, ``.gif``) picks the format. What the view reads from the run directory
is documented in ``docs/run-format.md``; runs of today's 1-D world work as they are.

On a fleet run directory (``crd fleet --out``, told by its ``fleet.json``) it writes ``fleet.mp4``
(``--gif``: ``fleet.gif``) and ``fleet.png`` (at ``--at-s``, default the end) showing every car
(:mod:`cosim.fleet.video`).
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
    p.add_argument("run_dir", type=Path, help="output directory of crd run/paper/fleet (--out)")
    p.add_argument("--strategy", action="append", default=None, help="only this strategy (repeatable)")
    p.add_argument("--out", type=Path, default=None, help="the video file (one strategy); .mp4 or .gif")
    p.add_argument("--gif", action="store_true", help="write a GIF instead of an MP4")
    p.add_argument("--fps", type=float, default=None, help="frame rate (default 25 for MP4, 12.5 for GIF)")
    p.add_argument("--width", type=int, default=None, help="width in px, a multiple of 32 (default 1280 MP4, 640 GIF)")
    p.add_argument("--view-m", type=float, default=60.0, help="width of the view that follows the ego (m)")
    p.add_argument("--playback", type=float, default=1.0, help="simulated seconds per video second")
    p.add_argument("--hold-s", type=float, default=1.0, help="hold the last frame this long (s)")
    p.add_argument("--no-png", action="store_true", help="do not write birdseye.png (fleet: fleet.png)")
    p.add_argument("--at-s", type=float, default=None, help="fleet: the time fleet.png shows (default: the end)")
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


def _options(args: argparse.Namespace, video: Path):
    from ..results.birdseye_video import VideoOptions

    fps, width = FORMAT_DEFAULTS.get(video.suffix.lower(), FORMAT_DEFAULTS[".mp4"])
    return VideoOptions(args.fps or fps, args.width or width, args.view_m, args.hold_s, args.playback)


def _animate_fleet(args: argparse.Namespace) -> list[str]:
    """A fleet run directory: ``fleet.mp4`` / ``fleet.gif`` (or ``--out``) and ``fleet.png``."""
    from ..fleet.video import animate_fleet

    if args.strategy:
        raise ConfigError(f"--strategy: {args.run_dir} is a fleet run (every car is drawn; it has no strategies)")
    video = args.out or args.run_dir / ("fleet.gif" if args.gif else "fleet.mp4")
    return animate_fleet(args.run_dir, video, _options(args, video), png=not args.no_png, at_s=args.at_s)


def _animate_run(args: argparse.Namespace) -> list[str]:
    """A run directory: each strategy's video and plot."""
    from ..results.run_view import load_run_view

    view = load_run_view(args.run_dir, args.strategy)
    return [line for strategy, video in _targets(args, list(view.tracks)).items()
            for line in _draw(view, strategy, video, _options(args, video), png=not args.no_png)]


def _do_animate(args: argparse.Namespace) -> int:
    from ..fleet.run_view import is_fleet_dir

    start = time.perf_counter()
    for line in (_animate_fleet if is_fleet_dir(args.run_dir) else _animate_run)(args):
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
