"""The ECU and the planar frames, as its equipment says (ecu.equipment): equipped with the planar
sensors it receives, checks and counts EscDynamics and the RadarTrack slots (latching them in SI for
the stopping region, ecu.core.planar); with steering authority it sends SteeringOverride every cycle
(pass-through, SteerActive 0, unless a steering contingency is held), authenticated when keyed. A
longitudinal ECU (the default) takes neither planar frame (each counted as an unknown frame, nothing
latched) and sends no SteeringOverride; a planar ECU without steering authority takes them and sends none
either."""

import math
import uuid

import can
import pytest

from can_dbc import LAYOUTS, LAYOUTS_BY_ID, CounterSequence, Receiver, SecOcSender, SecOcVerifier, encode
from can_dbc.planar import CORNER_SLOTS, TRACK_SLOTS, EscDynamics, Track, esc_signals, track_signals
from ecu import EcuConfig, EcuNode

KEY = bytes(range(16))
TRACK = Track(9, 2, 7, 14.25, -1.5, -6.0, 1.25)


def _inputs(k, seqs):
    frames = [encode("WheelSpeeds", {f"WheelSpeed{w}": 36.0 for w in ("FL", "FR", "RL", "RR")}, seqs["w"].next()),
              encode("DriverInput", {"AccelPedal": 30.0, "BrakePedal": 0.0, "SteeringWheelAngle": -45.0,
                                     "SteeringWheelRate": 10.0}, seqs["d"].next()),
              encode("EscDynamics", esc_signals(EscDynamics(0.25, 2.5, -1.0)), seqs["e"].next())]
    if k % 5 == 0:
        frames.append(encode("ObjectTrack", {"ObjectValid": 0, "ObjectRange": 0.0, "ObjectRangeRate": 0.0,
                                             "ObjectLateral": 0.0}, seqs["o"].next()))
        frames += [encode(name, track_signals(TRACK if slot == 1 else None, slot), seqs[name].next())
                   for name, slot in TRACK_SLOTS.items()]
    return frames


def _drive(equipment: str) -> tuple[EcuNode, list[can.Message]]:
    """20 cycles of the planar inputs, each authenticated, to an ECU of ``equipment``; the node and its frames."""
    seqs = {key: CounterSequence() for key in ("w", "d", "e", "o", *TRACK_SLOTS)}
    signer, channel = SecOcSender(KEY), f"planar-{uuid.uuid4().hex[:8]}"
    sent = []
    with can.Bus(interface="virtual", channel=channel) as ecu_bus, \
            can.Bus(interface="virtual", channel=channel) as tester:
        node = EcuNode(ecu_bus, EcuConfig(equipment=equipment), key=KEY)
        for k in range(20):
            for msg in _inputs(k, seqs):
                tester.send(msg)
                tester.send(signer.authenticator(msg))
            node.step(k * 0.01)
            while (m := tester.recv(timeout=0.0)) is not None:
                sent.append(m)
    return node, sent


def _sent_names(sent: list[can.Message]) -> set[str]:
    return {LAYOUTS_BY_ID[m.arbitration_id].name for m in sent if m.arbitration_id in LAYOUTS_BY_ID}


def test_ecu_receives_the_planar_frames_and_sends_steering_pass_through():
    node, sent = _drive("planar_steering")
    latch = node._latch
    assert latch.esc == pytest.approx(EscDynamics(0.25, 2.5, -1.0), abs=1e-4)  # yaw rate: 0.01 deg/s steps
    assert latch.tracks[1] == TRACK and latch.tracks[0] is None and latch.tracks[7] is None
    assert latch.steering_wheel_rad == pytest.approx(math.radians(-45.0))
    stats = node.stats
    # every frame accepted: 20 x (wheels, driver, ESC) + 4 x (ObjectTrack + 8 slots), all authenticated
    assert stats["good"] == 20 * 3 + 4 * 9 == stats["authenticated"]
    assert set(stats) <= {"good", "authenticated", "gate_interventions", "cycles"}
    rx = Receiver(names=["SteeringOverride"], secoc=SecOcVerifier(KEY))
    steering = [f for f in (rx.check(m) for m in sent if m.arbitration_id in (0x094, 0x095)) if f is not None]
    assert len(steering) == 20 and rx.stats["authenticated"] == 20
    assert all(f.signals == {"SteerActive": 0, "SteerAngleRequest": 0.0} for f in steering)
    assert LAYOUTS["SteeringOverride"].frame_id == 0x094
    assert _sent_names(sent) == {"SafetyOverride", "SteeringOverride", "EcuStatus", "EcuRegionStatus"}


@pytest.mark.parametrize("equipment, sensors", [("longitudinal", False), ("planar", True)])
def test_the_frames_follow_the_equipment(equipment, sensors):
    """planar: the planar frames taken, no SteeringOverride sent; longitudinal: neither (``sensors``: whether
    the ECU is equipped with the planar sensors, so takes EscDynamics and the slots)."""
    node, sent = _drive(equipment)
    stats, latch = node.stats, node._latch
    # no SteeringOverride without authority; the region's status with the planar sensors
    assert _sent_names(sent) == {"SafetyOverride", "EcuStatus", *(["EcuRegionStatus"] if sensors else [])}
    assert not any(m.arbitration_id in (0x094, 0x095) for m in sent)
    if sensors:
        assert stats["good"] == 20 * 3 + 4 * 9 == stats["authenticated"] and "UnknownFrame" not in stats
        assert latch.esc is not None and latch.tracks[1] == TRACK
    else:  # the core's frames taken; every ESC and slot frame (and its authenticator) unknown, nothing latched
        assert stats["good"] == 20 * 2 + 4 == stats["authenticated"]
        assert stats["UnknownFrame"] == 2 * (20 + 4 * 8)
        assert latch.esc is None and latch.tracks == [None] * (len(TRACK_SLOTS) + len(CORNER_SLOTS))
    assert latch.steering_wheel_rad == pytest.approx(math.radians(-45.0))
