"""Issue 25, finding 1: a replayed radar frame was acted on when authentication was off.

Before: "60 replayed ObjectTrack frames: the ECU braked for the phantom object
in 5/300 cycles (first 0 ms after the first replay)". The bench: an ECU at
15 m/s sees a real stationary object for 50 ``ObjectTrack`` frames (2.5 s,
45 m down to 8 m) and records them; the object goes; 1 s later, right after
each fresh ``ObjectTrack`` (object absent) the attacker replays the recorded
frame whose E2E counter is the fresh one + 1 (the nearest such: the most
dangerous), with its recorded authenticator when the bus is keyed. Now the
ECU acts on an object only once the radar has reported it consistently
(ecu/core/track_confirmation.py): 0 braking cycles, keyed or not.

``python -m tests.security.test_issue25_replayed_track`` prints the figures.
"""

from __future__ import annotations

import os
import uuid
from typing import NamedTuple

import can
import pytest

from can_dbc import CounterSequence, SecOcSender, encode
from ecu import EcuConfig, EcuNode
from ecu.core import Mode

CYCLE_S = 0.01
TRACK_EVERY = 5  # ObjectTrack: 50 ms (DBC GenMsgCycleTime), five ECU cycles
SPEED_KMH = 54.0  # 15 m/s
RECORDED = 50
ATTACK_CYCLES = 300
INTERVENING = (Mode.TIGHTENING, Mode.CONTINGENCY)
NO_OBJECT = {"ObjectValid": 0, "ObjectRange": 0.0, "ObjectRangeRate": 0.0, "ObjectLateral": 0.0}


class Figures(NamedTuple):
    """What the ECU did: for the real object, and under the replay attack."""

    real_first_brake_s: float | None  # after the object's first report
    replays: int
    braking_cycles: int  # attack: cycles with a brake request
    intervening_cycles: int  # attack: cycles in TIGHTENING or CONTINGENCY
    fault_cycles: int
    first_brake_after_replay_s: float | None


class Bench:
    """An ECU on a virtual bus, driven in lock step: every sender's frames, then one cycle."""

    def __init__(self, strategy: str, key: bytes | None) -> None:
        self.bus = can.Bus(interface="virtual", channel=f"replay-{uuid.uuid4().hex[:8]}")
        self.node = EcuNode(self.bus, EcuConfig(strategy=strategy), key=key)
        self.signer = SecOcSender(key) if key is not None else None
        self.seq = {name: CounterSequence() for name in ("WheelSpeeds", "DriverInput", "ObjectTrack")}
        self.k = 0

    def frames(self, name: str, signals: dict) -> list[can.Message]:
        """A genuine frame of ``name`` (next counter), followed by its authenticator when keyed."""
        msg = encode(name, signals, self.seq[name].next())
        return [msg, self.signer.authenticator(msg)] if self.signer else [msg]

    def cycle(self, track: dict | None, replay=lambda fresh: []):
        """One 10 ms cycle: wheels at 15 m/s, 20 % accelerator, the track every 50 ms (``replay(fresh)``
        right after it); returns (the genuine ObjectTrack frames sent, or [], and the outputs)."""
        t_s = self.k * CYCLE_S
        sent = self.frames("WheelSpeeds", {f"WheelSpeed{w}": SPEED_KMH for w in ("FL", "FR", "RL", "RR")})
        sent += self.frames("DriverInput", {"AccelPedal": 20.0, "BrakePedal": 0.0, "SteeringWheelAngle": 0.0,
                                            "SteeringWheelRate": 0.0})
        fresh = self.frames("ObjectTrack", track) if self.k % TRACK_EVERY == 0 else []
        for msg in sent + fresh + (replay(fresh) if fresh else []):
            self.node.ingest(msg, t_s)
        self.k += 1
        return fresh, self.node.step(t_s)


def _counter(frames: list[can.Message]) -> int:
    return frames[0].data[1] & 0x0F


def _real_object(bench: Bench) -> tuple[list[list[can.Message]], float | None]:
    """Drive 2.5 s toward the object; returns its recorded frames and the first brake (s after its first
    report)."""
    recorded, first = [], None
    for n in range(RECORDED * TRACK_EVERY):
        report = n // TRACK_EVERY
        track = {"ObjectValid": 1, "ObjectRange": 45.0 - 0.75 * report, "ObjectRangeRate": -15.0,
                 "ObjectLateral": 0.0}
        fresh, out = bench.cycle(track)
        if fresh:
            recorded.append(fresh)
        if first is None and out.brake_decel_request_mps2 > 0.0:
            first = n * CYCLE_S
    return recorded, first


def replay_attack(strategy: str = "tightening", keyed: bool = False) -> Figures:
    """Finding 1 of issue 25 on the bench (see the module doc)."""
    bench = Bench(strategy, os.urandom(16) if keyed else None)
    try:
        for _ in range(100):  # 1 s without an object: the ECU settles in STANDBY
            bench.cycle(NO_OBJECT)
        recorded, real_first = _real_object(bench)
        for _ in range(100):  # the object has gone
            bench.cycle(NO_OBJECT)

        def replay(fresh):
            wanted = (_counter(fresh) + 1) % 15
            return [f for f in reversed(recorded) if _counter(f) == wanted][0]

        braking = intervening = faults = 0
        first = None
        for n in range(ATTACK_CYCLES):
            _, out = bench.cycle(NO_OBJECT, replay)
            braking += out.brake_decel_request_mps2 > 0.0
            intervening += out.mode in INTERVENING
            faults += out.mode is Mode.FAULT
            if first is None and out.brake_decel_request_mps2 > 0.0:
                first = n * CYCLE_S
        return Figures(real_first, ATTACK_CYCLES // TRACK_EVERY, braking, intervening, faults, first)
    finally:
        bench.bus.shutdown()


@pytest.mark.parametrize("keyed", [False, True], ids=["keyless", "keyed"])
@pytest.mark.parametrize("strategy", ["none", "tightening"])
def test_a_replayed_track_frame_never_brakes(strategy, keyed):
    figures = replay_attack(strategy, keyed)
    assert figures.real_first_brake_s is not None, "the real object must still be braked for"
    assert (figures.braking_cycles, figures.intervening_cycles) == (0, 0), figures


if __name__ == "__main__":
    for s in ("none", "tightening"):
        for k in (False, True):
            print(f"{s:10s} {'keyed' if k else 'keyless':7s}", replay_attack(s, k))
