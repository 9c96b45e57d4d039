"""Buses in separate OS processes: exchange, ordering, a killed peer, a dead hub.

Every wait is bounded; a hang would fail the test by its timeout, not stall CI.
"""

import os
import select
import signal
import time

import can
import pytest

from can_transport import UnixSocketBus
from tests.transport.conftest import wait_for_peers

FAULT_TIMEOUT_S = 5.0


def _numbered(i: int) -> can.Message:
    return can.Message(arbitration_id=0x100 + i % 0x100, is_extended_id=False, data=i.to_bytes(4, "little"))


def test_frames_echoed_by_another_process_arrive_in_order(channel: str, processes) -> None:
    with UnixSocketBus(channel) as bus:
        echo = processes.start_peer("echo", channel)
        wait_for_peers(bus, 1)
        count = 2000
        for i in range(count):
            bus.send(_numbered(i))
        got = [bus.recv(timeout=FAULT_TIMEOUT_S) for _ in range(count)]
        assert [int.from_bytes(m.data, "little") for m in got] == list(range(count))
        assert [m.arbitration_id for m in got] == [0x100 + i % 0x100 for i in range(count)]
        assert bus.recv(timeout=0.05) is None
        echo.stdin.close()
        assert echo.wait(timeout=FAULT_TIMEOUT_S) == 0


def test_killed_peer_is_a_bus_error_not_a_hang(channel: str, processes) -> None:
    with UnixSocketBus(channel) as bus:
        peer = processes.start_peer("hold", channel)
        wait_for_peers(bus, 1)
        os.kill(peer.pid, signal.SIGKILL)
        peer.wait(timeout=FAULT_TIMEOUT_S)
        with pytest.raises(can.CanOperationError, match="disconnected without shutting down"):
            bus.recv(timeout=FAULT_TIMEOUT_S)
        # reported once; the bus itself is still usable
        assert bus.recv(timeout=0.05) is None
        assert bus.peer_count == 0
        bus.send(_numbered(0))


def test_killed_peer_is_seen_on_send_too(channel: str, processes) -> None:
    with UnixSocketBus(channel) as bus:
        peer = processes.start_peer("hold", channel)
        wait_for_peers(bus, 1)
        os.kill(peer.pid, signal.SIGKILL)
        peer.wait(timeout=FAULT_TIMEOUT_S)
        deadline = time.monotonic() + FAULT_TIMEOUT_S
        with pytest.raises(can.CanOperationError, match="disconnected"):
            while time.monotonic() < deadline:
                bus.send(_numbered(1))
                time.sleep(0.01)


def test_standalone_hub_death_breaks_every_participant(channel: str, processes) -> None:
    hub = processes.start_hub(channel)
    assert oct(os.stat(channel).st_mode & 0o777) == oct(0o600)
    with UnixSocketBus(channel, hub="connect") as a, UnixSocketBus(channel, hub="connect") as b:
        assert not a.owns_hub
        wait_for_peers(a, 1)
        wait_for_peers(b, 1)  # b has read the hub's announcements: what comes next on its socket is frame 7
        a.send(_numbered(7))
        readable, _, _ = select.select([b._sock], [], [], FAULT_TIMEOUT_S)  # the hub has delivered 7, unread
        assert readable, f"the hub did not deliver frame 7 within {FAULT_TIMEOUT_S} s"
        os.kill(hub.pid, signal.SIGKILL)
        hub.wait(timeout=FAULT_TIMEOUT_S)
        assert int.from_bytes(b.recv(timeout=FAULT_TIMEOUT_S).data, "little") == 7  # delivered before the fault
        for bus in (a, b):
            with pytest.raises(can.CanOperationError, match="hub closed the connection"):
                bus.recv(timeout=FAULT_TIMEOUT_S)
            with pytest.raises(can.CanOperationError):  # sticky
                bus.send(_numbered(8))
    # the killed hub left a stale socket file; "auto" replaces it with a live hub
    assert os.path.exists(channel)
    with UnixSocketBus(channel) as fresh, UnixSocketBus(channel, hub="connect") as other:
        assert fresh.owns_hub
        fresh.send(_numbered(9))
        assert int.from_bytes(other.recv(timeout=FAULT_TIMEOUT_S).data, "little") == 9


def test_standalone_hub_stops_cleanly_on_sigterm(channel: str, processes) -> None:
    hub = processes.start_hub(channel)
    with UnixSocketBus(channel, hub="connect") as bus:
        os.kill(hub.pid, signal.SIGTERM)
        assert hub.wait(timeout=FAULT_TIMEOUT_S) == 0
        with pytest.raises(can.CanOperationError):
            bus.recv(timeout=FAULT_TIMEOUT_S)
    assert not os.path.exists(channel)


def test_death_of_the_process_hosting_the_hub(channel: str, processes) -> None:
    host = processes.start_peer("hold", channel, "auto")
    with UnixSocketBus(channel, hub="connect") as bus:
        wait_for_peers(bus, 1)
        os.kill(host.pid, signal.SIGKILL)
        host.wait(timeout=FAULT_TIMEOUT_S)
        with pytest.raises(can.CanOperationError, match="lost"):
            bus.recv(timeout=FAULT_TIMEOUT_S)


def test_peer_sees_hub_owner_shutdown(channel: str, processes) -> None:
    owner = UnixSocketBus(channel)
    peer = processes.start_peer("hold", channel)
    wait_for_peers(owner, 1)
    owner.shutdown()
    assert peer.wait(timeout=FAULT_TIMEOUT_S) == 3  # the peer's recv raised CanOperationError
