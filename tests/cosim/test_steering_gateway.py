"""The steering gateway (EPS): a valid active SteeringOverride reaches the plant's steer_request
(vr 6) ramped; forged, out-of-range and out-of-rate requests are refused and counted; two
senders get the most restrictive request; silence ramps the overlay back to 0."""

import math

import can
import pytest

from can_dbc import LAYOUTS, CounterSequence, SecOcSender, encode
from can_dbc.crc import e2e_p01_crc8
from cosim.world.steering_gateway import MAX_RATE_DEGPS, SteeringGateway
from tests.fmu.plant_runner import initialise, open_plant

KEY = bytes(range(16))
CYCLE_S = 0.01


def _steer(counter: int, angle_deg: float, active: int = 1) -> can.Message:
    return encode("SteeringOverride", {"SteerActive": active, "SteerAngleRequest": angle_deg}, counter)


def _offer(gw: SteeringGateway, msg: can.Message, t_s: float, signer: SecOcSender | None) -> bool:
    held = gw.offer(msg, t_s)
    return gw.offer(signer.authenticator(msg), t_s) if signer is not None else held


def _ramp(gw, signer, cycles=20, step_deg=0.2, top_deg=2.0):
    """Requests rising at 20 deg/s (within the DBC's 23) to ``top_deg``; the overlay (rad) per cycle."""
    seq, applied = CounterSequence(), []
    for k in range(cycles):
        assert _offer(gw, _steer(seq.next(), min(top_deg, step_deg * (k + 1))), k * CYCLE_S, signer)
        applied.append(gw.steer_request_rad(k * CYCLE_S))
    return seq, applied


def test_valid_active_request_is_applied_to_the_plants_steer_request(plant_fmu3):
    gw = SteeringGateway(0.05, KEY)
    _, applied = _ramp(gw, SecOcSender(KEY))
    assert applied[-1] == pytest.approx(math.radians(2.0))
    assert gw.stats["authenticated"] == 20 and gw.stats["good"] == 20
    h = open_plant(plant_fmu3, 3)
    try:
        initialise(h, {"v0": 10.0, "steering_time_constant": 0.0})
        assert h.vrs["steer_request"] == 6
        for k, overlay_rad in enumerate(applied + [applied[-1]] * 30):
            h.set(steer_request=overlay_rad)
            h.slave.doStep(k * CYCLE_S, CYCLE_S)
        delta, yaw_rate = h.get("delta", "yaw_rate")
    finally:
        h.slave.freeInstance()
    assert delta == pytest.approx(math.radians(2.0), rel=1e-6) and yaw_rate > 0.0  # turning left


def test_forged_request_is_refused_and_counted():
    gw = SteeringGateway(0.05, KEY)
    forger = SecOcSender(bytes(16))
    assert not _offer(gw, _steer(0, 0.2), 0.0, forger)
    assert gw.steer_request_rad(0.0) == 0.0
    assert gw.stats["AuthError"] == 1 and [e.kind for e in gw.events] == ["auth_failure"]


def test_request_faster_than_the_dbc_rate_is_refused():
    gw = SteeringGateway(0.05, KEY)
    signer, seq = SecOcSender(KEY), CounterSequence()
    jump_deg = MAX_RATE_DEGPS * CYCLE_S + 0.05  # just beyond one cycle's allowance
    assert not _offer(gw, _steer(seq.next(), jump_deg), 0.0, signer)
    assert gw.steer_request_rad(0.0) == 0.0 and gw.stats["steering_rate"] == 1
    assert _offer(gw, _steer(seq.next(), 0.2), CYCLE_S, signer)  # within the rate: obeyed
    assert gw.steer_request_rad(CYCLE_S) == pytest.approx(math.radians(0.2))


def test_request_beyond_the_dbc_range_is_refused():
    gw = SteeringGateway(0.05)
    data = bytearray(((4050 << 16) | (1 << 12)).to_bytes(8, "little"))  # 40.5 deg, active, counter 0
    data[0] = e2e_p01_crc8(LAYOUTS["SteeringOverride"].crc_seed, data)
    assert not gw.offer(can.Message(arbitration_id=0x094, data=data, is_extended_id=False), 0.0)
    assert gw.stats["RangeError"] == 1 and gw.steer_request_rad(0.0) == 0.0


def test_second_sender_applies_the_most_restrictive_request():
    gw = SteeringGateway(0.05, KEY)
    signer = SecOcSender(KEY)
    seq, applied = _ramp(gw, signer, cycles=10)
    other = CounterSequence()
    for k in range(10, 40):  # a second sender's pass-through frames between the ECU's
        _offer(gw, _steer(seq.next(), 2.0), k * CYCLE_S, signer)
        _offer(gw, _steer(other.next(), 0.0, active=0), k * CYCLE_S, signer)
        applied.append(gw.steer_request_rad(k * CYCLE_S))
    assert applied[9] == pytest.approx(math.radians(2.0))
    assert applied[-1] == 0.0  # none: ramped out at the DBC rate
    assert applied[10] == pytest.approx(math.radians(2.0 - MAX_RATE_DEGPS * CYCLE_S))
    assert "steering_conflict" in {e.kind for e in gw.events}


def test_two_active_senders_get_the_smaller_angle():
    gw = SteeringGateway(0.05)
    a, b, applied = CounterSequence(), CounterSequence(), []
    for k in range(60):
        t = k * CYCLE_S
        gw.offer(_steer(a.next(), min(2.0, 0.2 * (k + 1))), t)
        gw.offer(_steer(b.next(), min(1.0, 0.2 * (k + 1))), t)
        applied.append(gw.steer_request_rad(t))
    assert applied[-1] == pytest.approx(math.radians(1.0))


def test_silence_ramps_the_overlay_back_to_zero():
    gw = SteeringGateway(0.05, KEY)
    _, applied = _ramp(gw, SecOcSender(KEY))
    later = [gw.steer_request_rad(k * CYCLE_S) for k in range(20, 45)]
    assert later[4] == pytest.approx(applied[-1])  # within the 50 ms timeout: held
    assert later[-1] == 0.0
    assert max(abs(x - y) for x, y in zip(later, later[1:])) <= math.radians(MAX_RATE_DEGPS * CYCLE_S) + 1e-12
