"""A small TOML writer for resolved scenarios (tomllib only reads).

Handles what a :class:`~cosim.scenarios.config.Scenario` holds: strings,
booleans, integers, floats (``repr``, so they read back bit-identical),
lists of numbers or strings, nested tables. ``None`` values are omitted.
"""

from __future__ import annotations

import json
import math
from typing import Any, Mapping


def value_text(v: Any) -> str:
    """``v`` as a TOML value (inline)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if not math.isfinite(v):
            raise ValueError(f"TOML value: expected a finite float, got {v!r}")
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)  # a JSON string is a valid TOML basic string
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(value_text(x) for x in v) + "]"
    if isinstance(v, Mapping):
        return "{ " + ", ".join(f"{_key(k)} = {value_text(x)}" for k, x in v.items() if x is not None) + " }"
    raise TypeError(f"TOML value: unsupported type {type(v).__name__}")


def _key(k: str) -> str:
    return k if k.replace("_", "").replace("-", "").isalnum() else json.dumps(k)


def dumps(data: Mapping[str, Any], header: str = "") -> str:
    """TOML text of ``data``: top-level scalars, then one ``[table]`` per mapping (recursively)."""
    lines = [f"# {line}" for line in header.splitlines()]
    _table(data, [], lines)
    return "\n".join(lines).lstrip("\n") + "\n"


def _table(data: Mapping[str, Any], path: list[str], lines: list[str]) -> None:
    scalars = {k: v for k, v in data.items() if not isinstance(v, Mapping) and v is not None}
    tables = {k: v for k, v in data.items() if isinstance(v, Mapping)}
    if path and (scalars or not tables):
        lines.append("")
        lines.append("[" + ".".join(_key(p) for p in path) + "]")
    for k, v in scalars.items():
        lines.append(f"{_key(k)} = {value_text(v)}")
    for k, v in tables.items():
        _table(v, path + [k], lines)
