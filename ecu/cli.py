"""``crd ecu``: run the ECU as a standalone process on any python-can interface.

``crd ecu --interface virtual --channel vcan0 --strategy tightening``
opens the bus, runs :meth:`ecu.EcuNode.run` (real time, or paced by SimClock
frames with ``--sim-time``) until SIGINT or SIGTERM sets the stop event,
shuts the bus down and prints a one-line summary of the run.
"""

from __future__ import annotations

import argparse
import dataclasses
import signal
import threading

import can

from can_dbc.contract import STRATEGIES

from .config import EcuConfig
from .node import EcuNode


def add_subparser(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("ecu", help="run the active-safety ECU on a CAN interface")
    parser.add_argument("--interface", required=True, help="python-can interface (virtual, socketcan, ...)")
    parser.add_argument("--channel", required=True, help="channel of the interface")
    parser.add_argument("--strategy", choices=sorted(STRATEGIES), help="override the config's strategy")
    parser.add_argument("--config", help="TOML file with the ECU settings (top level or [ecu])")
    parser.add_argument("--sim-time", action="store_true", help="one cycle per SimClock frame")
    parser.add_argument("--bitrate", type=int, help="bus bitrate in bit/s, for interfaces that take one")
    parser.set_defaults(func=_do_ecu)


def _config(args: argparse.Namespace) -> EcuConfig:
    config = EcuConfig.from_toml(args.config) if args.config else EcuConfig()
    changes = {}
    if args.strategy:
        changes["strategy"] = args.strategy
    if args.sim_time:
        changes["sim_time"] = True
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
    rejected = sum(v for k, v in stats.items() if k == "UnknownFrame" or k.endswith("Error"))
    print(f"ecu {config.strategy}: final mode {node.mode}; {report.summary()}; "
          f"frames good {stats.get('good', 0)}, rejected {rejected}, "
          f"gate interventions {stats['gate_interventions']}")
    return 0
