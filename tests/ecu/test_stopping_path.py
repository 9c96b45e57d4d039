"""Stopping distance and disjointness against hand calculations."""

import pytest

from ecu.core import CoreParams
from ecu.core.relative_stop import relative_approach_m
from ecu.core.stopping_path import closing_speed_mps, is_disjoint, stopping_distance_m

P = CoreParams(strategy="none")  # D = 0.9 * 9 = 8.1, t_h = 0.11, standoff 2


def test_hold_then_brake_matches_hand_calculation():
    # 20 * 0.11 + 0.5 * 3 * 0.0121 + 20.33^2 / 16.2 = 2.2 + 0.01815 + 25.51290...
    assert stopping_distance_m(20.0, 3.0, 0.11, 8.1) == pytest.approx(27.731045, abs=1e-6)


def test_standstill_with_throttle_still_travels_during_the_hold():
    assert stopping_distance_m(0.0, 3.0, 0.11, 8.1) == pytest.approx(0.5 * 3 * 0.0121 + 0.33**2 / 16.2)


def test_stopping_within_the_hold_uses_the_commanded_deceleration():
    # v + a t_h = 0.5 - 0.99 < 0: stops after 0.5^2 / 18 m
    assert stopping_distance_m(0.5, -9.0, 0.11, 8.1) == pytest.approx(0.25 / 18.0)


def test_conservative_fraction_lengthens_the_path():
    cons = CoreParams(strategy="conservative")
    assert cons.model_decel_mps2 == pytest.approx(7.2)
    assert stopping_distance_m(20, 3, cons.hold_time_s, cons.model_decel_mps2) > \
        stopping_distance_m(20, 3, P.hold_time_s, P.model_decel_mps2)


def test_moving_object_means_zero_relative_speed():
    assert closing_speed_mps(20.0, -5.0, P) == 5.0    # object at 15 m/s ahead
    assert closing_speed_mps(20.0, -20.0, P) == 20.0  # stationary: own speed
    assert closing_speed_mps(20.0, -30.0, P) == 20.0  # oncoming: zero absolute speed
    # behind it, the relative approach is the stopping distance from the closing speed
    assert relative_approach_m(-5.0, 3.0, P) == pytest.approx(stopping_distance_m(5.0, 3.0, 0.11, 8.1))


def test_disjointness_boundary_and_no_object():
    assert is_disjoint(10.0, True, 12.0, P)        # d + standoff == range: disjoint
    assert not is_disjoint(10.0001, True, 12.0, P)
    assert is_disjoint(1e6, False, 0.0, P)
