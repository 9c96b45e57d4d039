"""``crd sweep``: scenario and fleet sweeps, and Monte Carlo, on Dask.

::

    crd sweep SWEEP [--workers N] [--scheduler ADDRESS] [--out DIR] [--resume] [--keep-timeseries]
    crd sweep --list
    crd sweep report DIR [--axes X Y]

``SWEEP`` is a sweep TOML file or the name of a bundled sweep. Writes
``DIR/results.parquet`` (one row per run, incrementally), ``DIR/report.md`` and
``DIR/maps/*.png``. Exit status 0 when the sweep ran to the end (failed runs are
rows with their error, counted in the summary), 1 on an error.
"""

from __future__ import annotations

import argparse
import logging
import sys
import time
from pathlib import Path
from typing import Any

from ..errors import ConfigError


class ProgressBar:
    """Runs done, rate, ETA and failures on stderr, with the dashboard address above.

    On a terminal a tqdm bar; otherwise (a log file, CI) the same line, newline-terminated,
    every 10 s and at the end, never a carriage-return soup.
    """

    def __init__(self, header: str) -> None:
        self._header = header
        self._bar = None
        self._failed = 0
        self._tty = sys.stderr.isatty()
        self._last = 0.0

    def start(self, total: int, already: int, dashboard: str | None, note: str) -> None:
        from tqdm import tqdm

        print(self._header, file=sys.stderr)
        print(note, file=sys.stderr)
        if already:
            print(f"resuming: {already} of {total} runs already in the table", file=sys.stderr)
        self._bar = tqdm(total=total, initial=already, unit="run", file=sys.stderr, dynamic_ncols=True,
                         disable=not self._tty)
        self._total, self._done, self._t0 = total, already, time.monotonic()
        self._already = already

    def advance(self, row: dict[str, Any]) -> None:
        self._done += 1
        if row["status"] != "ok":
            self._failed += 1
            self._bar.set_postfix(failed=self._failed, refresh=False)
        self._bar.update(1)
        if not self._tty and (time.monotonic() - self._last >= 10.0 or self._done == self._total):
            self._last = time.monotonic()
            self._line()

    def _line(self) -> None:
        from tqdm import tqdm

        meter = tqdm.format_meter(self._done - self._already, self._total - self._already,
                                  time.monotonic() - self._t0, unit="run", ascii=True)
        print(f"{meter}, {self._failed} failed", file=sys.stderr, flush=True)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()


def add_subparser(subparsers: argparse._SubParsersAction) -> None:
    p = subparsers.add_parser("sweep", help="run a scenario sweep / Monte Carlo on Dask (or: sweep --list, "
                                            "sweep report DIR)")
    p.add_argument("target", nargs="*", metavar="SWEEP | report DIR",
                   help="a sweep TOML file or bundled sweep name; or 'report DIR' to redraw a report")
    p.add_argument("--list", action="store_true", help="list the bundled sweeps")
    p.add_argument("--workers", type=int, help="local worker processes (default: one per core)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="attach to an existing Dask scheduler (tcp://host:port)")
    p.add_argument("--out", type=Path, help="output directory (default out/sweep/<name>)")
    p.add_argument("--resume", action="store_true", help="skip runs already in DIR/results.parquet")
    p.add_argument("--keep-timeseries", action="store_true", help="also write DIR/timeseries/<run_key>.parquet")
    p.add_argument("--axes", nargs=2, metavar=("X", "Y"), help="report: draw the maps over these two axes only")
    p.set_defaults(func=_do_sweep)


def _do_list() -> int:
    from ..sweep.spec import bundled_sweeps, load_sweep

    for name, path in bundled_sweeps().items():
        spec = load_sweep(path)
        print(f"{name:<24} {spec.mode:<14} {spec.description.splitlines()[0] if spec.description else ''}")
    return 0


def _do_report(out_dir: Path, axes: list[str] | None) -> int:
    from ..sweep.report import write_report

    path = write_report(out_dir, [tuple(axes)] if axes else None)
    print(f"wrote {path}")
    return 0


def _summary(plan, outcome, out_dir: Path) -> None:
    from ..sweep.report import summary_table
    from ..sweep.table import read_results

    table, meta = read_results(out_dir / "results.parquet")
    print("\n".join(summary_table(table.to_pylist(), meta)))
    rate = outcome.done / outcome.wall_s if outcome.wall_s else 0.0
    print(f"\n{len(plan.runs)} runs: {outcome.done} run now ({outcome.failed} failed), {outcome.skipped} resumed; "
          f"{outcome.wall_s:.1f} s wall, {rate:.1f} runs/s")
    print(f"results: {out_dir / 'results.parquet'}\nreport:  {out_dir / 'report.md'}")


def _do_sweep(args: argparse.Namespace) -> int:
    if args.list:
        return _do_list()
    if not args.target:
        raise ConfigError("crd sweep: expected a sweep file or bundled name (or --list, or report DIR)")
    if args.target[0] == "report":
        if len(args.target) != 2:
            raise ConfigError("crd sweep report: expected one directory, e.g. crd sweep report out/sweep/x")
        return _do_report(Path(args.target[1]), args.axes)
    if len(args.target) != 1:
        raise ConfigError(f"crd sweep: expected one sweep, got {args.target}")
    if args.workers is not None and args.workers < 1:
        raise ConfigError(f"--workers: expected >= 1, got {args.workers}")
    from ..sweep.runner import ClusterOptions
    from ..sweep.session import run_sweep
    from ..sweep.spec import load_sweep

    if not args.debug:  # Dask logs every worker start and stop at INFO (its logging is set up on import)
        logging.getLogger("distributed").setLevel(logging.WARNING)

    spec = load_sweep(args.target[0])
    out_dir = args.out or Path("out/sweep") / spec.name
    where = args.scheduler or f"{args.workers or 'one per core'} local worker(s) on 127.0.0.1"
    header = f"crd sweep {spec.name} ({spec.mode}) on {where} -> {out_dir}"
    plan, outcome = run_sweep(spec, out_dir, ClusterOptions(args.workers, args.scheduler), args.resume,
                              args.keep_timeseries, ProgressBar(header))
    _summary(plan, outcome, out_dir)
    return 0
