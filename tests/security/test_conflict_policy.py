"""Issue 25, item 2: what the gateway applies while the sender of ``SafetyOverride`` is in doubt.

The policy (``cosim/world/gateway.py``, argued in ``docs/security.md``): the most
restrictive demand of every structurally valid override of the last ``override_timeout_s``
(lowest throttle limit, highest brake request). A forger's pass-through frame can
therefore never release the genuine ECU's limit or braking; its braking frame is obeyed
(the price, reported as ``second_ecu``).
"""

from __future__ import annotations

import pytest

from can_dbc import CounterSequence, encode
from cosim.scenarios.config import GatewayConfig
from cosim.world.driver_models import Pedals
from cosim.world.gateway import CONFLICT_HOLD_S, Gateway

FULL_DECEL = 12.0
BRAKE = {"Mode": 2, "OverrideActive": 1, "ThrottleLimit": 0.0, "BrakeDecelRequest": 6.0}
LIMIT = {"Mode": 1, "OverrideActive": 1, "ThrottleLimit": 30.0, "BrakeDecelRequest": 0.0}
PASS = {"Mode": 0, "OverrideActive": 0, "ThrottleLimit": 100.0, "BrakeDecelRequest": 0.0}
DRIVER = Pedals(accel_pct=100.0, brake_pct=0.0)  # the inattentive driver: full throttle


def _gateway(window: int) -> Gateway:
    return Gateway(GatewayConfig(brake_full_decel_mps2=FULL_DECEL), conflict_window_cycles=window)


def _run(window: int, cycles: int, frames_of):
    """Feed ``frames_of(cycle)`` each 10 ms cycle; returns the gateway and the actuation of each cycle."""
    gw, applied = _gateway(window), []
    for cycle in range(cycles):
        t_s = cycle * 0.01
        for msg in frames_of(cycle):
            gw.offer(msg, t_s)
        applied.append(gw.actuation(DRIVER, t_s))
    return gw, applied


def _forger_after_every_third(genuine_signals, forged_signals):
    """The genuine ECU's frame each cycle; after every third, a forged one with the next counter."""
    seq = CounterSequence()

    def frames_of(cycle):
        genuine = encode("SafetyOverride", genuine_signals, seq.next())
        if cycle % 3 != 2:
            return [genuine]
        return [genuine, encode("SafetyOverride", forged_signals, ((genuine.data[1] & 0x0F) + 1) % 15)]
    return frames_of


#: the cycles in which the forger's pass-through is obeyed: none in lock-step (two overrides in a cycle prove
#: a second sender at once); in real time the first forged frame's cycle, before anything marks it (the stated
#: residual risk of docs/security.md), and none after it
OBEYED = {1: [], 10: [2]}


@pytest.mark.parametrize("window", [1, 10], ids=["lock-step", "real time"])
def test_a_forged_pass_through_never_releases_the_genuine_braking(window):
    gw, applied = _run(window, 300, _forger_after_every_third(BRAKE, PASS))
    assert [e.kind for e in gw.events][:1] == ["second_ecu"]
    braked = [a.throttle == 0.0 and a.brake == pytest.approx(0.5) for a in applied]
    assert [i for i, ok in enumerate(braked) if not ok] == OBEYED[window]
    assert gw.contingency_invocations == 1  # the ECU's one contingency, however the frames interleave


@pytest.mark.parametrize("window", [1, 10], ids=["lock-step", "real time"])
def test_a_forged_pass_through_never_lifts_the_genuine_throttle_limit(window):
    gw, applied = _run(window, 300, _forger_after_every_third(LIMIT, PASS))
    limited = [a.throttle == pytest.approx(0.3) and a.brake == 0.0 for a in applied]
    assert [i for i, ok in enumerate(limited) if not ok] == OBEYED[window]
    assert "second_ecu" in [e.kind for e in gw.events]


def test_the_price_a_forged_brake_request_is_obeyed_and_reported():
    """The trade-off chosen: during a conflict phantom braking is possible (missed braking is not)."""
    gw, applied = _run(1, 300, _forger_after_every_third(PASS, BRAKE))
    assert [e.kind for e in gw.events] == ["second_ecu"]
    assert sum(a.brake > 0.0 for a in applied) >= 290  # braked from the first forged frame on
    assert gw.mode == "SECOND_ECU"


def test_two_independent_senders_whose_counters_jump_still_give_the_most_restrictive():
    """Counters 7 apart: every frame jumps (a CounterError), yet each is a valid demand (can_dbc.check_alone)."""
    a, b = CounterSequence(), CounterSequence(start=7)
    gw, applied = _run(1, 200, lambda cycle: [encode("SafetyOverride", LIMIT, a.next()),
                                               encode("SafetyOverride", BRAKE if cycle >= 100 else PASS, b.next())])
    assert gw.stats.get("CounterError", 0) > 100
    assert all(x.throttle == pytest.approx(0.3) and x.brake == 0.0 for x in applied[1:100])
    assert all(x.throttle == 0.0 and x.brake == pytest.approx(0.5) for x in applied[100:])


def test_a_flood_of_pass_through_frames_does_not_push_the_braking_out():
    seq, forged = CounterSequence(), CounterSequence(start=3)

    def frames_of(cycle):
        return [encode("SafetyOverride", BRAKE, seq.next())] + [
            encode("SafetyOverride", PASS, forged.next()) for _ in range(50)]
    gw, applied = _run(10, 50, frames_of)
    assert all(a.brake == pytest.approx(0.5) and a.throttle == 0.0 for a in applied)


def test_corrupted_frames_are_no_demand_and_silence_still_falls_back_to_the_driver():
    a, b = CounterSequence(), CounterSequence()  # two senders in step: the repeats give them away

    def frames_of(cycle):
        if cycle < 20:
            return [encode("SafetyOverride", LIMIT, a.next()), encode("SafetyOverride", LIMIT, b.next())]
        bad = encode("SafetyOverride", BRAKE, a.next())
        bad.data[0] ^= 0xFF  # a broken CRC: never a demand
        return [bad]
    gw, applied = _run(1, 40, frames_of)
    assert gw.conflict and [e.kind for e in gw.events] == ["second_ecu", "override_timeout"]
    assert all(x.brake == 0.0 for x in applied)  # the corrupted braking frames were never obeyed
    assert all(x.throttle == pytest.approx(0.3) for x in applied[:25])  # the limit held for 50 ms ...
    assert applied[-1].throttle == 1.0  # ... then no valid frame: driver only, as after any timeout


def test_when_the_second_sender_stops_the_genuine_ecu_alone_is_obeyed_again():
    seq = CounterSequence()

    def frames_of(cycle):
        genuine = encode("SafetyOverride", BRAKE if cycle < 150 else PASS, seq.next())
        if cycle < 50 and cycle % 3 == 2:
            return [genuine, encode("SafetyOverride", PASS, ((genuine.data[1] & 0x0F) + 1) % 15)]
        return [genuine]
    gw, applied = _run(1, 400, frames_of)
    kinds = [(e.kind, round(e.t_s, 2)) for e in gw.events]
    assert kinds[0][0] == "second_ecu" and kinds[1][0] == "override_restored"
    # the last forged frame at 0.47 s; the genuine frames then resynchronise (a repeat at 0.48 s, then
    # 0.49 and 0.50 s still out of sync): 1 s after that last sign of a second sender
    assert kinds[1][1] == pytest.approx(0.50 + CONFLICT_HOLD_S)
    assert all(a.brake == pytest.approx(0.5) for a in applied[:150])
    # the genuine ECU's release at 1.50 s: within its sender's doubt the window's braking holds 50 ms longer
    assert all(a.brake == 0.0 and a.throttle == 1.0 for a in applied[156:])
