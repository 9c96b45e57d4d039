"""The loader's rules for the planar keys that span several keys (one error, naming the key, each).

* an object with a ``target_class`` and no ``length_m``/``width_m`` takes the class's box;
* an object is placed by ``position_m``/``lateral_m``, ``pose``, ``road_pose``, ``trajectory`` or
  ``crossing``: one of them; a trajectory or a crossing moves it, so the 1-D motion keys are not given;
* anything that names the road (``road_pose``, a trajectory or steering ``lane``) needs ``[road]``, and
  a lane the road has;
* the driver's steering needs a steering input, and ``path_following`` on a third-party FMU needs
  its vehicle geometry.
"""

from __future__ import annotations

import dataclasses
from typing import Any, Mapping

from ecu.settings import SettingError

from ..world.targets import TARGET_CLASSES
from .config import ObjectConfig, Scenario

#: the keys of the 1-D motion, which a trajectory or a crossing replaces
MOTION_KEYS = ("position_m", "speed_mps", "lateral_m", "brake_decel_mps2", "brake_ramp_s", "brake_to_speed_mps",
               "brake_at_s", "brake_at_gap_m", "lateral_speed_mps", "lateral_end_m", "lateral_at_s", "lateral_at_gap_m")
PLACEMENTS = ("pose", "road_pose", "trajectory", "crossing")
_VEHICLE_KEYS = ("wheelbase_m", "cg_to_rear_axle_m", "steering_ratio", "max_road_wheel_angle_rad")


def _object_tables(data: Mapping[str, Any]) -> list[tuple[str, Mapping[str, Any]]]:
    """(key path, table) of every object table given: ``object`` or ``objects[i]``."""
    if "objects" in data:
        return [(f"objects[{i}]", t) for i, t in enumerate(data["objects"])]
    return [("object", data["object"])] if "object" in data else []


def with_target_boxes(scenario: Scenario, data: Mapping[str, Any]) -> Scenario:
    """Objects with a ``target_class`` take its length and width where the file gives none."""
    def boxed(obj: ObjectConfig, table: Mapping[str, Any]) -> ObjectConfig:
        if obj.target_class is None:
            return obj
        target = TARGET_CLASSES[obj.target_class]
        return dataclasses.replace(obj, length_m=table.get("length_m", target.length_m),
                                   width_m=table.get("width_m", target.width_m))

    tables = dict(_object_tables(data))
    if "objects" in data:
        return dataclasses.replace(scenario, objects=tuple(boxed(o, tables[f"objects[{i}]"])
                                                           for i, o in enumerate(scenario.objects)))
    return dataclasses.replace(scenario, object=boxed(scenario.object, tables.get("object", {})))


def replaced_keys(placement: str) -> tuple[str, ...]:
    """The object keys that ``placement`` (one of :data:`PLACEMENTS`) replaces: given with it, an error."""
    return ("position_m", "lateral_m") if placement in ("pose", "road_pose") else MOTION_KEYS


def _check_placement(where: str, table: Mapping[str, Any]) -> None:
    given = [p for p in PLACEMENTS if p in table]
    if len(given) > 1:
        raise SettingError(f"{where}.{given[1]}", f"expected one of {', '.join(PLACEMENTS)}, got {' and '.join(given)}")
    if not given:
        return
    taken = replaced_keys(given[0])
    clash = next((k for k in taken if k in table), None)
    if clash is not None:
        raise SettingError(f"{where}.{clash}", f"not used with {given[0]}; expected one placement of the object")


def _lane_ids(scenario: Scenario) -> set[int]:
    road = scenario.road
    return set() if road is None else {
        lane for sec in road.lane_sections for lane in
        [*range(1, len(sec.left_m) + 1), *range(-1, -len(sec.right_m) - 1, -1)]}


def _check_road_use(scenario: Scenario, where: str, lane: int | None, needs_road: bool) -> None:
    if not needs_road and lane is None:
        return
    if scenario.road is None:
        raise SettingError(where, "needs a [road]; expected a [road] table with [[road.geometry]]")
    if lane is not None and lane not in _lane_ids(scenario):
        raise SettingError(where, f"expected a lane of [road] ({sorted(_lane_ids(scenario))}), got {lane}")


def _check_steering(scenario: Scenario) -> None:
    steering = scenario.driver.steering
    if steering is None:
        return
    if scenario.plant.input_map("steering_wheel_angle") is None:
        raise SettingError("driver.steering", "this FMU has no steering input; expected [plant.inputs] "
                                              "steering_wheel_angle = \"<input name>\"")
    if steering.model != "path_following":
        return
    _check_road_use(scenario, "driver.steering.lane", steering.lane, False)
    for i, change in enumerate(steering.lane_changes):
        _check_road_use(scenario, f"driver.steering.lane_changes[{i}].to_lane", change.to_lane, True)
    missing = [k for k in _VEHICLE_KEYS if getattr(steering, k) is None]
    if scenario.plant.fmu != "builtin" and missing:
        raise SettingError(f"driver.steering.{missing[0]}", "a third-party FMU's vehicle geometry is unknown;"
                                                            " expected it here")


def check_planar(scenario: Scenario, data: Mapping[str, Any]) -> None:
    """The rules of the module docstring; ``scenario`` has its plant maps merged already."""
    for where, table in _object_tables(data):
        if isinstance(table, Mapping):
            _check_placement(where, table)
    objects = scenario.objects or (scenario.object,)
    prefix = "objects" if scenario.objects else "object"
    for i, obj in enumerate(objects):
        where = f"{prefix}[{i}]" if scenario.objects else prefix
        if obj.road_pose is not None:
            _check_road_use(scenario, f"{where}.road_pose", None, True)
        if obj.trajectory is not None and obj.trajectory.lane is not None:
            _check_road_use(scenario, f"{where}.trajectory.lane", obj.trajectory.lane, True)
    _check_steering(scenario)
