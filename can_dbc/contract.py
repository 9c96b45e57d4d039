"""Timing, limits, names and units of the contract, read from the DBC (the only source).

Every other package takes these facts from here instead of restating them:

* cycle times from ``GenMsgCycleTime``: :data:`ECU_CYCLE_S` (``SafetyOverride``,
  10 ms: the ECU's cycle and the co-simulation's lock-step), :func:`cycle_time_s`;
* reception timeouts, :func:`timeout_s` = :data:`TIMEOUT_CYCLES` missed cycles
  of the message (50 ms for the 10 ms messages, 250 ms for ``ObjectTrack``);
* rate-of-change limits, :func:`signal_max_rate` (the DBC's ``SigMaxRate``, e.g.
  ``SteeringOverride.SteerAngleRequest``: 23 deg/s);
* signal ranges, :func:`signal_range` (the DBC's [minimum, maximum]), e.g.
  :data:`BRAKE_DECEL_MAX_MPS2` = 15 m/s², the full scale of ``BrakeDecelRequest``;
* enumerations from ``VAL_``, :func:`enumeration`: :data:`MODE_NAMES`
  (``SafetyOverride.Mode``) and :data:`STRATEGY_CODES` (``EcuStatus.Strategy``,
  lower-cased: ``none``, ``conservative``, ``tightening``, ``adaptive``). A value
  added to that ``VAL_`` is a strategy everywhere: the command lines offer it, the
  configuration accepts it, ``EcuStatus`` carries it, and the ECU core runs the
  module of that name in ``ecu/core/strategies/`` (its registry refuses to load
  when the two disagree);
* the fault bits, :data:`FAULT_SIGNALS`: ``EcuStatus``'s one-bit ``Fault*``
  signals in bit order (fault bit k is the signal at DBC bit :data:`FAULT_BIT0` + k);
* unit conversions between the DBC's units and SI (:mod:`can_dbc.units`).
"""

from __future__ import annotations

from types import MappingProxyType
from typing import Mapping

from .database import LAYOUTS, choice_names, cycle_time_s, signal_layout
from .units import dbc_per_si

#: a receiver declares a message timed out after this many of its cycles without a fresh frame
TIMEOUT_CYCLES = 5


def timeout_s(message_name: str) -> float:
    """Reception timeout (s) of ``message_name``: :data:`TIMEOUT_CYCLES` × its cycle time."""
    return TIMEOUT_CYCLES * cycle_time_s(message_name)


def signal_range(message_name: str, signal_name: str) -> tuple[float, float]:
    """The signal's DBC [minimum, maximum], in DBC units."""
    sig = signal_layout(message_name, signal_name)
    return sig.minimum, sig.maximum


def signal_resolution(message_name: str, signal_name: str) -> float:
    """The signal's DBC scale: the physical value of one raw step, in DBC units."""
    return signal_layout(message_name, signal_name).scale


def signal_max_rate(message_name: str, signal_name: str) -> float:
    """The signal's DBC ``SigMaxRate``: the fastest change (DBC units per second) a receiver accepts."""
    rate = signal_layout(message_name, signal_name).max_rate
    if not rate:
        raise KeyError(f"{message_name}.{signal_name} has no SigMaxRate attribute")
    return rate


def enumeration(message_name: str, signal_name: str) -> Mapping[int, str]:
    """The signal's ``VAL_`` table: raw value -> name, in value order."""
    choices = choice_names(message_name, signal_name)
    if not choices:
        raise KeyError(f"{message_name}.{signal_name} has no VAL_ enumeration")
    return MappingProxyType(choices)


def _fault_signals(message_name: str = "EcuStatus") -> tuple[int, tuple[str, ...]]:
    """(start bit of fault bit 0, the one-bit ``Fault*`` signals of ``message_name`` in bit order).

    Raises ValueError unless they are one-bit signals on consecutive bits.
    """
    faults = sorted((s for s in LAYOUTS[message_name].signals if s.name.startswith("Fault")), key=lambda s: s.start)
    if not faults:
        raise ValueError(f"{message_name}: expected one-bit Fault* signals, got none")
    first = faults[0].start
    for k, sig in enumerate(faults):
        if sig.length != 1 or sig.start != first + k:
            raise ValueError(f"{message_name}.{sig.name}: expected a one-bit signal at bit {first + k}, "
                             f"got {sig.length} bits at bit {sig.start}")
    return first, tuple(sig.name for sig in faults)


def signal_dbc_per_si(message_name: str, signal_name: str) -> float:
    """DBC units per SI unit of the signal (``si = dbc / factor``; km/h: 3.6, %: 100)."""
    return dbc_per_si(signal_layout(message_name, signal_name).unit)


#: the ECU's cycle (s): SafetyOverride's GenMsgCycleTime
ECU_CYCLE_S = cycle_time_s("SafetyOverride")
#: ECU modes, value -> name (SafetyOverride.Mode)
MODE_NAMES = enumeration("SafetyOverride", "Mode")
#: strategy name (lower case) -> value of EcuStatus.Strategy
STRATEGY_CODES: Mapping[str, int] = MappingProxyType(
    {name.lower(): value for value, name in enumeration("EcuStatus", "Strategy").items()})
#: strategy names in DBC value order
STRATEGIES: tuple[str, ...] = tuple(STRATEGY_CODES)
#: fault bit k of the ECU travels as ``EcuStatus.FAULT_SIGNALS[k]``, at DBC bit FAULT_BIT0 + k
FAULT_BIT0, FAULT_SIGNALS = _fault_signals()
#: full scale of the deceleration request (m/s²): the largest deceleration the contract can carry
BRAKE_DECEL_MAX_MPS2 = signal_range("SafetyOverride", "BrakeDecelRequest")[1]

__all__ = ["BRAKE_DECEL_MAX_MPS2", "ECU_CYCLE_S", "FAULT_BIT0", "FAULT_SIGNALS", "LAYOUTS", "MODE_NAMES", "STRATEGIES", "STRATEGY_CODES",
           "TIMEOUT_CYCLES", "cycle_time_s", "enumeration", "signal_dbc_per_si", "signal_max_rate", "signal_range",
           "signal_resolution",
           "timeout_s"]
