"""The CAN contract of crd: the DBC and a strict, end-to-end protected codec.

``DBC_PATH`` is the single source of truth for IDs, signals, cycle times,
counters and checksums. :func:`encode` builds protected frames;
:class:`Receiver` checks received frames in the contract's order and keeps a
validity score per message. See ``docs/CONTRACTS.md``.
"""

from .codec import encode, encode_payload
from .counter import COUNTER_MODULUS, CounterSequence
from .crc import crc8_j1850, e2e_p01_crc
from .database import DATABASE, DBC_PATH, LAYOUTS, LAYOUTS_BY_ID, cycle_time_s, e2e_signal_names, signal_layout
from .errors import (
    ChecksumError,
    CounterError,
    DecodeError,
    EnumError,
    FrameError,
    LengthError,
    RangeError,
    SignalError,
    UnknownFrame,
)
from .receiver import Frame, Receiver

__all__ = [
    "COUNTER_MODULUS", "DATABASE", "DBC_PATH", "LAYOUTS", "LAYOUTS_BY_ID",
    "ChecksumError", "CounterError", "CounterSequence", "DecodeError", "EnumError",
    "Frame", "FrameError", "LengthError", "RangeError", "Receiver", "SignalError",
    "UnknownFrame", "crc8_j1850", "cycle_time_s", "e2e_signal_names", "signal_layout", "e2e_p01_crc", "encode", "encode_payload",
]
