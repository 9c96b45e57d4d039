"""Relevance along the predicted path (issue 22): the arc of the current curvature, and an object's own motion."""

import math

import pytest

from can_dbc.planar import Track
from ecu.core import CoreInputs, CoreParams
from ecu.core.relevance import object_in_path, path_offset_m

P = CoreParams(strategy="none")
R = P.region.rear_axle_to_front_m


def inputs(range_m, lateral_m, rate_mps, yaw_radps=0.0, tracks=()):
    return CoreInputs(t_s=0.0, object_valid=True, object_range_m=range_m, object_range_rate_mps=rate_mps,
                      object_lateral_m=lateral_m, yaw_rate_radps=yaw_radps, tracks=tuple(tracks))


@pytest.mark.parametrize("k", [0.01, -0.005, 0.002])
@pytest.mark.parametrize("s, e", [(10.0, 0.0), (30.0, 1.5), (50.0, -2.0)])
def test_path_offset_is_the_distance_from_the_arc(k, s, e):
    # the point e to the left of the arc of curvature k at arc length s from the rear axle
    r = 1.0 / k
    x, y = (r - e) * math.sin(k * s), r - (r - e) * math.cos(k * s)
    assert path_offset_m(x, y, k) == pytest.approx(e, abs=1e-9)


def test_straight_is_the_lateral_offset_itself():
    assert path_offset_m(30.0, -1.234, 0.0) == -1.234
    assert object_in_path(inputs(30.0, 1.5, -20.0), 20.0, P)
    assert not object_in_path(inputs(30.0, 2.5, -20.0), 20.0, P)
    assert object_in_path(inputs(30.0, float("nan"), -20.0), 20.0, P)  # fail-safe


def arc_point(k, s, e):
    """(range, lateral) from the front bumper of the point ``e`` left of the arc ``k`` at ``s`` from the rear axle."""
    r = 1.0 / k
    return (r - e) * math.sin(k * s) - R, r - (r - e) * math.cos(k * s)


def test_a_car_parked_beside_a_curve_is_beside_our_path():
    # a left curve of 100 m radius at 14 m/s; a car parked 3 m right of our path, 25 m on; our heading points at it
    speed, k = 14.0, 0.01
    range_m, lateral = arc_point(k, 25.0 + R, -3.0)
    assert abs(lateral) < 1.9  # in the straight corridor ...
    assert not object_in_path(inputs(range_m, lateral, -speed, yaw_radps=k * speed), speed, P)  # ... not on the arc
    # a standing car in our lane of the curve 10 m on is in it; 25 m on, off our heading, the line leaves it to
    # the stopping region, which follows the arc (the prediction only clears objects from the straight corridor)
    range_m, lateral = arc_point(k, 10.0 + R, 0.0)
    assert object_in_path(inputs(range_m, lateral, -speed, yaw_radps=k * speed), speed, P)
    range_m, lateral = arc_point(k, 25.0 + R, 0.0)
    assert lateral > 1.91 and not object_in_path(inputs(range_m, lateral, -speed, yaw_radps=k * speed), speed, P)


def test_an_oncoming_car_that_leaves_our_heading_before_we_meet_is_not_in_our_path():
    # at a right curve's entry (yaw rate not yet built up) the oncoming car is straight ahead, 50 m off, closing
    # at 25 m/s, and crosses our heading line at 2.5 m/s: when we meet it (2 s) it is 3 m to our left
    speed = 14.0
    track = Track(0, 4, 7, 50.0, -0.5, -25.0, 2.5)
    assert not object_in_path(inputs(50.0, -0.2, -25.0, tracks=[track]), speed, P)
    # the same car in our lane, coming straight at us, is in it; so is it without a planar track (the 1-D world)
    straight = track._replace(vy_mps=0.0)
    assert object_in_path(inputs(50.0, -0.2, -25.0, tracks=[straight]), speed, P)
    assert object_in_path(inputs(50.0, -0.2, -25.0), speed, P)


def test_a_lead_car_keeps_its_offset_however_slowly_we_close():
    # a lead car 30 m ahead closing at 0.5 m/s with a little lateral velocity: the horizon is our shortest stop
    speed = 20.0
    track = Track(0, 4, 7, 30.0, 0.0, -0.5, 0.3)
    assert object_in_path(inputs(30.0, 0.0, -0.5, tracks=[track]), speed, P)


def test_a_pedestrian_is_judged_where_it_is():
    # a pedestrian crossing our path at 1.4 m/s, 1 m left of our axis, 20 m ahead: it would be out of the
    # path in 2 s, but a pedestrian may stop: only a vehicle's held velocity predicts where it will be
    speed = 14.0
    walker = Track(0, 1, 7, 20.0, 1.0, -14.0, 1.4)
    assert object_in_path(inputs(20.0, 1.0, -14.0, tracks=[walker]), speed, P)
    assert not object_in_path(inputs(20.0, 1.0, -14.0, tracks=[walker._replace(size_class=4)]), speed, P)
