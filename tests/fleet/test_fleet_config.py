"""The fleet file: vehicles in their own frames, world objects brought into each, errors naming key and file."""

import math

import pytest

from cosim.errors import ConfigError
from cosim.fleet.bodies import Frame, PoseBoard, PuppetMotion, WorldBody
from cosim.fleet.config import fleet_from_dict, load_fleet
from cosim.world.trajectory import Kinematics

ROAD = {"y_m": 1.75, "geometry": [{"kind": "line", "length_m": 100.0}],
        "lane_sections": [{"left_m": [3.5], "right_m": [3.5]}]}


def _data(**extra):
    data = {"fleet": {"name": "t", "duration_s": 2.0},
            "vehicle": {"road": ROAD, "ecu": {"strategy": "none"}},
            "vehicles": [{"name": "a", "x_m": -40.0}, {"name": "b", "y_m": -40.0, "heading_rad": math.pi / 2}]}
    data.update(extra)
    return data


def test_each_vehicle_is_a_scenario_of_its_own_with_its_seed_and_overrides():
    data = _data()
    data["vehicles"][1]["ecu"] = {"strategy": "conservative"}
    fleet = fleet_from_dict(data)
    a, b = fleet.vehicles
    assert (a.scenario.ecu.strategy, b.scenario.ecu.strategy) == ("none", "conservative")
    assert (a.scenario.scenario.seed, b.scenario.scenario.seed) == (0, 1)
    assert a.scenario.scene_objects() == ()  # no default cyclist: the others are its objects
    assert b.placement.heading_rad == pytest.approx(math.pi / 2)


def test_a_world_object_is_placed_in_every_vehicle_frame():
    data = _data(objects=[{"name": "parked", "length_m": 4.0, "width_m": 1.8,
                           "pose": {"x_m": 0.0, "y_m": -10.0, "heading_rad": math.pi / 2}}])
    fleet = fleet_from_dict(data)
    pa = fleet.vehicles[0].scenario.scene_objects()[0].pose
    pb = fleet.vehicles[1].scenario.scene_objects()[0].pose
    assert (pa.x_m, pa.y_m, pa.heading_rad) == pytest.approx((40.0, -10.0, math.pi / 2))
    assert (pb.x_m, pb.y_m, pb.heading_rad) == pytest.approx((30.0, 0.0, 0.0), abs=1e-9)


@pytest.mark.parametrize("change, message", [
    (lambda d: d["vehicles"][1].update(ecu={"stratgy": "none"}), "vehicles[1].ecu.stratgy"),
    (lambda d: d["vehicles"][0].update(colour="red"), "vehicles[0].colour"),
    (lambda d: d["fleet"].update(conflict_radius_m=-1.0), "fleet.conflict_radius_m"),
    (lambda d: d.update(vehicles=d["vehicles"][:1]), "vehicles: expected two or more"),
    (lambda d: d["vehicles"][1].update(name="a"), "expected distinct names"),
    (lambda d: d["vehicle"].pop("road"), "vehicles[0].road: expected a planar vehicle"),
    (lambda d: d.update(objects=[{"name": "x"}]), "objects[0].pose"),
])
def test_bad_keys_are_one_line_errors_naming_the_key(change, message):
    data = _data()
    change(data)
    with pytest.raises(ConfigError) as info:
        fleet_from_dict(data)
    assert message in str(info.value) and "\n" not in str(info.value)


@pytest.mark.parametrize("seed", [0, 2158462969467110532])  # the second: a seed crd sweep drew
def test_under_a_way_out_rule_each_vehicle_draws_its_patience_and_its_back_off_seed(seed):
    """From its own seed (the fleet's plus its index), up to the largest scenario seed a sweep draws."""
    data = _data()
    data["fleet"]["seed"] = seed
    data["vehicle"]["ecu"]["way_out"] = "right_of_way"
    a, b = (v.scenario.ecu for v in fleet_from_dict(data).vehicles)
    assert (a.way_out_seed, b.way_out_seed) == (seed, seed + 1)
    assert 0.5 <= a.way_out_patience_s <= 3.0 and a.way_out_patience_s != b.way_out_patience_s


def test_an_error_in_a_file_names_the_file(tmp_path):
    path = tmp_path / "f.toml"
    path.write_text('[fleet]\nname = "t"\n[vehicle.road]\ny_m = 1.75\n[[vehicle.road.geometry]]\nkind = "line"\n'
                    'length_m = 50.0\n[[vehicles]]\nname = "a"\n[[vehicles]]\nname = "b"\n'
                    '[vehicles.driver]\nmodle = "cruise"\n')
    with pytest.raises(ConfigError, match=r"f\.toml: vehicles\[1\]\.driver\.modle"):
        load_fleet(path)


def test_frame_round_trip_and_the_puppet_seen_from_another_frame():
    f = Frame(-40.0, 0.0, 0.3)
    x, y = f.to_world(12.0, -3.0)
    assert f.from_world(x, y) == pytest.approx((12.0, -3.0))
    board = PoseBoard()
    board.write("b", WorldBody(1.0, Kinematics(0.0, -40.0, math.pi / 2, 0.0, 8.0, 0.0, 8.0)))
    seen = PuppetMotion(board, "b", Frame(-40.0, 0.0, 0.0))
    st = seen.state(1.0)
    assert (st.x_m, st.y_m, st.yaw_rad, st.vx_mps, st.vy_mps) == pytest.approx((40.0, -40.0, math.pi / 2, 0.0, 8.0))
    later = seen.state(1.5)  # past the board's time: at constant velocity
    assert (later.x_m, later.y_m) == pytest.approx((40.0, -36.0))
    assert seen.observe(1.0, 5.0, None) is False


def test_the_list_shows_each_bundled_scene_by_the_first_sentence_of_its_comment():
    """``crd fleet --list``: a whole sentence, not the first line cut mid-phrase."""
    from cosim.cli.fleet import bundled_scenes, find_scene
    from cosim.cli.scenarios import description

    for path in bundled_scenes():
        text = description(path)
        assert text.endswith((".", ")")) and "#" not in text and len(text) > 40, (path.name, text)
    assert description(find_scene("crossing")).endswith("(the paper's guidance task).")
