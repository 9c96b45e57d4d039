"""``UnixSocketBus``: a python-can interface that joins a broadcast hub over a Unix socket.

It behaves like python-can's ``virtual`` bus, but across processes of one
machine: every frame one participant sends is delivered to every other
participant on the same channel, in the order it was sent. The channel is a
name, e.g. ``can0``, for a socket in the user's private 0700 directory, or the
filesystem path of the hub's socket (at most 107 bytes); see
:mod:`can_transport.socket_path` for what is refused (a non-socket at the
path, another user's socket or hub, a symbolic-link lock file).

Hub lifecycle (``hub=``):

- ``"auto"`` (default): connect to the hub at ``channel``; if none is alive,
  start one in a daemon thread of *this* process (a lock file
  ``<channel>.lock``, removed after, makes concurrent starters agree on one
  hub; a stale socket of this user left by a dead hub is removed). That hub stops when this bus shuts down
  or this process dies, and every other participant then gets a bus error:
  like unplugging the harness. Open the longest-lived participant first.
- ``"connect"``: only connect; raise ``can.CanInitializationError`` if no hub
  runs (use with ``python -m can_transport.hub PATH``).

Errors are python-can's: a hub that dies makes every later ``send``/``recv``
raise ``can.CanOperationError`` (after the frames already received); a peer
whose process dies (disconnects without ``shutdown()``) is reported once as a
``can.CanOperationError`` on this bus's next ``send`` or ``recv``; so are frames
dropped because this bus did not read them: at most ``max_queue_frames``
(default 10,000, about 3 MB) wait for ``recv`` here, and at most 10,000 records
in the hub; more are dropped and counted (``dropped_frames``, the hub's
``OVERRUN`` counts included). Nothing ever waits without a bound
unless asked to: ``recv(timeout=None)`` waits for a frame or an error, and
``send`` waits at most ``timeout`` (``None`` means ``send_timeout_s``).

Filters are python-can's software filters (``BusABC.recv`` applies them, as
``_recv_internal`` reports frames as not yet filtered).
"""

from __future__ import annotations

import collections
import logging
import select
import socket
import threading
import time
from dataclasses import dataclass
from typing import Any, Literal

import can

from can_transport import socket_path, wire
from can_transport.hub import Hub
from can_transport.socket_path import connect_or_none

LOG = logging.getLogger(__name__)

_READ_CHUNK_BYTES = 1 << 16
DEFAULT_MAX_QUEUE_FRAMES = 10_000


@dataclass(frozen=True)
class _BusFault:
    """An error to raise, in order, from the receive queue."""

    text: str
    sticky: bool


class UnixSocketBus(can.BusABC):
    """A loopback CAN bus across processes, through a hub on a Unix socket.

    Parameters
    ----------
    channel : str
        A channel name (a socket in the user's private directory) or the path of the hub's socket.
    can_filters : list of dict, optional
        python-can filters, applied in software.
    receive_own_messages : bool
        Also receive the frames this bus sends (``is_rx=False``).
    hub : {"auto", "connect"}
        Start a hub in this process when none is alive, or only connect.
    send_timeout_s : float
        Bound on a blocked ``send`` when its ``timeout`` is ``None``, in seconds.
    max_queue_frames : int
        Frames kept for this bus between ``recv`` calls before dropping.
    """

    def __init__(self, channel: str, can_filters: Any = None, receive_own_messages: bool = False,
                 hub: Literal["auto", "connect"] = "auto", send_timeout_s: float = 5.0,
                 max_queue_frames: int = DEFAULT_MAX_QUEUE_FRAMES, **kwargs: Any) -> None:
        path = socket_path.resolve_channel(channel)
        if not (isinstance(max_queue_frames, int) and max_queue_frames >= 1):
            raise can.CanInitializationError(f"max_queue_frames must be an integer >= 1, got {max_queue_frames!r}")
        self._sock, self._hub = _open_channel(path, hub)
        self.channel = path
        self.channel_info = f"crd_unix hub {path}"
        self._receive_own = receive_own_messages
        self._send_timeout_s = send_timeout_s
        self._max_queue = max_queue_frames
        self._rx_buffer = bytearray()
        self._queue: collections.deque[can.Message | _BusFault] = collections.deque()
        self._queued_faults = 0
        self._dropped = 0
        self.dropped_frames = 0  # frames lost to this bus, here or in the hub (total)
        self._broken: str | None = None
        self._peer_count = 0
        self._rx_lock = threading.Lock()
        self._tx_lock = threading.Lock()
        self._poll_in = select.poll()
        self._poll_in.register(self._sock, select.POLLIN)
        self._poll_out = select.poll()
        self._poll_out.register(self._sock, select.POLLOUT)
        super().__init__(channel=path, can_filters=can_filters, **kwargs)

    @property
    def peer_count(self) -> int:
        """Other participants connected to the hub, as last announced by it."""
        with self._rx_lock:
            self._read_available()
        return self._peer_count

    @property
    def owns_hub(self) -> bool:
        """True when this bus started the hub (it stops when this bus shuts down)."""
        return self._hub is not None

    def _recv_internal(self, timeout: float | None) -> tuple[can.Message | None, bool]:
        deadline = None if timeout is None else time.monotonic() + timeout
        while True:
            item = self._pop()
            if item is not None:
                return item, False
            if self._broken is not None:
                raise can.CanOperationError(self._broken)
            remaining_ms = None if deadline is None else max(0.0, deadline - time.monotonic()) * 1000.0
            if self._poll_in.poll(remaining_ms):
                with self._rx_lock:
                    self._read_available()
            elif deadline is not None and time.monotonic() >= deadline:
                return None, False

    def send(self, msg: can.Message, timeout: float | None = None) -> None:
        """Send ``msg`` to every other participant; raise ``can.CanOperationError`` on a bus fault."""
        if self._is_shutdown:
            raise can.CanOperationError(f"bus on {self.channel} is shut down")
        with self._rx_lock:
            self._read_available()
        self._raise_first_fault()
        stamp = time.time()
        record = wire.pack_frame(msg, stamp)
        with self._tx_lock:
            self._write(record, self._send_timeout_s if timeout is None else timeout)
        if self._receive_own:
            own = can.Message(timestamp=stamp, arbitration_id=msg.arbitration_id,
                              is_extended_id=msg.is_extended_id, is_remote_frame=msg.is_remote_frame,
                              is_error_frame=msg.is_error_frame, dlc=msg.dlc, data=msg.data,
                              channel=self.channel, is_rx=False, check=False)
            self._queue.append(own)

    def shutdown(self) -> None:
        """Leave the bus (saying BYE) and stop the hub if this bus owns it. Idempotent."""
        if self._is_shutdown:
            return
        super().shutdown()
        try:
            self._sock.send(wire.pack_control(wire.KIND_BYE))
        except OSError:
            pass
        self._sock.close()
        if self._hub is not None:
            self._hub.stop()

    def _pop(self) -> can.Message | None:
        """Next queued frame, raising a queued fault when it comes first."""
        if not self._queue:
            return None
        item = self._queue.popleft()
        if isinstance(item, _BusFault):
            self._queued_faults -= 1
            if item.sticky:
                self._broken = item.text
            raise can.CanOperationError(item.text)
        return item

    def _raise_first_fault(self) -> None:
        if self._broken is not None:
            raise can.CanOperationError(self._broken)
        if not self._queued_faults:
            return
        fault = next(item for item in self._queue if isinstance(item, _BusFault))
        self._queue.remove(fault)
        self._queued_faults -= 1
        if fault.sticky:
            self._broken = fault.text
        raise can.CanOperationError(fault.text)

    def _fault(self, text: str, sticky: bool = False) -> None:
        LOG.warning("%s: %s", self.channel, text)
        self._queue.append(_BusFault(text, sticky))
        self._queued_faults += 1

    def _read_available(self) -> None:
        """Read whatever the socket holds without blocking (caller holds ``_rx_lock``)."""
        if self._broken is not None or self._sock.fileno() < 0:
            return
        try:
            chunk = self._sock.recv(_READ_CHUNK_BYTES)
        except BlockingIOError:
            return
        except OSError as exc:
            chunk, reason = b"", f"receive failed: {exc}"
        else:
            reason = "the hub closed the connection (hub stopped or its process died)"
        if not chunk:
            if not any(isinstance(i, _BusFault) and i.sticky for i in self._queue):
                self._fault(f"bus {self.channel} lost: {reason}", sticky=True)
            return
        self._rx_buffer += chunk
        self._parse()

    def _parse(self) -> None:
        buffer = self._rx_buffer
        whole = len(buffer) - len(buffer) % wire.RECORD_SIZE
        for offset in range(0, whole, wire.RECORD_SIZE):
            record = wire.unpack(buffer, offset)
            if record.kind == wire.KIND_FRAME:
                self._enqueue(wire.to_message(record, self.channel))
            elif record.kind == wire.KIND_PEERS:
                self._peer_count = record.arbitration_id
            elif record.kind == wire.KIND_PEER_LOST:
                self._fault(f"a participant on {self.channel} disconnected without shutting down (process died?)")
            elif record.kind == wire.KIND_OVERRUN:
                self.dropped_frames += record.arbitration_id
                self._fault(f"hub dropped {record.arbitration_id} frames for this bus: it did not read fast enough")
        del buffer[:whole]
        if self._dropped:
            self._fault(f"dropped {self._dropped} received frames: more than {self._max_queue} queued unread")
            self._dropped = 0

    def _enqueue(self, msg: can.Message) -> None:
        if len(self._queue) >= self._max_queue:
            self._dropped += 1
            self.dropped_frames += 1
        else:
            self._queue.append(msg)

    def _write(self, record: bytes, timeout_s: float) -> None:
        view = memoryview(record)
        deadline = time.monotonic() + timeout_s
        while view:
            try:
                view = view[self._sock.send(view):]
            except BlockingIOError:
                pass
            except OSError as exc:
                self._broken = f"bus {self.channel} lost: send failed: {exc}"
                raise can.CanOperationError(self._broken) from exc
            if view and not self._poll_out.poll(max(0.0, deadline - time.monotonic()) * 1000.0):
                if len(view) < len(record):
                    self._broken = f"bus {self.channel} lost: a send timed out mid-record"
                raise can.CanOperationError(
                    f"send timed out: expected the hub to accept a frame within {timeout_s} s, it did not")


def _open_channel(path: str, hub_mode: str) -> tuple[socket.socket, Hub | None]:
    """Connect to the hub at ``path``, starting one here when allowed and none is alive."""
    if hub_mode not in ("auto", "connect"):
        raise can.CanInitializationError(f"hub must be 'auto' or 'connect', got {hub_mode!r}")
    sock = connect_or_none(path, "the hub")
    if sock is not None:
        return sock, None
    if hub_mode == "connect":
        raise can.CanInitializationError(
            f"expected a hub listening on {path}, found none (start one: python -m can_transport.hub {path})")
    with socket_path.channel_lock(path):
        sock = connect_or_none(path, "the hub")
        if sock is not None:
            return sock, None
        socket_path.remove_stale_socket(path)
        hub = Hub(path).start()
        sock = connect_or_none(path, "the hub")
        if sock is None:
            hub.stop()
            raise can.CanInitializationError(f"started a hub on {path} but could not connect to it")
        return sock, hub
