"""ECU relevance (ObjectLateral) and planning at zero relative speed behind a moving object."""

import pytest

from ecu.core import CoreInputs, CoreParams, CoreState, Mode, step
from ecu.core.relative_stop import moving_margin_m, moving_proximity, relative_approach_m
from ecu.core.relevance import in_path

P = {s: CoreParams(strategy=s) for s in ("none", "conservative", "tightening")}
EDGE_M = 1.815 / 2 + 1.0  # vehicle half-width + path margin


def inputs(t, speed, range_m, rate, lateral=0.0, accel=1.0):
    return CoreInputs(t_s=t, wheel_speeds_mps=(speed,) * 4, accel_pedal=accel, object_valid=True,
                      object_range_m=range_m, object_range_rate_mps=rate, object_lateral_m=lateral,
                      wheel_rx_t_s=t, driver_rx_t_s=t, object_rx_t_s=t)


def settled(params, speed, range_m, rate, lateral=0.0, accel=1.0, cycles=12):
    """The core after ``cycles`` cycles of the same inputs (start-up FAULT is over after 10)."""
    state, out = CoreState(), None
    for k in range(cycles):
        state, out = step(state, inputs(k * 0.01, speed, range_m, rate, lateral, accel), params)
    return out


@pytest.mark.parametrize("lateral, expected", [
    (0.0, True), (EDGE_M - 1e-6, True), (-EDGE_M + 1e-6, True), (EDGE_M + 1e-6, False), (-3.5, False),
    (2.6575, False), (float("nan"), True)])
def test_in_path_corridor_edges(lateral, expected):
    assert in_path(lateral, P["none"]) is expected


@pytest.mark.parametrize("strategy", ["none", "conservative", "tightening"])
def test_object_outside_the_path_triggers_nothing(strategy):
    # a stationary car 10 m ahead at 20 m/s: certain contingency in our lane, nothing in the next lane
    assert settled(P[strategy], 20.0, 10.0, -20.0, lateral=0.0).mode == Mode.CONTINGENCY
    out = settled(P[strategy], 20.0, 10.0, -20.0, lateral=3.5)
    assert out.mode == Mode.STANDBY and not out.override_active


@pytest.mark.parametrize("strategy", ["none", "conservative", "tightening"])
def test_releases_behind_a_moving_target_when_the_gap_opens(strategy):
    # behind a car at 5.6 m/s, 1.5 m (inside the 2 m standoff), gap opening at 0.5 m/s, pedal released:
    # braking cannot make this safer, so the ECU must not brake on toward a standstill (old code: CONTINGENCY)
    out = settled(P[strategy], 5.1, 1.5, +0.5, accel=0.0)
    assert out.mode == Mode.STANDBY and out.brake_decel_request_mps2 == 0.0


@pytest.mark.parametrize("strategy", ["none", "conservative", "tightening"])
def test_brakes_while_closing_in_on_a_moving_target(strategy):
    out = settled(P[strategy], 6.0, 1.5, -0.4, accel=0.0)  # still closing inside the standoff
    assert out.mode == Mode.CONTINGENCY and out.brake_decel_request_mps2 == 15.0


def test_relative_approach_matches_the_stopping_distance_when_closing_and_is_zero_when_opening():
    p = P["none"]
    t_h, d = p.hold_time_s, p.model_decel_mps2
    assert relative_approach_m(-8.0, 0.0, p) == pytest.approx(8.0 * t_h + 64.0 / (2 * d))
    assert relative_approach_m(+0.3, 0.0, p) == 0.0
    assert relative_approach_m(+0.1, 3.0, p) == pytest.approx(-0.1 * t_h + 1.5 * t_h**2 + (3 * t_h - 0.1)**2 / (2 * d))
    assert relative_approach_m(+1.0, 3.0, p) == 0.0  # full throttle for t_h does not close a 1 m/s opening


def test_following_at_matched_speed_is_not_near_the_boundary():
    # 1 s headway at 30 km/h = 8.3 m at zero closing speed: the range-only margin (10 m + 2 m standoff)
    # made tightening restrict here; the time-scaled margin does not
    p = P["tightening"]
    assert moving_margin_m(0.0, p) == p.proximity_margin_min_m
    assert moving_margin_m(30.0, p) == p.proximity_margin_m
    assert moving_proximity(8.33, 0.0, p) == 0.0
    out = settled(p, 8.33, 8.33, 0.0)
    assert out.mode == Mode.STANDBY and not out.override_active


def test_tightening_still_acts_when_closing_fast_on_a_moving_target():
    p = P["tightening"]
    # closing at 8.3 m/s (50 vs 20 km/h) 14 m behind: inside margin, not yet a contingency
    out = settled(p, 13.9, 14.0, -8.33)
    assert out.mode == Mode.TIGHTENING and out.throttle_limit_pct < 100.0
