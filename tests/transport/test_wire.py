"""The wire record: a lossless round trip for every classic CAN frame, and nothing else accepted."""

import can
import pytest
from hypothesis import given, strategies as st

from can_transport import wire


@given(ext=st.booleans(), ident=st.integers(0, 0x1FFFFFFF), data=st.binary(max_size=8),
       stamp=st.floats(0, 1e10, allow_nan=False))
def test_frame_round_trip(ext: bool, ident: int, data: bytes, stamp: float) -> None:
    ident = ident if ext else ident & 0x7FF
    msg = can.Message(arbitration_id=ident, is_extended_id=ext, data=data)
    packed = wire.pack_frame(msg, stamp)
    assert len(packed) == wire.RECORD_SIZE == 24
    back = wire.to_message(wire.unpack(packed), "ch")
    assert back.equals(msg, timestamp_delta=None, check_channel=False, check_direction=False)
    assert back.timestamp == stamp and back.channel == "ch" and back.is_rx


def test_remote_and_error_flags_survive() -> None:
    msg = can.Message(arbitration_id=0x12, is_extended_id=False, is_remote_frame=True, dlc=4)
    back = wire.to_message(wire.unpack(wire.pack_frame(msg, 0.0)), "ch")
    assert back.is_remote_frame and back.dlc == 4 and not back.is_error_frame
    err = can.Message(arbitration_id=0x1, is_error_frame=True, data=b"\x01")
    assert wire.to_message(wire.unpack(wire.pack_frame(err, 0.0)), "ch").is_error_frame


def test_fd_frames_are_rejected() -> None:
    fd = can.Message(arbitration_id=0x12, is_fd=True, data=bytes(12))
    with pytest.raises(ValueError, match="classic CAN"):
        wire.pack_frame(fd, 0.0)


def test_control_record_kinds_are_distinct_from_frames() -> None:
    record = wire.unpack(wire.pack_control(wire.KIND_PEERS, 3))
    assert record.kind == wire.KIND_PEERS != wire.KIND_FRAME and record.arbitration_id == 3


@pytest.mark.parametrize("remote", [False, True])
@pytest.mark.parametrize("error", [False, True])
@pytest.mark.parametrize("ext", [False, True])
def test_a_received_message_has_every_attribute_of_the_keyword_construction(ext, error, remote) -> None:
    """``message_from_fields`` calls ``can.Message`` positionally; this holds it to python-can's keywords."""
    sent = can.Message(arbitration_id=0x123, is_extended_id=ext, is_remote_frame=remote, is_error_frame=error,
                       dlc=5, data=None if remote else b"\x01\x02\x03\x04\x05")
    fields = next(wire.RECORD.iter_unpack(wire.pack_frame(sent, 12.5)))
    got = wire.message_from_fields(fields, "ch")
    want = can.Message(timestamp=12.5, arbitration_id=0x123, is_extended_id=ext, is_remote_frame=remote,
                       is_error_frame=error, channel="ch", dlc=5, data=None if remote else b"\x01\x02\x03\x04\x05",
                       is_fd=False, is_rx=True, bitrate_switch=False, error_state_indicator=False, check=False)
    for slot in (s for s in can.Message.__slots__ if s != "__weakref__"):
        assert getattr(got, slot) == getattr(want, slot), slot
        assert type(getattr(got, slot)) is type(getattr(want, slot)), slot
