"""``crd ecu``: run the ECU as a standalone process on any python-can interface.

``crd ecu --interface virtual --channel vcan0 --strategy tightening``
opens the bus, prints a ready line (the bus, the strategy, the software
version and the settings digest it announces in ``EcuIdentity``) and serves
runs one after the other until SIGINT or SIGTERM sets the stop event (issue
25): each run by a fresh :class:`ecu.EcuNode` (real time, or paced by
SimClock frames with ``--sim-time``), so each starts from a clean state; a run
is over when its master has left the bus (:class:`ecu.scheduler.RunBoundary`),
and a one-line summary of it is printed then. At the end it shuts the bus down.
``--config`` takes an ECU settings file or a scenario file, whose ``[ecu]`` it
reads. Exit 4 if any run saw frames failing authentication or a foreign
``SafetyOverride``.

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
from .config_digest import SOFTWARE_VERSION, announced_digest, version_text
from .node import EcuNode
from .scheduler import RunBoundary

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
    parser.add_argument("--config", help="TOML file with the ECU settings (top level or [ecu]; a scenario file's "
                        "[ecu])")
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
            print(_ready_line(args, config), flush=True)
            return _serve(bus, config, stop)
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


def _ready_line(args: argparse.Namespace, config: EcuConfig) -> str:
    pacing = "sim time (one cycle per SimClock)" if config.sim_time else "real time"
    return (f"ecu ready on {args.interface} {args.channel}: strategy {config.strategy}, crd "
            f"{version_text(SOFTWARE_VERSION)}, config digest 0x{announced_digest(config):08x}, {pacing}, "
            f"{'SecOC' if config.key_file else 'E2E protection only'}; serving runs one after the other "
            "until SIGINT or SIGTERM")


def _serve(bus: can.BusABC, config: EcuConfig, stop: threading.Event) -> int:
    """Runs, each by a fresh node, until ``stop``; the exit code (EXIT_SECURITY after a security finding)."""
    served, security, node, report = 0, False, None, None
    while not stop.is_set():
        node = EcuNode(bus, config, standalone=True)
        boundary = RunBoundary(bus, node.announce)
        node.announce()  # waiting for a run, from a clean state
        try:
            report = node.run(stop, boundary)
        except can.CanError:
            if served and not boundary.started:  # the bus went away after the last run: nothing more to serve
                break
            raise
        if boundary.started:
            served += 1
            security |= _print_summary(node, report, config, served)
    if not served and node is not None and report is not None:  # stopped before any run: say so all the same
        security |= _print_summary(node, report, config, 0)
    return EXIT_SECURITY if security else 0


def _print_summary(node: EcuNode, report, config: EcuConfig, run: int) -> bool:
    """One line on the run; True if it saw frames failing authentication or a foreign SafetyOverride."""
    stats = node.stats
    auth_failures = stats.get("AuthError", 0) + stats.get("FreshnessError", 0)
    rejected = sum(v for k, v in stats.items() if k == "UnknownFrame" or k.endswith("Error"))
    print(f"ecu {config.strategy}: final mode {node.mode}; "
          f"{report.summary()}; frames good {stats.get('good', 0)}, rejected {rejected}, "
          f"gate interventions {stats['gate_interventions']}"
          + (f"; authenticated {stats.get('authenticated', 0)}, authentication failures {auth_failures}"
             if node.authenticated else "")
          + (f"; clock errors {stats['clock_errors']}" if stats.get("clock_errors") else "")
          + (f"; foreign SafetyOverride frames {stats['foreign_overrides']}" if stats.get("foreign_overrides") else "")
          + (f"; run {run}" if run else "; no run served"), flush=True)
    return bool(auth_failures or stats.get("foreign_overrides"))
