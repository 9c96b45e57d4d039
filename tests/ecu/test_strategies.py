"""Driver intent, proximity and our constraint-tightening formalisation."""

import pytest

from ecu.core import CoreParams
from ecu.core.strategies import driver_accel_mps2, proximity, tighten

P = CoreParams(strategy="tightening")  # D = 8.1, a_max = 3, standoff 2, proximity range 40


def test_driver_model():
    assert driver_accel_mps2(1.0, 0.0, P) == 3.0
    assert driver_accel_mps2(0.5, 0.5, P) == pytest.approx(1.5 - 4.5)


@pytest.mark.parametrize("valid,range_m,expected", [
    (False, 5.0, 0.0), (True, 42.0, 0.0), (True, 100.0, 0.0), (True, 22.0, 0.5), (True, 2.0, 1.0), (True, 0.0, 1.0),
])
def test_proximity(valid, range_m, expected):
    assert proximity(valid, range_m, P) == pytest.approx(expected)


def test_tightening_blends_nominal_into_contingency_bounds():
    far, half, near = tighten(0.0, P), tighten(0.5, P), tighten(1.0, P)
    assert (far.throttle_limit_pct, far.decel_request_mps2, far.restricts) == (100.0, 0.0, False)
    assert half.accel_upper_mps2 == pytest.approx(0.5 * 3.0 - 0.5 * 8.1)
    assert (half.throttle_limit_pct, half.decel_request_mps2) == (0.0, pytest.approx(2.55))
    assert near.decel_request_mps2 == pytest.approx(8.1) and near.restricts
    quarter = tighten(0.1, P)  # a_hi = 2.7 - 0.81 = 1.89 -> 63 %
    assert quarter.throttle_limit_pct == pytest.approx(63.0) and quarter.decel_request_mps2 == 0.0


def test_throttle_limit_is_monotone_in_proximity():
    limits = [tighten(p / 100, P).throttle_limit_pct for p in range(101)]
    assert limits == sorted(limits, reverse=True)
