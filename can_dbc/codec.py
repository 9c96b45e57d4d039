"""Encoding with end-to-end protection.

``encode(name, signals, counter)`` packs physical values (DBC units) into the
message's 8 bytes, writes the E2E Profile 1 counter into the low nibble of
byte 1 and the CRC-8 SAE J1850 into byte 0. Strict: a missing, unknown,
non-finite or out-of-range signal raises :class:`~can_dbc.errors.SignalError`.
Raw value = round((physical - offset) / scale), as in the DBC definition.
"""

from __future__ import annotations

import copy
import math
from typing import Mapping

import can

from .counter import COUNTER_MODULUS
from .crc import e2e_p01_crc8
from .database import LAYOUTS, FRAME_LENGTH, MessageLayout
from .errors import SignalError


def _signal_error(layout: MessageLayout, signals: Mapping[str, float]) -> SignalError:
    """The error for the first signal of ``layout`` that ``signals`` lacks or cannot encode."""
    for sig in layout.signals:
        if sig.name not in signals:
            unknown = sorted(set(signals) - {s.name for s in layout.signals})
            hint = f"; unknown signals {unknown}" if unknown else ""
            return SignalError(f"{layout.name}: missing signal {sig.name}{hint}")
        value = signals[sig.name]
        if not math.isfinite(value):
            return SignalError(f"{layout.name}.{sig.name}: expected a finite value, got {value}")
        raw = round((value - sig.offset) / sig.scale)
        if raw < sig.raw_min or raw > sig.raw_max:
            return SignalError(
                f"{layout.name}.{sig.name}: expected {sig.minimum}..{sig.maximum} {sig.unit}".rstrip()
                + f", got {value}"
            )
    return SignalError(f"{layout.name}: cannot encode {dict(signals)}")


#: a plain dict: looked up for every frame, and faster than the public read-only ``LAYOUTS`` proxy
_LAYOUTS = dict(LAYOUTS)


def encode_payload(message_name: str, signals: Mapping[str, float], counter: int) -> bytearray:
    """The protected 8-byte payload of ``message_name``."""
    layout = _LAYOUTS.get(message_name)
    if layout is None:
        raise SignalError(f"unknown message {message_name!r}; expected one of {sorted(LAYOUTS)}")
    return _payload(layout, signals, counter)


class _LastSignals:
    """The signals one message was last encoded from, and the frames they gave, by counter.

    Most frames of a cycle repeat the signals of the frame before them: the empty ``RadarTrack`` slots,
    the inactive ``SteeringOverride``, the driver's pedals while he holds them, ``SafetyOverride``
    outside an intervention. For those the payload is packed and its CRC computed once per counter
    value, not once per frame: a dict comparison and a copy instead of the packing loop and the CRC
    (measured when every run carried the planar frames, before ``ecu.equipment``: the paper run,
    tightening: 24,000 of its 27,600 frames repeat the last signals of their message; a
    repeated ``RadarTrack3`` encodes in 0.3x the time of a changed one, timeit in one process on the
    loaded 2-core machine).
    """

    __slots__ = ("signals", "packed", "frames")

    def __init__(self, signals: dict, packed: int) -> None:
        self.signals, self.packed = signals, packed
        #: the 8 bytes (CRC included) for each counter value, filled as the counters come round
        self.frames: list[bytes | None] = [None] * COUNTER_MODULUS


_LAST: dict[str, _LastSignals] = {}


def _payload(layout: MessageLayout, signals: Mapping[str, float], counter: int) -> bytearray:
    last = _LAST.get(layout.name)
    if last is None or last.signals != signals:  # NaN never equals itself: a bad value is never reused
        last = _LAST[layout.name] = _LastSignals(dict(signals), _packed(layout, signals))
    if not (isinstance(counter, int) and 0 <= counter < COUNTER_MODULUS):
        raise SignalError(f"{layout.name}: expected counter in 0..14, got {counter!r}")
    frame = last.frames[counter]
    if frame is None:  # this counter's first frame with these signals
        data = bytearray((last.packed | counter << 8).to_bytes(FRAME_LENGTH, "little"))
        data[0] = e2e_p01_crc8(layout.crc_seed, data)
        last.frames[counter] = bytes(data)
        return data
    return bytearray(frame)


def _packed(layout: MessageLayout, signals: Mapping[str, float]) -> int:
    """The raw values of ``signals`` in their bits of the payload (CRC and counter bits 0)."""
    if len(signals) != len(layout.signals):
        extra = set(signals) - {s.name for s in layout.signals}
        if extra:
            raise SignalError(f"{layout.name}: unknown signals {sorted(extra)}")
    payload = 0
    try:
        for name, start, mask, scale, offset, raw_min, raw_max in layout.pack_table:
            raw = round((signals[name] - offset) / scale)  # inf, NaN or a missing name raise
            if raw < raw_min or raw > raw_max:
                raise ValueError
            payload |= (raw & mask) << start
    except (KeyError, ValueError, OverflowError) as exc:
        raise _signal_error(layout, signals) from exc
    return payload


class ContractMessage(can.Message):
    """A ``can.Message`` whose deep copy copies its fields directly.

    python-can's virtual bus deep-copies every frame for every receiver; the
    generic ``copy.deepcopy`` of ``Message.data`` (a bytearray) goes through
    ``__reduce_ex__`` and costs several times the frame's own construction.
    The copy made here is the same: a new plain ``can.Message`` with its own
    ``bytearray`` (``channel`` is shared only when it is an immutable
    ``str``/``int``/``None``, as python-can's channels are).
    """

    __slots__ = ()

    def __deepcopy__(self, memo: dict | None) -> can.Message:
        channel = self.channel
        if not (channel is None or channel.__class__ in (str, int)):
            channel = copy.deepcopy(channel, memo)
        return can.Message(
            timestamp=self.timestamp, arbitration_id=self.arbitration_id, is_extended_id=self.is_extended_id,
            is_remote_frame=self.is_remote_frame, is_error_frame=self.is_error_frame, channel=channel,
            dlc=self.dlc, data=bytearray(self.data), is_fd=self.is_fd, is_rx=self.is_rx,
            bitrate_switch=self.bitrate_switch, error_state_indicator=self.error_state_indicator,
        )


def encode(message_name: str, signals: Mapping[str, float], counter: int) -> can.Message:
    """A ``can.Message`` for ``message_name`` with counter and CRC filled in."""
    layout = _LAYOUTS.get(message_name)
    if layout is None:
        raise SignalError(f"unknown message {message_name!r}; expected one of {sorted(LAYOUTS)}")
    data = _payload(layout, signals, counter)
    # positional: (timestamp, arbitration_id, is_extended_id, is_remote_frame, is_error_frame, channel,
    # dlc, data); python-can's 13 keyword parameters cost more to bind than the frame costs to pack
    return ContractMessage(0.0, layout.frame_id, False, False, False, None, FRAME_LENGTH, data)
