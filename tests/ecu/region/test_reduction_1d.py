"""The plane reduces to the 1-D core: wheel straight, no yaw rate, a standing object ahead in lane.

Over a grid of speeds, commands and gaps the driver's stopping distance equals
``ecu.core.stopping_path.stopping_distance_m`` bit for bit, the disjointness verdict equals
``is_disjoint`` (ties within 1e-9 m, where the two float paths may round apart, are left out and
counted), and the proximity and the tightened acceleration bound equal the 1-D core's."""

import itertools

import pytest

from ecu.core import CoreParams
from ecu.core.proximity import proximity
from ecu.core.region import EgoState, TrackBox, decide, region_params, tightened_bounds
from ecu.core.region.params import CAPABILITIES
from ecu.core.stopping_path import is_disjoint, stopping_distance_m
from ecu.core.strategies.tightening import tighten

CAR = next(k for k, cap in CAPABILITIES.items() if cap.length_m == 4.0 and cap.decel_mps2 == 4.0)
SPEEDS = (0.0, 0.3, 2.0, 5.5, 8.33, 13.9, 20.0, 27.8, 36.1)
ACCELS = (-9.0, -2.0, 0.0, 1.5, 3.0)
GAPS = (0.5, 2.0, 4.7, 9.1, 15.0, 22.2, 31.3, 47.0, 66.6, 90.0)


@pytest.mark.parametrize("strategy", ["none", "conservative", "tightening"])
def test_straight_path_equals_the_1d_stopping_path_and_verdict(strategy):
    core = CoreParams(strategy=strategy)
    params = region_params(core)
    ties = compared = 0
    for v, a, r in itertools.product(SPEEDS, ACCELS, GAPS):
        ego = EgoState(v, a, core.model_decel_mps2)
        decision = decide(ego, [TrackBox(r, 0.0, -v, 0.0, CAR, 0.0)], None, params)
        d = stopping_distance_m(v, a, core.hold_time_s, core.model_decel_mps2)
        assert decision.driver_stopping_distance_m == d
        if abs(d + core.standoff_m - r) < 1e-9:
            ties += 1
            continue
        compared += 1
        assert decision.driver_disjoint == is_disjoint(d, True, r, core), (v, a, r)
        assert decision.proximity == pytest.approx(proximity(True, r, v, core), abs=1e-9)
        bounds = tightened_bounds(ego, decision, params)
        assert bounds.accel_hi_mps2 == pytest.approx(tighten(decision.proximity, core).accel_upper_mps2, abs=1e-12)
    assert compared >= len(SPEEDS) * len(ACCELS) * len(GAPS) - 5 and ties <= 5
    # the grid holds both verdicts, so the comparison can fail either way
    verdicts = {is_disjoint(stopping_distance_m(v, a, core.hold_time_s, core.model_decel_mps2), True, r, core)
                for v, a, r in itertools.product(SPEEDS, ACCELS, GAPS)}
    assert verdicts == {True, False}


def test_no_object_is_disjoint_with_zero_proximity():
    core = CoreParams()
    decision = decide(EgoState(20.0, 3.0, core.model_decel_mps2), [], None, region_params(core))
    assert decision.driver_disjoint and decision.proximity == 0.0 == proximity(False, 0.0, 20.0, core)
