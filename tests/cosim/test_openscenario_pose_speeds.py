"""Export then import of what the planar catalogues needed (issue 24): a ``pose`` on the ego's axis, kept as a
``RelativeObjectPosition``, and a trajectory whose speed changes, kept as ``SpeedAction`` segments started by
``TraveledDistanceCondition`` (and a trajectory started by the ego's time to collision)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

pytest.importorskip("scenariogeneration")
from lxml import etree  # noqa: E402

from cosim.errors import ConfigError  # noqa: E402
from cosim.scenarios.loader import scenario_from_dict  # noqa: E402
from cosim.scenarios.openscenario import read_xosc  # noqa: E402
from cosim.scenarios.openscenario.export import export_xosc  # noqa: E402


def _scene(objects: list[dict]) -> dict:
    """A straight road under a steering ego (so it stays planar) with ``objects``."""
    return {"scenario": {"name": "ps", "duration_s": 5.0}, "plant": {"initial_speed_mps": 10.0},
            "driver": {"model": "hold_speed", "set_speed_mps": 10.0, "steering": {"lane": -1}},
            "road": {"y_m": 1.75, "geometry": [{"kind": "line", "length_m": 200.0}],
                     "lane_sections": [{"left_m": [3.5], "right_m": [3.5]}]},
            "objects": objects}


def _round_trip(tmp_path: Path, objects: list[dict]):
    scenario = scenario_from_dict(_scene(objects))
    xosc_path, _ = export_xosc(scenario, tmp_path, "ps")
    return scenario, read_xosc(xosc_path), etree.parse(str(xosc_path))


AXIS_POSES = [
    {"name": "parked ahead", "pose": {"x_m": 26.083, "y_m": -2.9125, "heading_rad": 0.0}},
    {"name": "oncoming", "pose": {"x_m": 40.5, "y_m": 3.5, "heading_rad": math.pi}, "speed_mps": 2.5},
    {"name": "straight on", "pose": {"x_m": 12.0, "y_m": 0.0, "heading_rad": 0.0}, "speed_mps": 1.0},
]


def test_a_pose_on_the_ego_axis_comes_back_as_the_pose(tmp_path: Path) -> None:
    scenario, back, tree = _round_trip(tmp_path, AXIS_POSES)
    assert back == scenario
    assert [o.pose for o in back.scene_objects()] == [o.pose for o in scenario.scene_objects()]
    rel = tree.xpath("//Init//RelativeObjectPosition")
    assert [(r.get("entityRef"), float(r.get("dx"))) for r in rel] == [("Ego", 26.083), ("Ego", 40.5), ("Ego", 12.0)]
    assert not tree.xpath("//Private[@entityRef='parked ahead']//WorldPosition")


def _walk(speeds: list, **start) -> dict:
    return {"name": "walker", "trajectory": {"waypoints": [[30.0, -8.0], [30.0, 0.0], [30.0, 6.0]],
                                             "speeds": speeds, **start}}


CHANGING = {  # case: (object, SpeedActions started by TraveledDistanceCondition, and with the path at s = 0)
    "from the start, held between changes": (_walk([[0.0, 2.0], [3.0, 2.0], [5.5, 4.0], [9.0, 0.5]]), 2, 0),
    "at a time from rest, stopping short": (_walk([[0.0, 0.0], [1.0, 1.5], [2.5, 1.5], [3.0, 0.0]],
                                                  start="time", start_value=1.25), 1, 1),
    "by the ego's time to collision": (_walk([[0.0, 0.0], [1.0, 1.3888888888888888], [1.3900000000000001,
                                                                                    1.3888888888888888],
                                              [1.8900000000000001, 0.0]], start="ego_ttc", start_value=3.6,
                                             start_point=[30.0, 0.0]), 1, 1),
}


@pytest.mark.parametrize("case", sorted(CHANGING))
def test_a_changing_trajectory_speed_comes_back_as_its_knots(tmp_path: Path, case: str) -> None:
    obj, by_distance, with_path = CHANGING[case]
    scenario, back, tree = _round_trip(tmp_path, [obj])
    assert back == scenario
    assert [list(k) for k in back.scene_objects()[0].trajectory.speeds] == obj["trajectory"]["speeds"]
    assert len(tree.xpath("//TraveledDistanceCondition")) == by_distance
    assert len(tree.xpath("//Event[@name='walker_trajectory']//SpeedAction")) == with_path
    assert len(tree.xpath("//Story//SpeedActionDynamics[@dynamicsShape='linear'][@dynamicsDimension='distance']")) \
        == by_distance + with_path


def test_an_ego_ttc_trajectory_start_comes_back(tmp_path: Path) -> None:
    obj = _walk([[0.0, 1.5]], start="ego_ttc", start_value=2.5, start_point=[30.0, 0.5])
    scenario, back, tree = _round_trip(tmp_path, [obj])
    assert back == scenario
    trajectory = back.scene_objects()[0].trajectory
    assert (trajectory.start, trajectory.start_value, list(trajectory.start_point)) == ("ego_ttc", 2.5, [30.0, 0.5])
    ttc = tree.xpath("//Event[@name='walker_trajectory']//TimeToCollisionCondition")[0]
    assert (ttc.get("freespace"), ttc.get("value")) == ("true", "2.5")


def _edited(tmp_path: Path, objects: list[dict], xpath: str, name: str, value: str) -> Path:
    xosc_path, _ = export_xosc(scenario_from_dict(_scene(objects)), tmp_path, "ps")
    tree = etree.parse(str(xosc_path))
    tree.xpath(xpath)[0].set(name, value)
    tree.write(str(xosc_path))
    return xosc_path


def test_an_object_placed_relative_to_another_object_is_a_pose(tmp_path: Path) -> None:
    """A foreign file: ``(dx, dy)`` in the walker's frame (heading +y), the heading the walker's plus ``h``."""
    path = _edited(tmp_path, [_walk([[0.0, 1.0]]), AXIS_POSES[0]], "//Private[@entityRef='parked ahead']"
                   "//RelativeObjectPosition", "entityRef", "walker")
    pose = read_xosc(path).scene_objects()[1].pose
    assert (pose.x_m, pose.y_m, pose.heading_rad) == pytest.approx((30.0 + 2.9125, -8.0 + 26.083, math.pi / 2))


def test_a_position_relative_to_a_relatively_placed_object_is_refused(tmp_path: Path) -> None:
    path = _edited(tmp_path, AXIS_POSES[:2], "//Private[@entityRef='oncoming']//RelativeObjectPosition",
                   "entityRef", "parked ahead")
    with pytest.raises(ConfigError, match=r"not supported yet: <RelativeObjectPosition> at line \d+ \(a position "
                                          r"relative to 'parked ahead', which Init does not place by an absolute"):
        read_xosc(path)


def test_speed_changes_that_overlap_are_refused(tmp_path: Path) -> None:
    obj = CHANGING["from the start, held between changes"][0]
    path = _edited(tmp_path, [obj], "(//TraveledDistanceCondition)[2]", "value", "4.0")  # the first ends at 5.5
    with pytest.raises(ConfigError, match=r"not supported yet: <SpeedAction> at line \d+ \(a speed change from 4 m "
                                          r"starts before the previous one ends at 5.5 m\)"):
        read_xosc(path)
