"""Object motion: speed profiles in closed form, paths, triggers, and Euro NCAP's synchronisation."""

from __future__ import annotations

import math

import pytest

import numpy as np

from cosim.world.reference_line import Arc, PlanView, Spiral
from cosim.world.road import LaneSection, Road
from cosim.world.targets import SIZE_CLASSES, TARGET_CLASSES, target_class
from cosim.world.trajectory import (
    TRIGGERS, AtTime, Behaviour, BehaviourState, EgoDistanceToPoint, EgoState, EgoTimeToPoint, OffsetPath,
    Polyline, SpeedProfile, advance, crossing, initial_state, kinematics,
)

KMH = 1 / 3.6


def test_speed_over_distance_is_constant_acceleration_between_knots():
    # Euro NCAP CPNA: 5 km/h after 1.0 m of acceleration (planar-protocol-facts.md §1.4)
    v = 5 * KMH
    profile = SpeedProfile.over_distance([(0.0, 0.0), (1.0, v)])
    t_acc = 2 * 1.0 / v  # 1.44 s
    assert profile.state(t_acc / 2) == pytest.approx((0.25, v / 2, v * v / 2))
    assert profile.state(t_acc) == pytest.approx((1.0, v, 0.0))
    assert profile.state(t_acc + 2.0) == pytest.approx((1.0 + 2 * v, v, 0.0))
    assert profile.time_to_reach(4.0) == pytest.approx(t_acc + 3.0 / v)
    assert profile.time_to_reach(0.25) == pytest.approx(t_acc / 2)
    assert profile.state(-1.0) == pytest.approx((0.0, 0.0, v * v / 2))  # before the start: at rest


def test_speed_over_time_is_linear_between_knots():
    profile = SpeedProfile.over_time([(1.0, 2.0), (3.0, 6.0), (5.0, 0.0)])
    assert profile.state(0.5) == pytest.approx((1.0, 2.0, 0.0))  # before the first knot: its speed
    assert profile.state(2.0) == pytest.approx((2.0 + 2.0 + 1.0, 4.0, 2.0))
    assert profile.state(4.0) == pytest.approx((2.0 + 8.0 + 6.0 - 1.5, 3.0, -3.0))
    assert profile.state(9.0) == pytest.approx((2.0 + 8.0 + 6.0, 0.0, 0.0))  # stopped at the end
    assert profile.time_to_reach(16.0) == pytest.approx(5.0)
    assert profile.time_to_reach(16.5) == math.inf


def test_bad_profiles_are_refused():
    with pytest.raises(ValueError, match="never gets there"):
        SpeedProfile.over_distance([(0.0, 0.0), (5.0, 0.0)])
    with pytest.raises(ValueError, match="increasing"):
        SpeedProfile.over_time([(0.0, 1.0), (0.0, 2.0)])
    with pytest.raises(ValueError, match="distinct"):
        Polyline(((0.0, 0.0), (0.0, 0.0)))


def test_waypoints_pose_and_velocity():
    behaviour = Behaviour(Polyline(((0.0, 0.0), (3.0, 4.0), (3.0, 10.0))), SpeedProfile.constant(2.0))
    state = initial_state(behaviour)
    k = kinematics(behaviour, state, 1.0)  # 2 m along the first leg, heading atan2(4, 3)
    assert k == pytest.approx((1.2, 1.6, math.atan2(4, 3), 1.2, 1.6, 0.0, 2.0))
    k = kinematics(behaviour, state, 4.0)  # 8 m: 3 m up the second leg
    assert k == pytest.approx((3.0, 7.0, math.pi / 2, 0.0, 2.0, 0.0, 2.0), abs=1e-12)
    assert kinematics(behaviour, state, 6.0)[:2] == pytest.approx((3.0, 11.0))  # 12 m: 1 m on beyond the end


def test_a_lane_path_on_an_arc_has_the_yaw_rate_of_its_radius():
    r = 40.0
    road = Road(PlanView.chained([Arc(60.0, 1.0 / r)]), (LaneSection.uniform(0.0, (3.5,), (3.5,)),))
    right_lane = OffsetPath(road, -1.75)  # its radius is r + 1.75
    behaviour = Behaviour(right_lane, SpeedProfile.constant(10.0))
    k = kinematics(behaviour, initial_state(behaviour), 2.0)
    assert k.yaw_rate_radps == pytest.approx(10.0 / (r + 1.75))
    assert k.yaw_rad == pytest.approx(20.0 / (r + 1.75))  # 20 m along the offset curve
    assert math.hypot(k.x_m, k.y_m - r) == pytest.approx(r + 1.75)


def test_a_lane_path_is_parametrised_by_its_own_length_through_clothoids():
    plan = PlanView.chained([Spiral(30.0, 0.0, 0.05), Arc(15.0, 0.05), Spiral(30.0, 0.05, 0.0)], 2.0, 1.0, 0.3)
    road = Road(plan, (LaneSection.uniform(0.0, (3.5,), (3.5,)),))
    lane = OffsetPath(road, 3.0)  # inside the bend: shorter than the reference line
    x, y, _ = road.pose(np.linspace(0.0, road.length_m, 20001), 3.0)
    assert lane.length_m == pytest.approx(np.hypot(np.diff(x), np.diff(y)).sum(), abs=1e-6)
    points = np.array([lane.pose(s)[:2] for s in np.linspace(0.0, lane.length_m, 301)])
    steps = np.hypot(*np.diff(points, axis=0).T)
    np.testing.assert_allclose(steps, lane.length_m / 300, rtol=1e-4)  # equal steps of its own length
    beyond = road.pose(road.length_m + 2.0, 3.0)  # straight on beyond the end, on both curves
    assert lane.pose(lane.length_m + 2.0)[:2] == pytest.approx((float(beyond[0]), float(beyond[1])), abs=1e-9)


def test_triggers():
    ego = EgoState(10.0, 0.0, 0.0, 20.0)
    assert AtTime(1.0).holds(1.0, ego) and not AtTime(1.0).holds(0.99, ego)
    assert EgoTimeToPoint(50.0, 3.0, 2.0).holds(0.0, ego)  # 40 m at 20 m/s: 2.0 s
    assert not EgoTimeToPoint(50.1, 3.0, 2.0).holds(0.0, ego)
    assert not EgoTimeToPoint(50.0, 3.0, 2.0).holds(0.0, ego._replace(speed_mps=0.0))
    assert EgoDistanceToPoint(40.0, -2.0, 30.0).holds(0.0, ego)
    assert not EgoDistanceToPoint(40.1, -2.0, 30.0).holds(0.0, ego)
    assert set(TRIGGERS) == {"time", "ego_ttc", "ego_distance"}


def test_a_triggered_target_stands_until_it_fires_and_fires_once():
    behaviour = Behaviour(Polyline(((0.0, 5.0), (0.0, -5.0))), SpeedProfile.constant(1.0), AtTime(2.0))
    state = initial_state(behaviour)
    ego = EgoState(0.0, 0.0, 0.0, 10.0)
    assert state == BehaviourState(None)
    state = advance(behaviour, state, 1.99, ego)
    assert kinematics(behaviour, state, 1.99) == (0.0, 5.0, -math.pi / 2, 0.0, 0.0, 0.0, 0.0)
    state = advance(behaviour, state, 2.0, ego)
    assert advance(behaviour, state, 3.0, ego) is state  # fired once; never again
    assert kinematics(behaviour, state, 3.5)[:2] == pytest.approx((0.0, 3.5))


@pytest.mark.parametrize("ego_speed_kmh", [10.0, 30.0, 60.0])
def test_ncap_crossing_meets_the_ego_at_the_synchronisation_point(ego_speed_kmh):
    """CPNA 50 %: an adult from 4.0 m to the near side of the ego's path, 5 km/h after 1.0 m; the ego at
    constant speed. Sampled every 10 ms like the ECU cycle, the target reaches the sync point when the ego's
    front does, within what one sample allows."""
    v_ego, v_ped, h = ego_speed_kmh * KMH, 5 * KMH, 0.01
    sync_x = 60.0
    behaviour = crossing((sync_x, -4.0), math.pi / 2, 4.0, v_ped, 1.0)
    state = initial_state(behaviour)
    t_meet = sync_x / v_ego  # the ego front starts at x = 0
    for k in range(int(t_meet / h) + 1):
        t = k * h
        state = advance(behaviour, state, t, EgoState(v_ego * t, 0.0, 0.0, v_ego))
    target = kinematics(behaviour, state, t_meet)
    assert target.x_m == pytest.approx(sync_x)
    assert target.y_m == pytest.approx(0.0, abs=v_ped * h + 1e-9)
    assert target.speed_mps == pytest.approx(v_ped)
    assert state.started_at_s == pytest.approx(t_meet - (2 * 1.0 / v_ped + 3.0 / v_ped), abs=h)


def test_target_classes_carry_the_protocol_boxes():
    assert (TARGET_CLASSES["EPTa"].length_m, TARGET_CLASSES["EPTa"].width_m) == (0.60, 0.50)
    assert (TARGET_CLASSES["EPTc"].length_m, TARGET_CLASSES["EPTc"].width_m) == (0.711, 0.298)
    assert (TARGET_CLASSES["EBTa"].length_m, TARGET_CLASSES["EBTa"].width_m) == (1.89, 0.50)
    assert (TARGET_CLASSES["GVT"].length_m, TARGET_CLASSES["GVT"].width_m) == (4.023, 1.712)
    assert all(t.size_class in SIZE_CLASSES and "ISO 19206" in t.source for t in TARGET_CLASSES.values())
    with pytest.raises(KeyError, match="known: "):
        target_class("EPTx")
