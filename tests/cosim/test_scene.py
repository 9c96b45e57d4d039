"""Scene geometry and motion (no FMU): braking and lateral profiles, contact, the radar's object, end conditions."""

import math

import pytest

from cosim.errors import ConfigError
from cosim.scenarios.config import EndConfig, ObjectConfig, PlantConfig, RadarConfig, Scenario
from cosim.scenarios.loader import scenario_from_dict
from cosim.scenarios.resolve import scenario_to_toml
from cosim.world.ego import EgoBody
from cosim.world.plant_fmu import PlantPose
from cosim.world.scene import Scene
from cosim.world.scene_build import build_objects
from cosim.world.scene_contact import ContactWatch
from cosim.world.scene_motion import Lateral, Longitudinal

CAR = {"length_m": 4.023, "width_m": 1.712}
BODY = EgoBody(PlantConfig())


def scene(*objects, end=EndConfig(), radar=RadarConfig()):
    sc = Scenario(objects=tuple(ObjectConfig(**o) for o in objects), object=ObjectConfig(enabled=False))
    return Scene(build_objects(sc, None), BODY, radar, end)


def ego(bumper_m, speed_mps=0.0):
    """The ego with its front bumper at ``bumper_m`` on the path, heading along it."""
    return BODY.at(PlantPose(bumper_m, speed_mps, 0.0, 0.0, 0.0, speed_mps, 0.0))


def touching(s, t_s, bumper_m):
    watch = ContactWatch(s)
    watch.candidates(t_s, ego(bumper_m), 0.01)
    return watch.contact(t_s, ego(bumper_m))


def test_braking_profile_matches_numerical_integration():
    lon = Longitudinal(rear0_m=10.0, speed_mps=20.0, decel_mps2=4.0, ramp_s=1.0, end_speed_mps=5.0)
    x, v, h = 10.0 + 20.0 * 2.0, 20.0, 1e-4
    for k in range(int(8.0 / h)):  # braking from t = 2 s: decel ramps to 4 m/s^2 within 1 s
        tau = (k + 0.5) * h
        a = 4.0 * min(1.0, tau / 1.0) if v > 5.0 else 0.0
        v = max(5.0, v - a * h)
        x += v * h
        if k % 5000 == 0:
            xs, vs = lon.state(2.0 + (k + 1) * h, 2.0)
            assert xs == pytest.approx(x, abs=2e-3) and vs == pytest.approx(v, abs=2e-3)
    assert lon.state(12.0, 2.0)[1] == 5.0
    assert lon.state(1.0, 2.0) == (30.0, 20.0)  # before the onset: constant speed
    assert lon.state(1.0, None) == (30.0, 20.0)


def test_deceleration_reached_within_the_ramp():
    lon = Longitudinal(0.0, 20.0, decel_mps2=4.0, ramp_s=1.0)
    dv = lambda t0, t1: lon.state(t1, 0.0)[1] - lon.state(t0, 0.0)[1]  # noqa: E731
    assert dv(0.5, 0.51) / 0.01 == pytest.approx(-2.0, rel=0.02)
    assert dv(1.5, 1.51) / 0.01 == pytest.approx(-4.0, rel=1e-6)
    assert lon.state(100.0, 0.0)[1] == 0.0


def test_lateral_motion_moves_then_stays():
    lat = Lateral(0.0, speed_mps=1.0, end_m=3.5)
    assert lat.state(1.0, None) == (0.0, 0.0)
    assert lat.state(3.0, 1.0) == (pytest.approx(2.0), 1.0)
    assert lat.state(10.0, 1.0) == (3.5, 0.0)
    assert Lateral(3.5, 1.0, 0.0).state(2.0, 0.0) == (pytest.approx(1.5), -1.0)  # cut-in from the left


def test_contact_needs_lateral_and_longitudinal_overlap():
    # ego: bumper at 0, 4.358 m long, 1.815 m wide; the limit of lateral overlap is (1.815 + 1.712) / 2
    limit = (1.815 + 1.712) / 2
    assert touching(scene(dict(position_m=-1.0, lateral_m=0.0, **CAR)), 0.0, 0.0) is not None
    assert touching(scene(dict(position_m=-1.0, lateral_m=limit - 0.01, **CAR)), 0.0, 0.0) is not None
    assert touching(scene(dict(position_m=-1.0, lateral_m=limit + 0.01, **CAR)), 0.0, 0.0) is None
    assert touching(scene(dict(position_m=-1.0, lateral_m=3.5, **CAR)), 0.0, 0.0) is None  # adjacent lane
    assert touching(scene(dict(position_m=0.5, **CAR)), 0.0, 0.0) is None  # still ahead
    assert touching(scene(dict(position_m=-9.0, **CAR)), 0.0, 0.0) is None  # passed behind us


def test_path_gap_ignores_objects_beside_the_path():
    s = scene(dict(name="adjacent", position_m=20.0, lateral_m=3.5, **CAR),
              dict(name="ahead", position_m=50.0, **CAR))
    assert s.path_gap(0.0, ego(0.0))[0] == 50.0 and s.path_gap(0.0, ego(0.0))[1].obj.name == "ahead"


def test_radar_reports_the_in_lane_object_before_a_nearer_one_beside_the_lane():
    s = scene(dict(name="adjacent", position_m=20.0, lateral_m=3.5, **CAR),
              dict(name="ahead", position_m=50.0, speed_mps=5.0, **CAR))
    truth = s.radar_truth(0.0, ego(0.0, 10.0))
    assert (truth.gap_m, truth.range_rate_mps, truth.lateral_m) == (50.0, -5.0, 0.0)
    alone = scene(dict(position_m=20.0, lateral_m=3.5, **CAR)).radar_truth(0.0, ego(0.0, 10.0))
    assert alone.lateral_m == 3.5  # nothing in the lane: the nearest visible object, the ECU decides


def test_radar_field_of_view():
    narrow = RadarConfig(field_of_view_deg=20.0)  # ±10°: the car's near edge 2.644 m off the axis
    near_edge = 3.5 - 0.856
    seen_from = near_edge / math.tan(math.radians(10.0))
    assert scene(dict(position_m=seen_from + 0.1, lateral_m=3.5, **CAR), radar=narrow).radar_truth(0, ego(0.0))
    assert scene(dict(position_m=seen_from - 0.1, lateral_m=3.5, **CAR), radar=narrow).radar_truth(0, ego(0.0)) is None
    assert scene(dict(position_m=-1.0, **CAR)).radar_truth(0, ego(0.0)) is None  # alongside or behind: not ahead


def test_gap_trigger_fires_once():
    s = scene(dict(position_m=50.0, speed_mps=10.0, brake_decel_mps2=4.0, brake_at_gap_m=30.0, **CAR))
    s.observe(0.0, ego(10.0))  # gap 40 m
    assert s.objects[0].motion.brake_t_s is None
    s.observe(1.0, ego(35.0))  # gap 25 m
    assert s.objects[0].motion.brake_t_s == 1.0
    s.observe(2.0, ego(0.0))
    assert s.objects[0].motion.brake_t_s == 1.0


def test_end_conditions():
    still = scene(dict(position_m=50.0, **CAR), end=EndConfig(standstill=True))
    assert still.end_reason(0.0, ego(0.0, 0.0)) is None  # at rest before moving: not an end
    assert still.end_reason(0.1, ego(0.0, 5.0)) is None
    assert still.end_reason(0.2, ego(0.0, 0.005)) == "standstill"
    matched = scene(dict(position_m=50.0, speed_mps=5.56, **CAR), end=EndConfig(matched_speed=True))
    assert matched.end_reason(0.0, ego(0.0, 5.56)) is None  # same speed from the start: not armed
    assert matched.end_reason(0.1, ego(0.0, 13.9)) is None
    assert matched.end_reason(0.2, ego(0.0, 5.60)) is None
    assert matched.end_reason(0.3, ego(0.0, 5.55)) == "matched_speed"


def test_objects_array_loads_and_round_trips():
    import tomllib
    data = {"objects": [dict(name="a", position_m=30.0, **CAR),
                        dict(name="b", position_m=60.0, lateral_m=3.5, lateral_end_m=0.0, lateral_speed_mps=1.0,
                             lateral_at_gap_m=40.0, **CAR)],
            "end": {"standstill": True}, "plant": {"initial_speed_mps": 10.0}}
    sc = scenario_from_dict(data)
    assert not sc.object.enabled and [o.name for o in sc.scene_objects()] == ["a", "b"]
    assert scenario_from_dict(tomllib.loads(scenario_to_toml(sc))) == sc


@pytest.mark.parametrize("data, fragment", [
    ({"object": {}, "objects": [{}]}, "either [object] or [[objects]]"),
    ({"objects": [{}, {"accel_mps2": 1.0}]}, "objects[1].accel_mps2: unknown key; "),
    ({"objects": [{"brake_decel_mps2": 30.0}]}, "objects[0].brake_decel_mps2"),
    ({"objects": []}, "objects: expected one or more"),
    ({"plant": {"fmu": "x.fmu", "initial_speed_mps": 5.0, "inputs": {"accel_command": "a"},
                "outputs": {"position": "p", "speed": "v"}}}, "plant.initial_speed_mps"),
    ({"plant": {"initial_speed_mps": 5.0, "parameters": {"v0": 3.0}}}, "plant.parameters.v0"),
])
def test_scene_keys_are_checked(data, fragment):
    with pytest.raises(ConfigError) as err:
        scenario_from_dict(data)
    assert fragment in str(err.value)
