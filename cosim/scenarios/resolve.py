"""A :class:`~cosim.scenarios.config.Scenario` back to a plain mapping / TOML text.

The resolved file reads back through :func:`cosim.scenarios.loader.scenario_from_dict`
to an equal scenario, so a run can be repeated exactly.
"""

from __future__ import annotations

import dataclasses
from typing import Any

from .config import Scenario, SignalMap
from .toml_writer import dumps


def _maps(maps: tuple[SignalMap, ...]) -> dict[str, Any]:
    return {m.role: {"name": list(m.names) if m.role == "wheel_speeds" else m.names[0],
                     "scale": m.scale, "offset": m.offset} for m in maps}


def scenario_to_dict(scenario: Scenario, strategy: str | None = None) -> dict[str, Any]:
    """Plain nested dict of every resolved value (defaults included)."""
    out: dict[str, Any] = {}
    for section in dataclasses.fields(scenario):
        value = getattr(scenario, section.name)
        if section.name == "objects":
            if value:  # [[objects]] replaces [object]
                out.pop("object", None)
                out["objects"] = [_table(section.name, o) for o in value]
            continue
        out[section.name] = _table(section.name, value)
    if strategy is not None:
        out["ecu"]["strategy"] = strategy
    return out


def _table(section: str, value: Any) -> dict[str, Any]:
    table: dict[str, Any] = {}
    for f in dataclasses.fields(value):
        v = getattr(value, f.name)
        if f.name in ("inputs", "outputs", "initial"):
            table[f.name] = _maps(v)
        elif f.name == "parameters":
            if section == "ecu":
                table.update(v)
            else:
                table[f.name] = dict(v)
        elif f.name == "points":
            table[f.name] = [list(row) for row in v]
        else:
            table[f.name] = v
    return table


def scenario_to_toml(scenario: Scenario, strategy: str | None = None, header: str = "") -> str:
    return dumps(scenario_to_dict(scenario, strategy), header=header)
