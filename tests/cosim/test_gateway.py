"""Gateway: throttle = min(pedal, limit) while active, brake = max(pedal, request), timeout fallback."""

import pytest

from can_dbc import CounterSequence, encode
from cosim.world.driver_models import Pedals
from cosim.world.gateway import Gateway
from cosim.scenarios.config import GatewayConfig


def _override(counter, mode=2, active=1, limit=0.0, decel=6.0):
    return encode("SafetyOverride", {"Mode": mode, "OverrideActive": active, "ThrottleLimit": limit,
                                     "BrakeDecelRequest": decel}, counter)


def test_override_applies_min_throttle_and_max_brake():
    gw = Gateway(GatewayConfig(brake_full_decel_mps2=12.0))
    assert gw.offer(_override(0, mode=1, limit=40.0, decel=6.0), 0.0)
    act = gw.actuation(Pedals(100.0, 20.0), 0.0)
    assert act.throttle == pytest.approx(0.4) and act.brake == pytest.approx(0.5)
    act = gw.actuation(Pedals(10.0, 80.0), 0.0)
    assert act.throttle == pytest.approx(0.1) and act.brake == pytest.approx(0.8)


def test_inactive_override_passes_driver_through():
    gw = Gateway(GatewayConfig())
    gw.offer(_override(0, mode=0, active=0, limit=100.0, decel=0.0), 0.0)
    act = gw.actuation(Pedals(70.0, 0.0), 0.0)
    assert (act.throttle, act.brake) == (pytest.approx(0.7), 0.0)


def test_contingency_entries_counted_separately():
    gw = Gateway(GatewayConfig())
    seq = CounterSequence()
    for i, mode in enumerate([0, 2, 2, 0, 2, 1, 2, 2]):
        gw.offer(_override(seq.next(), mode=mode), i * 0.01)
    assert gw.contingency_invocations == 3


def test_timeout_falls_back_to_driver_and_records_events():
    gw = Gateway(GatewayConfig(override_timeout_s=0.05))
    seq = CounterSequence()
    gw.offer(_override(seq.next(), limit=0.0, decel=12.0), 0.0)
    assert gw.actuation(Pedals(100.0, 0.0), 0.04) == pytest.approx(gw.actuation(Pedals(100.0, 0.0), 0.05))
    assert gw.actuation(Pedals(100.0, 0.0), 0.05).throttle == 0.0
    act = gw.actuation(Pedals(100.0, 0.0), 0.07)  # 70 ms silent
    assert gw.fallback and act.throttle == 1.0 and act.brake == 0.0
    assert [e.kind for e in gw.events] == ["override_timeout"] and gw.mode == "NO_OVERRIDE"
    gw.offer(_override(seq.next(), limit=0.0, decel=12.0), 0.08)
    assert gw.actuation(Pedals(100.0, 0.0), 0.08).throttle == 0.0
    assert [e.kind for e in gw.events] == ["override_timeout", "override_restored"]


def test_bad_crc_frames_are_ignored():
    gw = Gateway(GatewayConfig())
    msg = _override(0, limit=0.0)
    msg.data[0] ^= 0xFF
    assert not gw.offer(msg, 0.0)
    assert gw.actuation(Pedals(100.0, 0.0), 0.0).throttle == 1.0
    assert gw.stats.get("ChecksumError") == 1


def _real_time_run(batches):
    """Feed ``batches[i]`` (a list of frames) in cycle i to a real-time gateway; return its events."""
    gw = Gateway(GatewayConfig(override_timeout_s=1.0), conflict_window_cycles=10)
    for i, frames in enumerate(batches):
        for msg in frames:
            gw.offer(msg, i * 0.01)
        gw.actuation(Pedals(100.0, 0.0), i * 0.01)
    return {e.kind: round(e.t_s, 3) for e in reversed(gw.events)}  # kind -> time of its first event


def test_real_time_bunched_frames_of_one_ecu_are_not_a_second_ecu():
    """A stalled master takes six cycles' frames at once: more than 13 in 10 cycles, but one sender."""
    seq = CounterSequence()
    batches = []
    for i in range(300):
        stalled = i % 30 in range(1, 6)
        batches.append([] if stalled else [_override(seq.next()) for _ in range(6 if i % 30 == 6 else 1)])
    assert sum(len(b) for b in batches[:40]) > 0 and max(len(b) for b in batches) == 6
    assert "second_ecu" not in _real_time_run(batches)


def test_real_time_two_senders_are_a_second_ecu():
    """Interleaved counters fail E2E (so the gateway already falls back), and the excess names the cause."""
    a, b = CounterSequence(), CounterSequence(start=7)
    batches = [[_override(a.next()), _override(b.next())] for _ in range(30)]
    assert _real_time_run(batches)["second_ecu"] <= 0.07  # 14 frames in 7 cycles


def test_real_time_two_senders_in_step_are_a_second_ecu():
    """Two ECUs started together send the same counters: the repeats give them away."""
    a, b = CounterSequence(), CounterSequence()
    batches = [[_override(a.next()), _override(b.next())] for _ in range(30)]
    assert _real_time_run(batches) == {"second_ecu": 0.06}


def test_fault_entries_counted_after_start_up_only():
    """Issue 25: the start-up FAULT (until the ECU's inputs are valid) is not an entry; each later one is."""
    gw = Gateway(GatewayConfig())
    seq = CounterSequence()
    for i, mode in enumerate([3, 3, 0, 0, 3, 3, 0, 1, 3, 0]):
        gw.offer(_override(seq.next(), mode=mode, active=0, limit=100.0, decel=0.0), i * 0.01)
    assert gw.fault_entries == 2
