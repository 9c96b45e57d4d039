"""Encoding with end-to-end protection.

``encode(name, signals, counter)`` packs physical values (DBC units) into the
message's 8 bytes, writes the E2E Profile 1 counter into the low nibble of
byte 1 and the CRC-8 SAE J1850 into byte 0. Strict: a missing, unknown,
non-finite or out-of-range signal raises :class:`~can_dbc.errors.SignalError`.
Raw value = round((physical - offset) / scale), as in the DBC definition.
"""

from __future__ import annotations

import math
from typing import Mapping

import can

from .counter import COUNTER_MODULUS
from .crc import e2e_p01_crc
from .database import LAYOUTS, FRAME_LENGTH, MessageLayout
from .errors import SignalError


def _pack(layout: MessageLayout, signals: Mapping[str, float]) -> int:
    payload = 0
    for sig in layout.signals:
        try:
            value = signals[sig.name]
        except KeyError:
            unknown = sorted(set(signals) - {s.name for s in layout.signals})
            hint = f"; unknown signals {unknown}" if unknown else ""
            raise SignalError(f"{layout.name}: missing signal {sig.name}{hint}") from None
        if not math.isfinite(value):
            raise SignalError(f"{layout.name}.{sig.name}: expected a finite value, got {value}")
        raw = round((value - sig.offset) / sig.scale)
        if raw < sig.raw_min or raw > sig.raw_max:
            raise SignalError(
                f"{layout.name}.{sig.name}: expected {sig.minimum}..{sig.maximum} {sig.unit}".rstrip()
                + f", got {value}"
            )
        payload |= (raw & ((1 << sig.length) - 1)) << sig.start
    return payload


def encode_payload(message_name: str, signals: Mapping[str, float], counter: int) -> bytearray:
    """The protected 8-byte payload of ``message_name``."""
    try:
        layout = LAYOUTS[message_name]
    except KeyError:
        raise SignalError(f"unknown message {message_name!r}; expected one of {sorted(LAYOUTS)}") from None
    if len(signals) != len(layout.signals):
        extra = set(signals) - {s.name for s in layout.signals}
        if extra:
            raise SignalError(f"{message_name}: unknown signals {sorted(extra)}")
    if not (isinstance(counter, int) and 0 <= counter < COUNTER_MODULUS):
        raise SignalError(f"{message_name}: expected counter in 0..14, got {counter!r}")
    payload = _pack(layout, signals) | (counter << 8)
    data = bytearray(payload.to_bytes(FRAME_LENGTH, "little"))
    data[0] = e2e_p01_crc(layout.frame_id, data)
    return data


def encode(message_name: str, signals: Mapping[str, float], counter: int) -> can.Message:
    """A ``can.Message`` for ``message_name`` with counter and CRC filled in."""
    data = encode_payload(message_name, signals, counter)
    return can.Message(
        arbitration_id=LAYOUTS[message_name].frame_id,
        is_extended_id=False,
        dlc=FRAME_LENGTH,
        data=data,
    )
