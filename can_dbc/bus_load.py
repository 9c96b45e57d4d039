"""Bus load of the contract at its baud rate, from the DBC's cycle times.

A classic CAN data frame with an 11-bit identifier and ``n`` data bytes is
``47 + 8 n`` bits on the wire without stuff bits (SOF, identifier, RTR, IDE,
r0, DLC, data, CRC, CRC and ACK delimiters, ACK slot, EOF and the 3-bit
intermission); the 34 + 8 n bits from SOF to the end of the CRC are subject
to bit stuffing, at worst one stuff bit per 4 bits after the first, so the
worst case is::

    C(n) = 47 + 8 n + floor((34 + 8 n - 1) / 4)      (111 and 135 bits for n = 8)

(Davis, Burns, Bril, Lukkien, "Controller Area Network (CAN) schedulability
analysis: refuted, revisited and revised", Real-Time Systems 35(3), 2007,
eq. (1)). The load of a set of cyclic messages is ``sum(C / T) / baud``.
Authenticator frames are counted with the message they follow (same cycle).
A message sent on events only (``GenMsgSendType`` OnEvent: ``SimClock``,
``EcuIdentity``) is counted at its ``GenMsgCycleTime`` as if cyclic: the
load of a run in lock-step, which sends them every cycle or period.
"""

from __future__ import annotations

from typing import Iterable

from .database import AUTHENTICATORS, LAYOUTS, _MESSAGES

#: bits of an 11-bit-ID data frame outside the data field (incl. 3-bit intermission), no stuff bits
FRAME_OVERHEAD_BITS = 47
#: bits from SOF to the end of the CRC outside the data field: the stuffed span
STUFFED_OVERHEAD_BITS = 34


def frame_bits(data_bytes: int, worst_case: bool) -> int:
    """Bits on the wire of one 11-bit-ID data frame: ``47 + 8 n`` (+ worst-case stuff bits)."""
    bits = FRAME_OVERHEAD_BITS + 8 * data_bytes
    if worst_case:
        bits += (STUFFED_OVERHEAD_BITS + 8 * data_bytes - 1) // 4
    return bits


def baud_rate() -> int:
    """The DBC's ``Baudrate`` (bit/s)."""
    from .database import DATABASE

    return int(DATABASE.dbc.attributes["Baudrate"].value)


def bus_load(names: Iterable[str] | None = None, worst_case: bool = True, keyed: bool = True,
             baud: int | None = None) -> float:
    """Fraction of the bus taken by messages ``names`` (default: all) at their cycle times.

    ``keyed``: each protected message is followed by its SecOC authenticator (same length).
    Raises ``KeyError`` for a message without a ``GenMsgCycleTime``.
    """
    wanted = set(LAYOUTS) if names is None else set(names)
    bits_per_s = 0.0
    for message in _MESSAGES:
        name = message["name"]
        if name not in wanted or name not in LAYOUTS:
            continue
        if not message["cycle_time_ms"]:
            raise KeyError(f"message {name} has no GenMsgCycleTime")
        frames = 2 if keyed and name in AUTHENTICATORS else 1
        bits_per_s += frames * frame_bits(message["length"], worst_case) * 1000.0 / message["cycle_time_ms"]
    return bits_per_s / (baud if baud is not None else baud_rate())
