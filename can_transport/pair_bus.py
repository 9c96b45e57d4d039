"""``PairSocketBus`` (``crd_pair``): a point-to-point CAN bus between two processes, no hub.

For lock-step co-simulation with the ECU in another process, where every
cycle is a round trip. ``crd_unix`` relays each frame through a hub (two extra
hops of Python code, about 50 µs each on the development machine); here the
two participants share one Unix stream socket, and each frame goes straight
from one to the other. A bus with two nodes needs nothing more: every frame
one sends reaches the other, in order. A third participant is refused (its
connection is closed when the listener next waits, and a warning logged): use
``crd_unix`` for more.

The channel is a name or a socket path, as for ``crd_unix``
(:mod:`can_transport.socket_path`: names live in the user's private 0700
directory; a non-socket at the path, another user's socket or peer, and a
symbolic-link lock file are refused). The first participant listens (mode
0600; the lock ``<channel>.lock`` makes concurrent starters agree and is
removed after), the second connects. The wire format is ``crd_unix``'s
(:mod:`can_transport.wire`).

Waiting: ``recv`` blocks in ``poll`` on the socket. Before it blocks it may
poll without blocking for a short, learned time (:class:`~can_transport.spin.
AdaptiveSpin`, at most ``spin_s``, default 0.5 ms), and only while the machine
has a core for every runnable task: in lock-step on a quiet machine that saves
an OS wake-up per wait; on a busy one the bus only blocks, so it never takes a
core from the peer it waits for. ``spin_s=0`` always blocks.

Batches: the frames a participant sends inside ``with bus.batch():`` (or
between ``begin_batch()`` and ``end_batch()``) leave in one socket write at its end (each is still its own frame, stamped at
its ``send``, received one by one): one system call and one wake-up of the
peer per lock-step turn instead of one per frame.

Bounded: at most ``max_queue_frames`` (default 10,000, about 3 MB) received
frames wait for ``recv``; more are dropped and counted (``dropped_frames``), and
the next ``recv`` that finds the queue empty raises ``can.CanOperationError``
once for them.

Errors are python-can's: ``send`` with no peer connected, a peer that left
(``BYE``) or whose process died (end of file without ``BYE``) raise
``can.CanOperationError`` (the latter two on every later ``send`` and, after
the frames already received, ``recv``); ``peer_count`` is then 0.
"""

from __future__ import annotations

import collections
import contextlib
import logging
import select
import socket
import time
from typing import Any, Iterator, Literal

import can

from can_transport import socket_path, wire
from can_transport.spin import AdaptiveSpin

LOG = logging.getLogger(__name__)

_READ_CHUNK_BYTES = 1 << 16
DEFAULT_SPIN_S = 0.0005
DEFAULT_MAX_QUEUE_FRAMES = 10_000
_POLLIN = select.POLLIN | select.POLLHUP | select.POLLERR


class PairSocketBus(can.BusABC):
    """A CAN bus of exactly two processes over one Unix socket.

    Parameters
    ----------
    channel : str
        A channel name (a socket in the user's private directory) or a socket path.
    can_filters : list of dict, optional
        python-can filters, applied in software.
    receive_own_messages : bool
        Also receive the frames this bus sends (``is_rx=False``).
    role : {"auto", "connect"}
        Listen when nobody does yet (``auto``), or only connect.
    spin_s : float
        The longest ``recv`` polls without blocking before it blocks, in seconds (0: always block).
    send_timeout_s : float
        Bound on a blocked ``send`` when its ``timeout`` is ``None``, in seconds.
    max_queue_frames : int
        Received frames kept for ``recv``; more are dropped and counted.
    """

    def __init__(self, channel: str, can_filters: Any = None, receive_own_messages: bool = False,
                 role: Literal["auto", "connect"] = "auto", spin_s: float = DEFAULT_SPIN_S,
                 send_timeout_s: float = 5.0, max_queue_frames: int = DEFAULT_MAX_QUEUE_FRAMES,
                 **kwargs: Any) -> None:
        path = socket_path.resolve_channel(channel)
        if role not in ("auto", "connect"):
            raise can.CanInitializationError(f"role must be 'auto' or 'connect', got {role!r}")
        if not spin_s >= 0.0:
            raise can.CanInitializationError(f"spin_s must be >= 0 s, got {spin_s!r}")
        if not (isinstance(max_queue_frames, int) and max_queue_frames >= 1):
            raise can.CanInitializationError(f"max_queue_frames must be an integer >= 1, got {max_queue_frames!r}")
        self.channel = path
        self.channel_info = f"crd_pair {path}"
        self._receive_own = receive_own_messages
        self._send_timeout_s = send_timeout_s
        self._max_queue = max_queue_frames
        self._queue: collections.deque[can.Message] = collections.deque()
        self._rx_buffer = bytearray()
        self.dropped_frames = 0  # received frames dropped because the queue was full (total)
        self._unreported_drops = 0
        self._gone: str | None = None  # why the peer is no longer there
        self._listener: socket.socket | None = None
        self._inode = 0
        self._poller = select.poll()
        self._spin = AdaptiveSpin(float(spin_s))
        self._peer: socket.socket | None = None
        self._batch: bytearray | None = None  # records of a batch being sent (see batch())
        self._batch_timeout: float | None = None
        self._batch_depth = 0
        peer = _connect(path)
        if peer is None:
            if role == "connect":
                raise can.CanInitializationError(f"expected a crd_pair peer listening on {path}, found none")
            peer = self._listen_or_connect(path)
        if peer is not None:
            self._attach(peer)
        super().__init__(channel=path, can_filters=can_filters, **kwargs)

    # -- set-up ----------------------------------------------------------------
    def _listen_or_connect(self, path: str) -> socket.socket | None:
        with socket_path.channel_lock(path):
            peer = _connect(path)
            if peer is not None:
                return peer
            socket_path.remove_stale_socket(path)
            self._listener, self._inode = socket_path.listen(path, 4)
            self._poller.register(self._listener, select.POLLIN)
            return None

    def _attach(self, sock: socket.socket) -> None:
        self._peer = sock
        self._poller.register(sock, _POLLIN)

    def _accept(self) -> None:
        """Take waiting connections: the peer if there is none yet (of this user); refuse the rest."""
        listener = self._listener
        while listener is not None:
            try:
                sock, _ = listener.accept()
            except OSError:  # BlockingIOError: nobody waiting
                return
            if not socket_path.same_user(sock):
                LOG.warning("%s: refused a participant of uid %d (a bus is private to its user)",
                            self.channel, socket_path.peer_uid(sock))
                sock.close()
            elif self._peer is None and self._gone is None:
                _tune(sock)
                self._attach(sock)
                LOG.info("peer joined %s", self.channel)
            else:
                LOG.warning("%s: refused a third participant (crd_pair joins exactly two; use crd_unix)",
                            self.channel)
                sock.close()

    @property
    def peer_count(self) -> int:
        """1 while the other participant is connected, else 0."""
        self._poll(0)
        return 1 if self._peer is not None and self._gone is None else 0

    def wait_for_peer(self, timeout_s: float) -> bool:
        """Block (in ``poll``, no sleeping) up to ``timeout_s`` until the other participant joins."""
        deadline = time.monotonic() + timeout_s
        while self._peer is None and self._gone is None and not self._is_shutdown:
            remaining = deadline - time.monotonic()
            if remaining <= 0.0:
                break
            self._poll(remaining * 1000.0)
        return self.peer_count == 1

    # -- python-can -----------------------------------------------------------------
    def send(self, msg: can.Message, timeout: float | None = None) -> None:
        """Send ``msg`` to the peer; raise ``can.CanOperationError`` if there is none.

        Inside a :meth:`batch` the frame's record is kept and written with the batch's others.
        """
        if self._gone is not None or self._peer is None or self._is_shutdown:
            self._cannot_send()
        stamp = time.time()
        record = wire.pack_frame(msg, stamp)
        if self._batch is not None:
            self._batch += record
            self._batch_timeout = timeout
        else:
            self._send_records(record, timeout)
        if self._receive_own:
            self._queue.append(wire.own_message(msg, stamp, self.channel))

    @contextlib.contextmanager
    def batch(self) -> Iterator[None]:
        """Frames sent in this block leave in one socket write when it ends (begin/end_batch)."""
        self.begin_batch()
        try:
            yield
        finally:
            self.end_batch()

    def begin_batch(self) -> None:
        """Keep the frames sent from now on until the matching :meth:`end_batch` writes them in one go.

        Each stays its own frame, stamped at its send and received one by one, in order;
        what changes is one system call and one wake-up of the peer instead of one per
        frame (a write that wakes the peer costs 10 to 30 µs here). The outermost end writes.
        """
        if self._batch is None:
            self._batch, self._batch_timeout = bytearray(), None
        self._batch_depth += 1

    def end_batch(self) -> None:
        """End a batch; the outermost writes its frames (one write), raising ``can.CanOperationError`` on failure."""
        if self._batch_depth > 1:
            self._batch_depth -= 1
            return
        records, self._batch, self._batch_depth = self._batch, None, 0
        if records and self._gone is None and not self._is_shutdown:
            self._send_records(bytes(records), self._batch_timeout)

    def _send_records(self, records: bytes, timeout: float | None) -> None:
        try:
            sent = self._peer.send(records)
        except BlockingIOError:
            sent = 0
        except OSError as exc:
            self._lost(f"send failed: {exc}")
            raise can.CanOperationError(self._gone) from exc
        if sent < len(records):
            self._write(records, sent, self._send_timeout_s if timeout is None else timeout)

    def _cannot_send(self) -> None:
        if self._is_shutdown:
            raise can.CanOperationError(f"bus on {self.channel} is shut down")
        self._poll(0)
        if self._gone is not None:
            raise can.CanOperationError(self._gone)
        if self._peer is None:
            raise can.CanOperationError(f"no peer on {self.channel} yet: a frame needs a receiver")

    def recv(self, timeout: float | None = None) -> can.Message | None:
        # Fast path without filters (every frame passes): skips BusABC.recv's clock reads, filter
        # check and retry loop, about 1 µs of each of a lock-step turn's five to nine receives.
        if self._filters is None and not self._is_shutdown:
            if self._queue:
                return self._queue.popleft()
            return self._recv_internal(timeout)[0]
        return super().recv(timeout)

    def _recv_internal(self, timeout: float | None) -> tuple[can.Message | None, bool]:
        queue = self._queue
        if not queue:
            if timeout is not None and timeout <= 0.0:
                self._poll(0)
            else:
                self._wait(timeout)  # its first poll takes what is already there
            if not queue:
                self._raise_pending()
                return None, False
        return queue.popleft(), False

    def _wait(self, timeout: float | None) -> None:
        """Wait until a frame is queued, the peer is gone, or ``timeout`` (None: no bound) passes."""
        clock = time.monotonic
        start = clock()
        deadline = None if timeout is None else start + timeout
        spin_end = start + self._spin.budget_s(start)
        if deadline is not None and deadline < spin_end:
            spin_end = deadline
        queue = self._queue
        while not queue and self._gone is None and not self._unreported_drops:
            now = clock()
            if now < spin_end:
                self._poll(0)
            elif deadline is None:
                self._poll(None)
            elif now < deadline:
                self._poll((deadline - now) * 1000.0)
            else:
                self._poll(0)  # past the deadline (or a timeout too short to wait): one last look
                break
        if self._gone is None:
            self._spin.waited(clock() - start)

    def _raise_pending(self) -> None:
        if self._unreported_drops:
            dropped, self._unreported_drops = self._unreported_drops, 0
            raise can.CanOperationError(f"{self.channel}: dropped {dropped} received frames: more than "
                                        f"{self._max_queue} queued unread")
        if self._gone is not None:
            raise can.CanOperationError(self._gone)

    def shutdown(self) -> None:
        """Say BYE, close the socket and remove the socket file if this bus listened. Idempotent."""
        if self._is_shutdown:
            return
        super().shutdown()
        self._spin.close()
        if self._peer is not None:
            try:
                self._peer.send(wire.pack_control(wire.KIND_BYE))
            except OSError:
                pass
            self._peer.close()
        if self._listener is not None:
            self._listener.close()
            socket_path.unlink_if_ours(self.channel, self._inode)

    # -- the socket ----------------------------------------------------------------
    def _poll(self, timeout_ms: float | None) -> None:
        """Wait up to ``timeout_ms`` (0: not at all, None: no bound) and take what the sockets hold."""
        for fd, _events in self._poller.poll(timeout_ms):
            if self._peer is not None and fd == self._peer.fileno():
                self._read()
            else:
                self._accept()

    def _read(self) -> None:
        sock = self._peer
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
        if buffer or len(chunk) % wire.RECORD_SIZE:
            buffer += chunk
            whole = len(buffer) - len(buffer) % wire.RECORD_SIZE
            chunk = bytes(buffer[:whole])
            del buffer[:whole]
        self._take(chunk)

    def _take(self, records: bytes) -> None:
        """Queue the frames of whole ``records`` (dropping past the bound); note a BYE."""
        queue, channel, limit = self._queue, self.channel, self._max_queue
        for fields in wire.RECORD.iter_unpack(records):
            kind = fields[2]
            if kind == wire.KIND_FRAME:
                if len(queue) < limit:
                    queue.append(wire.message_from_fields(fields, channel))
                else:
                    self.dropped_frames += 1
                    self._unreported_drops += 1
            elif kind == wire.KIND_BYE:
                self._gone = f"bus {channel}: the peer left (BYE)"
                self._forget_peer()

    def _lost(self, reason: str) -> None:
        if self._gone is None:
            self._gone = f"bus {self.channel} lost: {reason}"
            LOG.warning("%s", self._gone)
        self._forget_peer()

    def _forget_peer(self) -> None:
        """Stop polling a peer that is gone (its end-of-file would wake every poll)."""
        if self._peer is not None:
            try:
                self._poller.unregister(self._peer)
            except (KeyError, ValueError):
                pass

    def _write(self, records: bytes, sent: int, timeout_s: float) -> None:
        """Finish sending ``records`` (``sent`` bytes are out), waiting up to ``timeout_s``."""
        sock = self._peer
        view = memoryview(records)[sent:]
        deadline = time.monotonic() + timeout_s
        while view:
            remaining = deadline - time.monotonic()
            if remaining <= 0.0 or not select.select([], [sock], [], remaining)[1]:
                raise can.CanOperationError(
                    f"send timed out: expected the peer to take a frame within {timeout_s} s, it did not")
            try:
                view = view[sock.send(view):]
            except BlockingIOError:
                pass
            except OSError as exc:
                self._lost(f"send failed: {exc}")
                raise can.CanOperationError(self._gone) from exc


def _tune(sock: socket.socket) -> None:
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, socket_path.SOCKET_BUFFER_BYTES)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, socket_path.SOCKET_BUFFER_BYTES)
    sock.setblocking(False)


def _connect(path: str) -> socket.socket | None:
    sock = socket_path.connect_or_none(path, "a crd_pair peer")
    if sock is not None:
        _tune(sock)
    return sock
