"""``crd dbc``: show the CAN contract, or decode a CAN log against it.

``crd dbc show`` prints every message with its ID, sender, cycle time and
signals (unit, range, resolution, enumeration labels). ``crd dbc decode LOG``
reads a log in any format python-can reads (:data:`LOG_SUFFIXES`: BLF, ASC,
TRC, candump ``.log``, CSV, SQLite, and MF4 with ``crd[mdf]``) and prints each frame after
the contract's checks, with rejected frames named by their error. SecOC
authenticator frames are verified with ``--key-file``; without it their freshness
and MAC are printed unverified (a run's fresh per-run key is never stored).
``crd dbc export --format arxml|kcd|sym OUT`` writes the contract for other
tools (:mod:`can_dbc.export`).
"""

from __future__ import annotations

import argparse

import can
from can.io.player import MESSAGE_READERS

from .database import AUTHENTICATORS, DATABASE, LAYOUTS
from .errors import FrameError
from .export import FORMATS, export
from .receiver import Receiver
from .secoc import SecOcVerifier, load_key_file

_AUTH_NAMES = {fid: name + "Auth" for name, fid in AUTHENTICATORS.items()}
#: the log suffixes ``crd dbc decode`` reads: python-can's readers, the same table ``can.LogReader`` picks from
LOG_SUFFIXES = tuple(sorted(MESSAGE_READERS))


def add_subparser(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("dbc", help="show the CAN contract or decode a log against it")
    sub = parser.add_subparsers(dest="dbc_command", metavar="ACTION")
    sub.required = True
    show = sub.add_parser("show", help="list messages and signals of the DBC")
    show.set_defaults(func=_do_show)
    decode = sub.add_parser("decode", help=f"decode a CAN log ({', '.join(LOG_SUFFIXES)}) with E2E checks")
    decode.add_argument("log", help="log file; the format follows its suffix")
    decode.add_argument("--limit", type=int, default=0, help="stop after this many frames (0: all)")
    decode.add_argument("--key-file", help="SecOC key file: verify the authenticator frames")
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
    for name, fid in AUTHENTICATORS.items():
        print(f"0x{fid:03X} {name + 'Auth':<15} SecOC authenticator of {name}: Freshness (16 bit), Mac (48 bit)")
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


def _unverified(msg: can.Message) -> str:
    data = bytes(msg.data)
    return (f"{_AUTH_NAMES[msg.arbitration_id]} Freshness {int.from_bytes(data[:2], 'little')} "
            f"Mac {data[2:8].hex()} (not verified: no --key-file)")


def _text(receiver: Receiver, msg: can.Message) -> str:
    try:
        frame = receiver.check(msg)
    except FrameError as exc:
        return f"REJECTED {type(exc).__name__}: {exc}"
    if frame is None:
        return "held for its authenticator"
    return f"{frame.name} {dict(frame.signals)}" + ("" if frame.fresh else " (repeat)")


def _do_decode(args: argparse.Namespace) -> int:
    verifier = SecOcVerifier(load_key_file(args.key_file)) if args.key_file else None
    receiver = Receiver(secoc=verifier)
    count = 0
    with can.LogReader(args.log) as reader:
        for msg in reader:
            if verifier is None and msg.arbitration_id in _AUTH_NAMES and not msg.is_extended_id:
                text = _unverified(msg)
            else:
                text = _text(receiver, msg)
            print(f"{msg.timestamp:12.3f} 0x{msg.arbitration_id:03X} {text}")
            count += 1
            if args.limit and count >= args.limit:
                break
    print(f"{count} frames; rejected: {dict((k, v) for k, v in receiver.stats.items() if k not in ('good', 'authenticated'))}")
    return 0
