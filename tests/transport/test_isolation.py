"""Nothing of the transport is reachable beyond this machine or by other users."""

import ast
import os
from pathlib import Path

import pytest

import can_transport
from can_transport import UnixSocketBus
from tests.transport.conftest import wait_for_peers

TRANSPORT_DIR = Path(can_transport.__file__).parent


def test_socket_file_is_private(channel: str) -> None:
    with UnixSocketBus(channel):
        assert os.stat(channel).st_mode & 0o777 == 0o600
        assert not os.path.lexists(channel + ".lock")  # the lock is removed once the hub runs


def _socket_inodes_of_this_process() -> set[str]:
    inodes = set()
    for fd in os.listdir("/proc/self/fd"):
        try:
            target = os.readlink(f"/proc/self/fd/{fd}")
        except OSError:
            continue
        if target.startswith("socket:["):
            inodes.add(target[len("socket:["):-1])
    return inodes


def _inodes_in(table: str, column: int) -> set[str]:
    path = Path("/proc/self/net") / table
    if not path.exists():
        return set()
    rows = path.read_text().splitlines()[1:]
    return {row.split()[column] for row in rows if len(row.split()) > column}


@pytest.mark.skipif(not Path("/proc/self/net/unix").exists(), reason="needs Linux /proc/self/net")
def test_only_unix_sockets_are_opened(channel: str) -> None:
    before = _socket_inodes_of_this_process()
    with UnixSocketBus(channel) as a, UnixSocketBus(channel) as b:
        wait_for_peers(a, 1)
        ours = _socket_inodes_of_this_process() - before
        assert len(ours) >= 3  # hub listener, wake pair, two connections and their hub ends
        inet = set()
        for table in ("tcp", "tcp6", "udp", "udp6", "raw", "raw6"):
            inet |= _inodes_in(table, 9)
        assert not ours & inet
        assert ours <= _inodes_in("unix", 6)
        del b


def test_source_uses_only_af_unix() -> None:
    families = set()
    for source in TRANSPORT_DIR.glob("*.py"):
        for node in ast.walk(ast.parse(source.read_text())):
            if isinstance(node, ast.Attribute) and node.attr.startswith("AF_"):
                families.add(node.attr)
            if isinstance(node, ast.Call) and getattr(node.func, "attr", "") == "socketpair":
                assert node.args and getattr(node.args[0], "attr", "") == "AF_UNIX", source
    assert families == {"AF_UNIX"}
