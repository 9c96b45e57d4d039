"""The evasive lane changes: their rows, their paths, and rule 3 over them when no arc is disjoint."""

import math

import numpy as np
import pytest

from can_dbc.contract import enumeration
from ecu.core import CoreParams
from ecu.core.region import Contingency, EgoState, Road, TrackBox, decide, region_params
from ecu.core.region.evasion import (
    EVASION_FRICTION_SHARE, EVASION_LEVELS, EVASION_OFFSETS, evasion_family, evasion_rows, piecewise_poses, s_half_m)
from ecu.core.region.overlap import corner_points
from ecu.core.region.road import lateral_offsets

CLASS = {name: value for value, name in enumeration("RadarTrack0", "Track0SizeClass").items()}
P = region_params(CoreParams())
D = CoreParams().model_decel_mps2
TWO_LANES = Road((-1.75, 1.75, 5.25))  # our lane and a free lane on the left


def _parked(x, v):
    return TrackBox(x, 0.0, -v, 0.0, CLASS["CAR"], 0.05)


def test_rows_cover_both_sides_every_offset_and_every_level_within_the_friction_share():
    v, lane = 25.0, 3.5
    kappa, offset = evasion_rows(v, D, lane, P)
    assert kappa.size == offset.size == 2 * EVASION_LEVELS * EVASION_OFFSETS
    half = kappa.size // 2
    assert np.array_equal(kappa[:half], -kappa[half:]) and np.all(kappa[:half] > 0.0)
    lateral = np.abs(kappa) * v * v
    assert lateral.min() == pytest.approx(P.emergency_lat_accel_max_mps2)
    assert lateral.max() == pytest.approx(EVASION_FRICTION_SHARE * D)
    farthest = 1.5 * lane - 0.5 * P.width_m - P.lateral_margin_m
    assert offset.min() == pytest.approx(lane) and offset.max() == pytest.approx(farthest)


def test_each_rows_s_ends_its_offset_over_and_parallel_to_the_road():
    ego = EgoState(27.7, 0.0, D)
    paths, offset, lead = evasion_family(ego, 3.5, P)
    half = s_half_m(paths.curvature_1pm, np.abs(offset))
    lengths = np.column_stack((lead, half, half, np.full(lead.size, np.inf)))
    k = paths.curvature_1pm
    curvatures = np.column_stack((0 * k, k, -k, 0 * k))
    end = (lead + 2.0 * half)[:, None] + np.array([[0.0, 30.0]])  # at the S's end and 30 m on
    position, heading = piecewise_poses(end, lengths, curvatures)
    assert np.allclose(position.imag, offset[:, None], atol=1e-9)
    assert np.allclose(np.angle(heading), 0.0, atol=1e-9)
    assert np.all(paths.stop_m > lead + 2.0 * half) and np.all(np.sign(offset) == np.sign(k))


def test_with_no_disjoint_arc_a_lane_change_into_the_free_lane_is_chosen():
    # 27.7 m/s, a car parked 41 m ahead: no arc stays on the road, a lane change to the left clears the car
    d = decide(EgoState(27.7, 0.0, D), [_parked(41.0, 27.7)], TWO_LANES, P)
    assert d.kind is Contingency.STEER_AND_BRAKE and d.steering and d.clearance_m >= 0.0
    assert d.evasion_offset_m >= 3.5 and d.curvature_1pm > 0.0 and d.evasion_lead_m > 0.0
    e = lateral_offsets(TWO_LANES, corner_points(d.paths, d.box)[d.row])
    assert e.min() >= -1.75 and e.max() <= 5.25
    mirrored = decide(EgoState(27.7, 0.0, D), [_parked(41.0, 27.7)], Road((-5.25, -1.75, 1.75)), P)
    assert mirrored.evasion_offset_m == pytest.approx(-d.evasion_offset_m)
    assert mirrored.curvature_1pm == pytest.approx(-d.curvature_1pm)


def test_an_arc_that_is_disjoint_is_kept_and_no_lane_change_is_judged():
    d = decide(EgoState(30.0, 0.0, D), [_parked(58.0, 30.0)], TWO_LANES, P)
    assert d.kind is Contingency.STEER_AND_BRAKE and d.evasion_offset_m == 0.0


@pytest.mark.parametrize("road", [Road((-1.75, 1.75)), None])
def test_without_a_free_lane_or_a_road_no_lane_change_is_chosen(road):
    d = decide(EgoState(27.7, 0.0, D), [_parked(41.0, 27.7)], road, P)
    assert d.evasion_offset_m == 0.0


def test_an_occupied_left_lane_forbids_the_lane_change():
    neighbour = TrackBox(50.0, 3.5, -2.0, 0.0, CLASS["CAR"], 0.05)  # a car driving in the left lane ahead
    d = decide(EgoState(27.7, 0.0, D), [_parked(41.0, 27.7), neighbour], TWO_LANES, P)
    assert d.evasion_offset_m == 0.0 and d.kind is Contingency.LEAST_IMPACT


def test_too_close_for_any_lane_change_it_is_the_least_impact():
    d = decide(EgoState(27.7, 0.0, D), [_parked(25.0, 27.7)], TWO_LANES, P)
    assert d.kind is Contingency.LEAST_IMPACT and d.evasion_offset_m == 0.0
    assert math.isfinite(d.impact_speed_mps)
