"""Giving way on a lane change (ecu.core.region.lane_change) and the tracks beside and behind the region judges
(ecu.core.planar.ahead_or_beside): the merge's geometry, seen from each car."""

import math

import pytest

from can_dbc.contract import enumeration
from can_dbc.planar import Track
from ecu.core.params import CoreParams
from ecu.core.planar import ahead_or_beside, lane_change, track_boxes
from ecu.core.region import EgoState, decide
from ecu.core.region.crossing import crossing_proximity

CAR = {name: value for value, name in enumeration("RadarTrack0", "Track0SizeClass").items()}["CAR"]
SPEED = 13.9  # both at 50 km/h


def _other(y_m: float, heading_rad: float, x_m: float = -0.5) -> Track:
    """A car at our speed beside us, its velocity ``heading_rad`` off ours (relative velocity, as the contract)."""
    return Track(1, CAR, 7, x_m, y_m, SPEED * math.cos(heading_rad) - SPEED, SPEED * math.sin(heading_rad))


def _proximity(track: Track, curvature_1pm: float, way_out: str) -> float:
    params = CoreParams(strategy="tightening", way_out=way_out)
    ego = EgoState(SPEED, 0.0, params.model_decel_mps2, yaw_rate_radps=curvature_1pm * SPEED)
    boxes = track_boxes([track], params.track_position_sigma_m)
    decision = decide(ego, boxes, None, params.region, steer=False)
    return crossing_proximity(decision, boxes, SPEED, params.region, way_out, params.way_out_path_m,
                              lane_change(decision, boxes, ego, params))


def test_the_car_whose_path_turns_into_the_next_lane_gives_way_to_the_car_in_it():
    # the ramp car in its S-curve (1/50 m), main on its left going straight: 8 degrees to our right of our heading
    main = _other(2.6, math.radians(-8.0))
    assert _proximity(main, 0.02, "right_of_way") > 0.5
    assert _proximity(main, 0.02, "none") == 0.0  # the plain method: not crossing (8 < 30 degrees)
    assert _proximity(main, 0.02, "reciprocal") == 0.0


def test_the_car_in_the_through_lane_does_not_give_way():
    # main's view: the ramp car on its right, converging at 8 degrees; main's own path is straight
    ramp = _other(-2.6, math.radians(8.0))
    assert _proximity(ramp, 0.0, "right_of_way") == 0.0


@pytest.mark.parametrize("curvature_1pm, heading_deg, why", [
    (-0.02, -8.0, "our path turns away from it"),
    (0.002, -8.0, "too gentle to take us half a lane over within way_out_path_m: a car keeping its lane"),
    (0.02, 2.0, "it turns with us: a car beside us in a bend we share"),
])
def test_what_is_not_a_lane_change_toward_it_does_not_tighten(curvature_1pm, heading_deg, why):
    assert _proximity(_other(2.6, math.radians(heading_deg)), curvature_1pm, "right_of_way") == 0.0, why


def test_a_car_in_the_lane_beyond_the_next_does_not_count():
    assert _proximity(_other(2.6 + 3.5, math.radians(-8.0)), 0.02, "right_of_way") == 0.0


P = CoreParams()


def test_forward_tracks_pass_unchanged():
    tracks = (Track(1, CAR, 7, 0.0, 2.6, 0.0, 0.0), Track(2, CAR, 7, 30.0, 0.0, -5.0, 0.0))
    assert ahead_or_beside(tracks, SPEED, P) is tracks


def test_a_follower_is_left_to_its_own_driver():
    follower = Track(1, CAR, 7, -8.0, 0.0, 1.0, 0.0)  # 3.6 m behind our rear bumper, closing at 1 m/s
    assert ahead_or_beside((follower,), SPEED, P) == ()


def test_a_car_beside_counts_only_while_it_closes_on_our_side():
    closing = _other(-2.6, math.radians(8.0), x_m=-2.0)
    parallel = _other(-2.6, 0.0, x_m=-2.0)
    standing = Track(1, CAR, 7, -2.0, -2.6, -SPEED, 0.0)
    leaving = _other(-2.6, math.radians(-8.0), x_m=-2.0)
    assert ahead_or_beside((closing, parallel, standing, leaving), SPEED, P) == (closing,)


def test_a_track_on_us_or_standing_behind_stays():
    on_us = Track(1, CAR, 7, -1.0, -0.5, -SPEED, 0.0)  # within our width: a contact, not a car beside us
    standing_behind = Track(2, CAR, 7, -9.0, 0.0, -SPEED, 0.0)  # harmless: our path runs away from it
    assert ahead_or_beside((on_us, standing_behind), SPEED, P) == (on_us, standing_behind)
