"""The contract's DBC, loaded once and strictly, and the layout tables built from it.

``DBC_PATH`` is the file; ``DATABASE`` the ``cantools`` database loaded with
``strict=True`` (overlapping signals or signals outside the frame are errors),
parsed on first use: the tables below come from a cache of that parse
(:mod:`can_dbc.table_cache`, keyed by the DBC's hash, this module's source and
the cantools version; rebuilt when stale or corrupt), so a process that only encodes and checks frames never imports cantools.
``LAYOUTS`` maps each message name to a :class:`MessageLayout`, a precomputed
table that lets :mod:`can_dbc.codec` and :mod:`can_dbc.receiver` encode and
decode a frame with integer shifts and masks only. All messages are classic
CAN, 11-bit IDs, DLC 8, little-endian (Intel) signals.

The SecOC authenticator messages (attribute ``SecOCAuthenticates``, see
:mod:`can_dbc.secoc`) carry no E2E header; they are kept out of ``LAYOUTS``
and listed in ``AUTHENTICATORS`` (protected message name -> authenticator ID).
"""

from __future__ import annotations

import importlib.metadata
import logging
import math
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import Any, Mapping

from . import table_cache
from .crc import data_id_seed

log = logging.getLogger(__name__)

DBC_PATH: Path = Path(__file__).with_name("active_safety.dbc")

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
    #: the DBC's ``SigMaxRate`` (DBC units per second): the fastest change a receiver accepts; 0 = unlimited
    max_rate: float = 0.0


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


def _signal_layout(signal: dict[str, Any]) -> SignalLayout:
    if signal["byte_order"] != "little_endian":
        raise ValueError(f"signal {signal['name']}: expected little_endian, got {signal['byte_order']}")
    scale = float(signal["scale"])
    offset = float(signal["offset"])
    minimum = float(signal["minimum"])
    maximum = float(signal["maximum"])
    raw_min = math.ceil(round((minimum - offset) / scale, 9))
    raw_max = math.floor(round((maximum - offset) / scale, 9))
    return SignalLayout(
        name=signal["name"],
        start=signal["start"],
        length=signal["length"],
        signed=signal["signed"],
        scale=scale,
        offset=offset,
        minimum=minimum,
        maximum=maximum,
        raw_min=raw_min,
        raw_max=raw_max,
        is_integer=scale == 1.0 and offset == 0.0,
        choices=frozenset(int(value) for value, _name in signal["choices"]),
        unit=signal["unit"],
        max_rate=float(signal["max_rate"]),
    )


def _message_layout(message: dict[str, Any]) -> MessageLayout:
    name = message["name"]
    if message["extended"] or message["length"] != FRAME_LENGTH:
        raise ValueError(f"message {name}: expected 11-bit ID and DLC 8")
    names = [s["name"] for s in message["signals"]]
    e2e = e2e_signal_names(name)
    if names[:2] != list(e2e):
        raise ValueError(f"message {name}: expected {e2e[0]}, {e2e[1]} first, got {names[:2]}")
    crc, counter = message["signals"][:2]
    if (crc["start"], crc["length"], counter["start"], counter["length"]) != (0, 8, 8, 4):
        raise ValueError(f"message {name}: expected {e2e[0]} at bit 0 (8 bits), {e2e[1]} at bit 8 (4 bits)")
    signals = tuple(_signal_layout(s) for s in message["signals"][2:])
    masks = [(1 << sig.length) - 1 for sig in signals]
    return MessageLayout(
        name=name,
        frame_id=message["frame_id"],
        length=message["length"],
        cycle_time_ms=message["cycle_time_ms"],
        senders=tuple(message["senders"]),
        signals=signals,
        pack_table=tuple((s.name, s.start, m, s.scale, s.offset, s.raw_min, s.raw_max)
                         for s, m in zip(signals, masks)),
        unpack_table=tuple((s.name, s.start, m, (1 << (s.length - 1)) if s.signed else 0, s.raw_min, s.raw_max,
                            s.scale, s.offset, s.is_integer, s.choices) for s, m in zip(signals, masks)),
        crc_seed=data_id_seed(message["frame_id"]),
    )


# -- reading the DBC (cantools), or its cached extract ---------------------------------------
def _parse():
    """The DBC loaded by cantools with ``strict=True`` (imported only here: it costs 20 to 80 ms)."""
    import cantools

    return cantools.database.load_file(str(DBC_PATH), strict=True)


def _authenticates(message) -> int | None:
    attribute = message.dbc.attributes.get("SecOCAuthenticates") if message.dbc else None
    return int(attribute.value) if attribute is not None and int(attribute.value) else None


def _max_rate(signal) -> float:
    attribute = signal.dbc.attributes.get("SigMaxRate") if signal.dbc else None
    return float(attribute.value) if attribute is not None else 0.0


def _extract(database) -> list[dict[str, Any]]:
    """What the tables below need of each message of ``database``, as plain JSON-able data."""
    return [{"name": m.name, "frame_id": m.frame_id, "extended": m.is_extended_frame, "length": m.length,
             "cycle_time_ms": m.cycle_time, "senders": list(m.senders), "send_type": m.send_type,
             "authenticates": _authenticates(m),
             "signals": [{"name": s.name, "start": s.start, "length": s.length, "byte_order": s.byte_order,
                          "signed": s.is_signed, "scale": s.scale, "offset": s.offset, "minimum": s.minimum,
                          "maximum": s.maximum, "unit": s.unit or "", "max_rate": _max_rate(s),
                          "choices": [[int(k), str(v)] for k, v in sorted((s.choices or {}).items())]}
                         for s in m.signals]}
            for m in database.messages]


def _layouts(messages: list[dict[str, Any]]) -> dict[str, MessageLayout]:
    return {m["name"]: _message_layout(m) for m in messages if m["authenticates"] is None}


def _cache_key() -> str:
    return table_cache.cache_key(DBC_PATH.read_bytes(), Path(__file__).read_bytes(),
                                 importlib.metadata.version("cantools").encode())


def _load(paths: tuple[Path, ...] | None = None) -> tuple[list[dict[str, Any]], dict[str, MessageLayout]]:
    """The DBC's messages and layouts: from the cache when it is current and sound, else parsed (and cached)."""
    key = _cache_key()
    paths = paths or table_cache.cache_paths(DBC_PATH.parent, key)
    cached, path = table_cache.read_first(paths, key)
    if cached is not None:
        try:
            return cached, _layouts(cached)
        except (KeyError, TypeError, ValueError, IndexError) as exc:  # sound JSON of a wrong shape
            log.warning("%s: unusable (%r); rebuilding it", path, exc)
    database = _parse()
    messages = _extract(database)
    layouts = _layouts(messages)  # a DBC that breaks the contract raises here, cache or not
    table_cache.write_first(paths, key, messages)
    globals()["DATABASE"] = database  # parsed anyway: spare a second parse
    return messages, layouts


_MESSAGES, _LAYOUTS = _load()
_NAMES_BY_ID = {m["frame_id"]: m["name"] for m in _MESSAGES}

LAYOUTS: Mapping[str, MessageLayout] = MappingProxyType(_LAYOUTS)
#: protected message name -> the arbitration ID of its SecOC authenticator frame.
AUTHENTICATORS: Mapping[str, int] = MappingProxyType(
    {_NAMES_BY_ID[m["authenticates"]]: m["frame_id"] for m in _MESSAGES if m["authenticates"] is not None}
)
#: messages sent periodically (``GenMsgSendType`` Cyclic); only these are rate-monitored.
CYCLIC: frozenset[str] = frozenset(m["name"] for m in _MESSAGES
                                   if m["send_type"] != "OnEvent" and m["name"] in LAYOUTS)
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


def choice_names(message_name: str, signal_name: str) -> dict[int, str]:
    """The signal's ``VAL_`` table, raw value -> name in value order (empty: not an enumeration)."""
    for message in _MESSAGES:
        if message["name"] == message_name:
            for sig in message["signals"]:
                if sig["name"] == signal_name:
                    return {int(value): name for value, name in sig["choices"]}
            raise KeyError(f"{message_name} has no signal {signal_name!r}")
    raise KeyError(f"the DBC has no message {message_name!r}")


def __getattr__(name: str) -> Any:
    """``DATABASE``: the cantools database, parsed on first use (the CLI's listing and the exports)."""
    if name == "DATABASE":
        globals()["DATABASE"] = _parse()
        return globals()["DATABASE"]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
