"""Track confirmation (ecu/core/track_confirmation.py): N consistent reports confirm, a jump or a lone stale one
never; a real object is still braked for."""

import math

from ecu.core import CoreInputs, CoreParams, CoreState, FaultFlag, Mode, step
from ecu.core.track_confirmation import TrackState, confirmed, continues, next_track

P = CoreParams(strategy="none")
REPORT_S = 0.05  # ObjectTrack's DBC cycle


def report(t_s, range_m, rate_mps=-15.0, valid=True):
    return CoreInputs(t_s=t_s, object_valid=valid, object_range_m=range_m, object_range_rate_mps=rate_mps,
                      object_rx_t_s=t_s)


def approach(n, range0_m=60.0, rate_mps=-15.0, t0_s=0.0, track=TrackState()):
    """The track after ``n`` reports of an object closing at ``rate_mps`` from ``range0_m``."""
    for i in range(n):
        t = t0_s + i * REPORT_S
        track = next_track(track, report(t, range0_m + rate_mps * i * REPORT_S, rate_mps), P)
    return track


def test_confirms_after_n_consistent_reports():
    assert P.track_confirm_reports == 3
    assert [confirmed(approach(n), P) for n in range(1, 5)] == [False, False, True, True]


def test_the_same_report_twice_is_not_a_second_report():
    track = approach(2)
    again = next_track(track, report(REPORT_S, 60.0 - 15.0 * REPORT_S), P)  # same receive time: no new report
    assert again == track and not confirmed(again, P)


def test_an_inconsistent_jump_resets_the_count():
    track = approach(4)
    jumped = next_track(track, report(4 * REPORT_S, 30.0), P)  # expected 60 - 15 * 0.2 = 57 m
    assert jumped.consistent_reports == 1 and not confirmed(jumped, P)
    # the new object is confirmed by its own consistent reports, N - 1 reports later
    later = approach(3, 30.0, t0_s=4 * REPORT_S, track=track)
    assert confirmed(later, P)


def test_a_range_rate_beyond_the_acceleration_limit_resets():
    track = approach(4)
    t = 4 * REPORT_S
    r = 60.0 - 15.0 * t
    # 20 m/s^2 * 0.05 s + 1 m/s allows 2 m/s per report; 4 m/s is no road vehicle (ranges fit the mean rate)
    assert not continues(track, t, r - 0.5 * 4.0 * REPORT_S, -19.0, P)
    assert continues(track, t, r - 0.5 * 1.5 * REPORT_S, -16.5, P)


def test_tolerances_at_their_bounds():
    track = approach(1)  # 60 m at t = 0, -15 m/s
    predicted = 60.0 - 15.0 * REPORT_S
    slack = P.track_range_tolerance_m + 15.0 * P.cycle_s  # 2 m + one cycle at 15 m/s
    assert continues(track, REPORT_S, predicted + slack - 1e-9, -15.0, P)
    assert not continues(track, REPORT_S, predicted + slack + 1e-6, -15.0, P)
    assert not continues(track, P.track_coast_s + 1e-6, 60.0 - 15.0 * (P.track_coast_s + 1e-6), -15.0, P)


def test_a_single_stale_report_between_fresh_ones_never_confirms():
    """Object absent, then one replayed report of it (its counter in sequence), then absent again."""
    track = TrackState()
    for i in range(40):
        t = i * REPORT_S
        stale = i % 4 == 2  # a replayed frame of an object recorded earlier, every fourth report
        track = next_track(track, report(t, 12.0 - i * 0.1, valid=stale), P)
        assert not confirmed(track, P), i


def test_stale_reports_of_a_recorded_approach_do_not_continue_each_other():
    """Replayed frames of one recorded approach, a second apart: each one alone, none consistent."""
    track = TrackState()
    for i in range(10):
        track = next_track(track, report(i * 1.0, 45.0 - 0.75 * (i % 5)), P)
        assert track.consistent_reports == 1


def test_a_dropout_coasts_and_a_long_gap_restarts():
    track = approach(3)
    gone = next_track(track, report(3 * REPORT_S, 0.0, valid=False), P)  # one dropout
    assert confirmed(gone, P)
    back = next_track(gone, report(4 * REPORT_S, 60.0 - 15.0 * 4 * REPORT_S), P)
    assert confirmed(back, P)
    late = next_track(gone, report(1.0, 60.0 - 15.0 * 1.0), P)  # beyond track_coast_s: a new track
    assert late.consistent_reports == 1


def test_non_finite_reports_never_confirm_and_never_raise():
    track = approach(3)
    for bad in (math.nan, math.inf):
        assert next_track(track, report(3 * REPORT_S, bad), P).consistent_reports == 1
    nan_t = next_track(track, report(math.nan, 10.0), P)
    assert not confirmed(next_track(nan_t, report(math.nan, 10.0), P), P)


def test_one_confirms_every_valid_report():
    p1 = CoreParams(strategy="none", track_confirm_reports=1)
    assert confirmed(next_track(TrackState(), report(0.0, 10.0), p1), p1)


def _cycles(state, t0_k, n, range_at, speed=15.0, **extra):
    """``n`` core cycles at 15 m/s; the radar reports ``range_at(t)`` every 50 ms (None: no object)."""
    outs = []
    for k in range(t0_k, t0_k + n):
        t = k * 0.01
        last_report_k = k - k % 5
        r = range_at(last_report_k * 0.01)
        inputs = CoreInputs(t_s=t, wheel_speeds_mps=(speed,) * 4, accel_pedal=0.2, object_valid=r is not None,
                            object_range_m=r or 0.0, object_range_rate_mps=-speed, wheel_rx_t_s=t,
                            driver_rx_t_s=t, object_rx_t_s=last_report_k * 0.01, **extra)
        state, out = step(state, inputs, P)
        outs.append(out)
    return state, outs


def test_a_real_object_appearing_close_is_braked_for_once_confirmed():
    """An object first reported 15 m ahead at 15 m/s: braking begins at its third report, 100 ms later."""
    state, outs = _cycles(CoreState(), 0, 20, lambda t: None)
    assert outs[-1].mode == Mode.STANDBY
    state, outs = _cycles(state, 20, 30, lambda t: 15.0 - 15.0 * (t - 0.2))
    braking = [k for k, o in enumerate(outs) if o.brake_decel_request_mps2 > 0.0]
    assert braking and braking[0] == 2 * 5  # the third report
    assert all(outs[k].mode == Mode.CONTINGENCY for k in braking)


def test_a_lone_phantom_never_starts_degraded_braking():
    """Wheels invalid (FAULT, degraded mode): one report of an object 10 m ahead is not braked for."""
    state, _ = _cycles(CoreState(), 0, 20, lambda t: None)
    stale = {"wheel_rx_flags": 1 << FaultFlag.RATE}
    state, outs = _cycles(state, 20, 5, lambda t: 10.0, **stale)
    assert all(o.mode == Mode.FAULT and o.brake_decel_request_mps2 == 0.0 for o in outs)
    # the same object, reported consistently, is braked for (degraded mode) at its third report
    state, outs = _cycles(state, 25, 15, lambda t: 10.0 - 15.0 * (t - 0.2), **stale)
    assert any(o.brake_decel_request_mps2 == P.contingency_decel_mps2 for o in outs)
