"""What other objects occupy: boxes from the nearest point, moving stopping regions, inflation."""

import numpy as np
import pytest

from can_dbc.contract import enumeration
from ecu.core import CoreParams
from ecu.core.region import CAPABILITIES, TrackBox, region_params
from ecu.core.region.objects import corners, object_set

P = region_params(CoreParams())
CLASS = {name: value for value, name in enumeration("RadarTrack0", "Track0SizeClass").items()}
R = P.rear_axle_to_front_m


def test_every_dbc_size_class_has_a_capability_with_the_dbc_boxes():
    assert set(CAPABILITIES) == set(CLASS.values())
    # the DBC's comment: pedestrian 0.6 x 0.5, bicycle 1.89 x 0.5, car 4.0 x 1.7 m
    for name, box in (("PEDESTRIAN", (0.6, 0.5)), ("BICYCLE", (1.89, 0.5)), ("CAR", (4.0, 1.7))):
        assert CAPABILITIES[CLASS[name]][:2] == box


def test_standing_car_off_axis_sits_behind_and_beside_its_nearest_point():
    objects = object_set([TrackBox(20.0, 2.0, -10.0, 0.0, CLASS["CAR"], 0.0)], 10.0, P)
    assert not objects.moving[0]
    assert objects.centre[0] == pytest.approx(complex(20.0 + 2.0 + R, 2.0 + 0.85))
    assert (objects.half_length_m[0], objects.half_width_m[0]) == (2.0, 0.85)


def test_a_face_across_the_sensor_axis_widens_the_box_to_every_position_it_allows():
    objects = object_set([TrackBox(20.0, 0.0, -10.0, 0.0, CLASS["CAR"], 0.1)], 10.0, P)
    assert objects.centre[0].imag == 0.0
    assert objects.half_width_m[0] == pytest.approx(0.85 + 0.85 + 3 * 0.1)  # union of placements, 3 sigma
    assert objects.half_length_m[0] == pytest.approx(2.0 + 0.3)


def test_moving_object_occupies_its_stopping_region_along_its_velocity():
    cap = CAPABILITIES[CLASS["CAR"]]
    # ego at 20 m/s, the lead at 14 m/s: relative -6 m/s
    objects = object_set([TrackBox(30.0, 3.5, -6.0, 0.0, CLASS["CAR"], 0.0)], 20.0, P)
    sweep = 14.0 ** 2 / (2 * cap.decel_mps2)
    side = min(cap.lateral_reach_max_m, 0.5 * cap.lateral_accel_mps2 * (14.0 / cap.decel_mps2) ** 2)
    assert objects.moving[0]
    assert objects.half_length_m[0] == pytest.approx(2.0 + sweep / 2)
    assert objects.half_width_m[0] == pytest.approx(0.85 + side)
    assert objects.centre[0].real == pytest.approx(30.0 + 2.0 + R + sweep / 2)


def test_crossing_pedestrian_region_points_across_the_road():
    objects = object_set([TrackBox(15.0, -3.0, -10.0, 1.4, CLASS["PEDESTRIAN"], 0.0)], 10.0, P)
    assert objects.axis[0] == pytest.approx(1j)
    box = corners(objects)[0]
    assert box.imag.max() == pytest.approx(objects.centre[0].imag + objects.half_length_m[0])


def test_a_walking_pedestrian_and_a_cyclist_go_on_for_their_response_time_before_they_brake():
    """CARLA's pedestrian (0.5 s at up to 2 m/s^2) and RSS's other road user (2 s, speed held): the region reaches
    that far further along the walk or ride than a stop the moment it is seen; a car keeps none."""
    walker = CAPABILITIES[CLASS["PEDESTRIAN"]]
    assert (walker.response_s, walker.accel_mps2) == (0.5, 2.0)
    objects = object_set([TrackBox(15.0, -3.0, -10.0, 1.4, CLASS["PEDESTRIAN"], 0.0)], 10.0, P)
    fast = 1.4 + 2.0 * 0.5
    sweep = (1.4 + 0.5 * 2.0 * 0.5) * 0.5 + fast ** 2 / (2 * walker.decel_mps2)
    assert objects.half_length_m[0] == pytest.approx(0.3 + sweep / 2)  # along the walk: half its 0.6 m and the sweep
    assert sweep > 2.0 * 1.4 ** 2 / (2 * walker.decel_mps2)  # more than twice the sweep without a response
    rider = object_set([TrackBox(15.0, -3.0, -10.0, 4.0, CLASS["BICYCLE"], 0.0)], 10.0, P)
    assert rider.half_length_m[0] == pytest.approx(1.89 / 2 + (4.0 * 2.0 + 4.0 ** 2 / (2 * 3.0)) / 2)
    assert CAPABILITIES[CLASS["CAR"]].response_s == 0.0


def test_unknown_class_falls_back_to_the_unknown_capability():
    a = object_set([TrackBox(20.0, 2.0, -10.0, 0.0, 7, 0.0)], 10.0, P)
    b = object_set([TrackBox(20.0, 2.0, -10.0, 0.0, CLASS["UNKNOWN"], 0.0)], 10.0, P)
    assert np.array_equal(a.centre, b.centre) and np.array_equal(a.half_width_m, b.half_width_m)
