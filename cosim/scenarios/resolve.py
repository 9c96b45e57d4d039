"""A :class:`~cosim.scenarios.config.Scenario` back to a plain mapping / TOML text.

Generic over the declared keys (:func:`ecu.settings.keys`): a nested
dataclass becomes a table, a list of them an array of tables, a field with a
:class:`~ecu.settings.Kind` is written by the kind's ``dump``. The resolved
file reads back through :func:`cosim.scenarios.loader.scenario_from_dict` to an
equal scenario, so a run can be repeated exactly.
"""

from __future__ import annotations

import dataclasses
from typing import Any, Mapping

from ecu.settings import keys

from .config import Scenario
from .planar_rules import PLACEMENTS, replaced_keys
from .toml_writer import dumps


#: ``[ecu]`` keys the scene gives (``Scenario.equipment``): not written, since reading the file back derives them
#: again (and so a sweep's run keys and seeds, hashed from this mapping, stay as they were before the key existed)
DERIVED_ECU_KEYS = ("equipment",)


def scenario_to_dict(scenario: Scenario, strategy: str | None = None) -> dict[str, Any]:
    """Plain nested dict of every resolved value (defaults included; not the scene's ``DERIVED_ECU_KEYS``)."""
    out = plain(scenario)
    for key in DERIVED_ECU_KEYS:
        del out["ecu"][key]
    out.pop("object" if out["objects"] else "objects")  # [[objects]] replaces [object]
    for table in out.get("objects") or [out.get("object") or {}]:
        _drop_replaced(table)
    if strategy is not None:
        out["ecu"]["strategy"] = strategy
    return out


def _drop_replaced(table: dict[str, Any]) -> None:
    """An object placed by a planar placement keeps only its keys: the file reads back (the loader refuses
    a placement given with the keys it replaces, :func:`cosim.scenarios.planar_rules.replaced_keys`)."""
    for placement in (p for p in PLACEMENTS if table.get(p) is not None):
        for key in replaced_keys(placement):
            table.pop(key, None)


def plain(obj: Any) -> Any:
    """A declared dataclass as nested dicts of its keys' values, in declaration order."""
    table: dict[str, Any] = {}
    for key in keys(type(obj)).values():
        value = getattr(obj, key.name)
        if key.declared.kind is not None:
            value = key.declared.kind.dump(value)
        elif dataclasses.is_dataclass(value):
            value = plain(value)
        elif isinstance(value, tuple) and value and dataclasses.is_dataclass(value[0]):
            value = [plain(v) for v in value]
        elif isinstance(value, Mapping):
            value = dict(value)
        table[key.name] = value
    return table


def scenario_to_toml(scenario: Scenario, strategy: str | None = None, header: str = "") -> str:
    return dumps(scenario_to_dict(scenario, strategy), header=header)
