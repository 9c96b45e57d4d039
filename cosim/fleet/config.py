"""A scene of several equipped vehicles (issue 23), read from TOML strictly.

A fleet file has three parts::

    [fleet]              name, duration, step, seed, the conflict zone the dance metrics judge
    [vehicle]            what every vehicle shares: any table of a scenario but [scenario] and [checks]
                         ([plant], [driver], [ecu], [radar], [gateway], [road], [end], [[objects]])
    [[vehicles]]         each vehicle: its name, where its own frame sits in the world (x_m, y_m,
                         heading_rad), and any of the same tables, which replace [vehicle]'s key by key
    [[objects]]          optional: standing objects in world coordinates ([objects.pose]), seen by every car

Each vehicle is an ordinary :class:`~cosim.scenarios.config.Scenario` in its **own frame**: its plant starts at
the origin heading along ``x``, and its road, objects and driver are written as in a one-car scenario. The
vehicle's ``x_m``, ``y_m``, ``heading_rad`` place that frame in the world; the other vehicles and the world's
objects are brought into it (:mod:`cosim.fleet.bodies`). Each vehicle's scenario is checked by the scenario
loader, so a bad key is named with its vehicle (``vehicles[1].ecu.strategy``) and the file. Vehicle ``i``'s
random sources are seeded with ``[fleet] seed + i``.
"""

from __future__ import annotations

import copy
import math
import random
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

from ecu.settings import Range, SettingError, check_keys, load, load_toml, setting

from ..scenarios.config import PoseConfig, Scenario, ScenarioSection
from ..scenarios.loader import scenario_from_dict
from ..world.targets import TARGET_CLASSES
from .bodies import Frame

_WIDE = Range(-1e5, 1e5)
#: the scenario tables a vehicle may give ([scenario] is the fleet's, [checks] the fleet's metrics)
#: the range of each car's way-out patience (s), drawn per car unless its [ecu] sets way_out_patience_s: from
#: a glance at the other cars (0.5 s) to about twice a driver's surprised reaction (Green 2000: 1.5 s)
PATIENCE_S = (0.5, 3.0)
VEHICLE_TABLES = ("plant", "driver", "ecu", "radar", "gateway", "road", "end", "object", "objects")


@dataclass(frozen=True)
class FleetSection(ScenarioSection):
    """``[fleet]``: a scenario's ``[scenario]`` keys (name, duration, step, seed, start time; vehicle ``i``'s
    random sources are seeded with ``seed + i``), and the conflict zone of the dance metrics."""

    conflict_x_m: float = setting(0.0, unit="m", allowed=_WIDE, doc="the conflict zone's centre, world frame")
    conflict_y_m: float = setting(0.0, unit="m", allowed=_WIDE, doc="the conflict zone's centre, world frame")
    conflict_radius_m: float = setting(8.0, unit="m", allowed=Range(0.5, 1e3),
                                       doc="a car whose centre is within this distance of the centre is in the "
                                           "conflict zone; past it (beyond, moving away) it has cleared")
    approach_radius_m: float = setting(30.0, unit="m", allowed=Range(1.0, 1e4),
                                       doc="deadlock: every car not yet cleared is within this distance of the "
                                           "centre and none makes progress")
    progress_speed_mps: float = setting(0.5, unit="m/s", allowed=Range(0.0, 10.0),
                                        doc="deadlock: a car slower than this makes no progress")


@dataclass(frozen=True)
class Placement:
    """Where a vehicle's own frame sits in the world (its plant starts at that frame's origin)."""

    name: str = setting(doc="the vehicle's name (its output directory, plots)")
    x_m: float = setting(0.0, unit="m", allowed=_WIDE, doc="its frame's origin, world frame")
    y_m: float = setting(0.0, unit="m", allowed=_WIDE, doc="its frame's origin, world frame")
    heading_rad: float = setting(0.0, unit="rad", allowed=Range(-2 * math.pi, 2 * math.pi),
                                 doc="its frame's x axis, counter-clockwise from the world's")


@dataclass(frozen=True)
class Vehicle:
    """One vehicle: its placement and its scenario in its own frame."""

    placement: Placement
    scenario: Scenario

    @property
    def name(self) -> str:
        return self.placement.name


@dataclass(frozen=True)
class Fleet:
    """A whole fleet file."""

    fleet: FleetSection
    vehicles: tuple[Vehicle, ...]
    objects: tuple[WorldObject, ...]

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(v.name for v in self.vehicles)


def _merged(base: Mapping[str, Any], given: Mapping[str, Any]) -> dict:
    """``base`` with ``given`` laid over it, table by table (arrays of tables are replaced whole)."""
    out = copy.deepcopy(dict(base))
    for key, value in given.items():
        if isinstance(value, Mapping) and isinstance(out.get(key), Mapping):
            out[key] = _merged(out[key], value)
        else:
            out[key] = copy.deepcopy(value)
    return out


def patience_s(seed: int) -> float:
    """A car's own way-out patience (:mod:`ecu.core.way_out`): uniform over ``PATIENCE_S``, seeded with its seed,
    to the ECU cycle (a production ECU would take it from its serial number)."""
    low, high = PATIENCE_S
    return round(random.Random(f"way-out patience/{seed}").uniform(low, high), 2)


def _vehicle(i: int, table: Any, base: Mapping[str, Any], section: FleetSection, base_dir: Path | None,
             world: tuple[WorldObject, ...]) -> Vehicle:
    where = f"vehicles[{i}]"
    table = check_keys(table, (*VEHICLE_TABLES, "name", "x_m", "y_m", "heading_rad"), where)
    placement = load(Placement, {k: v for k, v in table.items() if k not in VEHICLE_TABLES}, where)
    data = _merged(base, {k: v for k, v in table.items() if k in VEHICLE_TABLES})
    frame = Frame(placement.x_m, placement.y_m, placement.heading_rad)
    own = list(data.pop("objects", [])) + ([data.pop("object")] if "object" in data else [])
    own += [w.in_frame(frame) for w in world]
    if own:
        data["objects"] = own
    else:
        data["object"] = {"enabled": False}  # no cyclist by default: the others are its objects
    data["scenario"] = {"name": f"{section.name}.{placement.name}", "duration_s": section.duration_s,
                        "step_s": section.step_s, "seed": section.seed + i, "start_time": section.start_time}
    ecu = data.setdefault("ecu", {})
    if isinstance(ecu, dict) and ecu.get("way_out", "none") != "none" and "way_out_patience_s" not in ecu:
        ecu["way_out_patience_s"] = patience_s(section.seed + i)
    if isinstance(ecu, dict) and ecu.get("way_out", "none") != "none" and "way_out_seed" not in ecu:
        ecu["way_out_seed"] = section.seed + i
    try:
        scenario = scenario_from_dict(data, base_dir)
    except SettingError as exc:
        raise exc.under(where) from None
    if not scenario.planar:
        raise SettingError(f"{where}.road", "expected a planar vehicle (a [road] in [vehicle] or here): the others "
                                            "are seen in the plane")
    return Vehicle(placement, scenario)


@dataclass(frozen=True)
class WorldObject:
    """``[[objects]]`` of a fleet: a standing box placed in world coordinates, seen by every car."""

    pose: PoseConfig = setting(doc="[objects.pose]: the box's centre and heading, world frame")
    name: str = setting("object", doc="its name (reports, events)")
    target_class: str | None = setting(None, allowed=tuple(TARGET_CLASSES), doc="a protocol target: its box")
    length_m: float = setting(4.5, unit="m", allowed=Range(0.0, 50.0, low_open=True), doc="along its heading")
    width_m: float = setting(1.8, unit="m", allowed=Range(0.0, 10.0, low_open=True), doc="across it")

    def in_frame(self, frame: Frame) -> dict:
        """Its ``[[objects]]`` table in a vehicle's frame."""
        x, y = frame.from_world(self.pose.x_m, self.pose.y_m)
        table = {"name": self.name, "length_m": self.length_m, "width_m": self.width_m, "speed_mps": 0.0,
                 "pose": {"x_m": x, "y_m": y, "heading_rad": _wrapped(self.pose.heading_rad - frame.heading_rad)}}
        return table | ({"target_class": self.target_class} if self.target_class else {})


def _wrapped(angle_rad: float) -> float:
    return math.atan2(math.sin(angle_rad), math.cos(angle_rad))


def _world_objects(tables: Any) -> tuple[WorldObject, ...]:
    if not isinstance(tables, list):
        raise SettingError("objects", "expected [[objects]] tables")
    return tuple(load(WorldObject, table, f"objects[{i}]") for i, table in enumerate(tables))


def fleet_from_dict(data: Mapping[str, Any], base_dir: Path | None = None, way_out: str | None = None) -> Fleet:
    """Build and check a :class:`Fleet` from parsed TOML (module docstring); ``way_out``: every vehicle's
    ``[ecu] way_out`` instead of the file's."""
    data = check_keys(data, ("fleet", "vehicle", "vehicles", "objects"), "")
    section = load(FleetSection, data.get("fleet", {}), "fleet")
    base = check_keys(data.get("vehicle", {}), VEHICLE_TABLES, "vehicle")
    if way_out is not None:
        base = _merged(base, {"ecu": {"way_out": way_out}})
        data = {**data, "vehicles": [_merged(t, {"ecu": {"way_out": way_out}}) if isinstance(t, Mapping) else t
                                     for t in data.get("vehicles", [])]}
    tables = data.get("vehicles", [])
    if not isinstance(tables, list) or len(tables) < 2:
        raise SettingError("vehicles", "expected two or more [[vehicles]] tables")
    world = _world_objects(data.get("objects", []))
    vehicles = tuple(_vehicle(i, t, base, section, base_dir, world) for i, t in enumerate(tables))
    names = [v.name for v in vehicles]
    if len(set(names)) != len(names):
        raise SettingError("vehicles", f"expected distinct names, got {names}")
    return Fleet(section, vehicles, world)


def load_fleet(path: str | Path, way_out: str | None = None) -> Fleet:
    """Read and check a fleet TOML file; every error names the file and the key (``way_out``: see
    :func:`fleet_from_dict`)."""
    path = Path(path)
    return load_toml(path, lambda data: fleet_from_dict(data, base_dir=path.parent, way_out=way_out), "fleet")


def is_fleet_file(path: str | Path) -> bool:
    """Whether a TOML file is a fleet (it has ``[[vehicles]]``); False for anything unreadable."""
    import tomllib

    try:
        return "vehicles" in tomllib.loads(Path(path).read_text())
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
        return False
