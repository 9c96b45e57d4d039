"""Bounded, private transports (issue 15, item 6 and finding 9): each test fails on the old transports.

- a non-socket at the channel path is refused, never deleted;
- the lock file is opened without following a symbolic link, and removed;
- a channel name lives in the user's private 0700 directory;
- a hub of another user is refused;
- receive queues are bounded and the drops counted.
"""

from __future__ import annotations

import os
import stat
import time
from pathlib import Path

import can
import pytest

from can_transport import PairSocketBus, UnixSocketBus
from can_transport.hub import Hub
from can_transport.socket_path import connect_or_none
from tests.transport.conftest import wait_for_peers

BUSES = [UnixSocketBus, PairSocketBus]


def _frame(i: int) -> can.Message:
    return can.Message(arbitration_id=0x100 + i % 0x100, is_extended_id=False, data=i.to_bytes(4, "little"))


@pytest.mark.parametrize("bus_class", BUSES)
def test_a_regular_file_at_the_channel_path_is_refused_and_kept(channel: str, bus_class) -> None:
    Path(channel).write_text("precious")
    with pytest.raises(can.CanInitializationError, match="not a socket"):
        bus_class(channel)
    assert Path(channel).read_text() == "precious"


@pytest.mark.parametrize("bus_class", BUSES)
def test_a_symbolic_link_at_the_channel_path_is_refused(channel: str, bus_class, tmp_path) -> None:
    target = tmp_path / "target"
    target.write_text("x")
    os.symlink(target, channel)
    with pytest.raises(can.CanInitializationError, match="symbolic link"):
        bus_class(channel)
    assert os.path.islink(channel) and target.read_text() == "x"


@pytest.mark.parametrize("bus_class", BUSES)
def test_the_lock_does_not_follow_a_symbolic_link(channel: str, bus_class, tmp_path) -> None:
    victim = tmp_path / "victim"  # where an attacker points the lock file
    os.symlink(victim, channel + ".lock")
    with pytest.raises(can.CanInitializationError, match="lock file .* symbolic link"):
        bus_class(channel)
    assert not victim.exists()


@pytest.mark.parametrize("bus_class", BUSES)
def test_the_lock_file_is_removed(channel: str, bus_class) -> None:
    with bus_class(channel):
        assert stat.S_ISSOCK(os.lstat(channel).st_mode)
        assert not os.path.lexists(channel + ".lock")
    assert not os.path.lexists(channel) and not os.path.lexists(channel + ".lock")


@pytest.mark.parametrize("bus_class", BUSES)
def test_a_channel_name_lives_in_a_private_directory(bus_class, tmp_path, monkeypatch) -> None:
    monkeypatch.setenv("XDG_RUNTIME_DIR", str(tmp_path))
    with bus_class("can0") as bus:
        assert bus.channel == str(tmp_path / "crd-can" / "can0.sock")
        info = os.lstat(tmp_path / "crd-can")
        assert stat.S_ISDIR(info.st_mode) and stat.S_IMODE(info.st_mode) == 0o700
        assert info.st_uid == os.getuid()
        assert stat.S_IMODE(os.lstat(bus.channel).st_mode) == 0o600


def test_a_private_directory_open_to_others_or_linked_is_refused(tmp_path, monkeypatch) -> None:
    monkeypatch.setenv("XDG_RUNTIME_DIR", str(tmp_path))
    (tmp_path / "crd-can").mkdir(mode=0o755)
    os.chmod(tmp_path / "crd-can", 0o755)
    with pytest.raises(can.CanInitializationError, match="mode 755, expected 700"):
        UnixSocketBus("can0")
    os.rmdir(tmp_path / "crd-can")
    (tmp_path / "elsewhere").mkdir(mode=0o700)
    os.symlink(tmp_path / "elsewhere", tmp_path / "crd-can")
    from can_transport.socket_path import private_dir

    with pytest.raises(can.CanInitializationError, match="not a directory"):
        private_dir()
    with pytest.raises(can.CanInitializationError, match="letters, digits"):
        UnixSocketBus("..")


@pytest.mark.parametrize("bus_class", BUSES)
def test_a_hub_or_peer_of_another_user_is_refused(channel: str, bus_class, monkeypatch) -> None:
    """The socket and the process behind it belong to 'another user': this process pretends to
    have a different uid after the listener started."""
    with bus_class(channel):
        real = os.getuid()
        monkeypatch.setattr(os, "getuid", lambda: real + 4242)
        with pytest.raises(can.CanInitializationError, match=f"owned by uid {real}, not this user"):
            UnixSocketBus(channel, hub="connect") if bus_class is UnixSocketBus else PairSocketBus(channel,
                                                                                                    role="connect")


def test_the_pair_queue_is_bounded_and_drops_are_counted(channel: str) -> None:
    with PairSocketBus(channel) as a, PairSocketBus(channel, role="connect", max_queue_frames=10) as b:
        assert a.peer_count == 1
        for i in range(25):
            a.send(_frame(i))
        got = []
        with pytest.raises(can.CanOperationError, match="dropped 15 received frames"):
            while True:
                msg = b.recv(timeout=2.0)
                assert msg is not None, "neither a frame nor the drop report arrived"
                got.append(int.from_bytes(msg.data, "little"))
        assert got == list(range(10)) and b.dropped_frames == 15
        a.send(_frame(99))  # the bus goes on after the report
        assert int.from_bytes(b.recv(timeout=2.0).data, "little") == 99


def test_the_hub_backlog_is_bounded_and_drops_are_counted(channel: str) -> None:
    """A participant that never reads: the hub keeps at most its backlog for it and counts the rest."""
    hub = Hub(channel, max_backlog_records=50).start()
    try:
        sleeper = connect_or_none(channel, "the hub")  # joins and never reads
        with UnixSocketBus(channel, hub="connect") as a:
            wait_for_peers(a, 1)
            sent = 0
            deadline = time.monotonic() + 30.0
            while hub.dropped_frames == 0:
                assert time.monotonic() < deadline, f"the hub dropped nothing in {sent} frames"
                for _ in range(1000):
                    a.send(_frame(sent))
                    sent += 1
        sleeper.close()
    finally:
        hub.stop()
    assert 0 < hub.dropped_frames <= sent


@pytest.mark.parametrize("bus_class", BUSES)
def test_the_private_directory_goes_with_its_last_channel(bus_class, tmp_path, monkeypatch) -> None:
    """Nothing is left behind once the buses are closed (issue 24: ``/tmp/crd-can-0`` stayed)."""
    monkeypatch.setenv("XDG_RUNTIME_DIR", str(tmp_path))
    private = tmp_path / "crd-can"
    with bus_class("can0"):
        with bus_class("can1"):
            assert {"can0.sock", "can1.sock"} <= set(os.listdir(private))
        assert os.listdir(private) == ["can0.sock"]  # kept while a channel is in it
    assert not os.path.lexists(private)
    with bus_class("can0") as bus:  # and made again when needed
        assert bus.channel == str(private / "can0.sock") and stat.S_IMODE(os.lstat(private).st_mode) == 0o700
    assert not os.path.lexists(private)
