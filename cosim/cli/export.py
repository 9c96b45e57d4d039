"""``crd export RUN_DIR --format mcap [--out FILE] [--strategy S]``: a written run in another format.

Formats (:data:`FORMATS`, a registry):

* ``mcap``: one MCAP file of ROS 2 messages (CAN frames, decoded signals, the ego's odometry
  and transforms, the scene as markers, the events; :mod:`cosim.results.mcap_topics`) that
  Foxglove, ``ros2 bag`` and RViz open; ``docs/foxglove/crd-layout.json`` shows it as the
  paper's figure. Needs the ``mcap`` extra: ``pip install 'crd[mcap]'``.

``RUN_DIR`` is what ``crd run``/``crd paper --out`` wrote; with several runs in it,
``--strategy`` names one. The file goes to ``--out``, by default ``run.mcap`` in the
strategy's directory, beside its ``timeseries.csv``. ``crd run --record FILE`` writes the
same file at the end of the run (:func:`add_record_option`, :func:`record_run`).
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
from dataclasses import dataclass
from pathlib import Path

from ..errors import ConfigError


@dataclass(frozen=True)
class Format:
    """An export format: the function that writes it (module, name), its suffix and its extra."""

    module: str
    function: str
    suffix: str
    extra: str
    needs: tuple[str, ...]  # import names the extra brings


FORMATS = {"mcap": Format("cosim.results.mcap_export", "export_mcap", ".mcap", "mcap", ("mcap", "rosbags"))}


def check_format(name: str, option: str) -> Format:
    """The format, its extra installed; otherwise a :class:`ConfigError` naming ``option``."""
    fmt = FORMATS.get(name)
    if fmt is None:
        raise ConfigError(f"{option}: expected one of {sorted(FORMATS)}, got {name!r}")
    missing = [m for m in fmt.needs if importlib.util.find_spec(m) is None]
    if missing:
        verb = "is" if len(missing) == 1 else "are"
        raise ConfigError(f"{option}: the {name} format needs {' and '.join(missing)}, which {verb} not installed;"
                          f" install the extra: pip install 'crd[{fmt.extra}]'")
    return fmt


def export_run(fmt: Format, run_dir: Path, out: Path | None, strategy: str | None):
    """Write the run with ``fmt``; what its writer returns (``path``, ``counts``)."""
    write = getattr(importlib.import_module(fmt.module), fmt.function)
    if out is None:
        from ..results.run_dir import load_run_dir

        out = run_dir / load_run_dir(run_dir).record(strategy).strategy / f"run{fmt.suffix}"
    return write(run_dir, out, strategy)


def add_subparser(subparsers: argparse._SubParsersAction) -> None:
    p = subparsers.add_parser("export", help="write a run directory in another format (mcap: ROS 2 / Foxglove)")
    p.add_argument("run_dir", type=Path, help="output directory of crd run / crd paper")
    p.add_argument("--format", required=True, choices=sorted(FORMATS), help="mcap: ROS 2 messages for Foxglove, "
                   "ros2 bag and RViz (needs crd[mcap])")
    p.add_argument("--out", type=Path, help="the file (default: run.<format> in the strategy's directory)")
    p.add_argument("--strategy", help="the run to export when the directory holds several")
    p.set_defaults(func=_do_export)


def _do_export(args: argparse.Namespace) -> int:
    fmt = check_format(args.format, "--format")
    written = export_run(fmt, args.run_dir, args.out, args.strategy)
    for topic, count in written.counts.items():
        print(f"{count:8d}  {topic}")
    print(f"{args.format}: {written.path}")
    return 0


# -- crd run --record ---------------------------------------------------------------------------

def add_record_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--record", type=Path, metavar="FILE.mcap",
                        help="also write the run as one MCAP file of ROS 2 messages, as crd export --format mcap "
                             "does (Foxglove, ros2 bag; needs crd[mcap])")


def check_record(args: argparse.Namespace) -> None:
    """Before the run: the extra is installed and the file's directory exists (a ConfigError otherwise)."""
    if args.record is None:
        return
    check_format("mcap", "--record")
    if not args.record.parent.is_dir():
        raise ConfigError(f"--record {args.record}: its directory {args.record.parent} does not exist")


def record_run(args: argparse.Namespace) -> None:
    """After the run: its MCAP file, if ``--record`` asked for one."""
    if args.record is not None:
        written = export_run(FORMATS["mcap"], args.out, args.record, None)
        print(f"recorded: {written.path}")
