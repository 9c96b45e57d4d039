"""10^5 fuzzed frames against an authenticating receiver: none forged, replayed or corrupted is accepted.

A seeded generator plays an attacker that knows the contract (valid CRCs and
counters) and has recorded genuine traffic, but not the key. Genuine
authenticated frames keep flowing in between and must still get through.
"""

import random

import can

from can_dbc import AUTHENTICATORS, LAYOUTS, CounterSequence, Receiver, SecOcSender, SecOcVerifier, encode
from can_dbc.crc import e2e_p01_crc

ATTACK_FRAMES = 100_000
NAMES = ("WheelSpeeds", "DriverInput", "ObjectTrack", "SimClock")


def _signals(name, rng):
    if name == "WheelSpeeds":
        return {f"WheelSpeed{w}": rng.uniform(0, 200) for w in ("FL", "FR", "RL", "RR")}
    if name == "DriverInput":
        return {"AccelPedal": rng.uniform(0, 100), "BrakePedal": rng.uniform(0, 100),
                "SteeringWheelAngle": 0.0, "SteeringWheelRate": 0.0}
    if name == "ObjectTrack":
        return {"ObjectValid": 1, "ObjectRange": rng.uniform(0, 250), "ObjectRangeRate": rng.uniform(-50, 50),
                "ObjectLateral": 0.0}
    return {"SimTimeMs": rng.randrange(1 << 32)}


def _raw(arbitration_id, data):
    return can.Message(arbitration_id=arbitration_id, data=bytes(data), is_extended_id=False)


def _flip(msg, rng):
    data = bytearray(msg.data)
    data[rng.randrange(len(data))] ^= 1 << rng.randrange(8)
    return _raw(msg.arbitration_id, data)


class Attacker:
    def __init__(self, rng, recorded, signer):
        self.rng, self.recorded, self.signer = rng, recorded, signer
        self.counters = {name: CounterSequence() for name in NAMES}

    def frames(self, live):
        """One attack: a list of frames (each one counts as a fuzzed frame)."""
        rng = self.rng
        kind = rng.randrange(5)
        name = rng.choice(NAMES)
        if kind == 0:  # forged frame, valid E2E, with a guessed authenticator
            msg = encode(name, _signals(name, rng), self.counters[name].next())
            return [msg, _raw(AUTHENTICATORS[name], rng.randbytes(8))]
        if kind == 1:  # replay of a recorded genuine pair
            return list(rng.choice(self.recorded))
        if kind == 2:  # a genuine pair corrupted in flight (the live sender's FV and counter advance)
            msg = encode(name, _signals(name, rng), live[name].next())
            auth = self.signer.authenticator(msg)
            return [_flip(msg, rng), auth] if rng.random() < 0.5 else [msg, _flip(auth, rng)]
        if kind == 3:  # random data at a protected or an authenticator ID, CRC sealed half the time
            fid = rng.choice([LAYOUTS[name].frame_id, AUTHENTICATORS[name]])
            data = bytearray(rng.randbytes(8))
            if rng.random() < 0.5:
                data[0] = e2e_p01_crc(fid, data)
            return [_raw(fid, data)]
        return [_raw(AUTHENTICATORS[name], rng.randbytes(8))]  # a lone authenticator


def test_no_forged_replayed_or_corrupted_frame_is_accepted():
    rng = random.Random(15)
    key = rng.randbytes(16)
    signer = SecOcSender(key)
    rx = Receiver(names=NAMES, secoc=SecOcVerifier(key))
    live = {name: CounterSequence() for name in NAMES}
    recorded = []
    genuine_sent = genuine_ok = attacked = 0
    attacker = Attacker(rng, recorded, signer)
    while attacked < ATTACK_FRAMES:
        name = rng.choice(NAMES)
        msg = encode(name, _signals(name, rng), live[name].next())
        auth = signer.authenticator(msg)
        assert rx.receive(msg) is None
        frame = rx.receive(auth)
        genuine_sent += 1
        if frame is not None:
            assert frame.name == name and frame.counter == msg.data[1] & 0x0F
            genuine_ok += 1
        if len(recorded) < 500:
            recorded.append((msg, auth))
        for bad in attacker.frames(live):
            attacked += 1
            assert rx.receive(bad) is None, f"accepted an attacker's frame {bad}"
    assert attacked >= ATTACK_FRAMES
    rejected = rx.stats["AuthError"] + rx.stats["FreshnessError"]
    assert rejected >= ATTACK_FRAMES // 3
    # the genuine stream survives the attack, apart from frames resynchronising after a corrupted one
    assert genuine_ok >= 0.7 * genuine_sent
