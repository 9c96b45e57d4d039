"""Key paths over a scenario mapping: ``plant.road_friction``, ``objects[0].speed_mps``.

A key path is dot-separated names, each optionally followed by list indices
(``name[i][j]``). :func:`parse` splits it into steps (``str`` for a table key,
``int`` for a list index); :func:`check` walks it over a *schema view* of the
scenario (every key the scenario knows, with its current value) and raises
a :class:`~ecu.settings.SettingError` naming the path, in the one format of the
configuration loader (:func:`ecu.settings.unknown_key` for a near miss); :func:`assign` writes a value into a plain
mapping at that path. Nothing here knows the scenario's sections: the resolver
is generic over nested tables and lists, so new sections or arrays of tables
resolve without change.
"""

from __future__ import annotations

import re
from typing import Any, Mapping, MutableMapping, Sequence

from ecu.settings import SettingError, unknown_key

Step = str | int
_SEGMENT = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)((?:\[\d+\])*)$")


def parse(path: str) -> tuple[Step, ...]:
    """``"objects[0].speed_mps"`` -> ``("objects", 0, "speed_mps")``; a malformed path is a ConfigError."""
    if not isinstance(path, str) or not path:
        raise SettingError("", f"expected a non-empty key path such as 'plant.road_friction', got {path!r}")
    steps: list[Step] = []
    for segment in path.split("."):
        match = _SEGMENT.match(segment)
        if match is None:
            raise SettingError("", f"expected a key path of name or name[index] segments, got {path!r}")
        steps.append(match.group(1))
        steps.extend(int(i) for i in re.findall(r"\[(\d+)\]", match.group(2)))
    return tuple(steps)


def render(steps: Sequence[Step]) -> str:
    """The inverse of :func:`parse`."""
    out = ""
    for step in steps:
        out += f"[{step}]" if isinstance(step, int) else (f".{step}" if out else step)
    return out


def check(schema: Mapping[str, Any], path: str) -> Any:
    """Walk ``path`` over ``schema``; return the value found there (the base value).

    An unknown key raises the loader's ``a.b: unknown key; did you mean a.c?`` error;
    an index on a non-list or past the end, or a key below a scalar, names the path.
    """
    steps = parse(path)
    node: Any = schema
    for n, step in enumerate(steps):
        here, there = render(steps[:n]), render(steps[:n + 1])
        if isinstance(step, int):
            if not isinstance(node, list):
                raise SettingError(there, f"expected a list to index, {here} is {_what(node)}")
            if step >= len(node):
                raise SettingError(there, f"index out of range; {here} has {len(node)} entries")
            node = node[step]
        else:
            if not isinstance(node, Mapping):
                raise SettingError(there, f"expected a table, {here} is {_what(node)}")
            if step not in node:
                raise unknown_key(here, step, node.keys())
            node = node[step]
    if isinstance(node, (Mapping, list)):
        raise SettingError(path, f"expected a single value, got {_what(node)}")
    return node


def _what(node: Any) -> str:
    return "a table" if isinstance(node, Mapping) else "a list" if isinstance(node, list) else f"a value ({node!r})"


def assign(mapping: MutableMapping[str, Any], path: str, value: Any) -> None:
    """Set ``value`` at ``path`` in ``mapping`` (plain dicts and lists), creating missing tables."""
    steps = parse(path)
    node: Any = mapping
    for step, nxt in zip(steps, steps[1:]):
        if isinstance(step, int):
            node = node[step]
        else:
            node = node.setdefault(step, [] if isinstance(nxt, int) else {})
    node[steps[-1]] = value
