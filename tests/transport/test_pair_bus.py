"""``crd_pair``: two participants, point to point; order, errors, a refused third, python-can registration."""

from __future__ import annotations

import os
import signal
import time

import can
import pytest

from can_transport import PairSocketBus
from tests.transport.conftest import wait_until


def _frame(i: int) -> can.Message:
    return can.Message(arbitration_id=0x100 + i % 0x600, is_extended_id=False, data=i.to_bytes(4, "little"))


def _wait_peer(bus: PairSocketBus) -> None:
    wait_until(lambda: bus.peer_count == 1, "a peer to join")


def test_two_buses_exchange_frames_in_order_both_ways(channel: str) -> None:
    with can.Bus(interface="crd_pair", channel=channel) as a, PairSocketBus(channel, role="connect") as b:
        _wait_peer(a)
        assert b.peer_count == 1
        for i in range(500):
            a.send(_frame(i))
        got = [b.recv(timeout=2.0) for _ in range(500)]
        assert [int.from_bytes(m.data, "little") for m in got] == list(range(500))
        assert all(m.is_rx and m.channel == channel for m in got)
        b.send(_frame(7))
        back = a.recv(timeout=2.0)
        assert back.arbitration_id == 0x107 and a.recv(timeout=0.0) is None and b.recv(timeout=0.0) is None


@pytest.mark.wallclock
def test_no_peer_is_an_error_on_send_and_a_timeout_on_recv(channel: str) -> None:
    """Wall-clock by nature: ``recv`` must return None once its timeout (wall time) has passed."""
    with PairSocketBus(channel) as alone:
        with pytest.raises(can.CanOperationError, match="no peer"):
            alone.send(_frame(1))
        started = time.monotonic()
        assert alone.recv(timeout=0.05) is None
        assert time.monotonic() - started < 1.0
    with pytest.raises(can.CanInitializationError, match="found none"):
        PairSocketBus(channel, role="connect")


def test_a_peer_that_leaves_is_reported_after_its_frames(channel: str) -> None:
    with PairSocketBus(channel) as a:
        b = PairSocketBus(channel, role="connect")
        _wait_peer(a)
        b.send(_frame(3))
        b.shutdown()
        assert a.recv(timeout=2.0).arbitration_id == 0x103  # the frame sent before BYE still arrives
        with pytest.raises(can.CanOperationError, match="left"):
            a.recv(timeout=1.0)
        with pytest.raises(can.CanOperationError, match="left"):
            a.send(_frame(4))
        assert a.peer_count == 0
    assert not os.path.exists(channel)  # the listener removed its socket file


def test_a_killed_peer_process_is_a_bus_error_not_a_hang(channel: str, processes) -> None:
    with PairSocketBus(channel) as bus:
        peer = processes.start_peer("echo", channel, "pair")
        _wait_peer(bus)
        bus.send(_frame(5))
        assert bus.recv(timeout=5.0).arbitration_id == 0x105  # echoed by the other process
        os.kill(peer.pid, signal.SIGKILL)
        peer.wait(timeout=10)
        started = time.monotonic()
        with pytest.raises(can.CanOperationError, match="without BYE"):
            bus.recv(timeout=5.0)
        assert time.monotonic() - started < 5.0
        assert bus.peer_count == 0


def test_a_third_participant_is_refused(channel: str, caplog) -> None:
    with PairSocketBus(channel) as a, PairSocketBus(channel, role="connect") as b:
        _wait_peer(a)
        third = PairSocketBus(channel, role="connect")
        try:
            with caplog.at_level("WARNING", logger="can_transport.pair_bus"):
                deadline = time.monotonic() + 5.0
                while not any("third participant" in r.getMessage() for r in caplog.records):
                    assert time.monotonic() < deadline, "the third participant was not refused within 5 s"
                    a.recv(timeout=0.01)  # the listener takes (and refuses) waiting connections when it polls
            a.send(_frame(1))
            with pytest.raises(can.CanOperationError, match="without BYE"):
                third.recv(timeout=2.0)
            assert b.recv(timeout=2.0).arbitration_id == 0x101  # the pair itself is untouched
        finally:
            third.shutdown()


def test_spin_must_not_be_negative(channel: str) -> None:
    with pytest.raises(can.CanInitializationError, match="spin_s"):
        PairSocketBus(channel, spin_s=-1.0)


def _count_writes(bus: PairSocketBus, monkeypatch) -> list[int]:
    writes: list[int] = []
    real = bus._send_records

    def counted(records: bytes, timeout) -> None:
        writes.append(len(records))
        real(records, timeout)
    monkeypatch.setattr(bus, "_send_records", counted)
    return writes


def test_a_batch_leaves_in_one_write_and_arrives_frame_by_frame(channel: str, monkeypatch) -> None:
    with PairSocketBus(channel, receive_own_messages=True) as a, PairSocketBus(channel, role="connect") as b:
        _wait_peer(a)
        writes = _count_writes(a, monkeypatch)
        with a.batch():
            for i in range(5):
                a.send(_frame(i))
                with a.batch():  # nested: only the outermost end writes
                    a.send(_frame(10 + i))
            assert writes == [] and b.recv(timeout=0.05) is None  # kept until the block ends
        assert writes == [10 * 24]  # ten 24-byte records, one write
        got = [b.recv(timeout=2.0) for _ in range(10)]
        assert [int.from_bytes(m.data, "little") for m in got] == [n for i in range(5) for n in (i, 10 + i)]
        assert all(m.is_rx for m in got) and [m.timestamp for m in got] == sorted(m.timestamp for m in got)
        own = [a.recv(timeout=0.0) for _ in range(10)]  # own copies, at their send
        assert [int.from_bytes(m.data, "little") for m in own] == [n for i in range(5) for n in (i, 10 + i)]
        assert all(not m.is_rx for m in own) and b.recv(timeout=0.0) is None
        a.send(_frame(99))  # after the batch: one write per frame again
        assert writes[1:] == [24] and b.recv(timeout=2.0).data == (99).to_bytes(4, "little")


def test_a_frame_sent_in_a_batch_to_a_gone_peer_is_refused_at_once(channel: str) -> None:
    with PairSocketBus(channel) as a:
        b = PairSocketBus(channel, role="connect")
        _wait_peer(a)
        b.shutdown()
        with pytest.raises(can.CanOperationError, match="left"):
            a.recv(timeout=1.0)
        with pytest.raises(can.CanOperationError, match="left"), a.batch():
            a.send(_frame(1))


def test_wait_for_peer_returns_when_the_peer_connects(channel: str) -> None:
    with PairSocketBus(channel) as a:
        assert not a.wait_for_peer(0.0)
        with PairSocketBus(channel, role="connect"):
            assert a.wait_for_peer(5.0) and a.peer_count == 1
