"""The ECU and the rear corner radars' frames (``CornerTrack0..3``), as its equipment says: an ECU whose vehicle
has them fitted (``planar_corner``) checks, counts and latches them after the forward slots, so a car beside it
(x < 0) reaches the stopping region as a track like the others; a forged one (wrong MAC) is refused; an ECU
without them (``planar``) takes none (each an unknown frame, nothing latched)."""

import uuid

import can
import pytest

from can_dbc import CounterSequence, SecOcSender, encode
from can_dbc.planar import CORNER_SLOTS, TRACK_SLOTS, Track, track_signals
from ecu import EcuConfig, EcuNode

KEY = bytes(range(16))
BESIDE = Track(5, 4, 7, -2.5, 2.625, 0.2, -0.5)  # a car on our left, level with our middle, closing slowly


def _inputs(k: int, seqs: dict) -> list[can.Message]:
    frames = [encode("WheelSpeeds", {f"WheelSpeed{w}": 36.0 for w in ("FL", "FR", "RL", "RR")}, seqs["w"].next()),
              encode("DriverInput", {"AccelPedal": 30.0, "BrakePedal": 0.0, "SteeringWheelAngle": 0.0,
                                     "SteeringWheelRate": 0.0}, seqs["d"].next()),
              encode("EscDynamics", {"YawRate": 0.0, "LateralAccel": 0.0, "LongitudinalAccel": 0.0}, seqs["e"].next())]
    if k % 5 == 0:
        frames.append(encode("ObjectTrack", {"ObjectValid": 0, "ObjectRange": 0.0, "ObjectRangeRate": 0.0,
                                             "ObjectLateral": 0.0}, seqs["o"].next()))
        frames += [encode(name, track_signals(None, slot), seqs[name].next()) for name, slot in TRACK_SLOTS.items()]
        frames += [encode(name, track_signals(BESIDE if slot == 9 else None, slot), seqs[name].next())
                   for name, slot in CORNER_SLOTS.items()]
    return frames


def _drive(equipment: str, forge: bool = False) -> EcuNode:
    """20 cycles to an ECU of ``equipment``, every frame authenticated (``forge``: the corner frames' MACs
    flipped, as an attacker without the key would send them)."""
    seqs = {key: CounterSequence() for key in ("w", "d", "e", "o", *TRACK_SLOTS, *CORNER_SLOTS)}
    signer, channel = SecOcSender(KEY), f"corner-{uuid.uuid4().hex[:8]}"
    with can.Bus(interface="virtual", channel=channel) as ecu_bus, \
            can.Bus(interface="virtual", channel=channel) as tester:
        node = EcuNode(ecu_bus, EcuConfig(equipment=equipment), key=KEY)
        for k in range(20):
            for msg in _inputs(k, seqs):
                auth = signer.authenticator(msg)
                if forge and msg.arbitration_id in {0x0D2, 0x0D4, 0x0D6, 0x0D8}:
                    auth.data[7] ^= 0xFF
                tester.send(msg)
                tester.send(auth)
            node.step(k * 0.01)
            while tester.recv(timeout=0.0) is not None:
                pass
    return node


def test_a_corner_equipped_ecu_latches_the_car_beside_it():
    node = _drive("planar_corner")
    latch = node._latch
    assert latch.tracks[CORNER_SLOTS["CornerTrack1"]] == BESIDE
    assert all(t is None for i, t in enumerate(latch.tracks) if i != 9)
    # every frame accepted: 20 x (wheels, driver, ESC) + 4 x (ObjectTrack + 8 forward + 4 corner slots)
    assert node.stats["good"] == 20 * 3 + 4 * 13 == node.stats["authenticated"]
    assert latch.live_tracks(0.19, 1.0) == (BESIDE,)


def test_forged_corner_frames_are_refused():
    node = _drive("planar_corner", forge=True)
    assert node._latch.tracks[9] is None
    # the forward frames taken, every corner frame refused for its MAC (4 slots x 4 reports)
    assert node.stats["good"] == 20 * 3 + 4 * 9 == node.stats["authenticated"]
    assert node.stats["AuthError"] == 4 * 4


@pytest.mark.parametrize("equipment", ["planar", "planar_steering"])
def test_without_corner_radars_the_frames_are_not_taken(equipment):
    node = _drive(equipment)
    assert node._latch.tracks[9] is None
    assert node.stats["UnknownFrame"] == 2 * 4 * 4  # four corner slots and their authenticators, 4 reports
