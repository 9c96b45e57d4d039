"""``crd dbc``: show the CAN contract, or decode a CAN log against it.

``crd dbc show`` prints every message with its ID, sender, cycle time and
signals (unit, range, resolution, enumeration labels). ``crd dbc decode LOG``
reads a BLF/ASC/CSV log with python-can's readers and prints each frame after
the contract's checks, with rejected frames named by their error.
``crd dbc export --format arxml|kcd|sym OUT`` writes the contract for other
tools (:mod:`can_dbc.export`).
"""

from __future__ import annotations

import argparse

import can

from .database import DATABASE, LAYOUTS
from .errors import FrameError
from .export import FORMATS, export
from .receiver import Receiver


def add_subparser(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("dbc", help="show the CAN contract or decode a log against it")
    sub = parser.add_subparsers(dest="dbc_command", metavar="ACTION")
    sub.required = True
    show = sub.add_parser("show", help="list messages and signals of the DBC")
    show.set_defaults(func=_do_show)
    decode = sub.add_parser("decode", help="decode a CAN log (.blf, .asc, .csv) with E2E checks")
    decode.add_argument("log", help="log file; the format follows its suffix")
    decode.add_argument("--limit", type=int, default=0, help="stop after this many frames (0: all)")
    decode.set_defaults(func=_do_decode)
    exp = sub.add_parser("export", help="write the contract as AUTOSAR 4 ARXML, KCD or SYM")
    exp.add_argument("out", help="output file")
    exp.add_argument("--format", choices=FORMATS, default=None,
                     help="output format (default: from the suffix of OUT)")
    exp.set_defaults(func=_do_export)


def _do_show(args: argparse.Namespace) -> int:
    for layout in LAYOUTS.values():
        cycle = f"{layout.cycle_time_ms} ms" if layout.cycle_time_ms else "-"
        print(f"0x{layout.frame_id:03X} {layout.name:<15} from {','.join(layout.senders):<7} cycle {cycle}")
        for sig in layout.signals:
            rng = f"{sig.minimum:g}..{sig.maximum:g}"
            enum = f" {_labels(layout.name, sig.name)}" if sig.choices else ""
            print(f"    {sig.name:<20} {sig.unit or '-':<6} {rng:<16} res {sig.scale:g}{enum}")
    return 0


def _labels(message: str, signal: str) -> str:
    """``0=STANDBY 1=TIGHTENING ...``: the signal's enumeration as the DBC declares it."""
    choices = DATABASE.get_message_by_name(message).get_signal_by_name(signal).choices or {}
    return " ".join(f"{int(k)}={v}" for k, v in sorted(choices.items()))


def _do_export(args: argparse.Namespace) -> int:
    fmt = args.format or args.out.rsplit(".", 1)[-1].lower()
    if fmt not in FORMATS:
        raise ValueError(f"crd dbc export: cannot tell the format of {args.out!r} from its suffix; "
                         f"give --format, one of {', '.join(FORMATS)}")
    print(export(fmt, args.out))
    return 0


def _do_decode(args: argparse.Namespace) -> int:
    receiver = Receiver()
    count = 0
    with can.LogReader(args.log) as reader:
        for msg in reader:
            try:
                frame = receiver.check(msg)
                text = f"{frame.name} {dict(frame.signals)}" + ("" if frame.fresh else " (repeat)")
            except FrameError as exc:
                text = f"REJECTED {type(exc).__name__}: {exc}"
            print(f"{msg.timestamp:12.3f} 0x{msg.arbitration_id:03X} {text}")
            count += 1
            if args.limit and count >= args.limit:
                break
    print(f"{count} frames; rejected: {dict((k, v) for k, v in receiver.stats.items() if k not in ('good',))}")
    return 0
