"""``fleet.json``: the static part of a fleet run's bird's-eye view, so that its run directory describes itself.

Written with every fleet run (:mod:`cosim.fleet.output`), read by ``crd animate`` (:mod:`cosim.fleet.video`).
Everything is in the **world** frame but each car's box, which is given about its own pose point::

    {"format": "crd-fleet-scene/1", "name": "crossing", "duration_s": 20.0,
     "conflict": {"x_m": 0.0, "y_m": 0.0, "radius_m": 6.0},
     "vehicles": [{"name": "west", "x_m": -40.0, "y_m": 0.0, "heading_rad": 0.0,   # its frame in the world
                   "length_m": 4.5, "width_m": 1.8, "front_m": 2.2,                # its box ([plant])
                   "road": {"left": [[x, y], ...], "right": [...], "markings": [[[x, y], ...], ...]}}],
     "objects": [{"name": "parked", "class": "object", "x_m": 3.0, "y_m": 9.0, "heading_rad": 0.0,
                  "length_m": 4.5, "width_m": 1.8}]}

A vehicle's ``front_m`` runs from the pose point of its time series (``x_m``, ``y_m``, ``yaw_rad`` of
``<vehicle>/timeseries.csv``, its own frame) to its front bumper. Its ``road`` is its scenario's ``[road]``
(None: none) drawn as polylines every :data:`ROAD_STEP_M`: the two edges and the markings (lane borders within
it, the centre line between its directions; :func:`cosim.results.birdseye.road_lines`). The ``[[objects]]``
are the fleet's standing boxes, about their centres. Bad input raises :class:`~cosim.errors.ConfigError`
naming the key and the file.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..results.birdseye import road_lines
from ..results.scene_file import Body, JsonReader, read_json_table
from ..world.scene_build import build_road
from .bodies import Frame
from .config import Fleet

FLEET_SCENE_FILE = "fleet.json"
FLEET_SCENE_FORMAT = "crd-fleet-scene/1"
#: the spacing of the roads' polylines (m)
ROAD_STEP_M = 1.0


@dataclass(frozen=True)
class RoadLines:
    """A road in the world: its left and right edges and its markings, each an (n, 2) polyline."""

    left: np.ndarray
    right: np.ndarray
    markings: tuple[np.ndarray, ...]


@dataclass(frozen=True)
class SceneCar:
    """A vehicle: its frame in the world, its box (about its pose point) and its road in the world."""

    frame: Frame
    body: Body
    road: RoadLines | None

    @property
    def name(self) -> str:
        return self.body.name


@dataclass(frozen=True)
class SceneBox:
    """A standing object of the world: its box (about its centre) and its pose."""

    body: Body
    x_m: float
    y_m: float
    heading_rad: float


@dataclass(frozen=True)
class FleetScene:
    """What ``fleet.json`` holds (module docstring); ``conflict``: the zone's centre and radius (m)."""

    name: str
    duration_s: float
    conflict: tuple[float, float, float]
    cars: tuple[SceneCar, ...]
    objects: tuple[SceneBox, ...]


def _world_lines(frame: Frame, road_cfg) -> RoadLines | None:
    road = build_road(road_cfg)
    if road is None:
        return None
    left, right, markings = road_lines(road, ROAD_STEP_M)
    moved = [np.column_stack(frame.to_world(line[:, 0], line[:, 1])) for line in (left, right, *markings)]
    return RoadLines(moved[0], moved[1], tuple(moved[2:]))


def fleet_scene_of(fleet: Fleet) -> FleetScene:
    """The scene of ``fleet``: each vehicle's placement, box and road in the world, the objects, the zone."""
    cars = []
    for v in fleet.vehicles:
        p, plant = v.placement, v.scenario.plant
        frame = Frame(p.x_m, p.y_m, p.heading_rad)
        body = Body(v.name, "car", plant.length_m, plant.width_m, plant.front_m)
        cars.append(SceneCar(frame, body, _world_lines(frame, v.scenario.road)))
    objects = tuple(SceneBox(Body(o.name, o.target_class or "object", o.length_m, o.width_m, o.length_m / 2.0),
                             o.pose.x_m, o.pose.y_m, o.pose.heading_rad) for o in fleet.objects)
    z = fleet.fleet
    return FleetScene(z.name, z.duration_s, (z.conflict_x_m, z.conflict_y_m, z.conflict_radius_m), tuple(cars),
                      objects)


# -- writing -------------------------------------------------------------------------------------------
def _points(line: np.ndarray) -> list[list[float]]:
    return np.round(line, 3).tolist()


def _car_dict(car: SceneCar) -> dict:
    f, b, road = car.frame, car.body, car.road
    lines = None if road is None else {"left": _points(road.left), "right": _points(road.right),
                                       "markings": [_points(m) for m in road.markings]}
    return {"name": b.name, "x_m": f.x_m, "y_m": f.y_m, "heading_rad": f.heading_rad, "length_m": b.length_m,
            "width_m": b.width_m, "front_m": b.front_m, "road": lines}


def scene_to_dict(scene: FleetScene) -> dict:
    x, y, r = scene.conflict
    return {"format": FLEET_SCENE_FORMAT, "name": scene.name, "duration_s": scene.duration_s,
            "conflict": {"x_m": x, "y_m": y, "radius_m": r}, "vehicles": [_car_dict(c) for c in scene.cars],
            "objects": [{"name": o.body.name, "class": o.body.kind, "x_m": o.x_m, "y_m": o.y_m,
                         "heading_rad": o.heading_rad, "length_m": o.body.length_m, "width_m": o.body.width_m}
                        for o in scene.objects]}


def write_fleet_scene(path: Path, scene: FleetScene) -> None:
    Path(path).write_text(json.dumps(scene_to_dict(scene)) + "\n")


# -- reading -------------------------------------------------------------------------------------------
def _polyline(r: JsonReader, data: Any, where: str) -> np.ndarray:
    try:
        line = np.array(r.items(data, where), dtype=float)
    except (TypeError, ValueError):
        line = np.empty((0,))
    if line.ndim != 2 or line.shape[1] != 2 or len(line) < 2:
        raise r.fail(where, "a list of two or more [x, y] points", data)
    return line


def _road(r: JsonReader, data: Any, where: str) -> RoadLines | None:
    if data is None:
        return None
    r.table(data, where, {"left", "right", "markings"}, {"left", "right", "markings"})
    markings = tuple(_polyline(r, m, f"{where}.markings[{i}]")
                     for i, m in enumerate(r.items(data["markings"], f"{where}.markings")))
    return RoadLines(_polyline(r, data["left"], f"{where}.left"), _polyline(r, data["right"], f"{where}.right"),
                     markings)


def _car(r: JsonReader, data: Any, where: str) -> SceneCar:
    keys = {"name", "x_m", "y_m", "heading_rad", "length_m", "width_m", "front_m", "road"}
    r.table(data, where, keys, keys)
    n = {k: r.number(data, k, where) for k in keys - {"name", "road"}}
    body = Body(str(data["name"]), "car", n["length_m"], n["width_m"], n["front_m"])
    return SceneCar(Frame(n["x_m"], n["y_m"], n["heading_rad"]), body, _road(r, data["road"], f"{where}.road"))


def _box(r: JsonReader, data: Any, where: str) -> SceneBox:
    keys = {"name", "class", "x_m", "y_m", "heading_rad", "length_m", "width_m"}
    r.table(data, where, keys, keys)
    n = {k: r.number(data, k, where) for k in keys - {"name", "class"}}
    body = Body(str(data["name"]), str(data["class"]), n["length_m"], n["width_m"], n["length_m"] / 2.0)
    return SceneBox(body, n["x_m"], n["y_m"], n["heading_rad"])


def read_fleet_scene(path: Path) -> FleetScene:
    """``fleet.json`` at ``path``; a :class:`ConfigError` naming the key and the file for bad input."""
    keys = {"name", "duration_s", "conflict", "vehicles", "objects"}
    data, r = read_json_table(path, FLEET_SCENE_FORMAT, keys, keys)
    zone = r.table(data["conflict"], "conflict", {"x_m", "y_m", "radius_m"}, {"x_m", "y_m", "radius_m"})
    conflict = tuple(r.number(zone, k, "conflict") for k in ("x_m", "y_m", "radius_m"))
    cars = tuple(_car(r, c, f"vehicles[{i}]") for i, c in enumerate(r.items(data["vehicles"], "vehicles")))
    objects = tuple(_box(r, o, f"objects[{i}]") for i, o in enumerate(r.items(data["objects"], "objects")))
    return FleetScene(str(data["name"]), r.number(data, "duration_s", "scene"), conflict, cars, objects)
