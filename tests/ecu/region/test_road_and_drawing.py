"""Lane spans for emergency steering, road coordinates, and the polygons for the bird's-eye view."""

import math

import numpy as np
import pytest

from ecu.core import CoreParams
from ecu.core.region import EgoState, Road, TrackBox, decide, region_params
from ecu.core.region.drawing import footprint_boxes, object_polygons, stopping_path_outline
from ecu.core.region.road import allowed_span, lateral_offsets

THREE = Road((-5.25, -1.75, 1.75, 5.25))  # right lane, ours, left lane


@pytest.mark.parametrize("objects, span", [
    ([], (-5.25, 5.25)),
    ([3.5], (-5.25, 1.75)),           # a car in the left lane
    ([-3.5, 3.5], (-1.75, 1.75)),     # both neighbours taken: our lane only
    ([0.2, 7.0, -9.0], (-5.25, 5.25)),  # in our lane, or off the road: no lane is closed
])
def test_the_span_widens_over_free_lanes_only(objects, span):
    assert allowed_span(THREE, np.array(objects, float)) == span


def test_off_the_road_there_is_no_span():
    lo, hi = allowed_span(Road((1.0, 4.5)), np.array([]))
    assert lo > hi


def test_road_coordinates_follow_heading_and_curvature():
    points = np.array([10.0 + 0j, 0.0 + 2.0j])
    assert lateral_offsets(Road((0.0,), heading_rad=0.0, curvature_1pm=0.01), points) == pytest.approx([-0.5, 2.0])
    turned = Road((0.0,), heading_rad=math.radians(90.0))
    assert lateral_offsets(turned, np.array([0.0 + 2.0j, 3.0 + 0j])) == pytest.approx([0.0, -3.0])


def test_polygons_are_in_the_bumper_frame():
    params = region_params(CoreParams())
    decision = decide(EgoState(10.0, 0.0, 8.1), [TrackBox(30.0, 0.0, -10.0, 0.0, 4, 0.0)], None, params)
    boxes = footprint_boxes(decision, 0, params)
    assert boxes.shape == (params.path_samples, 4, 2)
    assert boxes[-1, 0, 0] == pytest.approx(decision.driver_stopping_distance_m + params.standoff_m)
    outline = stopping_path_outline(decision, 0, params)
    assert outline.shape == (2 * params.path_samples + 2, 2)
    assert outline[:, 0].max() == pytest.approx(boxes[..., 0].max())
    car = object_polygons(decision, params)[0]
    assert car[:, 0].min() == pytest.approx(30.0) and car[:, 0].max() == pytest.approx(34.0)
