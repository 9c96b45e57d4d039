"""Gateway: throttle = min(pedal, limit) while active, brake = max(pedal, request), timeout fallback."""

import pytest

from can_dbc import CounterSequence, encode
from cosim.driver_models import Pedals
from cosim.gateway import Gateway
from cosim.scenario_config import GatewayConfig


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
