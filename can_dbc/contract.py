"""Timing, limits, names and units of the contract, read from the DBC (the only source).

Every other package takes these facts from here instead of restating them:

* cycle times from ``GenMsgCycleTime``: :data:`ECU_CYCLE_S` (``SafetyOverride``,
  10 ms: the ECU's cycle and the co-simulation's lock-step), :func:`cycle_time_s`;
* reception timeouts, :func:`timeout_s` = :data:`TIMEOUT_CYCLES` missed cycles
  of the message (50 ms for the 10 ms messages, 250 ms for ``ObjectTrack``);
* signal ranges, :func:`signal_range` (the DBC's [minimum, maximum]), e.g.
  :data:`BRAKE_DECEL_MAX_MPS2` = 15 m/s², the full scale of ``BrakeDecelRequest``;
* enumerations from ``VAL_``, :func:`enumeration`: :data:`MODE_NAMES`
  (``SafetyOverride.Mode``) and :data:`STRATEGY_CODES` (``EcuStatus.Strategy``,
  lower-cased: ``none``, ``conservative``, ``tightening``; a value added to the
  DBC's ``VAL_`` is a strategy everywhere);
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


def enumeration(message_name: str, signal_name: str) -> Mapping[int, str]:
    """The signal's ``VAL_`` table: raw value -> name, in value order."""
    choices = choice_names(message_name, signal_name)
    if not choices:
        raise KeyError(f"{message_name}.{signal_name} has no VAL_ enumeration")
    return MappingProxyType(choices)


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
#: full scale of the deceleration request (m/s²): the largest deceleration the contract can carry
BRAKE_DECEL_MAX_MPS2 = signal_range("SafetyOverride", "BrakeDecelRequest")[1]

__all__ = ["BRAKE_DECEL_MAX_MPS2", "ECU_CYCLE_S", "LAYOUTS", "MODE_NAMES", "STRATEGIES", "STRATEGY_CODES",
           "TIMEOUT_CYCLES", "cycle_time_s", "enumeration", "signal_dbc_per_si", "signal_range", "signal_resolution",
           "timeout_s"]
