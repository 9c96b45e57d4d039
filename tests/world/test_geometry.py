"""Oriented boxes: hand-computed contacts, and properties against shapely as an independent oracle."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from cosim.world.geometry import (
    BodyMotion, Box, contact, impact_speed_mps, least_overlap, overlaps, overlaps_many,
)

CAR = Box(0.0, 0.0, 0.0, 4.0, 2.0)  # x in [-2, 2], y in [-1, 1]


def test_boxes_that_touch_overlap_with_zero_depth_at_the_middle_of_the_common_edge():
    other = Box(4.0, 0.5, 0.0, 4.0, 2.0)  # x in [2, 6], y in [-0.5, 1.5]: the faces meet at x = 2
    hit = contact(CAR, other)
    assert hit is not None
    assert hit.depth_m == pytest.approx(0.0, abs=1e-12)
    assert (hit.normal_x, hit.normal_y) == pytest.approx((1.0, 0.0))
    assert (hit.x_m, hit.y_m) == pytest.approx((2.0, 0.25))  # the common stretch is y in [-0.5, 1]
    assert not overlaps(CAR, other.moved(1e-6, 0.0))


def test_a_rotated_corner_entering_an_edge():
    # a 2 m square turned 45 deg: its left corner is 0.1 m inside CAR's front face at (1.9, 0)
    square = Box(2.0 + math.sqrt(2.0) - 0.1, 0.0, math.pi / 4, 2.0, 2.0)
    hit = contact(CAR, square)
    assert hit.depth_m == pytest.approx(0.1)
    assert (hit.normal_x, hit.normal_y) == pytest.approx((1.0, 0.0))
    # the overlap is the triangle (1.9, 0), (2, 0.1), (2, -0.1): centroid x = (1.9 + 2 + 2) / 3
    assert (hit.x_m, hit.y_m) == pytest.approx((5.9 / 3.0, 0.0))


def test_corner_to_edge_with_an_axis_aligned_box_arriving_diagonally():
    # a 1 m square whose lower-left corner (1.8, 0.8) is inside CAR's upper-right corner region
    small = Box(2.3, 1.3, 0.0, 1.0, 1.0)
    hit = contact(CAR, small)
    assert hit.depth_m == pytest.approx(0.2)  # 0.2 m on both axes: the first found, x
    assert (hit.x_m, hit.y_m) == pytest.approx((1.9, 0.9))  # middle of the 0.2 x 0.2 overlap square


def test_one_box_inside_the_other():
    inner = Box(0.5, 0.2, 0.3, 0.5, 0.5)
    hit = contact(CAR, inner)
    assert (hit.x_m, hit.y_m) == pytest.approx((0.5, 0.2))  # the intersection is the inner box itself
    # least overlap on CAR's y axis: 1 + r_inner - 0.2 with r_inner = 0.25 (|sin 0.3| + |cos 0.3|)
    r_inner = 0.25 * (abs(math.sin(0.3)) + abs(math.cos(0.3)))
    assert hit.depth_m == pytest.approx(1.0 + r_inner - 0.2)
    assert (hit.normal_x, hit.normal_y) == pytest.approx((0.0, 1.0))


def test_the_separating_axis_of_the_rotated_box_is_needed():
    # a thin box across CAR's corner diagonal (yaw 135 deg), 0.1 m beyond the corner (2, 1) along (1, 1):
    # CAR reaches 3/sqrt(2) along (1, 1)/sqrt(2); the thin box starts 0.2 m before its centre
    along = 3.0 / math.sqrt(2.0) + 0.3
    thin = Box(along / math.sqrt(2.0), along / math.sqrt(2.0), 3.0 * math.pi / 4.0, 2.0, 0.4)
    r_thin = 1.0 * math.sqrt(0.5) + 0.2 * math.sqrt(0.5)  # on either of CAR's axes
    o_car_axes = [2.0 + r_thin - thin.x_m, 1.0 + r_thin - thin.y_m]
    assert min(o_car_axes) > 0.1  # CAR's own two axes do not separate them
    assert least_overlap(CAR, thin)[0] == pytest.approx(-0.1)  # the thin box's short axis does
    assert not overlaps(CAR, thin)
    assert contact(CAR, thin) is None
    assert not shapely.Polygon(CAR.corners()).intersects(shapely.Polygon(thin.corners()))


def test_impact_speed_along_the_normal_with_yaw_rates():
    other = Box(4.0, 0.0, 0.0, 4.0, 2.0)  # touching at x = 2, contact point (2, 0)
    hit = contact(CAR, other)
    head_on = impact_speed_mps(hit, CAR, BodyMotion(10.0, 3.0), other, BodyMotion(-5.0, 0.0))
    assert head_on == pytest.approx(15.0)  # lateral velocities do not count
    # spinning the other box about its centre at 1 rad/s moves its contact point (2 m behind) at +2 m/s in y only
    assert impact_speed_mps(hit, CAR, BodyMotion(10.0, 0.0), other, BodyMotion(0.0, 0.0, 1.0)) == pytest.approx(10.0)
    # a yaw rate on CAR: its point (2, 0) moves (-w * 0, w * 2): no normal component either
    receding = impact_speed_mps(hit, CAR, BodyMotion(-1.0, 0.0, 0.5), other, BodyMotion(0.0, 0.0))
    assert receding == pytest.approx(-1.0)


def test_impact_speed_counts_the_yaw_rate_when_the_lever_arm_is_across_the_normal():
    other = Box(0.0, 2.0, 0.0, 4.0, 2.0)  # on top of CAR, touching along y = 1, contact at (0, 1)
    hit = contact(CAR, other.moved(1.0, 0.0))  # shifted: common stretch x in [-1, 2], contact (0.5, 1)
    assert (hit.x_m, hit.y_m, hit.normal_y) == pytest.approx((0.5, 1.0, 1.0))
    # CAR turning at 2 rad/s: its point (0.5, 1) moves at (-2 * 1, 2 * 0.5) = (-2, 1): 1 m/s toward the other
    assert impact_speed_mps(hit, CAR, BodyMotion(0.0, 0.0, 2.0), other, BodyMotion(0.0, 0.0)) == pytest.approx(1.0)


def test_overlaps_many_agrees_with_the_pairwise_test():
    rng = np.random.default_rng(7)
    rows = np.column_stack([rng.uniform(-6, 6, 300), rng.uniform(-4, 4, 300), rng.uniform(-3, 3, 300),
                            rng.uniform(0.2, 5, 300), rng.uniform(0.2, 2, 300)])
    many = overlaps_many(CAR, rows)
    assert 30 < many.sum() < 270  # both outcomes well represented
    assert many.tolist() == [overlaps(CAR, Box(*r)) for r in rows.tolist()]
    assert overlaps_many(CAR, np.empty((0, 5))).shape == (0,)


def test_a_box_with_negative_size_is_refused():
    with pytest.raises(ValueError, match="length_m"):
        Box(0.0, 0.0, 0.0, -1.0, 1.0)


coord = st.floats(-20.0, 20.0, allow_nan=False)
size = st.floats(0.2, 6.0, allow_nan=False)
angle = st.floats(-math.pi, math.pi, allow_nan=False)
boxes = st.builds(Box, coord, coord, angle, size, size)


@settings(max_examples=300, deadline=None)
@given(boxes, boxes)
def test_overlap_and_contact_are_symmetric(a, b):
    assert overlaps(a, b) == overlaps(b, a)
    ab, ba = contact(a, b), contact(b, a)
    assert (ab is None) == (ba is None)
    if ab is not None:
        assert ab.depth_m == pytest.approx(ba.depth_m, abs=1e-9)
        assert (ab.x_m, ab.y_m) == pytest.approx((ba.x_m, ba.y_m), abs=1e-6)
        # the least-overlap axis may tie between the two boxes; its depth is the same either way
        if abs(ab.normal_x + ba.normal_x) + abs(ab.normal_y + ba.normal_y) > 1e-9:
            assert least_overlap(a, b)[0] == pytest.approx(least_overlap(b, a)[0])


@settings(max_examples=300, deadline=None)
@given(boxes, boxes, coord, coord, angle)
def test_contact_moves_with_the_scene(a, b, dx, dy, turn):
    """Translation and rotation of both boxes about the origin move the contact with them."""
    c, s = math.cos(turn), math.sin(turn)

    def moved(box):
        x, y = box.x_m * c - box.y_m * s + dx, box.x_m * s + box.y_m * c + dy
        return Box(x, y, box.yaw_rad + turn, box.length_m, box.width_m)

    depth = least_overlap(a, b)[0]
    assume(abs(depth) > 1e-6)  # away from touching, where rounding may decide
    hit, hit_moved = contact(a, b), contact(moved(a), moved(b))
    assert (hit is None) == (hit_moved is None)
    if hit is not None:
        assert hit_moved.depth_m == pytest.approx(hit.depth_m, abs=1e-7)
        expected = (hit.x_m * c - hit.y_m * s + dx, hit.x_m * s + hit.y_m * c + dy)
        assert (hit_moved.x_m, hit_moved.y_m) == pytest.approx(expected, abs=1e-6)


@settings(max_examples=300, deadline=None)
@given(boxes, boxes)
def test_overlap_and_contact_point_agree_with_shapely(a, b):
    pa, pb = shapely.Polygon(a.corners()), shapely.Polygon(b.corners())
    assume(pa.distance(pb) > 1e-6 or pa.intersection(pb).area > 1e-6)  # not merely touching
    assert overlaps(a, b) == pa.intersects(pb)
    hit = contact(a, b)
    if hit is not None:
        centroid = pa.intersection(pb).centroid
        assert (hit.x_m, hit.y_m) == pytest.approx((centroid.x, centroid.y), abs=1e-6)
        # the depth is the shortest separating translation: moving b by it along the normal separates them
        shifted = b.moved(hit.normal_x * (hit.depth_m + 1e-6), hit.normal_y * (hit.depth_m + 1e-6))
        assert not overlaps(a, shifted)
