"""Behind a moving object that closes in: our stopping path stays clear of the object's own stopping region
(issue 22, braking targets; ecu/core/relative_stop.py)."""

import pytest

from ecu.core import Mode
from ecu.core.relative_stop import (clear_of_lead_m, lead_stop_m, moving_margin_m, relative_approach_m,
                                    relative_disjoint)
from ecu.core.stopping_path import stopping_distance_m

from .test_relevance_relative_stop import P, settled

STRATEGIES = ("none", "conservative", "tightening")


def test_the_lead_stops_where_a_full_stop_on_a_dry_road_takes_it_and_the_check_is_its_margin():
    p = P["tightening"]
    assert lead_stop_m(13.9, -3.0, p) == pytest.approx(10.9**2 / (2 * p.peak_decel_mps2))
    assert lead_stop_m(10.0, -12.0, p) == 0.0  # an oncoming object: its region ends where it is
    stop = stopping_distance_m(13.9, 0.0, p.hold_time_s, p.model_decel_mps2)
    assert clear_of_lead_m(13.9, 0.0, 8.0, -3.0, p, p.model_decel_mps2) == pytest.approx(
        8.0 + lead_stop_m(13.9, -3.0, p) - stop - p.standoff_m)


@pytest.mark.parametrize("strategy", STRATEGIES)
def test_a_closing_lead_whose_stop_we_would_overrun_is_a_contingency_the_constant_speed_check_misses(strategy):
    p = P[strategy]
    # 50 km/h, 8 m behind a lead that has slowed to 10.9 m/s (it brakes): at constant speed we would never reach it
    assert relative_disjoint(relative_approach_m(-3.0, 0.0, p), 8.0, p)
    assert clear_of_lead_m(13.9, 0.0, 8.0, -3.0, p, p.model_decel_mps2) < 0.0
    out = settled(p, 13.9, 8.0, -3.0, accel=0.0)
    # none and conservative invoke the contingency; tightening's bound (proximity 1) brakes first
    expected = Mode.TIGHTENING if strategy == "tightening" else Mode.CONTINGENCY
    assert out.mode == expected and out.override_active and out.brake_decel_request_mps2 > 0.0


@pytest.mark.parametrize("strategy", STRATEGIES)
def test_following_at_euro_ncaps_one_second_headway_is_no_contingency_at_any_test_speed(strategy):
    p = P[strategy]
    for kmh in (30, 50, 80, 130):  # CCRb's speeds: both at the same speed, closing barely (0.2 m/s)
        v = kmh / 3.6
        assert clear_of_lead_m(v, 0.0, v * 1.0, -0.2, p, p.model_decel_mps2) > 0.0, kmh
        out = settled(p, v, v * 1.0, -0.2, accel=0.0)
        assert out.mode == Mode.STANDBY and out.brake_decel_request_mps2 == 0.0, kmh


def test_a_closing_lead_raises_tightenings_proximity_before_the_contingency():
    p = P["tightening"]
    # the range at which full throttle's stopping path ends half the margin short of the lead's region
    margin = moving_margin_m(3.0, p)
    at_zero = 20.0 - clear_of_lead_m(13.9, p.driver_max_accel_mps2, 20.0, -3.0, p, p.model_decel_mps2)
    assert relative_disjoint(relative_approach_m(-3.0, p.driver_max_accel_mps2, p), at_zero + margin / 2, p)
    far = settled(p, 13.9, at_zero + 2 * margin, -3.0, accel=0.0)
    near = settled(p, 13.9, at_zero + margin / 2, -3.0, accel=0.0)
    assert far.proximity == 0.0 and near.proximity == pytest.approx(0.5, abs=0.05)
