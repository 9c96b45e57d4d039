"""``--ecu inprocess|process|attach`` and friends, shared by ``crd run`` and ``crd paper``."""

from __future__ import annotations

import argparse

from ..link.ecu_link import ECU_MODES, EcuOptions
from ..link.stall import DEFAULT_STALL_TIMEOUT_S
from ..results.run_record import RunRecord
from ..world.gateway import SECURITY_EVENTS


def add_ecu_arguments(parser: argparse.ArgumentParser, realtime: bool) -> None:
    g = parser.add_argument_group("ECU placement (see cosim/link/ecu_link.py)")
    g.add_argument("--ecu", choices=ECU_MODES, default="inprocess",
                   help="inprocess (default); process: spawn `crd ecu` on the bus and stop it at the end; "
                        "attach: use an ECU already running on --bus-channel")
    g.add_argument("--bus-interface", default=None,
                   help="python-can interface to the ECU (default: crd_inproc for --ecu inprocess, e.g. "
                        "'virtual' for python-can's; crd_pair, point to point, for --ecu process in "
                        "lock-step; crd_unix, through a hub, otherwise)")
    g.add_argument("--bus-channel", help="its channel (crd_unix: a socket path; process: a fresh one by default)")
    g.add_argument("--join-timeout", type=float, default=10.0, metavar="S",
                   help="wall-clock bound on waiting for the ECU to join (default 10 s)")
    g.add_argument("--reply-timeout", type=float, default=1.0, metavar="S",
                   help="real time: no frame from the ECU for this long is ecu_lost; lock-step: a longer wait "
                        "for a cycle's SafetyOverride is recorded as an ecu_stall event (default 1 s)")
    g.add_argument("--stall-timeout", type=float, default=DEFAULT_STALL_TIMEOUT_S, metavar="S",
                   help="lock-step: wall-clock bound on waiting for a stalled ECU's SafetyOverride, simulated "
                        f"time held; past it the run stops with an error (default {DEFAULT_STALL_TIMEOUT_S:g} s)")
    g.add_argument("--key-file", metavar="F",
                   help="SecOC key file (32 hex digits, mode 0600) shared with the ECU; default: a fresh key "
                        "per run in process and for --ecu process; attach without it: E2E protection only")
    g.add_argument("--ecu-settings", default="scenario", metavar="scenario|ecu|FILE",
                   help="an ECU on a bus announces what it runs: scenario (default): it must run the scenario's "
                        "[ecu], else a one-line error; ecu: run with its own settings (recorded); FILE: its "
                        "settings are this file (checked against its announcement, recorded)")
    if realtime:
        g.add_argument("--realtime", action="store_true",
                       help="pace the co-simulation to the wall clock; the ECU runs on its own clock")


def ecu_options(args: argparse.Namespace) -> EcuOptions:
    return EcuOptions(mode=args.ecu, interface=args.bus_interface, channel=args.bus_channel,
                      realtime=getattr(args, "realtime", False), join_timeout_s=args.join_timeout,
                      reply_timeout_s=args.reply_timeout, stall_timeout_s=args.stall_timeout,
                      key_file=args.key_file, ecu_settings=args.ecu_settings)


def timing_lines(records: list[RunRecord]) -> list[str]:
    """Real-time lag/jitter and ECU-link events, one line each."""
    lines = []
    for r in records:
        t = r.timing
        if t:
            lines.append(f"{r.strategy}: real-time master cycle lag p50 {t['lag_p50_s'] * 1e3:.3f} "
                         f"p99 {t['lag_p99_s'] * 1e3:.3f} max {t['lag_max_s'] * 1e3:.3f} ms; jitter p50 "
                         f"{t['jitter_p50_s'] * 1e3:.3f} p99 {t['jitter_p99_s'] * 1e3:.3f} "
                         f"max {t['jitter_max_s'] * 1e3:.3f} ms")
        for e in r.events:
            if e.kind in ("ecu_lost", "second_ecu", *SECURITY_EVENTS):
                lines.append(f"{r.strategy}: t={e.t_s:.3f} s {e.kind}: {e.detail}")
        if r.ecu_report:
            lines.append(f"{r.strategy}: {r.ecu_report.splitlines()[-1]}")
    return lines
