"""crd's own keys carried in OpenSCENARIO ``<Property>`` elements, as TOML values.

OpenSCENARIO has no words for a radar's latency or an ECU's strategy; its
``<Properties>`` are the place the standard leaves for such data. crd writes
and reads there, each value as a TOML value text (``0.1``, ``"tightening"``,
``["ecu_lost"]``, ``{ name = "x", scale = 1.0, offset = 0.0 }``):

* the ego's ``<Vehicle>``: ``crd.<section>.<key>`` for every section but
  ``[driver]`` and the objects (``crd.radar.latency_s``, ``crd.plant.parameters.v0``);
* the ego's ``<Controller name="crd_driver">``: ``[driver]`` keys by their own names;
* an object's ``<Vehicle>``/``<Pedestrian>``: ``crd.<key>`` for object keys the
  standard elements do not express (``crd.brake_ramp_s``).

Names without the ``crd.`` prefix belong to other tools and are left to them.
"""

from __future__ import annotations

import tomllib
from typing import Any, Iterator, Mapping

from ..toml_writer import value_text
from .xml_source import Element, fail

PREFIX = "crd."


def toml_value(text: str, elem: Element) -> Any:
    """A property's value text as a TOML value."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        raise fail(elem, f"property {elem.get('name')}: expected a TOML value, got {text!r}") from None


def nested(props: Mapping[str, tuple[str, Element]], prefix: str = PREFIX,
           origins: dict[str, Element] | None = None) -> dict[str, Any]:
    """The properties named ``prefix<a.b.c>`` as a nested mapping ``{a: {b: {c: value}}}``.

    ``origins`` collects each key path's element, so a loader error can name the property's line.
    """
    out: dict[str, Any] = {}
    for name, (text, elem) in props.items():
        if not name.startswith(prefix) or name == prefix:
            continue
        path = name[len(prefix):].split(".")
        table = out
        for part in path[:-1]:
            table = table.setdefault(part, {})
            if not isinstance(table, dict):
                raise fail(elem, f"property {name}: {part} is a value, not a table")
        table[path[-1]] = toml_value(text, elem)
        if origins is not None:
            origins[".".join(path)] = elem
    return out


def flat(data: Mapping[str, Any], prefix: str = PREFIX) -> Iterator[tuple[str, str]]:
    """``(name, TOML value text)`` for every leaf of a nested mapping (None values left out)."""
    for key, value in data.items():
        if isinstance(value, Mapping) and value:
            yield from flat(value, f"{prefix}{key}.")
        elif value is not None:
            yield f"{prefix}{key}", value_text(value)


def changed(data: Mapping[str, Any], default: Mapping[str, Any]) -> dict[str, Any]:
    """The leaves of ``data`` that differ from ``default`` (nested, same shape)."""
    out: dict[str, Any] = {}
    for key, value in data.items():
        base = default.get(key)
        if isinstance(value, Mapping) and isinstance(base, Mapping):
            sub = changed(value, base)
            if sub:
                out[key] = sub
        elif value != base or type(value) is not type(base):
            out[key] = value
    return out
