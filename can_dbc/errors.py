"""Typed errors of the CAN contract.

Hierarchy::

    FrameError (ValueError)          a received frame broke the contract
    ├── UnknownFrame (LookupError)   arbitration ID not in the DBC (or not accepted)
    ├── LengthError                  DLC / data length is not the DBC's
    ├── ChecksumError                E2E CRC-8 mismatch
    ├── CounterError                 E2E counter invalid (15) or jumped by more than 2
    ├── DecodeError                  the payload cannot be decoded
    ├── RangeError                   a signal outside its DBC [min, max]
    └── EnumError                    an enumeration value not declared with VAL_
    SignalError (ValueError)         ``encode`` was given missing, unknown or out-of-range signals
    ConfigError (ValueError)         a configuration key is unknown, out of range or contradicts
                                     the contract; the one base class for can_dbc, ecu and cosim
                                     (``ecu.errors`` and ``cosim.errors`` re-export it)

Every message states the expected and the actual value.
"""

from __future__ import annotations


class FrameError(ValueError):
    """A received frame violates the CAN contract."""


class UnknownFrame(FrameError, LookupError):
    """The arbitration ID is not part of the contract."""


class LengthError(FrameError):
    """The frame's DLC or data length differs from the DBC's."""


class ChecksumError(FrameError):
    """The E2E Profile 1 CRC does not match the payload."""


class CounterError(FrameError):
    """The E2E alive counter is invalid or jumped too far."""


class DecodeError(FrameError):
    """The payload could not be decoded."""


class RangeError(FrameError):
    """A decoded signal lies outside its DBC minimum and maximum."""


class EnumError(FrameError):
    """A decoded enumeration value is not declared in the DBC."""


class SignalError(ValueError):
    """``encode`` was given signals that do not fit the message."""


class ConfigError(ValueError):
    """A configuration key is unknown, a value is out of range, or it contradicts the DBC.

    The message names the key path (``ecu.cycle_s``) and, when loaded from a
    file, the file; it gives the expected and the actual value.
    """
