"""Scenario values that are not plain scalars or tables: each a :class:`ecu.settings.Kind`.

A field declared with one of these kinds is parsed by the kind's ``parse``
(which names the key path in every error, in the one format of
:mod:`ecu.settings`) and written back by its ``dump``
(:mod:`cosim.scenarios.resolve`): FMU start values, signal maps (``[plant.inputs]`` and the like),
the scripted driver's breakpoint table, the start time, and the list of
expected fault events.
"""

from __future__ import annotations

import datetime as dt
import math
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, Mapping

from ecu.settings import Kind, SettingError, check_keys, near_miss


@dataclass(frozen=True)
class SignalMap:
    """One role of ``[plant.inputs]``/``[plant.outputs]`` mapped to FMU variables.

    Outputs: ``si = fmu_value * scale + offset``.
    Inputs: ``fmu_value = role_value * scale + offset``.
    ``names`` has one entry, except ``wheel_speeds`` (1 to 4 names, rad/s after scaling).
    """

    role: str
    names: tuple[str, ...]
    scale: float = 1.0
    offset: float = 0.0


def _start_values(table: Any, where: str) -> Mapping[str, Any]:
    """FMU start values: any scalar (bool, integer, finite float or string) under any name."""
    if not isinstance(table, Mapping):
        raise SettingError(where, f"expected a table, got {table!r}")
    for key, value in table.items():
        if isinstance(value, (Mapping, list)):
            raise SettingError(f"{where}.{key}", f"expected a scalar, got {value!r}")
        if isinstance(value, float) and not math.isfinite(value):
            raise SettingError(f"{where}.{key}", f"expected a finite number, got {value!r}")
    return MappingProxyType(dict(table))


#: a free mapping of FMU start values: the FMU defines the names (checked when the plant opens,
#: :mod:`cosim.world.plant_fmu`; a sweep lists them from the model description, :mod:`cosim.sweep.plan`)
FMU_START_VALUES = Kind("table of FMU parameter name = start value (any scalar)", _start_values, dict)


def _number(value: Any, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise SettingError(where, f"expected a finite number, got {value!r}")
    return float(value)


def _signal_map(role: str, spec: Any, where: str) -> SignalMap:
    if isinstance(spec, (str, list)):
        spec = {"name": spec}
    if not isinstance(spec, Mapping):
        raise SettingError(where, f"expected a name or {{name, scale, offset}}, got {spec!r}")
    check_keys(spec, ("name", "scale", "offset"), where)
    if "name" not in spec:
        raise SettingError(f"{where}.name", "missing; expected the FMU variable name")
    names = spec["name"] if isinstance(spec["name"], list) else [spec["name"]]
    limit = 4 if role == "wheel_speeds" else 1
    if not 1 <= len(names) <= limit or not all(isinstance(n, str) and n for n in names):
        raise SettingError(f"{where}.name", f"expected 1..{limit} variable names, got {spec['name']!r}")
    scale = _number(spec.get("scale", 1.0), f"{where}.scale")
    if scale == 0.0:
        raise SettingError(f"{where}.scale", "expected a non-zero number, got 0")
    return SignalMap(role, tuple(names), scale, _number(spec.get("offset", 0.0), f"{where}.offset"))


def signal_maps(roles: tuple[str, ...]) -> Kind:
    """A table ``role = "name"`` or ``role = {name, scale, offset}`` for the given roles."""
    def parse(table: Any, where: str) -> tuple[SignalMap, ...]:
        check_keys(table, roles, where)
        return tuple(_signal_map(role, spec, f"{where}.{role}") for role, spec in table.items())

    def dump(maps: tuple[SignalMap, ...]) -> dict[str, Any]:
        return {m.role: {"name": list(m.names) if m.role == "wheel_speeds" else m.names[0],
                         "scale": m.scale, "offset": m.offset} for m in maps}

    return Kind(f"table of role = FMU variable name or {{name, scale, offset}}; roles: {', '.join(roles)}",
                parse, dump)


def _points(value: Any, where: str) -> tuple[tuple[float, float, float], ...]:
    if not isinstance(value, list):
        raise SettingError(where, f"expected a list of [at, accel_pct, brake_pct] rows, got {value!r}")
    rows: list[tuple[float, float, float]] = []
    for i, row in enumerate(value):
        here = f"{where}[{i}]"
        if not isinstance(row, list) or len(row) != 3:
            raise SettingError(here, f"expected [at, accel_pct, brake_pct], got {row!r}")
        at, acc, brk = (_number(v, here) for v in row)
        for name, pct in (("accel_pct", acc), ("brake_pct", brk)):
            if not 0.0 <= pct <= 100.0:
                raise SettingError(here, f"expected 0 <= {name} <= 100, got {pct!r}")
        if rows and at <= rows[-1][0]:
            raise SettingError(here, f"expected 'at' increasing beyond {rows[-1][0]!r}, got {at!r}")
        rows.append((at, acc, brk))
    return tuple(rows)


POINTS = Kind("list of [at, accel_pct, brake_pct] rows, at increasing", _points,
              lambda rows: [list(row) for row in rows])

_EARLIEST_START = dt.datetime(1990, 1, 1, tzinfo=dt.timezone.utc)  # BLF headers treat earlier dates as unset
_LATEST_START = dt.datetime(2100, 1, 1, tzinfo=dt.timezone.utc)


def _start_time(value: Any, where: str) -> str:
    """An offset date-time (TOML or ISO 8601 text) as normalised ISO 8601 text."""
    expected = "expected an ISO 8601 date-time with a UTC offset such as 2020-01-01T00:00:00Z"
    if isinstance(value, str):
        try:
            value = dt.datetime.fromisoformat(value)
        except ValueError:
            raise SettingError(where, f"{expected}, got {value!r}") from None
    if not isinstance(value, dt.datetime) or value.tzinfo is None:
        shown = value.isoformat() if isinstance(value, (dt.date, dt.time)) else repr(value)
        raise SettingError(where, f"{expected}, got {shown}" + (" (no offset)" if isinstance(value, dt.datetime)
                                                                else ""))
    if not _EARLIEST_START <= value < _LATEST_START:
        raise SettingError(where, f"expected a date from 1990 to 2099, got {value.isoformat()}")
    return value.isoformat()


START_TIME = Kind("date-time with a UTC offset (TOML or ISO 8601 text), 1990 to 2099", _start_time)


def event_names(events: tuple[str, ...]) -> Kind:
    """A list of names from ``events`` (repeats kept once)."""
    def parse(value: Any, where: str) -> tuple[str, ...]:
        if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
            raise SettingError(where, f"expected a list of event names, got {value!r}")
        for name in value:
            if name not in events:
                near = near_miss(name, events)
                hint = f"; did you mean {near!r}?" if near else ""
                raise SettingError(where, f"expected event names from {list(events)}, got {name!r}{hint}")
        return tuple(dict.fromkeys(value))

    return Kind(f"list of event names from: {', '.join(events)}", parse, list)
