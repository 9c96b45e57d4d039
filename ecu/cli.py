"""``crd ecu``: run the ECU as a standalone process on any python-can interface.

``crd ecu --interface virtual --channel vcan0 --strategy tightening``
opens the bus, runs :meth:`ecu.EcuNode.run` (real time, or paced by SimClock
frames with ``--sim-time``) until SIGINT or SIGTERM sets the stop event,
shuts the bus down and prints a one-line summary of the run.

:func:`main` is the same command without the ``crd`` dispatcher, for
``python -m ecu`` (:mod:`ecu.__main__`): the same arguments, output, errors
(one line, ``error: ...``, exit 1; ``--debug`` shows the traceback) and exit codes.
"""

from __future__ import annotations

import argparse
import dataclasses
import logging
import signal
import sys
import threading

import can

from can_dbc.contract import STRATEGIES

from .config import EcuConfig
from .node import EcuNode

#: exit status of a run that saw frames failing authentication or a foreign SafetyOverride
EXIT_SECURITY = 4

_HELP = "run the active-safety ECU on a CAN interface"


def add_subparser(subparsers: argparse._SubParsersAction) -> None:
    _add_arguments(subparsers.add_parser("ecu", help=_HELP))


def main(argv: list[str]) -> int:
    """``crd ecu`` as a program of its own (``python -m ecu ARGS``); returns the exit code."""
    parser = argparse.ArgumentParser(prog="python -m ecu", description=f"{_HELP} (as crd ecu).")
    parser.add_argument("--debug", action="store_true", help="show tracebacks and debug logging")
    _add_arguments(parser)
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.DEBUG if args.debug else logging.WARNING,
                        format="%(levelname)s %(name)s: %(message)s")
    try:
        return int(args.func(args))
    except KeyboardInterrupt:  # before the run installs its own SIGINT handler
        print("interrupted", file=sys.stderr)
        return 128 + signal.SIGINT
    except Exception as exc:  # noqa: BLE001 - the CLI boundary turns every error into one line
        if args.debug:
            raise
        print(f"error: {exc}", file=sys.stderr)
        return 1


def _add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--interface", required=True, help="python-can interface (virtual, socketcan, ...)")
    parser.add_argument("--channel", required=True, help="channel of the interface")
    parser.add_argument("--strategy", choices=sorted(STRATEGIES), help="override the config's strategy")
    parser.add_argument("--config", help="TOML file with the ECU settings (top level or [ecu])")
    parser.add_argument("--sim-time", action="store_true", help="one cycle per SimClock frame")
    parser.add_argument("--key-file", help="SecOC key file (32 hex digits, mode 0600): authenticate inputs "
                        "and SafetyOverride (default: the config's key_file; none: E2E protection only)")
    parser.add_argument("--bitrate", type=int, help="bus bitrate in bit/s, for interfaces that take one")
    parser.set_defaults(func=_do_ecu)


def _config(args: argparse.Namespace) -> EcuConfig:
    config = EcuConfig.from_toml(args.config) if args.config else EcuConfig()
    changes = {}
    if args.strategy:
        changes["strategy"] = args.strategy
    if args.sim_time:
        changes["sim_time"] = True
    if args.key_file:
        changes["key_file"] = args.key_file
    return dataclasses.replace(config, **changes) if changes else config


def _do_ecu(args: argparse.Namespace) -> int:
    config = _config(args)
    stop = threading.Event()
    previous = {sig: signal.signal(sig, lambda *_: stop.set()) for sig in (signal.SIGINT, signal.SIGTERM)}
    bus_kwargs = {"bitrate": args.bitrate} if args.bitrate else {}
    try:
        with can.Bus(interface=args.interface, channel=args.channel, **bus_kwargs) as bus:
            node = EcuNode(bus, config)
            report = node.run(stop)
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
    stats = node.stats
    auth_failures = stats.get("AuthError", 0) + stats.get("FreshnessError", 0)
    rejected = sum(v for k, v in stats.items() if k == "UnknownFrame" or k.endswith("Error"))
    print(f"ecu {config.strategy}: final mode {node.mode}; {report.summary()}; "
          f"frames good {stats.get('good', 0)}, rejected {rejected}, "
          f"gate interventions {stats['gate_interventions']}"
          + (f"; authenticated {stats.get('authenticated', 0)}, authentication failures {auth_failures}"
             if node.authenticated else "")
          + (f"; clock errors {stats['clock_errors']}" if stats.get("clock_errors") else "")
          + (f"; foreign SafetyOverride frames {stats['foreign_overrides']}" if stats.get("foreign_overrides") else ""))
    return EXIT_SECURITY if auth_failures or stats.get("foreign_overrides") else 0
