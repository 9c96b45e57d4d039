"""Scenario TOML → :class:`~cosim.scenarios.config.Scenario`, strictly.

Unknown keys raise :class:`~cosim.errors.ConfigError` naming the key path
(``plant.inputs.throtle``) and, for a near miss, the closest valid name
(:func:`difflib.get_close_matches`). Values are type- and range-checked
against each field's ``metadata``. ``[ecu]`` is checked at load, by
``ecu.EcuConfig.from_dict`` (ranges, and agreement with the DBC, e.g. no
``cycle_s`` other than the contract's 10 ms); every error names the file.
"""

from __future__ import annotations

import dataclasses
import datetime as dt
import difflib
import math
import tomllib
import typing
from pathlib import Path
from types import MappingProxyType
from typing import Any, Callable, Mapping, TypeVar

from can_dbc.contract import ECU_CYCLE_S
from ecu import EcuConfig

from ..errors import ConfigError
from .config import (
    BUILTIN_INPUTS,
    BUILTIN_OUTPUTS,
    INPUT_ROLES,
    OUTPUT_ROLES,
    INITIAL_ROLES,
    ChecksConfig,
    EXPECTABLE_EVENTS,
    DriverConfig,
    EcuSection,
    EndConfig,
    GatewayConfig,
    ObjectConfig,
    PlantConfig,
    RadarConfig,
    Scenario,
    ScenarioSection,
    SignalMap,
)

T = TypeVar("T")

_SECTIONS = {
    "scenario": ScenarioSection, "plant": PlantConfig, "driver": DriverConfig,
    "object": ObjectConfig, "radar": RadarConfig, "gateway": GatewayConfig,
    "ecu": EcuSection, "checks": ChecksConfig, "end": EndConfig,
}
_ARRAYS = {"objects": ObjectConfig}  # [[name]] arrays of tables
_SPECIAL = {"parameters", "inputs", "outputs", "points", "initial"}


def _unknown(key: str, path: str, valid: typing.Iterable[str]) -> ConfigError:
    full = f"{path}.{key}" if path else key
    close = difflib.get_close_matches(key, list(valid), n=1, cutoff=0.6)
    hint = f"; did you mean {close[0]!r}?" if close else f"; expected one of {sorted(valid)}"
    return ConfigError(f"unknown key {full!r}{hint}")


def _check_keys(table: Mapping[str, Any], valid: typing.Iterable[str], path: str) -> None:
    valid = list(valid)
    for key in table:
        if key not in valid:
            raise _unknown(key, path, valid)


def _coerce(value: Any, kind: type, where: str) -> Any:
    if kind is bool:
        if not isinstance(value, bool):
            raise ConfigError(f"{where}: expected true/false, got {value!r}")
        return value
    if kind is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise ConfigError(f"{where}: expected an integer, got {value!r}")
        return value
    if kind is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise ConfigError(f"{where}: expected a finite number, got {value!r}")
        return float(value)
    if kind is str:
        if not isinstance(value, str):
            raise ConfigError(f"{where}: expected a string, got {value!r}")
        return value
    raise TypeError(f"{where}: unsupported field type {kind}")


def _base_type(hint: Any) -> type:
    args = [a for a in typing.get_args(hint) if a is not type(None)]
    return args[0] if args else hint


_EARLIEST_START = dt.datetime(1990, 1, 1, tzinfo=dt.timezone.utc)  # BLF headers treat earlier dates as unset


def _start_time(value: Any, where: str) -> str:
    """An offset date-time (TOML or ISO 8601 text) as normalised ISO 8601 text."""
    expected = "expected an ISO 8601 date-time with a UTC offset such as 2020-01-01T00:00:00Z"
    if isinstance(value, str):
        try:
            value = dt.datetime.fromisoformat(value)
        except ValueError:
            raise ConfigError(f"{where}: {expected}, got {value!r}") from None
    if not isinstance(value, dt.datetime) or value.tzinfo is None:
        shown = value.isoformat() if isinstance(value, (dt.date, dt.time)) else repr(value)
        raise ConfigError(f"{where}: {expected}, got {shown} (no offset)" if isinstance(value, dt.datetime)
                          else f"{where}: {expected}, got {shown}")
    if not _EARLIEST_START <= value < dt.datetime(2100, 1, 1, tzinfo=dt.timezone.utc):
        raise ConfigError(f"{where}: expected a date from 1990 to 2099, got {value.isoformat()}")
    return value.isoformat()


def _plain_field(f: dataclasses.Field, hint: Any, value: Any, where: str) -> Any:
    if f.metadata.get("datetime"):
        return _start_time(value, where)
    value = _coerce(value, _base_type(hint), where)
    if "range" in f.metadata:
        lo, hi = f.metadata["range"]
        if not lo <= value <= hi:
            raise ConfigError(f"{where}: expected {lo:g} <= value <= {hi:g}, got {value!r}")
    if "choices" in f.metadata and value not in f.metadata["choices"]:
        close = difflib.get_close_matches(str(value), [str(c) for c in f.metadata["choices"]], n=1)
        hint_txt = f" (did you mean {close[0]!r}?)" if close else ""
        raise ConfigError(f"{where}: expected one of {list(f.metadata['choices'])}, got {value!r}{hint_txt}")
    return value


def _signal_maps(table: Any, roles: tuple[str, ...], path: str) -> tuple[SignalMap, ...]:
    if not isinstance(table, Mapping):
        raise ConfigError(f"{path}: expected a table of role = name, got {table!r}")
    maps = []
    for role, spec in table.items():
        if role not in roles:
            raise _unknown(role, path, roles)
        where = f"{path}.{role}"
        if isinstance(spec, (str, list)):
            spec = {"name": spec}
        if not isinstance(spec, Mapping):
            raise ConfigError(f"{where}: expected a name or {{name, scale, offset}}, got {spec!r}")
        _check_keys(spec, ("name", "scale", "offset"), where)
        if "name" not in spec:
            raise ConfigError(f"{where}.name: missing; expected the FMU variable name")
        names = spec["name"] if isinstance(spec["name"], list) else [spec["name"]]
        limit = 4 if role == "wheel_speeds" else 1
        if not 1 <= len(names) <= limit or not all(isinstance(n, str) and n for n in names):
            raise ConfigError(f"{where}.name: expected 1..{limit} variable names, got {spec['name']!r}")
        scale = _coerce(spec.get("scale", 1.0), float, f"{where}.scale")
        if scale == 0.0:
            raise ConfigError(f"{where}.scale: expected a non-zero number, got 0")
        maps.append(SignalMap(role, tuple(names), scale, _coerce(spec.get("offset", 0.0), float, f"{where}.offset")))
    return tuple(maps)


def _parameters(table: Any, path: str) -> Mapping[str, Any]:
    if not isinstance(table, Mapping):
        raise ConfigError(f"{path}: expected a table, got {table!r}")
    for key, value in table.items():
        if isinstance(value, (Mapping, list)):
            raise ConfigError(f"{path}.{key}: expected a scalar, got {value!r}")
        if isinstance(value, float) and not math.isfinite(value):
            raise ConfigError(f"{path}.{key}: expected a finite number, got {value!r}")
    return MappingProxyType(dict(table))


def _points(value: Any, path: str) -> tuple[tuple[float, float, float], ...]:
    if not isinstance(value, list):
        raise ConfigError(f"{path}: expected a list of [at, accel_pct, brake_pct] rows, got {value!r}")
    rows = []
    for i, row in enumerate(value):
        where = f"{path}[{i}]"
        if not isinstance(row, list) or len(row) != 3:
            raise ConfigError(f"{where}: expected [at, accel_pct, brake_pct], got {row!r}")
        at, acc, brk = (_coerce(v, float, where) for v in row)
        for name, pct in (("accel_pct", acc), ("brake_pct", brk)):
            if not 0.0 <= pct <= 100.0:
                raise ConfigError(f"{where}: expected 0 <= {name} <= 100, got {pct!r}")
        if rows and at <= rows[-1][0]:
            raise ConfigError(f"{where}: expected 'at' increasing beyond {rows[-1][0]!r}, got {at!r}")
        rows.append((at, acc, brk))
    return tuple(rows)


def _expect_events(value: Any, path: str) -> tuple[str, ...]:
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise ConfigError(f"{path}: expected a list of event names, got {value!r}")
    for name in value:
        if name not in EXPECTABLE_EVENTS:
            close = difflib.get_close_matches(name, EXPECTABLE_EVENTS, n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise ConfigError(f"{path}: expected event names from {list(EXPECTABLE_EVENTS)}, got {name!r}{hint}")
    return tuple(dict.fromkeys(value))


def _section(cls: type, table: Any, path: str) -> Any:
    if not isinstance(table, Mapping):
        raise ConfigError(f"{path}: expected a table, got {table!r}")
    hints = typing.get_type_hints(cls)
    fields = {f.name: f for f in dataclasses.fields(cls)}
    if cls is EcuSection:  # strategy here, every other key goes to EcuConfig.from_dict
        table = dict(table)
        kwargs = {"strategy": _plain_field(fields["strategy"], str, table.pop("strategy", "tightening"),
                                           f"{path}.strategy")}
        EcuConfig.from_dict({**table, **kwargs}, where=path)  # refused here, at load, not when a run starts
        return EcuSection(parameters=MappingProxyType(table), **kwargs)
    _check_keys(table, fields, path)
    kwargs: dict[str, Any] = {}
    for key, value in table.items():
        where = f"{path}.{key}"
        if key == "parameters":
            kwargs[key] = _parameters(value, where)
        elif key == "inputs":
            kwargs[key] = _signal_maps(value, INPUT_ROLES, where)
        elif key == "outputs":
            kwargs[key] = _signal_maps(value, OUTPUT_ROLES, where)
        elif key == "initial":
            kwargs[key] = _signal_maps(value, INITIAL_ROLES, where)
        elif key == "points":
            kwargs[key] = _points(value, where)
        elif key == "expect_events":
            kwargs[key] = _expect_events(value, where)
        else:
            kwargs[key] = _plain_field(fields[key], hints[key], value, where)
    return cls(**kwargs)


def _merge_builtin(plant: PlantConfig, given: Mapping[str, Any]) -> PlantConfig:
    """The builtin plant has default mappings; a given role replaces its default."""
    if plant.fmu != "builtin":
        return plant
    inputs = {m.role: m for m in BUILTIN_INPUTS} | {m.role: m for m in plant.inputs if "inputs" in given}
    if "accel_command" in inputs:
        raise ConfigError("plant.inputs.accel_command: the builtin plant takes throttle and brake, not accel_command")
    outputs = {m.role: m for m in BUILTIN_OUTPUTS} | {m.role: m for m in plant.outputs if "outputs" in given}
    return dataclasses.replace(plant, inputs=tuple(inputs.values()), outputs=tuple(outputs.values()))


def _arrays(data: Mapping[str, Any]) -> dict[str, Any]:
    """``[[objects]]``: a list of tables; with it, the single ``[object]`` is disabled."""
    out: dict[str, Any] = {}
    for name, cls in _ARRAYS.items():
        if name not in data:
            continue
        if "object" in data:
            raise ConfigError(f"{name}: expected either [object] or [[{name}]], got both")
        rows = data[name]
        if not isinstance(rows, list) or not rows:
            raise ConfigError(f"{name}: expected one or more [[{name}]] tables, got {rows!r}")
        out[name] = tuple(_section(cls, row, f"{name}[{i}]") for i, row in enumerate(rows))
        out["object"] = ObjectConfig(enabled=False)
    return out


def _check_initial(plant: PlantConfig) -> None:
    if plant.initial_speed_mps > 0.0 and not plant.initial:
        raise ConfigError("plant.initial_speed_mps: this FMU has no [plant.initial] speed mapping;"
                          " expected [plant.initial] speed = \"<parameter name>\"")
    for m in plant.initial:
        if m.names[0] in plant.parameters and plant.initial_speed_mps > 0.0:
            raise ConfigError(f"plant.parameters.{m.names[0]}: set by plant.initial_speed_mps"
                              f" through [plant.initial] {m.role}; expected only one of the two")


def _check_plant_roles(plant: PlantConfig) -> None:
    roles_in = {m.role for m in plant.inputs}
    if "accel_command" in roles_in and roles_in & {"throttle", "brake"}:
        raise ConfigError("plant.inputs: expected either accel_command or throttle/brake, got both")
    if "accel_command" not in roles_in and not {"throttle", "brake"} <= roles_in:
        raise ConfigError(f"plant.inputs: expected throttle and brake (or accel_command), got {sorted(roles_in)}")
    missing = {"position", "speed"} - {m.role for m in plant.outputs}
    if missing:
        raise ConfigError(f"plant.outputs: expected position and speed to be mapped, missing {sorted(missing)}")


def scenario_from_dict(data: Mapping[str, Any], base_dir: Path | None = None) -> Scenario:
    """Build and check a :class:`Scenario` from parsed TOML.

    A relative ``plant.fmu`` path is resolved against ``base_dir``.
    """
    _check_keys(data, list(_SECTIONS) + list(_ARRAYS), "")
    sections = {name: _section(cls, data[name], name) for name, cls in _SECTIONS.items() if name in data}
    sections.update(_arrays(data))
    plant = sections.get("plant", PlantConfig())
    if "plant" in data and plant.fmu == "builtin":
        plant = _merge_builtin(plant, data["plant"])
    elif plant.fmu != "builtin":
        if "inputs" not in data.get("plant", {}) or "outputs" not in data.get("plant", {}):
            raise ConfigError("plant: a third-party FMU needs [plant.inputs] and [plant.outputs]")
        if base_dir is not None and not Path(plant.fmu).is_absolute():
            plant = dataclasses.replace(plant, fmu=str((base_dir / plant.fmu).resolve()))
        if "initial" not in data["plant"]:
            plant = dataclasses.replace(plant, initial=())
    _check_plant_roles(plant)
    _check_initial(plant)
    sections["plant"] = plant
    scen = sections.get("scenario", ScenarioSection())
    cycles = ECU_CYCLE_S / scen.step_s
    if abs(cycles - round(cycles)) > 1e-9:
        raise ConfigError(f"scenario.step_s: expected a divisor of the {ECU_CYCLE_S} s ECU cycle, got {scen.step_s!r}")
    return Scenario(**sections)


def load_toml_file(path: Path, build: Callable[[dict], T], what: str) -> T:
    """``build(parsed TOML)``; a missing file, bad TOML or a :class:`ConfigError` becomes one ConfigError naming the file.

    Shared by the scenario, sweep and catalogue loaders (``what`` names the kind of file).
    """
    try:
        data = tomllib.loads(path.read_text())
    except FileNotFoundError:
        raise ConfigError(f"{path}: {what} file not found") from None
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path}: invalid TOML: {exc}") from None
    try:
        return build(data)
    except ConfigError as exc:
        raise ConfigError(f"{path}: {exc}") from None


def load_scenario(path: str | Path) -> Scenario:
    """Read and check a scenario TOML file; errors are :class:`ConfigError` with the file name."""
    path = Path(path)
    return load_toml_file(path, lambda data: scenario_from_dict(data, base_dir=path.parent), "scenario")
