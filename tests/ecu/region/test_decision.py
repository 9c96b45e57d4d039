"""The contingency rules in order, symmetry, road bounds, R79 limits, least impact speed."""

import math

import numpy as np
import pytest

from can_dbc.contract import enumeration
from ecu.core import CoreParams
from ecu.core.region import Contingency, EgoState, Road, TrackBox, decide, region_params
from ecu.core.region.decision import clearances
from ecu.core.region.overlap import corner_points
from ecu.core.region.paths import LANE, path_family
from ecu.core.region.road import lateral_offsets

CLASS = {name: value for value, name in enumeration("RadarTrack0", "Track0SizeClass").items()}
P = region_params(CoreParams())
D = CoreParams().model_decel_mps2
TWO_LANES = Road((-1.75, 1.75, 5.25))  # our lane and a free lane on the left


def _standing(x, y, v, cls="PEDESTRIAN", sigma=0.05):
    return TrackBox(x, y, -v, 0.0, CLASS[cls], sigma)


def test_rule_1_the_drivers_path_is_kept_when_disjoint():
    d = decide(EgoState(20.0, 1.0, D), [_standing(60.0, 0.0, 20.0)], TWO_LANES, P)
    assert d.kind is Contingency.DRIVER_PATH and d.decel_mps2 == 0.0 and d.clearance_m > 0.0


def test_rule_2_brakes_in_lane_when_the_drivers_curve_would_hit():
    # the driver drifts left (yaw rate 0.1 rad/s at 20 m/s: radius 200 m) toward a car parked in the left lane;
    # the lane row straightens the wheel after the hold and the steering lag (it keeps the heading gained)
    ego = EgoState(20.0, 0.0, D, yaw_rate_radps=0.1, road_wheel_angle_rad=math.atan(0.005 * P.wheelbase_m))
    d = decide(ego, [_standing(18.0, 2.8, 20.0, "CAR")], TWO_LANES, P)
    assert not d.driver_disjoint
    assert d.kind is Contingency.BRAKE_IN_LANE and d.row == LANE and d.curvature_1pm == 0.0
    assert d.decel_mps2 == P.contingency_decel_mps2


def test_rule_3_only_steering_avoids_a_stopped_car_beyond_the_braking_distance():
    # 30 m/s: braking needs 3.3 + 55.6 + 2 m; the car stands 58 m ahead in our lane, the left lane is free
    d = decide(EgoState(30.0, 0.0, D), [_standing(58.0, 0.0, 30.0, "CAR")], TWO_LANES, P)
    assert not d.driver_disjoint
    assert d.kind is Contingency.STEER_AND_BRAKE and d.curvature_1pm > 0.0 and d.clearance_m >= 0.0
    assert 0.0 < d.decel_mps2 < P.contingency_decel_mps2  # braking shares the friction circle


def test_steering_picks_the_largest_clearance_and_respects_the_road():
    d = decide(EgoState(25.0, 0.0, D), [_standing(43.0, 0.0, 25.0)], TWO_LANES, P)
    assert d.kind is Contingency.STEER_AND_BRAKE
    e = lateral_offsets(TWO_LANES, corner_points(d.paths, d.box)[d.row])
    assert e.min() >= -1.75 and e.max() <= 5.25
    assert d.paths.curvature_1pm[d.row] > 0.0  # the right side is off the road
    free = decide(EgoState(25.0, 0.0, D), [_standing(43.0, 0.0, 25.0)], None, P)
    assert free.clearance_m >= d.clearance_m  # without a road the choice is at least as clear


def test_symmetric_scenes_give_mirrored_choices():
    road_left = Road((-1.75, 1.75, 5.25))
    road_right = Road((-5.25, -1.75, 1.75))
    left = decide(EgoState(30.0, 0.0, D), [_standing(58.0, 0.0, 30.0, "CAR")], road_left, P)
    right = decide(EgoState(30.0, 0.0, D), [_standing(58.0, 0.0, 30.0, "CAR")], road_right, P)
    assert left.kind is right.kind is Contingency.STEER_AND_BRAKE
    assert left.curvature_1pm == pytest.approx(-right.curvature_1pm)
    assert left.clearance_m == pytest.approx(right.clearance_m)
    # without a road, a centred object gives two mirrored best rows of equal clearance
    free = decide(EgoState(30.0, 0.0, D), [_standing(58.0, 0.0, 30.0, "CAR")], None, P)
    _, clearance = clearances(free.paths, free.objects, free.box)
    mirror = len(clearance) - 1 - free.row  # the steering rows alone, symmetric about the middle one
    assert mirror != free.row and clearance[mirror] == pytest.approx(free.clearance_m)
    assert free.clearance_m == pytest.approx(clearance.max())


def test_an_occupied_left_lane_forbids_steering_into_it():
    lead = _standing(58.0, 0.0, 30.0, "CAR")
    neighbour = TrackBox(80.0, 3.5, -5.0, 0.0, CLASS["CAR"], 0.05)  # a car driving in the left lane
    d = decide(EgoState(30.0, 0.0, D), [lead, neighbour], TWO_LANES, P)
    assert d.kind is Contingency.LEAST_IMPACT
    free = decide(EgoState(30.0, 0.0, D), [lead], TWO_LANES, P)
    assert free.kind is Contingency.STEER_AND_BRAKE


def test_between_walls_nothing_avoids_and_the_least_impact_speed_is_chosen():
    one_lane = Road((-1.75, 1.75))
    ego = EgoState(20.0, 0.0, D)
    d = decide(ego, [_standing(15.0, 0.0, 20.0, "CAR")], one_lane, P)
    assert d.kind is Contingency.LEAST_IMPACT and d.clearance_m < 0.0
    assert 0.0 < d.impact_speed_mps < 20.0
    lane_only = decide(ego, [_standing(15.0, 0.0, 20.0, "CAR")], one_lane, region_params(CoreParams(), steer_paths=1))
    assert d.impact_speed_mps <= lane_only.impact_speed_mps


def test_steering_rows_keep_the_r79_lateral_acceleration_cap():
    capped = region_params(CoreParams(), emergency_lat_accel_max_mps2=1.0)
    d = decide(EgoState(30.0, 0.0, D), [_standing(58.0, 0.0, 30.0, "CAR")], TWO_LANES, capped)
    steer = path_family(EgoState(30.0, 0.0, D), 0.0, capped, base=False)
    assert np.max(np.abs(steer.curvature_1pm)) * steer.hold_speed_mps[0] ** 2 == pytest.approx(1.0)
    # 1 m/s^2 cannot clear the car in time; 3 m/s^2 does (rule 3 test): no arc is disjoint, so a lane change is
    # judged (ecu.core.region.evasion, only then) and chosen
    assert d.kind is Contingency.STEER_AND_BRAKE and d.evasion_offset_m != 0.0
