"""``scene.json``: the static part of a run's bird's-eye view (the road, the ego's and the objects' boxes).

The format is documented in ``docs/run-format.md`` (``"format": "crd-scene/1"``). The road is
written as OpenDRIVE's plan view and lane sections (:mod:`cosim.world.road`), so it reads back
into the same :class:`~cosim.world.road.Road`. Bad input raises :class:`~cosim.errors.ConfigError`
naming the key path and the file.
"""

from __future__ import annotations

import dataclasses
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import ConfigError
from ..scenarios.config import Scenario
from ..world.scene_build import build_road
from ..world.reference_line import Arc, Line, Placed, PlanView, Spiral
from ..world.road import Lane, LaneSection, LaneWidth, Road

SCENE_FORMAT = "crd-scene/1"
#: geometry kind in scene.json -> segment class (its fields are the keys)
SEGMENT_KINDS: dict[str, type] = {"line": Line, "arc": Arc, "spiral": Spiral}


@dataclass(frozen=True, slots=True)
class Body:
    """A box in the view: name, kind (``ego`` or a target class), size (m), and ``front_m``: from the pose point
    of its time series forward to its front (``length_m / 2``: the pose is the box's centre)."""

    name: str
    kind: str
    length_m: float
    width_m: float
    front_m: float


@dataclass(frozen=True)
class SceneFile:
    """What ``scene.json`` holds."""

    road: Road | None
    ego: Body
    objects: tuple[Body, ...]


# -- writing -------------------------------------------------------------------------------------------
def road_to_dict(road: Road) -> dict:
    geometry = []
    for p in road.plan.placed:
        kind = next(k for k, cls in SEGMENT_KINDS.items() if isinstance(p.segment, cls))
        fields = {f.name: getattr(p.segment, f.name) for f in dataclasses.fields(p.segment) if f.init}
        geometry.append({"kind": kind, "s_m": p.s_m, "x_m": p.x_m, "y_m": p.y_m, "heading_rad": p.heading_rad,
                         **fields})
    sections = [{"s_m": sec.s_m, "left": [_lane_dict(ln) for ln in sec.left],
                 "right": [_lane_dict(ln) for ln in sec.right]} for sec in road.sections]
    return {"geometry": geometry, "lane_sections": sections}


def _lane_dict(lane: Lane) -> dict:
    return {"type": lane.type, "widths": [dataclasses.asdict(w) for w in lane.widths]}


def scene_to_dict(scene: SceneFile) -> dict:
    return {"format": SCENE_FORMAT, "road": None if scene.road is None else road_to_dict(scene.road),
            "ego": _body_dict(scene.ego), "objects": [_body_dict(b) for b in scene.objects]}


def _body_dict(body: Body) -> dict:
    return {"name": body.name, "class": body.kind, "length_m": body.length_m, "width_m": body.width_m,
            "front_m": body.front_m}


def write_scene(path: Path, scene: SceneFile) -> None:
    Path(path).write_text(json.dumps(scene_to_dict(scene), indent=2) + "\n")


def scene_of(scenario: Scenario) -> SceneFile:
    """The ``scene.json`` of a planar run of ``scenario``: its road, the ego's box about the plant's pose point,
    the objects' boxes about their centres (the pose columns the loop writes, cosim.results.run_record)."""
    plant = scenario.plant
    ego = Body("ego", "ego", plant.length_m, plant.width_m, plant.front_m)
    objects = tuple(Body(o.name, o.target_class or "object", o.length_m, o.width_m, o.length_m / 2.0)
                    for o in scenario.scene_objects())
    return SceneFile(build_road(scenario.road), ego, objects)


# -- reading -------------------------------------------------------------------------------------------
class JsonReader:
    """Typed access to a JSON tree, with errors naming the key path and the file."""

    def __init__(self, source: str) -> None:
        self.source = source

    def fail(self, where: str, expected: str, got: Any) -> ConfigError:
        return ConfigError(f"{self.source}: {where}: expected {expected}, got {got!r}")

    def table(self, data: Any, where: str, keys: set[str], required: set[str]) -> dict:
        if not isinstance(data, dict):
            raise self.fail(where, "a table", data)
        unknown, missing = set(data) - keys, required - set(data)
        if unknown:
            raise self.fail(f"{where}.{sorted(unknown)[0]}", f"one of {sorted(keys)}", "an unknown key")
        if missing:
            raise self.fail(f"{where}.{sorted(missing)[0]}", "a value", "nothing")
        return data

    def number(self, data: dict, key: str, where: str, default: float | None = None) -> float:
        value = data.get(key, default)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.fail(f"{where}.{key}", "a number", value)
        return float(value)

    def items(self, data: Any, where: str) -> list:
        if not isinstance(data, list):
            raise self.fail(where, "a list", data)
        return data


def _segment(r: JsonReader, data: Any, where: str) -> Placed:
    kind = data.get("kind") if isinstance(data, dict) else None
    if kind not in SEGMENT_KINDS:
        raise r.fail(f"{where}.kind", f"one of {sorted(SEGMENT_KINDS)}", kind)
    cls = SEGMENT_KINDS[kind]
    names = [f.name for f in dataclasses.fields(cls) if f.init]
    place = {"kind", "s_m", "x_m", "y_m", "heading_rad"}
    r.table(data, where, place | set(names), place | set(names))
    try:
        segment = cls(*(r.number(data, n, where) for n in names))
    except ValueError as exc:
        raise ConfigError(f"{r.source}: {where}: {exc}") from None
    return Placed(*(r.number(data, k, where) for k in ("s_m", "x_m", "y_m", "heading_rad")), segment)


def _lane(r: JsonReader, data: Any, lane_id: int, where: str) -> Lane:
    r.table(data, where, {"type", "widths", "width_m"}, set())
    if "width_m" in data:
        widths = (LaneWidth(0.0, r.number(data, "width_m", where)),)
    else:
        widths = tuple(LaneWidth(*(r.number(w, k, f"{where}.widths[{i}]", 0.0) for k in ("s_offset_m", "a", "b", "c", "d")))
                       for i, w in enumerate(r.items(data.get("widths"), f"{where}.widths")))
    try:
        return Lane(lane_id, widths, str(data.get("type", "driving")))
    except ValueError as exc:
        raise ConfigError(f"{r.source}: {where}: {exc}") from None


def road_from_dict(data: Any, source: str = "scene.json", where: str = "road") -> Road:
    """The road of a ``road`` table (see ``docs/run-format.md``)."""
    r = JsonReader(source)
    r.table(data, where, {"geometry", "lane_sections"}, {"geometry", "lane_sections"})
    placed = tuple(_segment(r, g, f"{where}.geometry[{i}]") for i, g in enumerate(r.items(data["geometry"], f"{where}.geometry")))
    sections = []
    for i, sec in enumerate(r.items(data["lane_sections"], f"{where}.lane_sections")):
        at = f"{where}.lane_sections[{i}]"
        r.table(sec, at, {"s_m", "left", "right"}, {"s_m"})
        left = tuple(_lane(r, ln, j + 1, f"{at}.left[{j}]") for j, ln in enumerate(r.items(sec.get("left", []), f"{at}.left")))
        right = tuple(_lane(r, ln, -(j + 1), f"{at}.right[{j}]") for j, ln in enumerate(r.items(sec.get("right", []), f"{at}.right")))
        sections.append(LaneSection(r.number(sec, "s_m", at), left, right))
    try:
        return Road(PlanView(placed), tuple(sections))
    except ValueError as exc:
        raise ConfigError(f"{source}: {where}: {exc}") from None


def _body(r: JsonReader, data: Any, where: str, default_kind: str) -> Body:
    r.table(data, where, {"name", "class", "length_m", "width_m", "front_m"}, {"length_m", "width_m"})
    length, width = r.number(data, "length_m", where), r.number(data, "width_m", where)
    if length <= 0.0 or width <= 0.0:
        raise r.fail(where, "length_m and width_m > 0", (length, width))
    return Body(str(data.get("name", default_kind)), str(data.get("class", default_kind)), length, width,
                r.number(data, "front_m", where, length / 2.0))


def read_json_table(path: Path, fmt: str, keys: set[str], required: set[str]) -> tuple[dict, JsonReader]:
    """The top table of the JSON file at ``path`` (its ``format`` ``fmt``, its ``keys``, of which ``required``),
    and a reader for the rest; a :class:`ConfigError` naming the key and the file for bad input."""
    try:
        data = json.loads(Path(path).read_text())
    except json.JSONDecodeError as exc:
        raise ConfigError(f"{path}: not JSON: {exc}") from None
    r = JsonReader(str(path))
    r.table(data, "scene", keys | {"format"}, required | {"format"})
    if data["format"] != fmt:
        raise r.fail("format", repr(fmt), data["format"])
    return data, r


def read_scene(path: Path) -> SceneFile:
    """``scene.json`` at ``path``; a :class:`ConfigError` naming the key and the file for bad input."""
    data, r = read_json_table(path, SCENE_FORMAT, {"road", "ego", "objects"}, {"ego"})
    road = None if data.get("road") is None else road_from_dict(data["road"], str(path))
    objects = tuple(_body(r, o, f"objects[{i}]", "object") for i, o in enumerate(r.items(data.get("objects", []), "objects")))
    return SceneFile(road, _body(r, data["ego"], "ego", "ego"), objects)
