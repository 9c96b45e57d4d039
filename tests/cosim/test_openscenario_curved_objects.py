"""Objects on a curved road in an OpenSCENARIO file (written with scenariogeneration, not crd's exporter).

A lane or road position on the arc becomes crd's ``[objects.road_pose]`` (the box centre at the
reference point) or ``[objects.pose]`` (a box centre elsewhere: moved by ``R(h) (cx, cy)``); both
must put the object where the file does, checked against crd's own road built from ``[road]``.
What stays outside the subset is a one-line error naming the element and its line.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

pytest.importorskip("scenariogeneration")
from lxml import etree  # noqa: E402
from scenariogeneration import xodr, xosc  # noqa: E402

from cosim.cli.main import main as crd  # noqa: E402
from cosim.errors import ConfigError  # noqa: E402
from cosim.scenarios.openscenario import read_xosc  # noqa: E402
from cosim.world.scene_build import build_road  # noqa: E402

CURVE_1PM = 1 / 150.0
EGO = (4.5, 1.8, 1.4)  # length, width, box centre ahead of the reference point (m)
CAR_CENTRE_M = 1.4  # the parked car's box centre ahead of its reference point (its rear axle)
WALKER = (100.0, -2, 0.5)  # s, lane, offset: on the arc (50 m to 285.6 m), in lane -2
CAR = (120.0, -5.25, 0.3)  # s, t, heading relative to the road's


def _step(speed: float) -> xosc.AbsoluteSpeedAction:
    return xosc.AbsoluteSpeedAction(speed, xosc.TransitionDynamics(xosc.DynamicsShapes.step,
                                                                   xosc.DynamicsDimension.time, 0.0))


def _entities() -> xosc.Entities:
    length, width, centre = EGO
    axles = (xosc.Axle(0.5, 0.65, 1.6, 2.7, 0.33), xosc.Axle(0.0, 0.65, 1.6, 0.0, 0.33))
    entities = xosc.Entities()
    entities.add_scenario_object("Ego", xosc.Vehicle("car", xosc.VehicleCategory.car, xosc.BoundingBox(
        width, length, 1.4, centre, 0.0, 0.7), *axles, 60.0, 8.0, 10.0))
    entities.add_scenario_object("walker", xosc.Pedestrian("walker", 70.0, xosc.PedestrianCategory.pedestrian,
                                                           xosc.BoundingBox(0.5, 0.6, 1.8, 0.0, 0.0, 0.9)))
    entities.add_scenario_object("parked", xosc.Vehicle("parked", xosc.VehicleCategory.car, xosc.BoundingBox(
        1.8, 4.5, 1.4, CAR_CENTRE_M, 0.0, 0.7), *axles, 60.0, 8.0, 10.0))
    return entities


def _write(out: Path, story: xosc.Maneuver | None = None, walker_at=None, walker_path=None) -> Path:
    road = xodr.create_road([xodr.Line(50.0), xodr.Arc(CURVE_1PM, angle=math.pi / 2), xodr.Line(80.0)], id=1,
                            left_lanes=1, right_lanes=2, lane_width=3.5)
    odr = xodr.OpenDrive("curve")
    odr.add_road(road)
    odr.adjust_roads_and_lanes()
    odr.write_xml(str(out / "curve.xodr"))
    init = xosc.Init()
    init.add_init_action("Ego", xosc.TeleportAction(xosc.LanePosition(10.0, 0.0, -1, 1)))
    init.add_init_action("Ego", _step(50 / 3.6))
    s, lane, offset = WALKER
    init.add_init_action("walker", xosc.TeleportAction(walker_at or xosc.LanePosition(s, offset, lane, 1)))
    if walker_path is not None:
        init.add_init_action("walker", _step(1.5))
        init.add_init_action("walker", walker_path)
    s, t, h = CAR
    init.add_init_action("parked", xosc.TeleportAction(xosc.RoadPosition(s, t, 1, xosc.Orientation(
        h=h, reference=xosc.ReferenceContext.relative))))
    board = xosc.StoryBoard(init, xosc.ValueTrigger("end", 0.0, xosc.ConditionEdge.rising,
                                                    xosc.SimulationTimeCondition(2.0, xosc.Rule.greaterThan), "stop"))
    if story is not None:
        board.add_maneuver(story, "walker")
    scenario = xosc.Scenario("curve", "crd tests", xosc.ParameterDeclarations(), _entities(), board,
                             xosc.RoadNetwork(roadfile="curve.xodr"), xosc.Catalog(), osc_minor_version=2)
    path = out / "curve.xosc"
    scenario.write_xml(str(path))
    return path


def test_lane_and_road_positions_on_an_arc_place_the_objects_there(tmp_path: Path) -> None:
    scenario = read_xosc(_write(tmp_path))
    walker, parked = scenario.objects
    s, lane, offset = WALKER
    assert walker.road_pose is not None and walker.pose is None
    assert (walker.road_pose.s_m, walker.road_pose.t_m, walker.road_pose.heading_rad) == (s, -5.25 + offset, 0.0)
    assert parked.road_pose is None and parked.pose is not None  # its box centre is not its reference point
    road = build_road(scenario.road)  # crd's own road, in crd's frame
    s, t, h = CAR
    x, y, hdg, _ = road.pose_at(s, t)
    expected = (x + CAR_CENTRE_M * math.cos(hdg + h), y + CAR_CENTRE_M * math.sin(hdg + h), hdg + h)
    assert (parked.pose.x_m, parked.pose.y_m, parked.pose.heading_rad) == pytest.approx(expected, abs=1e-9)
    assert hdg > 0.3  # on the arc: the road has turned there
    assert crd(["run", str(tmp_path / "curve.xosc"), "--out", str(tmp_path / "run")]) == 0


ROAD_END_M = 50.0 + (math.pi / 2) / CURVE_1PM + 80.0


@pytest.mark.parametrize("step_m", [5.0, 40.0])
def test_a_polyline_along_a_lane_is_the_lane_when_its_chords_keep_to_it(tmp_path: Path, step_m: float) -> None:
    """Lane positions every 5 m on the arc: chords 2 cm off the lane, read as the lane; every 40 m: 1.3 m, as points."""
    s0, lane, offset = WALKER
    stations = [*range(int(s0), int(ROAD_END_M), int(step_m)), ROAD_END_M]
    trajectory = xosc.Trajectory("along", False)
    trajectory.add_shape(xosc.Polyline([], [xosc.LanePosition(s, offset, lane, 1) for s in stations]))
    path = _write(tmp_path, walker_path=xosc.FollowTrajectoryAction(trajectory, xosc.FollowingMode.position))
    traj = read_xosc(path).objects[0].trajectory
    assert traj.start == "at_start" and traj.speeds == ((0.0, 1.5),)
    if step_m == 5.0:
        assert (traj.lane, traj.lane_offset_m, traj.start_s_m, traj.waypoints) == (lane, offset, s0, ())
    else:
        assert traj.lane is None and len(traj.waypoints) == len(stations)


def _story(action) -> xosc.Maneuver:
    """The walker's one event: ``action`` at 1 s."""
    event = xosc.Event("go", xosc.Priority.override)
    event.add_action("go", action)
    event.add_trigger(xosc.ValueTrigger("at", 0.0, xosc.ConditionEdge.rising,
                                        xosc.SimulationTimeCondition(1.0, xosc.Rule.greaterThan)))
    maneuver = xosc.Maneuver("m")
    maneuver.add_event(event)
    return maneuver


_LINEAR = xosc.TransitionDynamics(xosc.DynamicsShapes.linear, xosc.DynamicsDimension.rate, 1.0)
CASES = {  # what stays refused for an object on the curved road: (story, walker's position, element named)
    "speed action of a placed object": (lambda: _story(xosc.AbsoluteSpeedAction(1.0, _LINEAR)), None, "SpeedAction"),
    "lane change of a placed object": (lambda: _story(xosc.AbsoluteLaneChangeAction(-1, _LINEAR)), None,
                                       "LaneChangeAction"),
    "relative lane position": (None, lambda: xosc.RelativeLanePosition(1, "Ego", 0.0, ds=20.0), "RelativeLanePosition"),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_what_an_object_on_a_curve_cannot_do_is_a_one_line_error(tmp_path: Path, case: str) -> None:
    story, position, tag = CASES[case]
    path = _write(tmp_path, story() if story else None, position() if position else None)
    line = [e.sourceline for e in etree.parse(str(path)).iter(tag)][-1]  # the story's, after the ego's Init speed
    with pytest.raises(ConfigError) as err:
        read_xosc(path)
    assert "\n" not in str(err.value)
    assert str(err.value).startswith(f"{path}: not supported yet: <{tag}> at line {line}"), str(err.value)
