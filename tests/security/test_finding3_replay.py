"""Finding 3: 100 of 100 stale frames were accepted as fresh; one valid-CRC frame re-synchronised the receiver.

A recorded stream of genuine frames is replayed later. Without a key (E2E only), the
attacker picks recorded frames whose counter is the live counter + 1, so each one is
in sequence; the receiver now treats the live sender's resulting repeat as a
sequence error and needs 3 consecutive in-sequence frames before it delivers data
again, so at most the first stale frame gets through (E2E alone cannot tell it from
the live one). With SecOC, a replayed frame fails its freshness check: 0 accepted.
"""

import os

from can_dbc import CounterSequence, Receiver, encode

STALE = {"ObjectValid": 1, "ObjectRange": 200.0, "ObjectRangeRate": 0.0, "ObjectLateral": 0.0}
LIVE = {"ObjectValid": 1, "ObjectRange": 30.0, "ObjectRangeRate": -20.0, "ObjectLateral": 0.0}


def _recording(n, signer=None):
    """``n`` recorded genuine frames (each with its authenticator when signed)."""
    counters = CounterSequence()
    out = []
    for _ in range(n):
        msg = encode("ObjectTrack", STALE, counters.next())
        out.append((msg, signer.authenticator(msg) if signer else None))
    return out


def test_replay_interleaved_with_the_live_stream_keyless():
    recorded = _recording(150)
    rx = Receiver(names=["ObjectTrack"])
    live = CounterSequence()
    stale_accepted = 0
    for _ in range(100):
        msg = encode("ObjectTrack", LIVE, live.next())
        rx.receive(msg)
        wanted = ((msg.data[1] & 0x0F) + 1) % 15  # the recorded frame with the live counter + 1
        stale = next(m for m, _ in recorded if m.data[1] & 0x0F == wanted)
        frame = rx.receive(stale)
        stale_accepted += frame is not None and frame.signals["ObjectRange"] == 200.0
    assert stale_accepted <= 1


def test_replay_with_authentication_is_rejected_as_stale():
    from can_dbc import SecOcSender, SecOcVerifier
    key = os.urandom(16)
    signer = SecOcSender(key)
    recorded = _recording(100, signer)
    rx = Receiver(names=["ObjectTrack"], secoc=SecOcVerifier(key))
    for msg, auth in recorded:  # the live stream the attacker recorded: all accepted
        assert rx.receive(msg) is None and rx.receive(auth) is not None
    accepted = 0
    for msg, auth in recorded:  # replayed later, alone (no live sender to interleave with)
        accepted += rx.receive(msg) is not None
        accepted += rx.receive(auth) is not None
    assert accepted == 0
    assert rx.stats["FreshnessError"] == 100


def test_replay_interleaved_with_authentication():
    from can_dbc import SecOcSender, SecOcVerifier
    key = os.urandom(16)
    signer = SecOcSender(key)
    recorded = _recording(100, signer)
    rx = Receiver(names=["ObjectTrack"], secoc=SecOcVerifier(key))
    live = CounterSequence()
    for msg, auth in recorded:
        live_msg = encode("ObjectTrack", LIVE, live.next())
        assert rx.receive(live_msg) is None
        frame = rx.receive(signer.authenticator(live_msg))
        assert frame is not None and frame.signals["ObjectRange"] == 30.0  # the live sender is never displaced
        assert rx.receive(msg) is None and rx.receive(auth) is None  # each stale frame rejected
