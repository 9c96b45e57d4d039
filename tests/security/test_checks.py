"""Each receiver and plausibility check of issue 15 raises its named fault flag (EcuStatus.Fault<Name>)."""

import uuid

import can
import pytest

from can_dbc import RX_RATE, CounterSequence, Receiver, encode
from can_dbc.contract import enumeration
from can_dbc.planar import Track
from ecu import EcuConfig, EcuNode
from ecu.core import CoreInputs, CoreParams, CoreState, FaultFlag, Mode, step

#: objects appear here from one cycle to the next, so track confirmation (tests/ecu/test_track_confirmation.py)
#: is off: every valid report confirms itself
P = CoreParams(strategy="none", track_confirm_reports=1)


def _inputs(t, speed=20.0, wheels=None, range_m=None, rate=None, accel=0.5, brake=0.0, **extra):
    return CoreInputs(t_s=t, wheel_speeds_mps=wheels or (speed,) * 4, accel_pedal=accel, brake_pedal=brake,
                      object_valid=range_m is not None, object_range_m=range_m or 0.0,
                      object_range_rate_mps=-speed if rate is None else rate,
                      wheel_rx_t_s=t, driver_rx_t_s=t, object_rx_t_s=t, **extra)


def _settled(inputs_at=lambda t: _inputs(t, range_m=200.0)):
    state = CoreState()
    for k in range(12):
        state, _ = step(state, inputs_at(k * 0.01), P)
    assert state.mode == Mode.STANDBY
    return state


@pytest.mark.parametrize("flag, inputs", [
    (FaultFlag.WHEEL_SLIP, _inputs(0.12, wheels=(20.0, 20.0, 20.0, 32.0))),
    (FaultFlag.SPEED_RADAR, _inputs(0.12, speed=20.0, range_m=100.0, rate=-27.0)),
    (FaultFlag.PEDALS, _inputs(0.12, accel=0.8, brake=0.8)),
    (FaultFlag.CLOCK, _inputs(0.12)._replace(wheel_rx_t_s=5.0)),
    (FaultFlag.RATE, _inputs(0.12, wheel_rx_flags=1 << FaultFlag.RATE)),
    (FaultFlag.SEQUENCE, _inputs(0.12, object_rx_flags=1 << FaultFlag.SEQUENCE)),
    (FaultFlag.FOREIGN_OVERRIDE, _inputs(0.12, node_flags=1 << FaultFlag.FOREIGN_OVERRIDE)),
], ids=lambda v: v.name if isinstance(v, FaultFlag) else "")
def test_each_check_flags_and_faults(flag, inputs):
    _, out = step(_settled(), inputs, P)
    assert out.fault_flags & (1 << flag)
    assert out.mode == Mode.FAULT and out.throttle_limit_pct == 0.0


def test_plausible_inputs_raise_nothing():
    """ABS braking spreads the wheels (not checked while braking); a slower radar closing speed is fine."""
    _, out = step(_settled(), _inputs(0.12, wheels=(20.0, 12.0, 20.0, 5.0), brake=1.0, accel=0.0), P)
    assert out.fault_flags == 0
    _, out = step(_settled(), _inputs(0.12, range_m=100.0, rate=-5.0), P)  # an object ahead moving away
    assert out.fault_flags == 0


def test_oncoming_traffic_in_the_next_lane_is_not_a_speed_radar_fault():
    """Only an object in our path is compared with our speed (ecu.core.relevance)."""
    oncoming = _inputs(0.12, range_m=100.0, rate=-45.0)._replace(object_lateral_m=3.5)
    _, out = step(_settled(), oncoming, P)
    assert out.fault_flags == 0 and out.mode == Mode.STANDBY


#: the DBC's size class of a car (Track<i>SizeClass)
CAR = next(v for v, name in enumeration("RadarTrack0", "Track0SizeClass").items() if name == "CAR")


def _head_on(wheel_speed, true_speed=20.0):
    """An oncoming car in our path 60 m ahead at 15 m/s, and a car parked beside the road 30 m ahead, seen by a
    radar while we go ``true_speed``; our wheels read ``wheel_speed``."""
    tracks = (Track(1, CAR, 7, 60.0, 0.0, -(true_speed + 15.0), 0.0),
              Track(2, CAR, 7, 30.0, -2.9, -true_speed, 0.0))
    return _inputs(0.12, speed=wheel_speed, range_m=60.0, rate=-(true_speed + 15.0), tracks=tracks)


def test_an_oncoming_car_in_our_path_is_not_a_speed_radar_fault_when_the_ground_confirms_our_speed():
    """The parked car closes at our wheel speed: the wheels agree with the radar, so the in-path object that
    closes 15 m/s faster moves toward us (ecu.core.plausibility.ground_confirms)."""
    _, out = step(_settled(), _head_on(20.0), P)
    assert not out.fault_flags & (1 << FaultFlag.SPEED_RADAR)
    assert out.mode != Mode.FAULT


def test_wheels_that_read_wrong_are_still_caught_beside_standing_objects():
    """Wheels forged 8 m/s low: the parked car closes at the true 20 m/s, confirms nothing, SPEED_RADAR."""
    low = lambda t: _inputs(t, speed=12.0, range_m=200.0)  # noqa: E731
    _, out = step(_settled(low), _head_on(12.0), P)
    assert out.fault_flags & (1 << FaultFlag.SPEED_RADAR) and out.mode == Mode.FAULT


def test_auth_failures_are_reported_but_do_not_fault():
    """A rejected forged frame leaves the authenticated stream trustworthy: flag, no FAULT."""
    _, out = step(_settled(), _inputs(0.12, node_flags=1 << FaultFlag.AUTH), P)
    assert out.fault_flags == 1 << FaultFlag.AUTH and out.mode == Mode.STANDBY


def test_degraded_mode_brakes_from_the_radar_when_the_wheels_are_invalid():
    """Wheels forged to 0 km/h: the speed estimate says stopped, the radar says closing at 25 m/s."""
    forged = _inputs(0.12, wheels=(0.0,) * 4, range_m=40.0, rate=-25.0, accel=1.0,
                     wheel_rx_flags=1 << FaultFlag.RATE)
    _, out = step(_settled(lambda t: _inputs(t, speed=25.0, range_m=200.0)), forged, P)
    assert out.mode == Mode.FAULT and out.throttle_limit_pct == 0.0
    assert out.brake_decel_request_mps2 == P.contingency_decel_mps2


def test_degraded_mode_never_brakes_from_an_invalid_track():
    bad_track = _inputs(0.12, range_m=10.0, object_rx_flags=1 << FaultFlag.RATE,
                        wheel_rx_flags=1 << FaultFlag.SEQUENCE)
    _, out = step(_settled(), bad_track, P)
    assert out.mode == Mode.FAULT and out.brake_decel_request_mps2 == 0.0


def test_degraded_mode_ignores_a_far_obstacle():
    far = _inputs(0.12, range_m=150.0, wheel_rx_flags=1 << FaultFlag.RATE)
    _, out = step(_settled(), far, P)
    assert out.mode == Mode.FAULT and out.brake_decel_request_mps2 == 0.0


def _wheels(counter):
    return encode("WheelSpeeds", {f"WheelSpeed{w}": 72.0 for w in ("FL", "FR", "RL", "RR")}, counter)


def test_rate_too_fast_within_100_ms_and_clear_a_window_later():
    rx = Receiver(names=["WheelSpeeds"])
    seq = CounterSequence()
    for k in range(20):
        rx.receive(_wheels(seq.next()), k * 0.01)
    assert rx.rx_flags("WheelSpeeds", 0.19) == 0
    flagged = None
    for k in range(20, 40):  # three times the rate, counters in sequence (a flood from one sender)
        for _ in range(3):
            rx.receive(_wheels(seq.next()), k * 0.01)
        if flagged is None and rx.rx_flags("WheelSpeeds", k * 0.01) & RX_RATE:
            flagged = k * 0.01
    assert flagged is not None and flagged - 0.20 <= 0.1 + 1e-9
    for k in range(40, 70):  # back to one per cycle: clear once a whole window has no excess
        rx.receive(_wheels(seq.next()), k * 0.01)
    assert rx.rx_flags("WheelSpeeds", 0.69) & RX_RATE == 0


def test_a_burst_after_a_stalled_sender_is_not_too_fast():
    """A host stall of 100 ms, then the sender's ten overdue frames at once: no rate fault."""
    rx = Receiver(names=["WheelSpeeds"])
    seq = CounterSequence()
    for k in range(20):
        rx.receive(_wheels(seq.next()), k * 0.01)
    for _ in range(11):
        rx.receive(_wheels(seq.next()), 0.30)
    for k in range(31, 40):
        rx.receive(_wheels(seq.next()), k * 0.01)
        assert rx.rx_flags("WheelSpeeds", k * 0.01) == 0


def test_rate_too_slow():
    rx = Receiver(names=["WheelSpeeds"])
    seq = CounterSequence()
    for k in range(0, 60, 3):  # one frame per 30 ms: never a 50 ms timeout, but under half the rate
        rx.receive(_wheels(seq.next()), k * 0.01)
    assert rx.rx_flags("WheelSpeeds", 0.57) & RX_RATE


def test_node_flags_a_foreign_safety_override_and_reports_it_in_ecu_status():
    channel = f"fo-{uuid.uuid4().hex[:8]}"
    with can.Bus(interface="virtual", channel=channel) as ecu_bus, \
            can.Bus(interface="virtual", channel=channel) as tester:
        node = EcuNode(ecu_bus, EcuConfig())
        tester.send(encode("SafetyOverride", {"Mode": 0, "OverrideActive": 0, "ThrottleLimit": 100.0,
                                              "BrakeDecelRequest": 0.0}, 0))
        out = node.step(0.0)
        assert out.fault_flags & (1 << FaultFlag.FOREIGN_OVERRIDE)
        status = Receiver(names=["EcuStatus"])
        frames = [status.receive(m) for m in iter(lambda: tester.recv(timeout=0.0), None)]
        assert any(f is not None and f.signals["FaultForeignOverride"] == 1 for f in frames)
        assert node.stats["foreign_overrides"] == 1
