"""Fixed-size binary records exchanged between a loopback bus and its hub.

Every record is 24 bytes, little-endian, and carries either one classic CAN
frame or one control event; nothing is pickled, so a peer can only ever send
data, never code::

    offset size field
    0      8    timestamp_s   float64, wall-clock seconds (time.time()) at send
    8      4    arbitration_id uint32 (for control records: an event argument)
    12     1    kind          FRAME=0, PEERS=1, PEER_LOST=2, BYE=3, OVERRUN=4
    13     1    flags         bit0 extended id, bit1 remote, bit2 error frame
    14     1    dlc           0..8
    15     1    (padding)
    16     8    data          payload, zero-padded to 8 bytes

Control kinds (sent by the hub unless stated):

- ``PEERS``: the number of *other* participants now connected (in
  ``arbitration_id``), sent to everyone on every join and leave;
- ``PEER_LOST``: a participant disconnected without saying ``BYE`` (its
  process died): the receiver reports it once as a bus error;
- ``BYE``: sent by a participant that is shutting down cleanly;
- ``OVERRUN``: the hub dropped frames for this participant because it did not
  read them (count in ``arbitration_id``): reported once as a bus error.

Classic CAN only: CAN FD frames and DLC > 8 are rejected.
"""

from __future__ import annotations

import struct
from typing import NamedTuple

import can

RECORD = struct.Struct("<dIBBBx8s")
RECORD_SIZE = RECORD.size  # 24 bytes
_pack = RECORD.pack
_Message = can.Message

KIND_FRAME = 0
KIND_PEERS = 1
KIND_PEER_LOST = 2
KIND_BYE = 3
KIND_OVERRUN = 4

_FLAG_EXTENDED = 0x01
_FLAG_REMOTE = 0x02
_FLAG_ERROR = 0x04


class Record(NamedTuple):
    """One decoded wire record."""

    timestamp_s: float
    arbitration_id: int
    kind: int
    flags: int
    dlc: int
    data: bytes


def pack_frame(msg: can.Message, timestamp_s: float) -> bytes:
    """Encode a classic CAN frame; raise ValueError for anything else.

    The DLC is taken from ``msg.dlc`` (a remote frame has a DLC but no data).
    """
    if msg.is_fd:
        raise ValueError(f"expected a classic CAN frame, got a CAN FD frame (id 0x{msg.arbitration_id:X})")
    dlc, data = msg.dlc, msg.data
    if not 0 <= dlc <= 8 or len(data) > 8:
        raise ValueError(f"expected DLC 0..8, got DLC {dlc} with {len(data)} data bytes")
    # the flags from the bools as integers (True == 1): no branches, about 0.3 µs less a frame
    flags = msg.is_extended_id | msg.is_remote_frame << 1 | msg.is_error_frame << 2
    return _pack(timestamp_s, msg.arbitration_id, KIND_FRAME, flags, dlc, data)


def pack_control(kind: int, argument: int = 0) -> bytes:
    """Encode a control record (``argument`` goes in the arbitration-id slot)."""
    return RECORD.pack(0.0, argument, kind, 0, 0, b"")


def unpack(buffer: bytes | bytearray | memoryview, offset: int = 0) -> Record:
    """Decode the record starting at ``offset``."""
    return Record(*RECORD.unpack_from(buffer, offset))


def to_message(record: Record, channel: str) -> can.Message:
    """Turn a FRAME record into a received ``can.Message``."""
    return message_from_fields(record, channel)


def message_from_fields(fields: tuple, channel: str) -> can.Message:
    """A received ``can.Message`` from the fields of a FRAME record (``RECORD.iter_unpack`` gives them).

    Every receive builds one, so the constructor is called with positional arguments
    in python-can's order (timestamp, arbitration_id, is_extended_id, is_remote_frame,
    is_error_frame, channel, dlc, data, is_fd, is_rx, bitrate_switch,
    error_state_indicator, check) and the data already a ``bytearray`` (kept, not
    copied again): about half the cost of keywords. ``tests/transport/test_wire.py``
    checks every attribute against the keyword call, so a change of that order fails there.
    """
    timestamp_s, arbitration_id, _kind, flags, dlc, data = fields
    if flags & _FLAG_REMOTE:
        return _Message(timestamp_s, arbitration_id, bool(flags & _FLAG_EXTENDED), True, bool(flags & _FLAG_ERROR),
                        channel, dlc, None, False, True, False, False, False)
    return _Message(timestamp_s, arbitration_id, bool(flags & _FLAG_EXTENDED), False, bool(flags & _FLAG_ERROR),
                    channel, dlc, bytearray(data[:dlc]), False, True, False, False, False)


def own_message(msg: can.Message, timestamp_s: float, channel: str) -> can.Message:
    """The copy of a sent frame that a bus with ``receive_own_messages`` receives (``is_rx=False``)."""
    return can.Message(
        timestamp=timestamp_s, arbitration_id=msg.arbitration_id, is_extended_id=msg.is_extended_id,
        is_remote_frame=msg.is_remote_frame, is_error_frame=msg.is_error_frame, dlc=msg.dlc,
        data=msg.data, channel=channel, is_rx=False, check=False)
