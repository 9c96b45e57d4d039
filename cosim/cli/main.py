"""The ``crd`` command: one dispatcher, one module per subcommand.

Each subcommand module exposes ``add_subparser(subparsers)``, which registers
its parser and sets ``func`` to its ``_do_<cmd>(args) -> int`` handler. Modules
are imported lazily from the table below, so ``crd ecu`` never loads fmpy and
``crd fmu`` never loads the ECU.

Errors become a one-line ``error: ...`` on stderr and exit code 1; ``--debug``
shows the traceback instead. An interrupt exits ``128 + signal`` (130 SIGINT,
143 SIGTERM; ``crd run``/``crd paper`` write their results so far first, see
:mod:`cosim.cli.signals`).
"""

from __future__ import annotations

import argparse
import atexit
import importlib
import logging
import os
import sys
import threading
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..results.plot_worker import PlotWorker

# numpy's OpenBLAS starts a thread per core on import (50 ms of CPU, and a thread in every
# process crd forks); crd's arrays are small, so one thread does. Set before numpy is imported;
# a value in the environment wins.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

#: subcommand name -> module that implements it (imported on demand).
SUBCOMMANDS: dict[str, str] = {
    "dbc": "can_dbc.cli",
    "fmu": "fmu_plant.cli",
    "ecu": "ecu.cli",
    "run": "cosim.cli.run",
    "paper": "cosim.cli.paper",
    "matrix": "cosim.cli.matrix",
    "scenarios": "cosim.cli.scenarios",
    "compare": "cosim.cli.compare",
    "sweep": "cosim.cli.sweep",
    "animate": "cosim.cli.animate",
}


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return f"crd {version('crd')}"
    except PackageNotFoundError:
        return "crd (version unknown: not installed)"


class _VersionAction(argparse.Action):
    """``--version``: the installed version, looked up only when asked (reading the metadata costs 10 ms)."""

    def __init__(self, option_strings: list[str], dest: str = argparse.SUPPRESS, **kwargs) -> None:
        super().__init__(option_strings, dest, nargs=0, default=argparse.SUPPRESS, help="show the version and exit")

    def __call__(self, parser, namespace, values, option_string=None) -> None:
        print(_version())
        parser.exit()


def _build_parser(argv: list[str]) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="crd",
        description="Colliding reciprocal dance: FMI co-simulation and CAN active-safety ECU.",
    )
    parser.add_argument("--debug", action="store_true", help="show tracebacks and debug logging")
    parser.add_argument("--version", action=_VersionAction)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    wanted = next((a for a in argv if a in SUBCOMMANDS), None)
    for name, module_name in SUBCOMMANDS.items():
        if wanted is not None and name != wanted:
            sub.add_parser(name, help=f"(see crd {name} --help)")
            continue
        try:
            module = importlib.import_module(module_name)
        except ModuleNotFoundError as exc:
            if exc.name != module_name:
                raise
            continue  # subcommand not built yet
        module.add_subparser(sub)
    return parser


def _hide_unused_asammdf(argv: list[str]) -> None:
    """Start without asammdf unless a ``.mf4`` file is named.

    python-can imports asammdf (and with it pandas: about 1 s and 60 MB) on
    ``import can`` whenever it is installed (the ``crd[mdf]`` extra), although
    only MF4 files need it. Marking it absent before ``can`` is imported keeps
    every other command, and each spawned ``crd ecu``, as quick to start as
    without the extra. Only the ``crd`` command does this, never an in-process call.
    """
    if "can" not in sys.modules and not any(a.lower().endswith(".mf4") for a in argv):
        sys.modules.setdefault("asammdf", None)


def _start_ahead(argv: list[str]) -> PlotWorker | None:
    """Work started before the subcommand's modules are imported: ``crd paper``'s plot worker
    (:func:`cosim.cli.paper.plot_worker_ahead`), or None."""
    wanted = next((a for a in argv if a in SUBCOMMANDS), None)
    if wanted != "paper":
        return None
    from .paper import plot_worker_ahead

    return plot_worker_ahead(argv)


def _exit_without_teardown(code: int) -> None:
    """End the ``crd`` command now: the exit handlers run and the output is flushed, as at any exit,
    but the interpreter's teardown is skipped. Freeing the objects of crd's ~500 modules one by one
    costs about 0.1 s of CPU, and it is the last thing ``crd paper`` waits for (every file is closed
    by then). Not while another thread runs (the interpreter would wait for it): then it returns."""
    if threading.active_count() > 1:
        return
    atexit._run_exitfuncs()  # what the interpreter's exit runs first (logging's flush, multiprocessing's)
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except (OSError, ValueError):
        return  # a closed pipe: the interpreter reports it as usual
    os._exit(code)


def main(argv: list[str] | None = None) -> int:
    command = argv is None  # the crd command, not a call in process
    if command:
        _hide_unused_asammdf(sys.argv[1:])
    argv = list(sys.argv[1:] if argv is None else argv)
    plot_worker = _start_ahead(argv)
    try:
        code = _main(argv, plot_worker)
    finally:
        if plot_worker is not None:
            plot_worker.stop()  # unused (an error before the runs, or they ran one after the other)
    if command:
        _exit_without_teardown(code)
    return code


def _main(argv: list[str], plot_worker: PlotWorker | None) -> int:
    parser = _build_parser(argv)
    args = parser.parse_args(argv)
    if plot_worker is not None:
        args.plot_worker = plot_worker
    logging.basicConfig(
        level=logging.DEBUG if args.debug else logging.WARNING,
        format="%(levelname)s %(name)s: %(message)s",
    )
    try:
        return int(args.func(args) or 0)
    except KeyboardInterrupt as exc:  # SIGINT, or SIGTERM under cosim.cli.signals: 130 / 143
        from ..errors import interrupt_signal  # here: importing it early would import python-can first
        print(f"interrupted: {exc}" if str(exc) else "interrupted", file=sys.stderr)
        return 128 + interrupt_signal(exc)
    except Exception as exc:  # noqa: BLE001 - the CLI boundary turns every error into one line
        if args.debug:
            raise
        print(f"error: {exc}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
