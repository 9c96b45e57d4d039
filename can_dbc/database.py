"""The contract's DBC, loaded once and strictly, and the layout tables built from it.

``DBC_PATH`` is the file; ``DATABASE`` the ``cantools`` database loaded with
``strict=True`` (overlapping signals or signals outside the frame are errors).
``LAYOUTS`` maps each message name to a :class:`MessageLayout`, a precomputed
table that lets :mod:`can_dbc.codec` and :mod:`can_dbc.receiver` encode and
decode a frame with integer shifts and masks only. All messages are classic
CAN, 11-bit IDs, DLC 8, little-endian (Intel) signals.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import Mapping

import cantools

from .crc import data_id_seed

DBC_PATH: Path = Path(__file__).with_name("active_safety.dbc")
DATABASE = cantools.database.load_file(str(DBC_PATH), strict=True)

FRAME_LENGTH = 8


def e2e_signal_names(message_name: str) -> tuple[str, str]:
    """Names of the E2E Profile 1 header signals (CRC byte 0, counter low nibble of byte 1),
    handled by the codec itself. They carry the message name (``SafetyOverride_CRC``,
    ``SafetyOverride_Counter``) so that AUTOSAR exports, which key signals by name alone,
    keep the six messages' headers apart."""
    return f"{message_name}_CRC", f"{message_name}_Counter"


@dataclass(frozen=True, slots=True)
class SignalLayout:
    """Bit position, scaling and limits of one signal.

    ``raw_min``/``raw_max`` are the raw integers that map inside the DBC's
    physical [minimum, maximum]; ``choices`` is the set of declared enum values
    (empty when the signal is not an enumeration).
    """

    name: str
    start: int
    length: int
    signed: bool
    scale: float
    offset: float
    minimum: float
    maximum: float
    raw_min: int
    raw_max: int
    is_integer: bool
    choices: frozenset[int]
    unit: str


@dataclass(frozen=True, slots=True)
class MessageLayout:
    """A message of the contract: its ID, cycle time and payload signals."""

    name: str
    frame_id: int
    length: int
    cycle_time_ms: int | None
    senders: tuple[str, ...]
    signals: tuple[SignalLayout, ...]
    #: per signal ``(name, start, mask, scale, offset, raw_min, raw_max)``: the encoder's loop
    pack_table: tuple[tuple, ...] = ()
    #: per signal ``(name, start, mask, sign_bit, raw_min, raw_max, scale, offset, is_integer, choices)``
    unpack_table: tuple[tuple, ...] = ()
    #: E2E CRC state after the data ID (= frame ID) bytes
    crc_seed: int = 0


def _signal_layout(signal) -> SignalLayout:
    if signal.byte_order != "little_endian":
        raise ValueError(f"signal {signal.name}: expected little_endian, got {signal.byte_order}")
    scale = float(signal.scale)
    offset = float(signal.offset)
    minimum = float(signal.minimum)
    maximum = float(signal.maximum)
    raw_min = math.ceil(round((minimum - offset) / scale, 9))
    raw_max = math.floor(round((maximum - offset) / scale, 9))
    choices = frozenset(int(k) for k in (signal.choices or {}))
    return SignalLayout(
        name=signal.name,
        start=signal.start,
        length=signal.length,
        signed=signal.is_signed,
        scale=scale,
        offset=offset,
        minimum=minimum,
        maximum=maximum,
        raw_min=raw_min,
        raw_max=raw_max,
        is_integer=scale == 1.0 and offset == 0.0,
        choices=choices,
        unit=signal.unit or "",
    )


def _message_layout(message) -> MessageLayout:
    if message.is_extended_frame or message.length != FRAME_LENGTH:
        raise ValueError(f"message {message.name}: expected 11-bit ID and DLC 8")
    names = [s.name for s in message.signals]
    e2e = e2e_signal_names(message.name)
    if names[:2] != list(e2e):
        raise ValueError(f"message {message.name}: expected {e2e[0]}, {e2e[1]} first, got {names[:2]}")
    crc, counter = message.signals[:2]
    if (crc.start, crc.length, counter.start, counter.length) != (0, 8, 8, 4):
        raise ValueError(f"message {message.name}: expected {e2e[0]} at bit 0 (8 bits), {e2e[1]} at bit 8 (4 bits)")
    signals = tuple(_signal_layout(s) for s in message.signals[2:])
    masks = [(1 << sig.length) - 1 for sig in signals]
    return MessageLayout(
        name=message.name,
        frame_id=message.frame_id,
        length=message.length,
        cycle_time_ms=message.cycle_time,
        senders=tuple(message.senders),
        signals=signals,
        pack_table=tuple((s.name, s.start, m, s.scale, s.offset, s.raw_min, s.raw_max)
                         for s, m in zip(signals, masks)),
        unpack_table=tuple((s.name, s.start, m, (1 << (s.length - 1)) if s.signed else 0, s.raw_min, s.raw_max,
                            s.scale, s.offset, s.is_integer, s.choices) for s, m in zip(signals, masks)),
        crc_seed=data_id_seed(message.frame_id),
    )


LAYOUTS: Mapping[str, MessageLayout] = MappingProxyType(
    {m.name: _message_layout(m) for m in DATABASE.messages}
)
LAYOUTS_BY_ID: Mapping[int, MessageLayout] = MappingProxyType(
    {layout.frame_id: layout for layout in LAYOUTS.values()}
)


def signal_layout(message_name: str, signal_name: str) -> SignalLayout:
    """The layout (bit position, scaling, DBC min/max, unit) of one signal."""
    for sig in LAYOUTS[message_name].signals:
        if sig.name == signal_name:
            return sig
    raise KeyError(f"{message_name} has no signal {signal_name!r}")


def cycle_time_s(message_name: str) -> float:
    """The message's ``GenMsgCycleTime`` in seconds."""
    cycle = LAYOUTS[message_name].cycle_time_ms
    if cycle is None:
        raise KeyError(f"message {message_name} has no GenMsgCycleTime")
    return cycle / 1000.0
