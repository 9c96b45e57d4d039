"""What other objects occupy: boxes from the nearest point, moving stopping regions, inflation."""

import math

import numpy as np
import pytest

from can_dbc.contract import enumeration
from ecu.core import CoreParams
from ecu.core.region import CAPABILITIES, Road, TrackBox, region_params
from ecu.core.region.objects import corners, object_set, standing_heading_rad

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


def _parked_on_the_outside(theta: float, radius_m: float = 100.0) -> tuple[complex, float, TrackBox]:
    """A car parked 3 m outside a left curve of ``radius_m`` through the rear axle, ``theta`` rad into it, turned with
    the road: (its centre, its heading, the track of its box's point nearest the sensor at the front bumper)."""
    centre = complex(0.0, radius_m) + (radius_m + 3.0) * complex(math.sin(theta), -math.cos(theta))
    axis = complex(math.cos(theta), math.sin(theta))
    local = (R - centre) * axis.conjugate()  # the sensor in the car's axes; its nearest point is it clamped
    nearest = centre + axis * complex(min(2.0, max(-2.0, local.real)), min(0.85, max(-0.85, local.imag)))
    return centre, theta, TrackBox(nearest.real - R, nearest.imag, -10.0, 0.0, CLASS["CAR"], 0.17)


def test_standing_heading_is_the_roads_where_the_object_stands():
    kappa = 0.01
    for theta in (-0.4, 0.0, 0.3):
        for off in (-3.0, 0.0, 2.0):  # on the line and beside it, on the same radius
            r = 1.0 / kappa - off
            point = complex(r * math.sin(theta), 1.0 / kappa - r * math.cos(theta))
            assert standing_heading_rad(point.real, point.imag, Road((-1.75, 1.75), 0.0, kappa)) == pytest.approx(theta)
    assert standing_heading_rad(20.0, 3.0, Road((-1.75, 1.75), 0.1, 0.0)) == pytest.approx(0.1)
    assert standing_heading_rad(20.0, 3.0, None) == 0.0


@pytest.mark.parametrize("theta", [0.22, 0.25])
def test_a_car_parked_along_a_curve_is_placed_along_the_road_not_across_our_lane(theta):
    centre, heading, track = _parked_on_the_outside(theta)
    road = Road((-1.75, 1.75), 0.0, 0.01)
    objects = object_set([track], 10.0, P, road)
    tol = 3 * 0.17
    assert (objects.half_length_m[0], objects.half_width_m[0]) == pytest.approx((2.0 + tol, 0.85 + tol))
    true = [centre + complex(math.cos(heading), math.sin(heading)) * complex(i * 2.0, j * 0.85)
            for i in (-1, 1) for j in (-1, 1)]
    local = (np.array(true) - objects.centre[0]) * objects.axis_conj[0]
    assert (np.abs(local.real) <= objects.half_length_m[0]).all()
    assert (np.abs(local.imag) <= objects.half_width_m[0]).all()
    # in the ego's axes the corner near the bore sight was widened across our lane (0.22), or put on its wrong side
    # (0.25: a box left of the corner, missing the car's right half)
    ego_axes = object_set([track], 10.0, P)
    wrong = ego_axes.centre[0].imag - ego_axes.half_width_m[0] > min(c.imag for c in true)
    assert ego_axes.half_width_m[0] > 0.85 + 0.85 or wrong


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


def test_unknown_class_falls_back_to_the_unknown_capability():
    a = object_set([TrackBox(20.0, 2.0, -10.0, 0.0, 7, 0.0)], 10.0, P)
    b = object_set([TrackBox(20.0, 2.0, -10.0, 0.0, CLASS["UNKNOWN"], 0.0)], 10.0, P)
    assert np.array_equal(a.centre, b.centre) and np.array_equal(a.half_width_m, b.half_width_m)
