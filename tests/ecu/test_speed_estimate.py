"""Reference-speed estimate under braking and traction slip."""

import pytest

from ecu.core import CoreParams
from ecu.core.speed_estimate import update_speed_mps

P = CoreParams()  # front-wheel driven, slope limits -(9+2) and +(3+2) m/s^2


def test_braking_takes_the_fastest_wheel():
    assert update_speed_mps(0.0, False, (0.0, 18.0, 20.0, 19.0), True, P) == 20.0  # not initialised: the candidate


def test_accelerating_takes_the_slowest_non_driven_wheel():
    assert update_speed_mps(0.0, False, (25.0, 26.0, 20.0, 20.5), False, P) == 20.0
    rear = CoreParams(driven_axle="rear")
    assert update_speed_mps(0.0, False, (20.0, 20.5, 25.0, 26.0), False, rear) == 20.0
    assert update_speed_mps(0.0, False, (20.0, 20.5, 25.0, 19.0), False, CoreParams(driven_axle="all")) == 19.0


def test_all_wheels_locked_falls_no_faster_than_the_slope_limit():
    v = 20.0
    for _ in range(100):
        v = update_speed_mps(v, True, (0.0, 0.0, 0.0, 0.0), True, P)
    assert v == pytest.approx(20.0 - 11.0 * 1.0)


def test_spinning_wheels_rise_no_faster_than_the_slope_limit():
    v = 10.0
    for _ in range(10):
        v = update_speed_mps(v, True, (30.0, 30.0, 30.0, 30.0), False, P)
    assert v == pytest.approx(10.0 + 5.0 * 0.1)


def test_first_sample_initialises_and_estimate_is_never_negative():
    assert update_speed_mps(0.0, False, (12.0, 12.0, 11.0, 11.5), False, P) == 11.0
    assert update_speed_mps(0.05, True, (0.0,) * 4, True, P) == 0.0
