"""A crd scenario as an OpenSCENARIO 1.2 file and its OpenDRIVE road, built with ``scenariogeneration``.

The files are the inverse of the import (:mod:`.reader`, docs/openscenario.md),
written so that reading them back gives the same scenario bit for bit:

* the road: a straight line along x from the origin, lanes of 3.5 m (lane 1 left,
  lanes -1 and -2 right), shifted by a lane offset of half a lane so that the
  ego's lane -1 is centred on y = 0;
* the ego: reference point at its front bumper (box centre ``-length/2``), at
  the origin heading along x, its start speed in Init; crd's keys that differ
  from their defaults as ``crd.*`` properties; its driver as the properties of
  ``<Controller name="crd_driver">``;
* each object: reference point at its rear (box centre ``+length/2``; an
  oncoming object at its front, heading pi), at ``(position_m, lateral_m)``;
  a category from its width (up to 1 m a bicycle, else a car: crd's objects
  have no category); braking as a linear ``SpeedAction`` (rate) and a lateral
  move as a linear ``LaneChangeAction`` (rate) to lane -1 plus an offset, each
  started by simulation time or the ego's bumper-to-bumper distance;
* the duration as the storyboard's stop trigger (simulation time).

A planar scenario (docs/openscenario.md, "Export"): its ``[road]`` is the OpenDRIVE road, and the
objects placed or moved in the plane are written by :mod:`.export_plane`; a target class chooses
the entity (a ``<Pedestrian>``, or a bicycle, motorbike or car) and is kept as ``crd.target_class``.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from scenariogeneration import xodr, xosc

from ...errors import ConfigError
from ...world.road import Road
from ...world.scene_build import build_road
from ..config import DriverConfig, ObjectConfig, Scenario
from ..planar_rules import PLACEMENTS
from ..resolve import plain, scenario_to_dict
from .entities import DRIVER_CONTROLLER
from .export_plane import PlaneExportError, category, in_plane, opendrive_road, plane_actions
from .properties import PREFIX, changed, flat
from .reader import EGO_SECTIONS, OBJECTS_TABLE

LANE_WIDTH_M = 3.5
BICYCLE_MAX_WIDTH_M = 1.0
OSC_MINOR = 2
#: object keys the standard elements carry (the rest go into crd.* properties when not default)
STANDARD_OBJECT_KEYS = ("enabled", "name", "position_m", "speed_mps", "length_m", "width_m", "lateral_m",
                        "brake_decel_mps2", "brake_to_speed_mps", "brake_at_s", "brake_at_gap_m",
                        "lateral_speed_mps", "lateral_end_m", "lateral_at_s", "lateral_at_gap_m")
#: keys the standard elements carry for the ego and the run
STANDARD_EGO_KEYS = {"scenario": ("name", "duration_s"), "plant": ("initial_speed_mps", "length_m", "width_m")}


class ExportError(ConfigError):
    """A scenario that the OpenSCENARIO subset cannot carry exactly (the CLI names the scenario file)."""


def _road(scenario: Scenario) -> xodr.OpenDrive:
    if scenario.road is not None:
        straight = all(g.kind == "line" for g in scenario.road.geometry)
        if straight and scenario.driver.steering is None:
            raise ExportError("a straight [road] without [driver.steering] reads back as crd's 1-D road: "
                              "give the driver's steering, or leave the road out")
        return opendrive_road(scenario.road, scenario.scenario.name)
    reach = max([abs(o.position_m) + o.length_m for o in scenario.scene_objects()] + [0.0])
    length = math.ceil(reach + 80.0 * scenario.scenario.duration_s + 100.0)
    road = xodr.create_road(xodr.Line(length), id=0, left_lanes=1, right_lanes=2, lane_width=LANE_WIDTH_M)
    road.lanes.add_laneoffset(xodr.LaneOffset(0, LANE_WIDTH_M / 2, 0, 0, 0))
    odr = xodr.OpenDrive(scenario.scenario.name)
    odr.add_road(road)
    odr.adjust_roads_and_lanes()
    return odr


def _properties(pairs) -> xosc.Properties:
    props = xosc.Properties()
    for name, text in pairs:
        props.add_property(name, text)
    return props


def _with_properties(vehicle: xosc.Vehicle, pairs) -> xosc.Vehicle:
    for name, text in pairs:
        vehicle.add_property(name, text)
    return vehicle


def _ego_properties(scenario: Scenario):
    data = scenario_to_dict(scenario)
    default = plain(Scenario())
    sections = {s: {k: v for k, v in data[s].items() if k not in STANDARD_EGO_KEYS.get(s, ())}
                for s in EGO_SECTIONS}
    base = {s: default[s] for s in EGO_SECTIONS}
    table = {OBJECTS_TABLE: "objects"} if len(scenario.objects) == 1 else {}  # else the import's default
    return flat(changed(sections, base) | table)


def _ego(scenario: Scenario) -> tuple[xosc.Vehicle, xosc.Controller]:
    plant = scenario.plant
    box = xosc.BoundingBox(plant.width_m, plant.length_m, 1.5, -plant.length_m / 2, 0.0, 0.75)
    vehicle = _with_properties(xosc.Vehicle("ego", xosc.VehicleCategory.car, box, _axle(2.8), _axle(0.0),
                                            80.0, 10.0, 12.0), _ego_properties(scenario))
    driver = plain(scenario.driver)
    keys = {"model": driver["model"]} | changed(driver, plain(DriverConfig()))
    controller = xosc.Controller(DRIVER_CONTROLLER, _properties(flat(keys, prefix="")))
    return vehicle, controller


def _axle(x_m: float) -> xosc.Axle:
    return xosc.Axle(0.5 if x_m else 0.0, 0.6, 1.6, x_m, 0.3)


def _object_entity(obj: ObjectConfig) -> xosc.Vehicle | xosc.Pedestrian:
    direction = -1.0 if obj.speed_mps < 0.0 else 1.0
    centre_x = 0.0 if in_plane(obj) else direction * obj.length_m / 2  # the reference point: crd's
    box = xosc.BoundingBox(obj.width_m, obj.length_m, 1.5, centre_x, 0.0, 0.75)
    kind, vehicle_category = category(obj, BICYCLE_MAX_WIDTH_M)
    rest = {k: v for k, v in plain(obj).items() if k not in STANDARD_OBJECT_KEYS + PLACEMENTS}
    if kind == "Pedestrian":
        entity = xosc.Pedestrian(obj.name, 75.0, xosc.PedestrianCategory.pedestrian, box)
    else:
        entity = xosc.Vehicle(obj.name, vehicle_category, box, _axle(1.0), _axle(0.0), 80.0, 10.0, 12.0)
    return _with_properties(entity, flat(changed(rest, plain(ObjectConfig()))))


def _step_speed(speed_mps: float) -> xosc.AbsoluteSpeedAction:
    return xosc.AbsoluteSpeedAction(speed_mps, xosc.TransitionDynamics(xosc.DynamicsShapes.step,
                                                                       xosc.DynamicsDimension.time, 0.0))


def _start(obj: ObjectConfig, kind: str, ego: str) -> xosc.EntityTrigger | xosc.ValueTrigger:
    at_s, at_gap = getattr(obj, f"{kind}_at_s"), getattr(obj, f"{kind}_at_gap_m")
    if (at_s is None) == (at_gap is None):
        raise ExportError(f"object {obj.name!r}: {kind} needs exactly one of {kind}_at_s and {kind}_at_gap_m "
                          "to be exported (OpenSCENARIO starts an event on one condition here)")
    if at_s is not None:
        return xosc.ValueTrigger(f"{kind}_time", 0.0, xosc.ConditionEdge.none,
                                 xosc.SimulationTimeCondition(at_s, xosc.Rule.greaterOrEqual))
    cond = xosc.RelativeDistanceCondition(at_gap, xosc.Rule.lessOrEqual, xosc.RelativeDistanceType.longitudinal,
                                          obj.name, freespace=True)
    return xosc.EntityTrigger(f"{kind}_gap", 0.0, xosc.ConditionEdge.none, cond, ego)


def _events(obj: ObjectConfig, ego: str) -> list[xosc.Event]:
    events = []
    if obj.brake_decel_mps2 > 0.0:
        ev = xosc.Event(f"{obj.name}_brake", xosc.Priority.parallel)
        dyn = xosc.TransitionDynamics(xosc.DynamicsShapes.linear, xosc.DynamicsDimension.rate, obj.brake_decel_mps2)
        ev.add_action("brake", xosc.AbsoluteSpeedAction(obj.brake_to_speed_mps, dyn))
        ev.add_trigger(_start(obj, "brake", ego))
        events.append(ev)
    if obj.lateral_end_m is not None:
        ev = xosc.Event(f"{obj.name}_lateral", xosc.Priority.parallel)
        dyn = xosc.TransitionDynamics(xosc.DynamicsShapes.linear, xosc.DynamicsDimension.rate, obj.lateral_speed_mps)
        ev.add_action("lateral", xosc.AbsoluteLaneChangeAction(-1, dyn, target_lane_offset=obj.lateral_end_m))
        ev.add_trigger(_start(obj, "lateral", ego))
        events.append(ev)
    return events


def _object_story(obj: ObjectConfig, road: Road | None, ego: str) -> tuple[list, list[xosc.Event]]:
    """(Init actions, story events) of one object."""
    if in_plane(obj):
        try:
            return plane_actions(obj, road, ego)
        except PlaneExportError as exc:
            raise ExportError(str(exc)) from None
    h = math.pi if obj.speed_mps < 0.0 else 0.0
    init = [xosc.TeleportAction(xosc.WorldPosition(obj.position_m, obj.lateral_m, 0.0, h)),
            _step_speed(abs(obj.speed_mps))]
    return init, _events(obj, ego)


def build(scenario: Scenario, road_file: str, ego: str = "Ego") -> tuple[xosc.Scenario, xodr.OpenDrive]:
    """The OpenSCENARIO object (its RoadNetwork names ``road_file``) and the OpenDRIVE road."""
    odr, road = _road(scenario), build_road(scenario.road)
    entities, init = xosc.Entities(), xosc.Init()
    vehicle, controller = _ego(scenario)
    entities.add_scenario_object(ego, vehicle, controller)
    init.add_init_action(ego, xosc.TeleportAction(xosc.WorldPosition(0.0, 0.0, 0.0, 0.0)))
    init.add_init_action(ego, _step_speed(scenario.plant.initial_speed_mps))
    stop = xosc.ValueTrigger("duration", 0.0, xosc.ConditionEdge.rising,
                             xosc.SimulationTimeCondition(scenario.scenario.duration_s, xosc.Rule.greaterThan), "stop")
    board = xosc.StoryBoard(init, stop)
    for obj in scenario.scene_objects():
        entities.add_scenario_object(obj.name, _object_entity(obj))
        actions, events = _object_story(obj, road, ego)
        for action in actions:
            init.add_init_action(obj.name, action)
        if events:
            maneuver = xosc.Maneuver(f"{obj.name}_maneuver")
            for ev in events:
                maneuver.add_event(ev)
            board.add_maneuver(maneuver, obj.name)
    sce = xosc.Scenario(scenario.scenario.name, "crd", xosc.ParameterDeclarations(), entities, board,
                        xosc.RoadNetwork(roadfile=road_file), xosc.Catalog(), osc_minor_version=OSC_MINOR)
    return sce, odr


def export_xosc(scenario: Scenario, out_dir: str | Path, stem: str | None = None) -> tuple[Path, Path]:
    """Write ``<stem>.xosc`` and ``<stem>.xodr`` into ``out_dir``; returns both paths."""
    out_dir = Path(out_dir)
    stem = stem or scenario.scenario.name
    xosc_path, xodr_path = out_dir / f"{stem}.xosc", out_dir / f"{stem}.xodr"
    sce, odr = build(scenario, xodr_path.name)  # an ExportError before anything is written
    out_dir.mkdir(parents=True, exist_ok=True)
    odr.write_xml(str(xodr_path))
    sce.write_xml(str(xosc_path))
    return xosc_path, xodr_path
