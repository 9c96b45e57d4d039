"""Fixtures for the transport tests: a socket path and peer processes stopped by PID."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Callable

import pytest

from can_transport import UnixSocketBus

REPO_ROOT = Path(__file__).resolve().parents[2]
START_TIMEOUT_S = 10.0


@pytest.fixture
def channel(tmp_path_factory: pytest.TempPathFactory) -> str:
    """A short socket path (sun_path holds at most 107 bytes)."""
    return str(tmp_path_factory.mktemp("bus") / "c.sock")


class Processes:
    """Starts helper processes and stops each of them by its PID."""

    def __init__(self) -> None:
        self.started: list[subprocess.Popen] = []

    def start(self, *args: str) -> subprocess.Popen:
        proc = subprocess.Popen([sys.executable, *args], cwd=REPO_ROOT, stdin=subprocess.PIPE,
                                stdout=subprocess.PIPE, text=True)
        self.started.append(proc)
        return proc

    def start_peer(self, mode: str, channel: str, hub: str = "connect") -> subprocess.Popen:
        proc = self.start("-m", "tests.transport.peer", mode, channel, hub)
        assert proc.stdout.readline().strip() == "READY"
        return proc

    def start_hub(self, channel: str) -> subprocess.Popen:
        proc = self.start("-m", "can_transport.hub", channel)
        assert proc.stdout.readline().startswith("hub listening")
        return proc

    def stop_all(self) -> None:
        for proc in self.started:
            if proc.poll() is None:
                os.kill(proc.pid, signal.SIGKILL)
            proc.wait(timeout=10)
            for stream in (proc.stdin, proc.stdout):
                if stream:
                    stream.close()


@pytest.fixture
def processes():
    procs = Processes()
    try:
        yield procs
    finally:
        procs.stop_all()


def wait_until(condition: Callable[[], bool], what: str, timeout_s: float = START_TIMEOUT_S) -> None:
    """Wait until ``condition()`` holds, checking every 10 ms; fail naming ``what`` after ``timeout_s``.

    A condition wait, not a sleep: it returns as soon as the condition holds, and the
    bound only matters on a machine so busy that the test should fail.
    """
    deadline = time.monotonic() + timeout_s
    while not condition():
        assert time.monotonic() < deadline, f"expected {what} within {timeout_s} s"
        time.sleep(0.01)


def wait_for_peers(bus: UnixSocketBus, count: int, timeout_s: float = START_TIMEOUT_S) -> None:
    """Wait (bounded) until the hub announces ``count`` other participants."""
    wait_until(lambda: bus.peer_count == count, f"{count} peers (have {bus.peer_count})", timeout_s)
