"""The scenario reference (``docs/scenario-reference.md``), rendered from the declared keys.

``python -m cosim.scenarios.reference > docs/scenario-reference.md`` writes it;
a test fails when the committed page differs from a fresh render, so the page
cannot drift from the dataclasses (:mod:`cosim.scenarios.config`,
:class:`ecu.EcuConfig`) and the driver models (:mod:`cosim.world.driver_models`).
"""

from __future__ import annotations

import dataclasses
import inspect
import json
import re
import typing
from typing import Any

from ecu.settings import Declared, Key, _plain, keys, type_text

from ..world.driver_models import DRIVER_MODELS
from ..world.steering_models import STEERING_MODELS
from .config import Scenario
from .resolve import plain
from .toml_writer import value_text

COMMAND = "python -m cosim.scenarios.reference > docs/scenario-reference.md"

_INTRO = """\
# Scenario reference

Generated from the declared keys by `{command}`; do not edit by hand
(a test compares this page with a fresh render).

A scenario is a TOML file with the tables below, all optional. Every key is
checked at load: an unknown key, a value of the wrong type or outside its range
stops with one line naming the file and the key path, e.g.
`s.toml: radar.max_range_m: expected a value in [1, 250] m, got 500.0` or
`s.toml: plant.road_fricton: unknown key; did you mean plant.road_friction?`.
Catalogue, sweep and ECU files are checked the same way.

## Where things are: path coordinates

`x` runs along the path, in the coordinate of the plant's position output;
`y` across it, left positive. The ego's front bumper is at the plant's position
plus `[plant] front_bumper_offset_m`. The builtin plant starts with its front
bumper at x = 0, so an object's `position_m`, the position of its **rear** at
t = 0, is the initial gap between the ego's front bumper and the object. The
ego's body reaches `[plant] length_m` back from its bumper; an object occupies
`[position_m, position_m + length_m]` along the path and `lateral_m ± width_m/2`
across it. Contact needs both a longitudinal and a lateral overlap.

## The plane

The world is one frame for every scenario: the path frame above, x and y in
metres, headings counter-clockwise from x (ISO 8855, OpenDRIVE). A scenario is
*planar* when it has a `[road]`, a `[driver.steering]`, an initial pose
(`[plant] initial_y_m`, `initial_yaw_rad`) or an object placed or moved in the
plane (`target_class`, `[objects.pose]`, `[objects.road_pose]`,
`[objects.trajectory]`, `[objects.crossing]`). Then the builtin plant maps its
planar outputs (`y`, `yaw`, `yaw_rate`, `vx`, `vy`, `ax`, `ay`), its steering
inputs (the driver's `steering_wheel_angle` and the ECU's `steer_request`, the
overlay the steering gateway passes on) and its initial pose (`y0`, `yaw0`),
the run writes `scene.json` and the pose
columns (`docs/run-format.md`), and a collision records its contact point and
normal. The plant's pose point (builtin: the centre of gravity, about which
the car turns) sits `[plant] cg_to_front_m` behind the front bumper; with the
wheel straight the car stays on y = 0 and the run is the 1-D world's, bit for
bit. What the ego sees of an object (its gap, the radar's range and lateral
offset) is measured in the ego's frame, from its front bumper along its
heading (`cosim/world/scene.py`).
"""


def _markdown(text: str) -> str:
    """reStructuredText of the docstrings as Markdown: ``x`` -> `x`, :mod:`x` -> `x`."""
    return re.sub(r":[a-z]+:`~?([^`]+)`", r"`\1`", text.replace("``", "`"))


def _cell(text: str) -> str:
    return " ".join(str(text).split()).replace("|", "\\|")


def _allowed(declared: Declared) -> str:
    if declared.choices is not None:
        return ", ".join(f"`{json.dumps(c)}`" for c in declared.choices)
    return "" if declared.range is None else str(declared.range)


def _default(key: Key) -> str:
    if key.required:
        return "required"
    value = key.default
    if value is None:
        return "unset"
    if key.declared.kind is not None:
        value = key.declared.kind.dump(value)
    if isinstance(value, tuple) and value and dataclasses.is_dataclass(value[0]):
        value = [plain(v) for v in value]
    if isinstance(value, dict) and not value:
        return "`{}`"
    return f"`{value_text(value)}`"


def key_table(cls: type) -> list[str]:
    """A Markdown table of ``cls``'s declared keys: type, unit, allowed values, default, doc."""
    rows = ["| key | type | unit | allowed | default | description |", "|---|---|---|---|---|---|"]
    for key in keys(cls).values():
        kind = type_text(key).removeprefix("a ").removeprefix("an ")
        rows.append(f"| `{key.name}` | {_cell(kind)} | {_cell(key.declared.unit)} | {_cell(_allowed(key.declared))} "
                    f"| {_cell(_default(key))} | {_cell(key.declared.doc)} |")
    return rows


def _table_of(key: Key) -> tuple[type | None, bool]:
    """The dataclass a key's value is a table of (None: a plain value), and whether it is a list of tables."""
    hint = _plain(key.hint)
    if dataclasses.is_dataclass(hint):
        return hint, False
    if typing.get_origin(hint) is tuple and dataclasses.is_dataclass(_plain(typing.get_args(hint)[0])):
        return _plain(typing.get_args(hint)[0]), True
    return None, False


def _subtables(path: str, cls: type) -> list[str]:
    """``### [path.key]`` for every key of ``cls`` that is a table or a list of tables (recursively)."""
    lines = []
    for key in keys(cls).values():
        sub, many = _table_of(key)
        if sub is None or key.declared.kind is not None:
            continue
        title = f"[[{path}.{key.name}]]" if many else f"[{path}.{key.name}]"
        lines += [f"### `{title}`", "", _markdown(inspect.cleandoc(sub.__doc__ or "")), "", *key_table(sub), ""]
        lines += _subtables(f"{path}.{key.name}", sub)
    return lines


def _section(name: str, key: Key) -> list[str]:
    cls = _plain(key.hint)
    title = f"[[{name}]]" if name == "objects" else f"[{name}]"
    if name == "objects":
        return [f"## `{title}`", "", "Several objects: each `[[objects]]` table takes the keys of `[object]` "
                "(above), and its tables as `[objects.pose]` etc. With `[[objects]]` the single `[object]` is not "
                "used; give one or the other.", ""]
    own = cls.__module__.startswith("cosim.")  # [ecu] is ecu.EcuConfig: its field doc says what it is
    doc = _markdown(inspect.cleandoc(cls.__doc__ or "")) if own else \
        f"{key.declared.doc[0].upper()}{key.declared.doc[1:]} (`ecu.EcuConfig`; `crd ecu --config` reads the " \
        "same table from a scenario file)."
    return [f"## `{title}`", "", doc, "", *key_table(cls), "", *(_subtables(name, cls) if own else [])]


def _driver_models() -> list[str]:
    lines = ["## Driver models", "",
             "`[driver] model` names one of these; each maps the car's state to pedal positions once per "
             "ECU cycle and disregards the object (the paper's driver is distracted). The keys each model "
             "reads are named in the `[driver]` table above.", ""]
    for name, factory in DRIVER_MODELS.items():
        lines += [f"### `{name}`", "", _markdown(inspect.cleandoc(factory.__doc__ or "")), ""]
    lines += ["## Steering models", "", "`[driver.steering] model` names one of these; without `[driver.steering]` "
              "the wheel is held straight.", ""]
    for name, factory in STEERING_MODELS.items():
        lines += [f"### `{name}` (steering)", "", _markdown(inspect.cleandoc(factory.__doc__ or "")), ""]
    return lines


def render() -> str:
    """The whole page."""
    lines = [_INTRO.format(command=COMMAND)]
    for name, key in keys(Scenario).items():
        if dataclasses.is_dataclass(_plain(key.hint)) or name == "objects":
            lines += _section(name, key)
        if name == "driver":
            lines += _driver_models()
    return "\n".join(lines).rstrip("\n") + "\n"


def _main() -> None:
    print(render(), end="")


if __name__ == "__main__":
    _main()
