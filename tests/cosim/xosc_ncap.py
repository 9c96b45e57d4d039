"""NCAP/R152-style OpenSCENARIO files written directly with scenariogeneration (not with crd's exporter).

Each file states its test the way a protocol engineer would: a road from
scenariogeneration's generator, the vehicle under test and the Global Vehicle
Target (ISO 19206-3, 4.023 x 1.712 m) in lane -1 by LanePosition, reference
points at the rear axles (not at the bumpers, as crd's exporter puts them), the
gap from the protocol (TTC 4 s after 2 s of steady approach, or a 1 s headway
for CCRb), the target's braking as a linear speed action at 4 m/s^2 started by
simulation time. What OpenSCENARIO has no element for goes into crd's
documented properties: the robot driver (hold the speed, release after a 5 km/h
drop), CCRb's 1 s deceleration ramp, and Euro NCAP's end of test.
"""

from __future__ import annotations

from pathlib import Path

from scenariogeneration import xodr, xosc

KMH = 3.6
VUT = (4.358, 1.815, 1.40)  # length, width, box centre ahead of the rear axle (m)
GVT = (4.023, 1.712, 1.30)
START_S_M = 20.0


def _vehicle(name: str, dims: tuple[float, float, float]) -> xosc.Vehicle:
    length, width, centre = dims
    box = xosc.BoundingBox(width, length, 1.4, centre, 0.0, 0.7)
    return xosc.Vehicle(name, xosc.VehicleCategory.car, box, xosc.Axle(0.5, 0.65, 1.6, 2.7, 0.33),
                        xosc.Axle(0.0, 0.65, 1.6, 0.0, 0.33), 60.0, 8.0, 10.0)


def _speed(v_mps: float, shape=xosc.DynamicsShapes.step, dim=xosc.DynamicsDimension.time, value=0.0):
    return xosc.AbsoluteSpeedAction(v_mps, xosc.TransitionDynamics(shape, dim, value))


def _write_road(out: Path, name: str) -> None:
    """``name.xodr``: a straight 2 km road, one 3.5 m lane each way."""
    road = xodr.create_road(xodr.Line(2000.0), id=1, left_lanes=1, right_lanes=1, lane_width=3.5)
    odr = xodr.OpenDrive(name)
    odr.add_road(road)
    odr.adjust_roads_and_lanes()
    odr.write_xml(str(out / f"{name}.xodr"))


def write_case(out: Path, name: str, ego_kmh: float, target_kmh: float, gap_m: float, duration_s: float,
               brake: tuple[float, float, float] | None = None) -> Path:
    """One test as ``name.xosc`` + ``name.xodr``; ``brake``: (decel m/s^2, ramp s, start time s)."""
    v, vt = ego_kmh / KMH, target_kmh / KMH
    _write_road(out, name)
    ego, target = _vehicle("vut", VUT), _vehicle("gvt", GVT)
    ego_front = VUT[2] + VUT[0] / 2
    target_rear = GVT[2] - GVT[0] / 2
    ego.add_property("crd.end." + ("standstill" if vt == 0.0 else "matched_speed"), "true")
    robot = xosc.Properties()
    for key, value in (("model", '"hold_speed"'), ("set_speed_mps", repr(v)), ("release_drop_mps", repr(5 / KMH))):
        robot.add_property(key, value)
    entities = xosc.Entities()
    entities.add_scenario_object("Ego", ego, xosc.Controller("crd_driver", robot))
    entities.add_scenario_object("Target", target)
    init = xosc.Init()
    target_s = START_S_M + ego_front + gap_m - target_rear
    for entity, s_m, speed in (("Ego", START_S_M, v), ("Target", target_s, vt)):
        init.add_init_action(entity, xosc.TeleportAction(xosc.LanePosition(s_m, 0.0, -1, 1)))
        init.add_init_action(entity, _speed(speed))
    stop = xosc.ValueTrigger("end", 0.0, xosc.ConditionEdge.rising,
                             xosc.SimulationTimeCondition(duration_s, xosc.Rule.greaterThan), "stop")
    board = xosc.StoryBoard(init, stop)
    if brake is not None:
        decel, ramp, at_s = brake
        target.add_property("crd.brake_ramp_s", repr(ramp))
        event = xosc.Event("target_brakes", xosc.Priority.overwrite)
        event.add_action("brake", _speed(0.0, xosc.DynamicsShapes.linear, xosc.DynamicsDimension.rate, decel))
        event.add_trigger(xosc.ValueTrigger("at", 0.0, xosc.ConditionEdge.rising,
                                            xosc.SimulationTimeCondition(at_s, xosc.Rule.greaterThan)))
        maneuver = xosc.Maneuver("braking")
        maneuver.add_event(event)
        board.add_maneuver(maneuver, "Target")
    scenario = xosc.Scenario(name, "crd tests", xosc.ParameterDeclarations(), entities, board,
                             xosc.RoadNetwork(roadfile=f"{name}.xodr"), xosc.Catalog(), osc_minor_version=1)
    path = out / f"{name}.xosc"
    scenario.write_xml(str(path))
    return path
