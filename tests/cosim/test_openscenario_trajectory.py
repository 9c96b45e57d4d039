"""A ``FollowTrajectoryAction`` with a polyline (written with scenariogeneration) as ``[objects.trajectory]``.

A pedestrian walks a polyline across the ego's path and then along it; the run's pose columns must
put its box centre on the polyline, at its own speed's distance along it since the start time.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("scenariogeneration")
from lxml import etree  # noqa: E402
from scenariogeneration import xosc  # noqa: E402

from cosim.cli.main import main as crd  # noqa: E402
from cosim.errors import ConfigError  # noqa: E402
from cosim.scenarios.openscenario import read_xosc  # noqa: E402

EGO = (4.5, 1.8, 1.4)  # length, width, box centre ahead of the reference point
PATH = [(80.0, -5.0), (80.0, 5.0), (90.0, 5.0)]  # in the file's frame; the ego starts at (0, 0) heading 0
WALK_MPS, START_S = 2.0, 0.5


def _step(speed: float) -> xosc.AbsoluteSpeedAction:
    return xosc.AbsoluteSpeedAction(speed, xosc.TransitionDynamics(xosc.DynamicsShapes.step,
                                                                   xosc.DynamicsDimension.time, 0.0))


def _write(out: Path) -> Path:
    length, width, centre = EGO
    ego = xosc.Vehicle("car", xosc.VehicleCategory.car, xosc.BoundingBox(width, length, 1.4, centre, 0.0, 0.7),
                       xosc.Axle(0.5, 0.65, 1.6, 2.7, 0.33), xosc.Axle(0.0, 0.65, 1.6, 0.0, 0.33), 60.0, 8.0, 10.0)
    walker = xosc.Pedestrian("walker", 70.0, xosc.PedestrianCategory.pedestrian,
                             xosc.BoundingBox(0.5, 0.6, 1.8, 0.0, 0.0, 0.9))
    entities = xosc.Entities()
    entities.add_scenario_object("Ego", ego)
    entities.add_scenario_object("walker", walker)
    init = xosc.Init()
    init.add_init_action("Ego", xosc.TeleportAction(xosc.WorldPosition(0.0, 0.0, 0.0, 0.0)))
    init.add_init_action("Ego", _step(40 / 3.6))
    init.add_init_action("walker", xosc.TeleportAction(xosc.WorldPosition(*PATH[0], 0.0, math.pi / 2)))
    init.add_init_action("walker", _step(WALK_MPS))
    trajectory = xosc.Trajectory("cross", False)
    trajectory.add_shape(xosc.Polyline([0.0, 5.0, 10.0], [xosc.WorldPosition(x, y) for x, y in PATH]))
    event = xosc.Event("walk", xosc.Priority.override)
    event.add_action("walk", xosc.FollowTrajectoryAction(trajectory, xosc.FollowingMode.position))
    event.add_trigger(xosc.ValueTrigger("at", 0.0, xosc.ConditionEdge.rising,
                                        xosc.SimulationTimeCondition(START_S, xosc.Rule.greaterThan)))
    maneuver = xosc.Maneuver("walking")
    maneuver.add_event(event)
    board = xosc.StoryBoard(init, xosc.ValueTrigger("end", 0.0, xosc.ConditionEdge.rising,
                                                    xosc.SimulationTimeCondition(10.0, xosc.Rule.greaterThan), "stop"))
    board.add_maneuver(maneuver, "walker")
    scenario = xosc.Scenario("walk", "crd tests", xosc.ParameterDeclarations(), entities, board, xosc.RoadNetwork(),
                             xosc.Catalog(), osc_minor_version=2)
    path = out / "walk.xosc"
    scenario.write_xml(str(path))
    return path


def test_a_polyline_trajectory_moves_the_object_along_its_points(tmp_path: Path) -> None:
    path = _write(tmp_path)
    front = EGO[0] / 2 + EGO[2]  # crd's origin: the ego's front bumper
    traj = read_xosc(path).object.trajectory
    assert [list(p) for p in traj.waypoints] == [[x - front, y] for x, y in PATH]
    out = tmp_path / "run"
    assert crd(["run", str(path), "--out", str(out), "--strategy", "none"]) == 0
    with open(out / "none" / "timeseries.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    t = np.array([float(r["time_s"]) for r in rows])
    xy = np.array([[float(r["obj0_x_m"]) + front, float(r["obj0_y_m"])] for r in rows])
    travelled = np.clip(WALK_MPS * (t - START_S), 0.0, 20.0)  # 10 m across, 10 m along, then it stands
    on_first = travelled <= 10.0
    expected = np.where(on_first[:, None], np.column_stack([np.full_like(t, 80.0), -5.0 + travelled]),
                        np.column_stack([70.0 + travelled, np.full_like(t, 5.0)]))
    assert np.abs(xy - expected).max() < WALK_MPS * 0.011  # within one step of the object's motion
    assert on_first.any() and (~on_first).any() and t[-1] > 9.9  # both legs walked, to the end of the run


CASES = {  # what stays refused in a FollowTrajectoryAction: (xpath, new element, the element named)
    "clothoid": ("//Shape/Polyline", '<Clothoid curvature="0.1" curvatureDot="0" length="10"/>', "Clothoid"),
    # absolute vertex times from 0 s, for a trajectory that starts at 0.5 s: crd's object would lag behind them
    "timing before the start": ("//TimeReference/None", '<Timing domainAbsoluteRelative="absolute" scale="1" '
                                                        'offset="0"/>', "Timing"),
    # times 0, 5, 7 s over 10 m and 10 m: 2 m/s, then 5 m/s, a step crd's speed profile cannot make
    "timing with a speed step": ("//Vertex[3]", '<Vertex time="7.0"><Position><WorldPosition x="90.0" y="5.0"/>'
                                                '</Position></Vertex>', "Timing"),
    "follow mode": ("//TrajectoryFollowingMode", '<TrajectoryFollowingMode followingMode="follow"/>',
                    "TrajectoryFollowingMode"),
}


def _edit(path: Path, *edits: tuple[str, str]) -> None:
    """Replace the element at each xpath with the given XML."""
    tree = etree.parse(str(path))
    for xpath, xml in edits:
        old = tree.xpath(xpath)[0]
        old.getparent().replace(old, etree.fromstring(xml))
    tree.write(str(path))


TIMING = {  # <Timing> attributes -> (speed, start) the vertex times 0, 5, 10 s over 10 m + 10 m give
    'domainAbsoluteRelative="relative" scale="1" offset="0"': (WALK_MPS, START_S),
    'domainAbsoluteRelative="absolute" scale="1" offset="0.5"': (WALK_MPS, START_S),
    'domainAbsoluteRelative="relative" scale="0.5" offset="1.5"': (2 * WALK_MPS, START_S + 1.5),
}


@pytest.mark.parametrize("timing", sorted(TIMING))
def test_vertex_times_with_a_timing_reference_give_the_speed_and_start(tmp_path: Path, timing: str) -> None:
    path = _write(tmp_path)
    untimed = read_xosc(path).object.trajectory
    _edit(path, ("//TimeReference/None", f"<Timing {timing}/>"))
    traj = read_xosc(path).object.trajectory
    speed, start = TIMING[timing]
    assert traj.speeds == ((0.0, pytest.approx(speed, rel=1e-12)),)
    assert (traj.start, traj.start_value) == ("time", pytest.approx(start, abs=1e-12))
    assert traj.waypoints == untimed.waypoints
    if speed == WALK_MPS:
        assert traj.speeds == untimed.speeds and traj.start_value == untimed.start_value  # the same motion


@pytest.mark.parametrize("case", sorted(CASES))
def test_what_a_trajectory_cannot_hold_is_a_one_line_error(tmp_path: Path, case: str) -> None:
    path = _write(tmp_path)
    xpath, xml, tag = CASES[case]
    if tag == "Timing" and "Timing" not in xml:
        _edit(path, ("//TimeReference/None", '<Timing domainAbsoluteRelative="relative" scale="1" offset="0"/>'))
    _edit(path, (xpath, xml))
    line = next(e.sourceline for e in etree.parse(str(path)).iter(tag))
    with pytest.raises(ConfigError) as err:
        read_xosc(path)
    assert "\n" not in str(err.value)
    assert str(err.value).startswith(f"{path}: not supported yet: <{tag}> at line {line}"), str(err.value)
