"""UnixSocketBus semantics within one process: delivery, filters, own messages, timeouts, lifecycle."""

import os
import re
import time

import can

import pytest

from can_transport import UnixSocketBus
from tests.transport.conftest import wait_for_peers, wait_until


def _frame(ident: int, payload: bytes = b"") -> can.Message:
    return can.Message(arbitration_id=ident, is_extended_id=False, data=payload)


def test_entry_point_registers_crd_unix(channel: str) -> None:
    with can.Bus(interface="crd_unix", channel=channel) as bus:
        assert isinstance(bus, UnixSocketBus) and bus.owns_hub


def test_broadcast_reaches_every_other_participant(channel: str) -> None:
    with UnixSocketBus(channel) as a, UnixSocketBus(channel) as b, UnixSocketBus(channel) as c:
        wait_for_peers(a, 2)
        a.send(_frame(0x42, b"\x01\x02"))
        for bus in (b, c):
            got = bus.recv(timeout=2)
            assert got.arbitration_id == 0x42 and bytes(got.data) == b"\x01\x02" and got.is_rx
        assert a.recv(timeout=0.05) is None  # no echo to the sender by default


def test_filters_are_honoured_and_can_change(channel: str) -> None:
    filters = [{"can_id": 0x100, "can_mask": 0x7FF, "extended": False}]
    with UnixSocketBus(channel) as a, UnixSocketBus(channel, can_filters=filters) as b:
        wait_for_peers(a, 1)
        for ident in (0x100, 0x200, 0x100, 0x300):
            a.send(_frame(ident))
        assert [b.recv(timeout=2).arbitration_id for _ in range(2)] == [0x100, 0x100]
        assert b.recv(timeout=0.1) is None
        b.set_filters([{"can_id": 0x300, "can_mask": 0x7FF}])
        a.send(_frame(0x100))
        a.send(_frame(0x300))
        assert b.recv(timeout=2).arbitration_id == 0x300


def test_receive_own_messages(channel: str) -> None:
    with UnixSocketBus(channel, receive_own_messages=True) as a, UnixSocketBus(channel) as b:
        a.send(_frame(0x7, b"\xAA"))
        own = a.recv(timeout=1)
        assert own.arbitration_id == 0x7 and not own.is_rx
        assert b.recv(timeout=2).arbitration_id == 0x7


@pytest.mark.wallclock
def test_recv_timeout_is_honoured(channel: str) -> None:
    """Wall-clock by nature: the timeout is wall time, and ``recv`` must neither return early nor hang."""
    with UnixSocketBus(channel) as bus:
        start = time.monotonic()
        assert bus.recv(timeout=0.1) is None
        elapsed = time.monotonic() - start
        assert 0.095 <= elapsed < 2.0
        assert bus.recv(timeout=0) is None


def test_clean_shutdown_is_not_a_fault_and_is_idempotent(channel: str) -> None:
    with UnixSocketBus(channel) as a:
        b = UnixSocketBus(channel)
        wait_for_peers(a, 1)
        b.shutdown()
        b.shutdown()
        wait_for_peers(a, 0)
        assert a.recv(timeout=0.1) is None
        a.send(_frame(0x1))
    assert not os.path.exists(channel)  # the owning bus stopped its hub and removed the socket


def test_connect_without_hub_fails(channel: str) -> None:
    with pytest.raises(can.CanInitializationError, match="expected a hub listening"):
        UnixSocketBus(channel, hub="connect")


def test_overlong_path_rejected(tmp_path) -> None:
    with pytest.raises(can.CanInitializationError, match="1..107 bytes"):
        UnixSocketBus(str(tmp_path / ("x" * 120)))


def test_unread_overflow_is_reported_after_the_kept_frames(channel: str) -> None:
    with UnixSocketBus(channel) as a, UnixSocketBus(channel, max_queue_frames=10) as b:
        wait_for_peers(a, 1)
        for i in range(20):
            a.send(_frame(i))
        wait_until(lambda: b.peer_count == 1 and b.dropped_frames == 10, "b to read all 20 frames")
        assert [b.recv(timeout=1).arbitration_id for _ in range(10)] == list(range(10))
        # The 20 frames may reach b in several socket reads, and each read that overflows reports its own
        # drops ("dropped 9", then "dropped 1" on a busy host): the reports, in order, add up to 10.
        reported = 0
        while reported < 10:
            with pytest.raises(can.CanOperationError, match=r"dropped \d+ received frames") as fault:
                b.recv(timeout=1)
            reported += int(re.search(r"dropped (\d+)", str(fault.value)).group(1))
        assert reported == 10


def test_send_after_shutdown_raises(channel: str) -> None:
    bus = UnixSocketBus(channel)
    bus.shutdown()
    with pytest.raises(can.CanOperationError):
        bus.send(_frame(1))
