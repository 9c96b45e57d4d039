"""Receiver checks in order, counters, validity score and statistics."""

import can
import pytest

from can_dbc import (
    LAYOUTS, RX_SEQUENCE,
    ChecksumError, CounterError, EnumError, LengthError, RangeError, Receiver,
    UnknownFrame, encode, e2e_p01_crc,
)

PEDALS = {"AccelPedal": 50.0, "BrakePedal": 0.0, "SteeringWheelAngle": 0.0, "SteeringWheelRate": 0.0}


def _frame(counter, **changes):
    return encode("DriverInput", {**PEDALS, **changes}, counter)


def _resealed(msg, mutate):
    data = bytearray(msg.data)
    mutate(data)
    data[0] = e2e_p01_crc(msg.arbitration_id, data)
    return can.Message(arbitration_id=msg.arbitration_id, is_extended_id=False, data=data)


def test_unknown_id_raises_in_check_and_is_counted_in_receive():
    rx = Receiver()
    stranger = can.Message(arbitration_id=0x123, is_extended_id=False, data=bytes(8))
    with pytest.raises(UnknownFrame, match="0x123"):
        rx.check(stranger)
    assert rx.receive(stranger) is None
    assert rx.stats["UnknownFrame"] == 2


def test_restricted_receiver_treats_other_messages_as_unknown():
    rx = Receiver(names=["WheelSpeeds"])
    assert rx.receive(_frame(0)) is None
    assert rx.stats["UnknownFrame"] == 1


def test_wrong_length_rejected_before_crc():
    msg = _frame(0)
    short = can.Message(arbitration_id=msg.arbitration_id, is_extended_id=False, data=msg.data[:7])
    with pytest.raises(LengthError, match="expected DLC 8, got 7"):
        Receiver().check(short)


def test_bad_crc_rejected():
    msg = _frame(0)
    bad = bytearray(msg.data)
    bad[0] ^= 0x01
    with pytest.raises(ChecksumError, match="expected CRC"):
        Receiver().check(can.Message(arbitration_id=msg.arbitration_id, is_extended_id=False, data=bad))


def test_counter_sequence_repeat_and_jump():
    rx = Receiver()
    assert rx.check(_frame(0)).fresh
    assert rx.check(_frame(2)).fresh  # one lost frame is tolerated
    assert not rx.check(_frame(2)).fresh  # repeat: no new data
    assert rx.receive(_frame(2)) is None
    with pytest.raises(CounterError, match="expected counter 3"):
        rx.check(_frame(6))  # a jump of 4
    # after a sequence error the frames are checked but not used until SYNC_FRAMES (3) in a row step by 1
    assert rx.rx_flags("DriverInput", 0.0) & RX_SEQUENCE
    frame = rx.check(_frame(7))
    assert frame.fresh and not frame.synced
    assert rx.receive(_frame(8)) is None
    assert rx.receive(_frame(9)).counter == 9  # third in a row: in sync again
    assert rx.rx_flags("DriverInput", 0.0) == 0


def test_counter_wraps_14_to_0():
    rx = Receiver()
    rx.check(_frame(14))
    assert rx.check(_frame(0)).fresh


def test_counter_15_is_an_error():
    msg = _resealed(_frame(0), lambda d: d.__setitem__(1, (d[1] & 0xF0) | 0x0F))
    with pytest.raises(CounterError, match="got 15"):
        Receiver().check(msg)


def test_range_violation_rejected():
    # AccelPedal raw 1023 = 102.3 % > 100 %
    def mutate(data):
        payload = int.from_bytes(data, "little") | (0x3FF << 16)
        data[:] = payload.to_bytes(8, "little")
    with pytest.raises(RangeError, match="AccelPedal: expected 0.0..100.0, got 102.3"):
        Receiver().check(_resealed(_frame(0), mutate))


def test_undefined_enum_rejected():
    # Every raw value of the 2-bit enumerations is declared since ADAPTIVE (3) joined Strategy, so the
    # check is exercised on the EcuStatus layout with Strategy declared as before (0..2 only).
    import dataclasses

    from can_dbc.receiver import _decode
    layout = LAYOUTS["EcuStatus"]
    table = tuple(row[:9] + (frozenset({0, 1, 2}),) if row[0] == "Strategy" else row for row in layout.unpack_table)
    old_layout = dataclasses.replace(layout, unpack_table=table)
    msg = encode("EcuStatus", {"Strategy": 3, "Proximity": 0, "StoppingDistance": 0,
                               "SpeedEstimate": 0,
                               **{s.name: 0 for s in LAYOUTS["EcuStatus"].signals if s.name.startswith("Fault")}}, 0)
    with pytest.raises(EnumError, match="Strategy"):
        _decode(old_layout, int.from_bytes(msg.data, "little"))
    assert Receiver().check(msg).signals["Strategy"] == 3  # declared now: accepted
    override = encode("SafetyOverride", {"Mode": 0, "OverrideActive": 0, "ThrottleLimit": 100,
                                         "BrakeDecelRequest": 0}, 0)
    assert Receiver().check(override).signals["Mode"] == 0


def test_validity_score_stuck_counter_invalidates_and_recovers():
    rx = Receiver()
    rx.check(_frame(0))
    for _ in range(5):
        rx.check(_frame(0))  # stuck counter
    assert rx.score("DriverInput") == 5 and not rx.is_valid("DriverInput")
    for counter in range(1, 2):
        rx.check(_frame(counter))
    assert rx.score("DriverInput") == 4 and rx.is_valid("DriverInput")


def test_score_clamped_to_0_5():
    rx = Receiver()
    for counter in range(10):
        rx.check(_frame(counter))
    assert rx.score("DriverInput") == 0
    bad = bytearray(_frame(10).data)
    bad[0] ^= 0xFF
    for _ in range(9):
        rx.receive(can.Message(arbitration_id=0x0B0, is_extended_id=False, data=bad))
    assert rx.score("DriverInput") == 5
    assert rx.stats["ChecksumError"] == 9
