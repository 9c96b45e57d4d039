"""The codec's and the receiver's memos of repeated payloads change no frame and no verdict.

A frame whose signals repeat the last frame's of its message is built from the payload remembered for
its counter (``can_dbc.codec._LAST``); a payload seen before skips the CRC and the decode
(``can_dbc.receiver._DECODED``). Both must give exactly what the work they skip would give.
"""

from __future__ import annotations

import math

import pytest

import can_dbc.codec as codec
import can_dbc.receiver as receiver
from can_dbc import ChecksumError, Receiver, SignalError, encode
from can_dbc.counter import COUNTER_MODULUS
from can_dbc.planar import track_signals

WHEELS = {"WheelSpeedFL": 50.0, "WheelSpeedFR": 50.25, "WheelSpeedRL": 49.75, "WheelSpeedRR": 50.0}


def _cold(name: str, signals: dict, counter: int) -> bytes:
    """The frame as a codec without a memo builds it."""
    codec._LAST.pop(name, None)
    return bytes(encode(name, signals, counter).data)


@pytest.mark.parametrize("name, signals", [("WheelSpeeds", WHEELS), ("RadarTrack3", track_signals(None, 3))])
def test_repeated_signals_give_the_frames_of_a_cold_encode(name: str, signals: dict) -> None:
    cold = [_cold(name, signals, k % COUNTER_MODULUS) for k in range(2 * COUNTER_MODULUS)]
    codec._LAST.pop(name, None)
    warm = [bytes(encode(name, dict(signals), k % COUNTER_MODULUS).data) for k in range(2 * COUNTER_MODULUS)]
    assert warm == cold
    changed = dict(WHEELS, WheelSpeedFL=60.0) if name == "WheelSpeeds" else track_signals(None, 3)
    assert bytes(encode(name, changed, 4).data) == _cold(name, changed, 4)


def test_a_caller_mutating_its_dict_after_encoding_does_not_change_the_next_frame() -> None:
    signals = dict(WHEELS)
    encode("WheelSpeeds", signals, 1)
    signals["WheelSpeedFL"] = 70.0
    assert bytes(encode("WheelSpeeds", signals, 2).data) == _cold("WheelSpeeds", signals, 2)


def test_bad_values_and_counters_still_raise_after_good_frames() -> None:
    encode("WheelSpeeds", WHEELS, 1)
    with pytest.raises(SignalError, match="WheelSpeedFL"):
        encode("WheelSpeeds", dict(WHEELS, WheelSpeedFL=math.nan), 2)
    with pytest.raises(SignalError, match="counter"):
        encode("WheelSpeeds", WHEELS, COUNTER_MODULUS)


def test_a_corrupted_copy_of_a_remembered_payload_is_rejected() -> None:
    rx = Receiver(names=["WheelSpeeds"])
    good = [encode("WheelSpeeds", WHEELS, k) for k in range(3)]
    for msg in good:
        assert rx.check(msg).signals == pytest.approx(WHEELS, abs=0.01)
    bad = encode("WheelSpeeds", WHEELS, 3)
    bad.data[0] ^= 0x01  # CRC byte flipped: not a payload seen before
    with pytest.raises(ChecksumError):
        rx.check(bad)
    assert rx.stats["ChecksumError"] == 1


def test_the_decode_memo_is_bounded() -> None:
    rx = Receiver(names=["WheelSpeeds"])
    for k in range(3 * receiver._DECODED_MAX):
        rx.check(encode("WheelSpeeds", dict(WHEELS, WheelSpeedFL=k * 0.1), k % COUNTER_MODULUS))
    assert 0 < len(receiver._DECODED[0x0A0]) <= receiver._DECODED_MAX
