"""The socket-path channel shared by ``crd_unix`` and ``crd_pair``: its check and the client's connect."""

from __future__ import annotations

import errno
import os
import socket

import can

from can_transport.hub import SOCKET_BUFFER_BYTES

MAX_PATH_BYTES = 107  # sizeof(sockaddr_un.sun_path) - 1 on Linux
_NOBODY_LISTENS = (errno.ENOENT, errno.ECONNREFUSED)


def check_path(path: str) -> None:
    """Raise ``can.CanInitializationError`` unless ``path`` fits a Unix socket address."""
    size = len(os.fsencode(path))
    if not path or size > MAX_PATH_BYTES:
        raise can.CanInitializationError(
            f"channel must be a socket path of 1..{MAX_PATH_BYTES} bytes, got {size} bytes: {path!r}")


def connect_or_none(path: str, listener: str) -> socket.socket | None:
    """A non-blocking stream socket connected to ``path``; None if nobody listens there.

    ``listener`` names what should be listening, for the error on any other failure.
    """
    sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    try:
        sock.connect(path)
    except OSError as exc:
        sock.close()
        if exc.errno in _NOBODY_LISTENS:
            return None
        raise can.CanInitializationError(f"cannot connect to {listener} at {path}: {exc}") from exc
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, SOCKET_BUFFER_BYTES)
    sock.setblocking(False)
    return sock
