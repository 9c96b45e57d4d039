"""``PairSocketBus`` (``crd_pair``): a point-to-point CAN bus between two processes, no hub.

For lock-step co-simulation with the ECU in another process, where every
cycle is a round trip. ``crd_unix`` relays each frame through a hub (two extra
hops of Python code, about 50 µs each on the development machine); here the
two participants share one Unix stream socket, and each frame goes straight
from one to the other. A bus with two nodes needs nothing more: every frame
one sends reaches the other, in order. A third participant is refused (its
connection is closed at once and a warning logged): use ``crd_unix`` for more.

The channel is a socket path, as for ``crd_unix``. The first participant
listens on it (mode 0600, a lock file ``<channel>.lock`` makes concurrent
starters agree), the second connects. The wire format is ``crd_unix``'s
(:mod:`can_transport.wire`).

Waiting: ``recv`` first polls the socket without blocking for up to
``spin_s`` (default 2 ms), then blocks. In lock-step the peer answers within
a fraction of a millisecond, so neither side pays an OS wake-up; the price is
up to ``spin_s`` of one core per wait. ``spin_s=0`` always blocks.

Errors are python-can's: ``send`` with no peer connected, a peer that left
(``BYE``) or whose process died (end of file without ``BYE``) raise
``can.CanOperationError`` (the latter two on every later ``send`` and, after
the frames already received, ``recv``); ``peer_count`` is then 0.
"""

from __future__ import annotations

import collections
import fcntl
import logging
import os
import select
import socket
import time
from typing import Any, Literal

import can

from can_transport import wire
from can_transport.hub import SOCKET_BUFFER_BYTES
from can_transport.socket_path import check_path, connect_or_none

LOG = logging.getLogger(__name__)

_READ_CHUNK_BYTES = 1 << 16
DEFAULT_SPIN_S = 0.002


class PairSocketBus(can.BusABC):
    """A CAN bus of exactly two processes over one Unix socket.

    Parameters
    ----------
    channel : str
        Path of the socket file.
    can_filters : list of dict, optional
        python-can filters, applied in software.
    receive_own_messages : bool
        Also receive the frames this bus sends (``is_rx=False``).
    role : {"auto", "connect"}
        Listen when nobody does yet (``auto``), or only connect.
    spin_s : float
        How long ``recv`` polls without blocking before it blocks, in seconds.
    send_timeout_s : float
        Bound on a blocked ``send`` when its ``timeout`` is ``None``, in seconds.
    """

    def __init__(self, channel: str, can_filters: Any = None, receive_own_messages: bool = False,
                 role: Literal["auto", "connect"] = "auto", spin_s: float = DEFAULT_SPIN_S,
                 send_timeout_s: float = 5.0, **kwargs: Any) -> None:
        path = os.fspath(channel)
        check_path(path)
        if role not in ("auto", "connect"):
            raise can.CanInitializationError(f"role must be 'auto' or 'connect', got {role!r}")
        if not spin_s >= 0.0:
            raise can.CanInitializationError(f"spin_s must be >= 0 s, got {spin_s!r}")
        self.channel = path
        self.channel_info = f"crd_pair {path}"
        self._receive_own = receive_own_messages
        self._spin_s = float(spin_s)
        self._send_timeout_s = send_timeout_s
        self._queue: collections.deque[can.Message] = collections.deque()
        self._rx_buffer = bytearray()
        self._gone: str | None = None  # why the peer is no longer there
        self._listener: socket.socket | None = None
        self._inode = 0
        self._peer: socket.socket | None = _connect(path)
        if self._peer is None:
            if role == "connect":
                raise can.CanInitializationError(f"expected a crd_pair peer listening on {path}, found none")
            self._peer = self._listen_or_connect(path)
        super().__init__(channel=path, can_filters=can_filters, **kwargs)

    # -- set-up ----------------------------------------------------------------
    def _listen_or_connect(self, path: str) -> socket.socket | None:
        lock_fd = os.open(path + ".lock", os.O_CREAT | os.O_RDWR, 0o600)
        try:
            fcntl.flock(lock_fd, fcntl.LOCK_EX)
            peer = _connect(path)
            if peer is not None:
                return peer
            if os.path.lexists(path):
                LOG.info("removing stale socket %s", path)
                os.unlink(path)
            listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
            os.fchmod(listener.fileno(), 0o600)
            listener.bind(path)
            listener.listen(4)
            listener.setblocking(False)
            self._listener, self._inode = listener, os.stat(path).st_ino
            return None
        finally:
            os.close(lock_fd)

    def _accept(self) -> None:
        """Take a waiting connection: the peer if there is none yet, otherwise refuse it."""
        listener = self._listener
        if listener is None:
            return
        while True:
            try:
                sock, _ = listener.accept()
            except (BlockingIOError, OSError):
                return
            if self._peer is None and self._gone is None:
                _tune(sock)
                self._peer = sock
                LOG.info("peer joined %s", self.channel)
            else:
                LOG.warning("%s: refused a third participant (crd_pair joins exactly two; use crd_unix)",
                            self.channel)
                sock.close()

    @property
    def peer_count(self) -> int:
        """1 while the other participant is connected, else 0."""
        self._accept()
        if self._peer is not None and self._gone is None:
            self._read(block_s=0.0)
        return 1 if self._peer is not None and self._gone is None else 0

    # -- python-can -----------------------------------------------------------------
    def send(self, msg: can.Message, timeout: float | None = None) -> None:
        """Send ``msg`` to the peer; raise ``can.CanOperationError`` if there is none."""
        if self._is_shutdown:
            raise can.CanOperationError(f"bus on {self.channel} is shut down")
        self._accept()
        if self._gone is not None:
            raise can.CanOperationError(self._gone)
        if self._peer is None:
            raise can.CanOperationError(f"no peer on {self.channel} yet: a frame needs a receiver")
        stamp = time.time()
        self._write(wire.pack_frame(msg, stamp), self._send_timeout_s if timeout is None else timeout)
        if self._receive_own:
            self._queue.append(can.Message(
                timestamp=stamp, arbitration_id=msg.arbitration_id, is_extended_id=msg.is_extended_id,
                is_remote_frame=msg.is_remote_frame, is_error_frame=msg.is_error_frame, dlc=msg.dlc,
                data=msg.data, channel=self.channel, is_rx=False, check=False))

    def _recv_internal(self, timeout: float | None) -> tuple[can.Message | None, bool]:
        now = time.monotonic()
        deadline = None if timeout is None else now + timeout
        spin_until = now + (self._spin_s if timeout is None else min(self._spin_s, timeout))
        while True:
            if self._queue:
                return self._queue.popleft(), False
            if self._gone is not None:
                raise can.CanOperationError(self._gone)
            now = time.monotonic()
            if deadline is not None and now >= deadline and timeout != 0.0:
                return None, False
            if now < spin_until or timeout == 0.0:
                if self._peer is None:
                    self._accept()
                self._read(block_s=0.0)
                if timeout == 0.0 and not self._queue:
                    if self._gone is not None:
                        raise can.CanOperationError(self._gone)
                    return None, False
                continue
            self._read(block_s=None if deadline is None else max(0.0, deadline - now))

    def shutdown(self) -> None:
        """Say BYE, close the socket and remove the socket file if this bus listened. Idempotent."""
        if self._is_shutdown:
            return
        super().shutdown()
        if self._peer is not None:
            try:
                self._peer.send(wire.pack_control(wire.KIND_BYE))
            except OSError:
                pass
            self._peer.close()
        if self._listener is not None:
            self._listener.close()
            try:
                if os.stat(self.channel).st_ino == self._inode:
                    os.unlink(self.channel)
            except FileNotFoundError:
                pass

    # -- the socket ----------------------------------------------------------------
    def _read(self, block_s: float | None) -> None:
        """Read what the peer sent; wait up to ``block_s`` (None: no bound) for it or a connection."""
        sock = self._peer
        if sock is None:
            if block_s != 0.0 and self._listener is not None:
                select.select([self._listener], [], [], block_s)
                self._accept()
            return
        if block_s != 0.0:
            readable, _, _ = select.select([sock], [], [], block_s)
            if not readable:
                return
        try:
            chunk = sock.recv(_READ_CHUNK_BYTES)
        except BlockingIOError:
            return
        except OSError as exc:
            self._lost(f"receive failed: {exc}")
            return
        if not chunk:
            self._lost("the peer's connection ended without BYE (its process died?)")
            return
        buffer = self._rx_buffer
        buffer += chunk
        whole = len(buffer) - len(buffer) % wire.RECORD_SIZE
        for offset in range(0, whole, wire.RECORD_SIZE):
            record = wire.unpack(buffer, offset)
            if record.kind == wire.KIND_FRAME:
                self._queue.append(wire.to_message(record, self.channel))
            elif record.kind == wire.KIND_BYE:
                self._gone = f"bus {self.channel}: the peer left (BYE)"
        del buffer[:whole]

    def _lost(self, reason: str) -> None:
        if self._gone is None:
            self._gone = f"bus {self.channel} lost: {reason}"
            LOG.warning("%s", self._gone)

    def _write(self, record: bytes, timeout_s: float) -> None:
        sock = self._peer
        view = memoryview(record)
        deadline = time.monotonic() + timeout_s
        while view:
            try:
                view = view[sock.send(view):]
            except BlockingIOError:
                pass
            except OSError as exc:
                self._lost(f"send failed: {exc}")
                raise can.CanOperationError(self._gone) from exc
            if view:
                remaining = deadline - time.monotonic()
                if remaining <= 0.0 or not select.select([], [sock], [], remaining)[1]:
                    raise can.CanOperationError(
                        f"send timed out: expected the peer to take a frame within {timeout_s} s, it did not")


def _tune(sock: socket.socket) -> None:
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, SOCKET_BUFFER_BYTES)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, SOCKET_BUFFER_BYTES)
    sock.setblocking(False)


def _connect(path: str) -> socket.socket | None:
    sock = connect_or_none(path, "a crd_pair peer")
    if sock is not None:
        _tune(sock)
    return sock
