"""The CAN contract's tables, rendered from ``can_dbc/active_safety.dbc`` (through cantools).

The DBC is the single source of IDs, cycle times, ranges, enumerations and the
comments that say what each signal means; these tables are what it declares,
so they cannot disagree with the codec, which reads the same file.
"""

from __future__ import annotations

import re

from cantools.database.can import Message, Signal

from can_dbc import DATABASE, DBC_PATH
from can_dbc.contract import TIMEOUT_CYCLES
from can_dbc.database import AUTHENTICATORS, e2e_signal_names


def _cell(text: object) -> str:
    return " ".join(str(text).split()).replace("|", "\\|")


def _num(x: float) -> str:
    return f"{x:.15g}"


def _messages() -> list[Message]:
    return sorted(DATABASE.messages, key=lambda m: m.frame_id)


def _attribute(message: Message, name: str, default: object = None) -> object:
    attr = message.dbc.attributes.get(name) if message.dbc else None
    return default if attr is None else attr.value


def _protection(m: Message) -> str:
    protects = _attribute(m, "SecOCAuthenticates", 0)
    if protects:
        return f"SecOC authenticator of 0x{protects:03X}"
    e2e = "E2E" if set(e2e_signal_names(m.name)) <= {s.name for s in m.signals} else "none"
    auth = f" + SecOC (0x{AUTHENTICATORS[m.name]:03X})" if m.name in AUTHENTICATORS else ""
    return e2e + auth


def _cycle(m: Message) -> str:
    if m.send_type == "OnEvent":
        return "on event (each ECU cycle in lock-step)"
    return f"{m.cycle_time} ms" if m.cycle_time else "-"


def message_table() -> str:
    """Messages: ID, name, sender, cycle time, the receivers' timeout (``TIMEOUT_CYCLES`` cycles; an
    authenticator is timed with the frame it protects), DLC, protection and the DBC comment."""
    lines = ["| ID | message | sender | cycle | timeout | DLC | protection | what it is |",
             "|---|---|---|---|---|---|---|---|"]
    for m in _messages():
        timed = m.send_type == "Cyclic" and m.cycle_time and not _attribute(m, "SecOCAuthenticates", 0)
        timeout = f"{TIMEOUT_CYCLES * m.cycle_time} ms" if timed else "-"
        lines.append(f"| 0x{m.frame_id:03X} | `{m.name}` | {', '.join(m.senders)} | {_cycle(m)} | {timeout} "
                     f"| {m.length} | {_protection(m)} | {_cell(m.comment or '')} |")
    return "\n".join(lines)


def _enumeration(s: Signal) -> str:
    if not s.choices:
        return ""
    return ", ".join(f"{int(k)} {v}" for k, v in sorted(s.choices.items()))


def _signal_row(s: Signal) -> str:
    sign = "signed" if s.is_signed else "unsigned"
    start = "" if s.initial is None or s.initial == 0 else _num(float(s.initial))
    return (f"| `{s.name}` | {s.start} | {s.length} ({sign}) | {s.unit or ''} | {_num(s.scale)} "
            f"| {_num(s.minimum)} … {_num(s.maximum)} | {start} | {_enumeration(s)} | {_cell(s.comment or '')} |")


def signal_tables() -> str:
    """Per message, a table of its signals: start bit, length, unit, resolution, range, start value, values."""
    lines = []
    for m in _messages():
        lines += [f"### `{m.name}` (0x{m.frame_id:03X})", "", _cell(m.comment or ""), "",
                  "| signal | start bit | bits | unit | resolution | range | start value | values | meaning |",
                  "|---|---|---|---|---|---|---|---|---|"]
        lines += [_signal_row(s) for s in m.signals] + [""]
    return "\n".join(lines)


def fault_bits() -> str:
    """``EcuStatus``'s fault bits: bit in the frame, flag number, signal and meaning."""
    status = DATABASE.get_message_by_name("EcuStatus")
    faults = [s for s in status.signals if s.name.startswith("Fault")]
    lines = [f"`EcuStatus` (0x{status.frame_id:03X}) carries {len(faults)} fault bits, one 1-bit signal each, "
             f"at bits {faults[0].start}–{faults[-1].start} of the frame:", "",
             "| bit | signal | meaning |", "|---|---|---|"]
    lines += [f"| {s.start} | `{s.name}` | {_cell(s.comment or '')} |" for s in faults]
    return "\n".join(lines)


def bus_summary() -> str:
    """The bus (type, bit rate, DBC name), the nodes with their comments, and the DBC's own comment."""
    attrs = {k: v.value for k, v in DATABASE.dbc.attributes.items()}
    comment = re.search(r'^CM_ "(.*?)";', DBC_PATH.read_text(), re.M | re.S)
    lines = [f"{attrs.get('BusType', 'CAN')}, {int(attrs.get('Baudrate', 0)) // 1000} kbit/s, DBC "
             f"`{attrs.get('DBName', '')}` version `{DATABASE.version}`. The DBC says:", "",
             "> " + _cell(comment.group(1) if comment else ""), "", "| node | what it is |", "|---|---|"]
    lines += [f"| {n.name} | {_cell(n.comment or '')} |" for n in DATABASE.nodes]
    return "\n".join(lines)
