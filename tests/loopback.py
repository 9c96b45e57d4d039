"""The loopback rule as a fixture: every socket a test opens goes to 127.0.0.1, ::1 or a Unix socket.

Import ``loopback_only`` into a test module (it is autouse there)."""

from __future__ import annotations

import socket

import pytest


@pytest.fixture(autouse=True)
def loopback_only(monkeypatch):
    """Any socket this process opens must go to 127.0.0.1 (or ::1, or a Unix socket)."""
    real = socket.socket.connect

    def connect(self, address):
        if self.family in (socket.AF_INET, socket.AF_INET6):
            assert address[0] in ("127.0.0.1", "::1", "localhost"), f"connection beyond loopback: {address}"
        return real(self, address)

    monkeypatch.setattr(socket.socket, "connect", connect)
