"""Finding 2: a low-rate forger of SafetyOverride.

Before issue 15, one forged braking frame (counter + 1) every 4 cycles gave full
phantom braking in 988 of 2,000 cycles at the real-time gateway with no
``second_ecu`` event, and a forged pass-through frame after every 4th genuine one
caused a collision. With SecOC the gateway obeys only authenticated overrides:
forged ones are rejected, counted and reported, the genuine ECU stays in control,
and the run exits non-zero.
"""

import os

import pytest

from can_dbc import LAYOUTS, CounterSequence, encode

try:
    from can_dbc import SecOcSender
except ImportError:  # the code before issue 15: the attack runs against E2E alone
    SecOcSender = None
from cosim.scenarios.config import GatewayConfig
from cosim.world.driver_models import Pedals
from cosim.world.gateway import Gateway

from .attacks import attacked_run

OVERRIDE_ID = LAYOUTS["SafetyOverride"].frame_id
LIMIT = {"Mode": 1, "OverrideActive": 1, "ThrottleLimit": 50.0, "BrakeDecelRequest": 0.0}
BRAKE = {"Mode": 2, "OverrideActive": 1, "ThrottleLimit": 0.0, "BrakeDecelRequest": 15.0}
PASS = {"Mode": 0, "OverrideActive": 0, "ThrottleLimit": 100.0, "BrakeDecelRequest": 0.0}


def _gateway(key):
    try:
        return Gateway(GatewayConfig(), conflict_window_cycles=10, key=key)
    except TypeError:  # the code before issue 15 has no key
        return Gateway(GatewayConfig(), conflict_window_cycles=10)


def _forged_auth(msg):
    """The attacker's best guess at an authenticator: random bytes at the right ID."""
    return encode_raw(msg.arbitration_id + 1, os.urandom(8))


def encode_raw(arbitration_id, data):
    import can
    return can.Message(arbitration_id=arbitration_id, data=data, is_extended_id=False)


def test_gateway_obeys_only_authenticated_overrides():
    key = os.urandom(16)
    signer = SecOcSender(key) if SecOcSender else None
    gw = _gateway(key)
    counters = CounterSequence()
    phantom = limited = 0
    for cycle in range(2000):
        t_s = cycle * 0.01
        genuine = encode("SafetyOverride", LIMIT, counters.next())
        frames = [genuine, signer.authenticator(genuine)] if signer else [genuine]
        if cycle % 4 == 3:  # the forger: counter + 1, right after the genuine frame
            forged = encode("SafetyOverride", BRAKE, ((genuine.data[1] & 0x0F) + 1) % 15)
            frames += [forged, _forged_auth(forged)]
        for msg in frames:
            gw.offer(msg, t_s)
        act = gw.actuation(Pedals(accel_pct=100.0, brake_pct=0.0), t_s)
        phantom += act.brake > 0.5
        limited += act.throttle == pytest.approx(0.5)
    assert phantom == 0
    assert limited >= 1998  # the genuine ECU stays in control (the first cycle has no override yet)
    kinds = [e.kind for e in gw.events]
    assert "auth_failure" in kinds and "second_ecu" not in kinds
    assert gw.auth_failures == 500


@pytest.mark.slow
def test_forged_pass_through_after_every_4th_genuine_frame_with_authentication(plant_fmu3):
    seen = {"n": 0}

    def forger(t_s, cycle, genuine):
        out = []
        for msg in genuine:
            if msg.arbitration_id == OVERRIDE_ID:
                seen["n"] += 1
                if seen["n"] % 4 == 0:
                    forged = encode("SafetyOverride", PASS, ((msg.data[1] & 0x0F) + 1) % 15)
                    out += [forged, _forged_auth(forged)]
        return out

    rec = attacked_run(plant_fmu3, "tightening", authenticate=True, to_gateway=forger)
    assert not rec.metrics.collided, f"collided at {rec.metrics.impact_speed_mps} m/s"
    kinds = {e.kind for e in rec.events}
    assert "auth_failure" in kinds and "second_ecu" not in kinds
    assert "ecu_security_fault" in kinds  # the ECU saw a SafetyOverride it did not send
