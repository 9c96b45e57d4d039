"""The CAN contract of crd: the DBC and a strict, end-to-end protected codec.

``DBC_PATH`` is the single source of truth for IDs, signals, cycle times,
counters and checksums; :mod:`can_dbc.contract` reads the timing, limits,
enumerations and units everyone else uses from it. :func:`encode` builds protected frames;
:class:`Receiver` checks received frames in the contract's order and keeps a
validity score per message. See ``docs/CONTRACTS.md``.
"""

from .codec import encode, encode_payload
from .counter import COUNTER_MODULUS, CounterSequence
from .crc import crc8_j1850, e2e_p01_crc
from .database import AUTHENTICATORS, DBC_PATH, LAYOUTS, LAYOUTS_BY_ID, cycle_time_s, e2e_signal_names, signal_layout
from .contract import (
    BRAKE_DECEL_MAX_MPS2,
    ECU_CYCLE_S,
    FAULT_SIGNALS,
    MODE_NAMES,
    STRATEGIES,
    STRATEGY_CODES,
    enumeration,
    signal_dbc_per_si,
    signal_range,
    timeout_s,
)
from .errors import (
    AuthError,
    FreshnessError,
    KeyFileError,
    ChecksumError,
    ConfigError,
    CounterError,
    DecodeError,
    EnumError,
    FrameError,
    LengthError,
    RangeError,
    SignalError,
    UnknownFrame,
)
from .receiver import RX_RATE, RX_SEQUENCE, SYNC_FRAMES, Frame, Receiver, check_alone
from .secoc import SecOcSender, SecOcVerifier, generate_key, load_key_file, write_key_file

__all__ = [
    "AUTHENTICATORS", "AuthError", "FreshnessError", "KeyFileError", "RX_RATE", "RX_SEQUENCE", "SYNC_FRAMES",
    "SecOcSender", "SecOcVerifier", "generate_key", "load_key_file", "write_key_file",
    "BRAKE_DECEL_MAX_MPS2", "ECU_CYCLE_S", "FAULT_SIGNALS", "MODE_NAMES", "STRATEGIES", "STRATEGY_CODES",
    "ConfigError", "enumeration", "signal_dbc_per_si", "signal_range", "timeout_s",
    "COUNTER_MODULUS", "DATABASE", "DBC_PATH", "LAYOUTS", "LAYOUTS_BY_ID",
    "ChecksumError", "CounterError", "CounterSequence", "DecodeError", "EnumError",
    "Frame", "FrameError", "LengthError", "RangeError", "Receiver", "SignalError",
    "UnknownFrame", "check_alone", "crc8_j1850", "cycle_time_s", "e2e_signal_names", "signal_layout", "e2e_p01_crc", "encode", "encode_payload",
]


def __getattr__(name: str):
    """``DATABASE`` (the cantools database) is parsed on first use: most processes never need it."""
    if name == "DATABASE":
        from . import database

        return database.DATABASE
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
