"""Driver intent, proximity and our constraint-tightening formalisation."""

import pytest

from ecu.core import CoreParams
from ecu.core.intent import driver_accel_mps2
from ecu.core.proximity import proximity
from ecu.core.strategies.tightening import tighten

# D = 0.9 * 9 = 8.1, a_max = 3, standoff 2, t_h = 0.01 + 0.1, margin scale 10 m, C = 15.
P = CoreParams(strategy="tightening")
D_STANDSTILL = 0.5 * 3.0 * 0.11**2 + (3.0 * 0.11) ** 2 / (2 * 8.1)  # hold full throttle 0.11 s from rest, then stop
D_20 = 20 * 0.11 + 0.5 * 3.0 * 0.11**2 + (20 + 3.0 * 0.11) ** 2 / (2 * 8.1)  # 27.731 m


def test_driver_model():
    assert driver_accel_mps2(1.0, 0.0, P) == 3.0
    assert driver_accel_mps2(0.5, 0.5, P) == pytest.approx(1.5 - 4.5)


@pytest.mark.parametrize("valid,range_m,speed,expected", [
    (False, 5.0, 0.0, 0.0),
    (True, 2.0 + D_STANDSTILL + 10.0, 0.0, 0.0),
    (True, 100.0, 0.0, 0.0),
    (True, 2.0 + D_STANDSTILL + 5.0, 0.0, 0.5),
    (True, 2.0 + D_STANDSTILL, 0.0, 1.0),
    (True, 0.0, 0.0, 1.0),
    (True, 2.0 + D_20 + 5.0, 20.0, 0.5),
    (True, 2.0 + D_20 + 12.0, 20.0, 0.0),
])
def test_proximity_is_the_margin_to_the_contingency_boundary(valid, range_m, speed, expected):
    assert proximity(valid, range_m, speed, P) == pytest.approx(expected)


def test_proximity_grows_with_speed_at_the_same_range():
    values = [proximity(True, 40.0, v, P) for v in range(0, 30, 2)]
    assert values == sorted(values) and values[0] == 0.0 and values[-1] == 1.0


def test_tightening_blends_nominal_into_contingency_bounds():
    far, half, near = tighten(0.0, P), tighten(0.5, P), tighten(1.0, P)
    assert (far.throttle_limit_pct, far.decel_request_mps2, far.restricts) == (100.0, 0.0, False)
    assert half.accel_upper_mps2 == pytest.approx(0.5 * 3.0 - 0.5 * 15.0)
    assert (half.throttle_limit_pct, half.decel_request_mps2) == (0.0, pytest.approx(6.0))
    assert near.decel_request_mps2 == pytest.approx(15.0) and near.restricts
    tenth = tighten(0.1, P)  # a_hi = 2.7 - 1.5 = 1.2 -> 40 %
    assert tenth.throttle_limit_pct == pytest.approx(40.0) and tenth.decel_request_mps2 == 0.0
    zero_crossing = 3.0 / (3.0 + 15.0)
    assert tighten(zero_crossing, P).accel_upper_mps2 == pytest.approx(0.0, abs=1e-12)


def test_throttle_limit_is_monotone_in_proximity():
    limits = [tighten(p / 100, P).throttle_limit_pct for p in range(101)]
    assert limits == sorted(limits, reverse=True)
    decels = [tighten(p / 100, P).decel_request_mps2 for p in range(101)]
    assert decels == sorted(decels)
