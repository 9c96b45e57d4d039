"""Joint constraint tightening: nominal far away, the contingency at the boundary, a blend between."""

import math

import pytest

from can_dbc.contract import enumeration
from ecu.core import CoreParams
from ecu.core.region import Contingency, EgoState, Road, TrackBox, decide, region_params, tightened_bounds
from ecu.core.region.tightening import contingency_bounds, nominal_bounds
from ecu.core.strategies.tightening import tighten

CAR = {name: value for value, name in enumeration("RadarTrack0", "Track0SizeClass").items()}["CAR"]
CORE = CoreParams()
P = region_params(CORE)
D = CORE.model_decel_mps2


def _decision(gap_m, speed=20.0):
    return decide(EgoState(speed, 0.0, D), [TrackBox(gap_m, 0.0, -speed, 0.0, CAR, 0.0)], None, P)


def test_far_from_the_boundary_the_bounds_are_nominal():
    d = _decision(80.0)
    assert d.proximity == 0.0
    assert tightened_bounds(EgoState(20.0, 0.0, D), d, P) == nominal_bounds(EgoState(20.0, 0.0, D), D, P)
    kappa = nominal_bounds(EgoState(20.0, 0.0, D), D, P).curvature_hi_1pm
    assert kappa == pytest.approx(D / 400.0)  # friction, not the steering angle, limits at 20 m/s


def test_at_the_boundary_the_bounds_are_the_contingency():
    ego = EgoState(30.0, 0.0, D)
    d = decide(ego, [TrackBox(58.0, 0.0, -30.0, 0.0, CAR, 0.0)], Road((-1.75, 1.75, 5.25)), P)
    assert d.kind is Contingency.STEER_AND_BRAKE and d.proximity == 1.0
    bounds = tightened_bounds(ego, d, P)
    assert bounds == contingency_bounds(ego, d, P)
    assert bounds.curvature_lo_1pm == bounds.curvature_hi_1pm == d.curvature_1pm
    # the wheel turns left toward delta_c = atan(kappa_c L) within one hold time
    assert bounds.steer_rate_hi_radps == pytest.approx(math.atan(d.curvature_1pm * P.wheelbase_m) / P.hold_time_s)
    assert 0.0 < bounds.steer_rate_hi_radps <= P.steer_rate_max_radps
    assert bounds.accel_hi_mps2 == -P.contingency_decel_mps2


def test_in_between_every_bound_is_the_linear_blend_and_stays_ordered():
    ego = EgoState(20.0, 0.0, D)
    d = _decision(34.0)
    assert 0.0 < d.proximity < 1.0
    p, n, c = d.proximity, nominal_bounds(ego, D, P), contingency_bounds(ego, d, P)
    b = tightened_bounds(ego, d, P)
    for got, lo, hi in zip(b, n, c):
        assert got == pytest.approx((1 - p) * lo + p * hi)
    assert b.accel_hi_mps2 == tighten(p, CORE).accel_upper_mps2
    assert b.accel_lo_mps2 <= b.accel_hi_mps2 and b.curvature_lo_1pm <= b.curvature_hi_1pm
    assert b.steer_rate_lo_radps <= b.steer_rate_hi_radps


def test_low_speed_curvature_is_limited_by_the_steering_angle():
    n = nominal_bounds(EgoState(1.0, 0.0, D), D, P)
    assert n.curvature_hi_1pm == pytest.approx(math.tan(P.steer_angle_max_rad) / P.wheelbase_m)
