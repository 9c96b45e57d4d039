"""SocketCAN on vcan0: the ECU's transport on Linux with the vcan module loaded."""

from pathlib import Path

import can
import pytest

pytestmark = pytest.mark.skipif(
    not Path("/sys/class/net/vcan0").exists(),
    reason="kernel has no vcan0 (needs: sudo modprobe vcan; sudo ip link add dev vcan0 type vcan; "
           "sudo ip link set up vcan0)")


def test_two_socketcan_buses_exchange_a_frame_on_vcan0() -> None:
    filters = [{"can_id": 0x321, "can_mask": 0x7FF, "extended": False}]
    with can.Bus(interface="socketcan", channel="vcan0") as tx, \
            can.Bus(interface="socketcan", channel="vcan0", can_filters=filters) as rx:
        tx.send(can.Message(arbitration_id=0x123, is_extended_id=False, data=b"\x00"))
        tx.send(can.Message(arbitration_id=0x321, is_extended_id=False, data=b"\x01\x02"))
        got = rx.recv(timeout=1.0)
        assert got is not None and got.arbitration_id == 0x321 and bytes(got.data) == b"\x01\x02"
