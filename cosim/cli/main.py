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
import importlib
import logging
import os
import sys

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
    "export": "cosim.cli.export",
    "sweep": "cosim.cli.sweep",
    "animate": "cosim.cli.animate",
    "fleet": "cosim.cli.fleet",
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
    ``import can`` whenever it is installed (the ``crd[mdf]`` and ``crd[test]``
    extras), although only MF4 files need it. Marking it absent before ``can`` is
    imported (``None`` in :data:`sys.modules`: the import system's documented way to
    say "not installed") keeps every other command, and each spawned ``crd ecu``, as
    quick to start as without the extra. Only the ``crd`` command does this, never an
    in-process call. Measured (issue 20): ``import can`` 0.09 s instead of 0.55 s;
    ``crd paper`` 4.46 s instead of 5.63 s wall, 4.20 s instead of 5.22 s CPU
    (medians of 9 alternating runs on the shared 2-core machine): 21 % of its time.
    """
    if "can" not in sys.modules and not any(a.lower().endswith(".mf4") for a in argv):
        sys.modules.setdefault("asammdf", None)


def _exit_quickly() -> None:
    """The ``crd`` command is about to exit: freeze every object it holds (:func:`gc.freeze`), so that the
    interpreter's last collections, as it shuts down, skip them (the OS takes the memory back whole).
    Those collections walk every object matplotlib, numpy, fmpy and crd made, on one core after the
    command's last figure. Measured (issue 20, ``crd paper``, CPU of all its processes, medians of 3
    alternating rounds at load average 25-29): 8.09 s without, 7.15 s with the freeze (-12 %); the
    shutdown alone, after ``main`` returned: 0.46 s of CPU without, 0.07 s with (medians of 4). Only the
    ``crd`` command does this, never a call in process (there the objects live on)."""
    import gc

    gc.freeze()


def main(argv: list[str] | None = None) -> int:
    if argv is None:  # the crd command, not a call in process
        _hide_unused_asammdf(sys.argv[1:])
        try:
            return _main(sys.argv[1:])
        finally:
            _exit_quickly()
    return _main(argv)


def _main(argv: list[str]) -> int:
    argv = list(argv)
    parser = _build_parser(argv)
    args = parser.parse_args(argv)
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
