"""Roads: closed-form checks on lines, arcs and clothoids, lanes, and (s, t) round trips."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cosim.world.reference_line import Arc, Line, PlanView, Spiral
from cosim.world.road import Lane, LaneSection, LaneWidth, Road

TWO_LANES = (LaneSection.uniform(0.0, left_m=(3.5,), right_m=(3.5,)),)


def straight(length_m=100.0, x=0.0, y=0.0, heading=0.0) -> Road:
    return Road(PlanView.chained([Line(length_m)], x, y, heading), TWO_LANES)


def test_a_straight_road_in_road_coordinates():
    road = straight(100.0, 10.0, -5.0, math.pi / 6)
    x, y, h = road.pose(40.0, 2.0)
    c, s = math.cos(math.pi / 6), math.sin(math.pi / 6)
    assert (float(x), float(y), float(h)) == pytest.approx((10 + 40 * c - 2 * s, -5 + 40 * s + 2 * c, math.pi / 6))
    assert road.to_st(float(x), float(y)) == pytest.approx((40.0, 2.0))
    # beyond the end the reference line goes straight on
    assert road.to_st(*(float(v) for v in road.pose(130.0, -1.0)[:2])) == pytest.approx((130.0, -1.0))


def test_an_arc_against_the_circle():
    r = 50.0
    road = Road(PlanView.chained([Arc(math.pi * r / 2, 1.0 / r)]), TWO_LANES)  # a left quarter circle
    s = np.linspace(0.0, math.pi * r / 2, 7)
    x, y, h = road.pose(s)
    np.testing.assert_allclose(x, r * np.sin(s / r), atol=1e-12)
    np.testing.assert_allclose(y, r * (1 - np.cos(s / r)), atol=1e-12)
    np.testing.assert_allclose(h, s / r, atol=1e-15)
    # a point at radius 47 from the centre (0, 50), 30 deg round: t = +3 (toward the centre, left), s = r * angle
    a = math.radians(30.0)
    assert road.to_st(47.0 * math.sin(a), 50.0 - 47.0 * math.cos(a)) == pytest.approx((r * a, 3.0), abs=1e-9)


def _fresnel_series(c: float, s: float) -> tuple[float, float]:
    """x, y of a clothoid from curvature 0 with c = dk/ds: the power series of the Fresnel integrals."""
    x = y = 0.0
    for n in range(12):
        x += (-1) ** n * (c / 2) ** (2 * n) * s ** (4 * n + 1) / (math.factorial(2 * n) * (4 * n + 1))
        y += (-1) ** n * (c / 2) ** (2 * n + 1) * s ** (4 * n + 3) / (math.factorial(2 * n + 1) * (4 * n + 3))
    return x, y


def test_a_clothoid_against_the_fresnel_series():
    spiral = Spiral(40.0, 0.0, 1.0 / 20.0)  # curvature 0 -> 1/20 over 40 m: turns 1 rad
    c = (1.0 / 20.0) / 40.0
    for s in (0.0, 5.0, 17.3, 33.0, 40.0):
        x, y, h = spiral.local(s)
        assert (float(x), float(y)) == pytest.approx(_fresnel_series(c, s), abs=1e-11)
        assert float(h) == pytest.approx(0.5 * c * s * s)


def test_a_clothoid_of_constant_curvature_is_an_arc():
    spiral, arc = Spiral(30.0, 0.04, 0.04), Arc(30.0, 0.04)
    s = np.linspace(0, 30, 11)
    for a, b in zip(spiral.local(s), arc.local(s)):
        np.testing.assert_allclose(a, b, atol=1e-11)


def test_the_euro_ncap_turn_is_clothoid_arc_clothoid_and_turns_a_right_angle():
    # planar-protocol-facts §2.2 (Euro NCAP CA-FC v1.1 §1.2.4), 10 km/h to the far side:
    # clothoid R 1500 -> 9 m over alpha = 20.62 deg, arc R 9 m over beta = 48.75 deg, clothoid back
    alpha, beta, k0, k1 = math.radians(20.62), math.radians(48.75), 1 / 1500, 1 / 9.0
    entry = 2 * alpha / (k0 + k1)  # a clothoid turns by its mean curvature times its length
    plan = PlanView.chained([Line(20.0), Spiral(entry, k0, k1), Arc(beta / k1, k1), Spiral(entry, k1, k0), Line(20.0)])
    road = Road(plan, TWO_LANES)
    _, _, h_end = road.pose(road.length_m)
    assert math.degrees(float(h_end)) == pytest.approx(2 * 20.62 + 48.75, abs=1e-9)  # 89.99 deg
    # the pieces join without a kink: the heading and position are continuous at each joint
    for p, q in zip(plan.placed, plan.placed[1:]):
        end = p.pose(p.segment.length_m)
        assert (float(end[0]), float(end[1]), float(end[2])) == pytest.approx((q.x_m, q.y_m, q.heading_rad), abs=1e-12)
    # and the curvature is continuous from clothoid to arc to clothoid (the lines join R = 1500 m: 1/1500 1/m)
    for p, q in zip(plan.placed[1:3], plan.placed[2:4]):
        assert float(p.segment.curvature(p.segment.length_m)) == pytest.approx(float(q.segment.curvature(0.0)))


def test_lanes_widths_and_the_lane_of_a_point():
    lanes = LaneSection(0.0, left=(Lane(1, (LaneWidth(0.0, 3.5),)), Lane(2, (LaneWidth(0.0, 2.0),), "shoulder")),
                        right=(Lane(-1, (LaneWidth(0.0, 3.0, 0.01),)),))  # -1 widens 1 cm per m
    road = Road(PlanView.chained([Line(100.0)]), (lanes,))
    assert road.lane_at(10.0, 1.0) == 1
    assert road.lane_at(10.0, 3.5) == 1  # on the border: the inner lane
    assert road.lane_at(10.0, 4.0) == 2
    assert road.lane_at(10.0, 0.0) == -1
    assert road.lane_at(10.0, -3.05) == -1  # width 3.1 at s = 10
    assert road.lane_at(10.0, -3.15) is None
    assert road.lane_at(50.0, -3.45) == -1  # width 3.5 at s = 50
    assert road.lane_at(10.0, 5.6) is None and road.lane_at(-1.0, 1.0) is None and road.lane_at(101.0, 1.0) is None
    assert road.is_on_road(10.0, 5.4) and not road.is_on_road(10.0, 5.6)
    left, right = road.edges(step_m=10.0)
    np.testing.assert_allclose(left[:, 1], 5.5)
    np.testing.assert_allclose(right[:, 1], -(3.0 + 0.01 * left[:, 0]))
    centre = road.lane_centre_line(-1, step_m=50.0)
    np.testing.assert_allclose(centre, [[0.0, -1.5], [50.0, -1.75], [100.0, -2.0]])
    assert road.lane_ids() == [2, 1, -1]


def test_lane_sections_change_the_lanes_along_the_road():
    sections = (LaneSection.uniform(0.0, left_m=(3.5,), right_m=(3.5,)),
                LaneSection.uniform(50.0, left_m=(3.5,), right_m=(3.5, 3.5)))  # a right lane opens at s = 50
    road = Road(PlanView.chained([Line(100.0)]), sections)
    assert road.lane_at(40.0, -5.0) is None and road.lane_at(60.0, -5.0) == -2
    line = road.lane_centre_line(-2, step_m=25.0)
    assert np.isnan(line[:2]).all() and line[3:, 1] == pytest.approx([-5.25, -5.25])


def test_bad_roads_are_refused_with_the_reason():
    with pytest.raises(ValueError, match="left ids 1, 2"):
        LaneSection(0.0, left=(Lane(2, (LaneWidth(0.0, 3.5),)),))
    with pytest.raises(ValueError, match="starting at s=0"):
        Road(PlanView.chained([Line(10.0)]), (LaneSection.uniform(5.0, (3.5,)),))
    with pytest.raises(ValueError, match="length_m > 0"):
        Line(0.0)
    with pytest.raises(ValueError, match="curvature_1pm != 0"):
        Arc(10.0, 0.0)


CURVY = Road(PlanView.chained([Line(30.0), Spiral(25.0, 0.0, 0.04), Arc(20.0, 0.04), Spiral(25.0, 0.04, -0.02),
                               Line(10.0)], 5.0, 3.0, 0.4), TWO_LANES)


@settings(max_examples=200, deadline=None)
@given(st.floats(0.0, CURVY.length_m), st.floats(-4.0, 4.0))
def test_road_coordinates_round_trip(s, t):
    """(s, t) -> (x, y) -> (s, t) on a road of lines, clothoids and an arc (|t| below the 25 m radius)."""
    x, y, _ = CURVY.pose(s, t)
    assert CURVY.to_st(float(x), float(y)) == pytest.approx((s, t), abs=1e-8)
