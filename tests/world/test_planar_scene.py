"""The scene in the plane: the ego frame's arithmetic, contact between turned boxes, the radar's object in a turn."""

from __future__ import annotations

import math
import random

import numpy as np
import pytest

from cosim.scenarios.config import EndConfig, ObjectConfig, PlantConfig, RadarConfig, Scenario
from cosim.scenarios.planar_config import CrossingConfig, PoseConfig
from cosim.world.ego import EgoBody
from cosim.world.geometry import Box, BodyMotion, least_overlap, overlaps, swept_contact
from cosim.world.plant_fmu import PlantPose
from cosim.world.scene import Scene, relative
from cosim.world.scene_build import build_objects
from cosim.world.scene_contact import ContactWatch, object_box

PLANT = PlantConfig()
BODY = EgoBody(PLANT)


def scene(*objects: ObjectConfig, radar: RadarConfig = RadarConfig()) -> Scene:
    sc = Scenario(objects=objects, object=ObjectConfig(enabled=False))
    return Scene(build_objects(sc, None), BODY, radar, EndConfig())


def ego_at(front_x: float, front_y: float, yaw: float, speed: float = 0.0, yaw_rate: float = 0.0):
    """The ego whose front bumper's centre is at (front_x, front_y), heading ``yaw``."""
    d = BODY.front_m
    cg_x, cg_y = front_x - d * math.cos(yaw), front_y - d * math.sin(yaw)
    return BODY.at(PlantPose(cg_x + d, speed, cg_y, yaw, yaw_rate, speed, 0.0))


def test_ego_front_is_the_1d_bumper_to_the_bit_when_straight():
    rng = random.Random(1)
    for _ in range(200):
        x = rng.uniform(-50.0, 500.0)
        ego = BODY.at(PlantPose(x, 10.0, 0.0, 0.0, 0.0, 10.0, 0.0))
        assert ego.front_x_m == x + PLANT.front_bumper_offset_m and ego.front_y_m == 0.0
    turned = ego_at(10.0, 2.0, 0.7)
    assert (turned.front_x_m, turned.front_y_m) == pytest.approx((10.0, 2.0))
    assert math.hypot(turned.front_x_m - turned.x_m, turned.front_y_m - turned.y_m) == pytest.approx(BODY.front_m)


def test_gap_and_lateral_are_the_1d_values_bit_for_bit_on_the_path():
    rng = random.Random(2)
    for _ in range(200):
        rear, lat, bumper = rng.uniform(-20, 300), rng.uniform(-5, 5), rng.uniform(0, 250)
        obj = ObjectConfig(position_m=rear, lateral_m=lat, length_m=rng.uniform(0.5, 5), width_m=rng.uniform(0.3, 2))
        s = scene(obj)
        r = s.seen_from(0.0, BODY.at(PlantPose(bumper, 5.0, 0.0, 0.0, 0.0, 5.0, 0.0)))[0]
        assert r.gap_m == rear - bumper and r.y_c_m == lat and r.half_y_m == obj.width_m / 2.0 and r.aligned


def _corners_in_ego_frame(box: Box, ego) -> np.ndarray:
    rel = box.corners() - (ego.front_x_m, ego.front_y_m)
    c, s = ego.cos_yaw, ego.sin_yaw
    return np.column_stack([rel @ (c, s), rel @ (-s, c)])


def test_ego_frame_extents_match_the_corners_of_turned_boxes():
    rng = random.Random(3)
    for _ in range(300):
        pose = PoseConfig(rng.uniform(-30, 30), rng.uniform(-30, 30), rng.uniform(-3.1, 3.1))
        obj = ObjectConfig(pose=pose, length_m=rng.uniform(0.5, 5), width_m=rng.uniform(0.3, 2))
        s = scene(obj)
        ego = ego_at(rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-3.1, 3.1))
        r = s.seen_from(0.0, ego)[0]
        corners = _corners_in_ego_frame(object_box(s.objects[0], r.state), ego)
        assert r.gap_m == pytest.approx(corners[:, 0].min(), abs=1e-9)
        assert r.far_m == pytest.approx(corners[:, 0].max(), abs=1e-9)
        assert r.y_c_m == pytest.approx(corners[:, 1].mean(), abs=1e-9)
        assert r.half_y_m == pytest.approx(np.ptp(corners[:, 1]) / 2.0, abs=1e-9)


def test_contact_agrees_with_the_separating_axis_test_for_turned_boxes():
    rng = random.Random(4)
    hits = 0
    for _ in range(400):
        pose = PoseConfig(rng.uniform(-6, 6), rng.uniform(-4, 4), rng.uniform(-3.1, 3.1))
        obj = ObjectConfig(pose=pose, length_m=rng.uniform(0.5, 5), width_m=rng.uniform(0.3, 2))
        s = scene(obj)
        ego = ego_at(rng.uniform(-2, 2), rng.uniform(-1, 1), rng.uniform(-0.6, 0.6))
        box = object_box(s.objects[0], s.states(0.0)[0])
        if abs(least_overlap(BODY.box(ego), box)[0]) < 1e-6:
            continue  # touching: the two tests' boundaries differ by design (1-D conventions on the ego's axes)
        watch = ContactWatch(s)
        watch.candidates(0.0, ego, 0.01)
        hit = watch.contact(0.0, ego)
        assert (hit is not None) == overlaps(BODY.box(ego), box)
        hits += hit is not None
    assert 50 < hits < 350  # both outcomes were tried


def test_swept_normal_is_the_side_the_boxes_met_on():
    # a car running into a box near its edge: 3 cm deep along the road after a 1 ms step, 2 cm across
    standing = Box(10.3, 1.18, 0.0, 0.6, 0.6)
    before, after = Box(7.99, 0.0, 0.0, 4.0, 1.8), Box(8.03, 0.0, 0.0, 4.0, 1.8)
    assert abs(least_overlap(after, standing)[2]) == 1.0  # the least overlap is across: the wrong side
    hit = swept_contact((before, standing), (after, standing))
    assert (hit.normal_x, hit.normal_y) == (1.0, 0.0)
    # a box moved sideways into the car's flank: the normal is across
    side0, side1 = Box(8.0, 1.22, 0.0, 0.6, 0.6), Box(8.0, 1.18, 0.0, 0.6, 0.6)
    hit = swept_contact((after, side0), (after, side1))
    assert (hit.normal_x, hit.normal_y) == (0.0, 1.0)


def test_radar_in_a_turn_sees_a_standing_object_as_standing():
    # the ego turning left at 10 m/s; a parked car 20 m ahead along its heading, 1 m to its left
    ego = ego_at(0.0, 0.0, 0.4, speed=10.0, yaw_rate=0.2)
    c, s = math.cos(0.4), math.sin(0.4)
    centre = (20.0 + 2.0115) * c - 1.0 * s, (20.0 + 2.0115) * s + 1.0 * c
    sc = scene(ObjectConfig(pose=PoseConfig(*centre, 0.4), length_m=4.023, width_m=1.712))
    truth = sc.radar_truth(0.0, ego)
    assert truth.gap_m == pytest.approx(20.0) and truth.lateral_m == pytest.approx(1.0)
    assert truth.range_rate_mps == pytest.approx(-10.0)  # no frame-rotation term: the ECU reads it as standing


def test_a_crossing_target_meets_the_middle_of_the_front():
    """CPNA's timing: with the ego at a constant speed the target reaches the synchronisation point with it."""
    crossing = CrossingConfig(x_m=40.0, y_m=0.0, heading_rad=math.pi / 2)
    sc = scene(ObjectConfig(crossing=crossing, target_class="EPTa", length_m=0.6, width_m=0.5))
    speed, h = 11.11, 0.01
    for k in range(int(6.0 / h)):
        t = k * h
        ego = ego_at(speed * t, 0.0, 0.0, speed=speed)
        sc.observe(t, ego)
        if ego.front_x_m >= 40.0:
            break
    started = sc.objects[0].motion.started.started_at_s
    assert started is not None
    x, y = sc.objects[0].centre(sc.states(t)[0])
    assert x == pytest.approx(40.0) and y == pytest.approx(0.0, abs=speed * h * 0.2)


def test_standing_objects_are_worked_out_once_and_moving_ones_move():
    sc = scene(ObjectConfig(position_m=30.0), ObjectConfig(position_m=40.0, speed_mps=5.0))
    assert sc.objects[0].motion.state(0.0) is sc.objects[0].motion.state(7.0)
    assert sc.objects[1].motion.state(2.0).x_m == 50.0
    motion = BodyMotion(1.0, 0.0)
    assert motion.yaw_rate_radps == 0.0
