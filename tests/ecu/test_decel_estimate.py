"""The ``adaptive`` strategy's estimate of the achievable deceleration, on its own (issue 14)."""

import math

import numpy as np
import pytest

from ecu.core import CoreInputs, CoreParams, CoreState, Mode, step
from ecu.core.decel_estimate import DecelEstimate, achievable_decel_mps2, update

PARAMS = CoreParams(strategy="adaptive")
DT = PARAMS.cycle_s


def _brake(decel_mps2: float, seconds: float, v0: float = 25.0, request: float = 15.0,
           noise_mps: float = 0.0, seed: int = 0, est: DecelEstimate = DecelEstimate()) -> list[float]:
    """Feed the estimator a car braking at ``decel_mps2``; returns the estimate after each cycle."""
    rng = np.random.default_rng(seed)
    v, out = v0, []
    for _ in range(int(round(seconds / DT))):
        v_new = max(0.0, v - decel_mps2 * DT)
        wheels = tuple(float(w) for w in v_new + noise_mps * rng.standard_normal(4))
        est = update(est, v + noise_mps * rng.standard_normal(), v_new + noise_mps * rng.standard_normal(),
                     wheels, request, PARAMS)
        out.append(achievable_decel_mps2(est, PARAMS))
        v = v_new
    return out


def test_prior_is_the_configured_peak_before_evidence():
    assert achievable_decel_mps2(DecelEstimate(), PARAMS) == PARAMS.peak_decel_mps2
    assert CoreState().decel.achievable_mps2 == math.inf


def test_converges_to_the_deceleration_achieved_at_the_limit():
    estimates = _brake(5.0, 2.0)  # full braking requested, the road gives 5 m/s^2
    assert abs(estimates[-1] - 5.0) < 0.2
    # no evidence before the brakes have settled (dead time + build-up)
    assert all(e == PARAMS.peak_decel_mps2 for e in estimates[: PARAMS.decel_settle_cycles - 1])


def test_never_exceeds_the_peak_nor_falls_below_the_floor():
    assert max(_brake(12.0, 1.5)) <= PARAMS.peak_decel_mps2
    low = _brake(0.2, 1.5, v0=20.0)
    assert min(low) >= PARAMS.decel_estimate_floor_mps2
    assert low[-1] == pytest.approx(PARAMS.decel_estimate_floor_mps2)


def test_braking_that_delivers_the_request_is_no_evidence_of_a_slippery_road():
    # a gentle 3 m/s^2 request met in full: the road may allow more; the estimate stays at the prior
    assert _brake(3.0, 1.5, request=3.0)[-1] == PARAMS.peak_decel_mps2


def test_noisy_wheel_speeds_converge_within_tolerance_and_stay_bounded():
    # 0.02 m/s (0.07 km/h) per sample on every wheel and on the speed: the derivative's noise is
    # 0.02 * sqrt(2) / 0.01 s = 2.8 m/s^2 per cycle before the filters
    for seed in range(5):
        estimates = _brake(5.0, 2.0, noise_mps=0.02, seed=seed)
        assert max(estimates) <= PARAMS.peak_decel_mps2
        assert abs(float(np.mean(estimates[-50:])) - 5.0) < 0.5, (seed, estimates[-1])
        assert abs(estimates[-1] - 5.0) < 0.8, (seed, estimates[-1])


def test_traction_slip_of_the_driven_wheels_lowers_the_estimate():
    est, v = DecelEstimate(), 10.0
    for _ in range(200):
        v_new = v + 2.5 * DT  # the car gains 2.5 m/s^2 while the front (driven) wheels spin 20 % fast
        wheels = (1.2 * v_new, 1.2 * v_new, v_new, v_new)
        est = update(est, v, v_new, wheels, 0.0, PARAMS)
        v = v_new
    expected = 2.5 / PARAMS.driven_axle_load_share
    assert abs(achievable_decel_mps2(est, PARAMS) - expected) < 0.3


def test_cruising_with_noisy_wheels_is_no_evidence():
    rng = np.random.default_rng(3)
    est = DecelEstimate()
    for _ in range(500):
        wheels = tuple(float(w) for w in 20.0 + 0.05 * rng.standard_normal(4))
        est = update(est, 20.0, 20.0, wheels, 0.0, PARAMS)
    assert achievable_decel_mps2(est, PARAMS) == PARAMS.peak_decel_mps2


def _inputs(t_s: float, wheels: float, rx_t_s: float, range_m: float) -> CoreInputs:
    return CoreInputs(t_s=t_s, wheel_speeds_mps=(wheels,) * 4, accel_pedal=1.0, object_valid=True,
                      object_range_m=range_m, object_range_rate_mps=-wheels,
                      wheel_rx_t_s=rx_t_s, driver_rx_t_s=t_s, object_rx_t_s=t_s)


def test_no_evidence_and_no_braking_from_invalid_wheel_speeds():
    state = CoreState()
    for k in range(20):  # valid start-up, far from the object
        state, out = step(state, _inputs(k * DT, 20.0, k * DT, 200.0), PARAMS)
    assert out.mode is Mode.STANDBY
    before = state.decel
    for k in range(20, 30):  # wheel speeds stop arriving, still far: FAULT after the 50 ms timeout
        state, out = step(state, _inputs(k * DT, 20.0, 19 * DT, 200.0), PARAMS)
    assert out.mode is Mode.FAULT
    for k in range(30, 50):  # the object is close now: no new braking from invalid data
        state, out = step(state, _inputs(k * DT, 20.0, 19 * DT, 30.0), PARAMS)
        assert out.brake_decel_request_mps2 == 0.0
    assert out.mode is Mode.FAULT
    assert state.decel == before


def test_without_evidence_adaptive_plans_exactly_like_tightening():
    tight = CoreParams(strategy="tightening")
    s_a, s_t = CoreState(), CoreState()
    for k in range(60):
        inputs = _inputs(k * DT, 20.0, k * DT, 120.0 - 20.0 * k * DT)
        s_a, out_a = step(s_a, inputs, PARAMS)
        s_t, out_t = step(s_t, inputs, tight)
        assert out_a == out_t


def test_a_held_contingency_dead_reckons_with_the_estimate_not_the_dry_peak():
    wet = DecelEstimate(achievable_mps2=4.0)
    state = CoreState(mode=Mode.CONTINGENCY, speed_mps=10.0, speed_initialised=True, decel=wet,
                      prev_decel_request_mps2=15.0, valid_cycles=10)
    stale = CoreInputs(t_s=1.0, wheel_speeds_mps=(10.0,) * 4, wheel_rx_t_s=0.0, driver_rx_t_s=1.0,
                       object_rx_t_s=1.0)
    state, out = step(state, stale, PARAMS)
    assert out.speed_estimate_mps == pytest.approx(10.0 - 0.9 * 4.0 * DT)
