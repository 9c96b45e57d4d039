"""The broadcast hub of the loopback bus: relays every frame to every other participant.

A hub owns one Unix-domain stream socket at a filesystem path (the bus's
*channel*). It runs one selector loop in one thread, so frames from one sender
are relayed in the order they were sent. It never blocks on a slow reader: each
participant has an output backlog; past ``max_backlog_records`` (default 10,000
records, 240 kB) the hub drops frames for that participant, counts them
(``dropped_frames``) and later tells it how many (``OVERRUN``).

Guarantees:

- Unix socket only (``AF_UNIX``), created with mode 0600 (``fchmod`` before
  ``bind``, so there is no window with wider permissions); nothing listens on
  any network address and nothing serves files.
- Private to its user: a connection from a process of another user
  (``SO_PEERCRED``) is closed at once and logged.
- A participant that disconnects without ``BYE`` is announced to the others
  with ``PEER_LOST``; every join and leave is announced with ``PEERS``.
- When the hub stops (or its process dies) every participant reads end-of-file
  and its bus raises ``can.CanOperationError``.

Run standalone with ``python -m can_transport.hub CHANNEL`` (a name in the
user's private directory, or a path; stops on SIGINT/SIGTERM).
"""

from __future__ import annotations

import logging
import selectors
import socket
import threading
from dataclasses import dataclass, field

from can_transport import socket_path, wire
from can_transport.socket_path import SOCKET_BUFFER_BYTES

LOG = logging.getLogger(__name__)

_READ_CHUNK_BYTES = 1 << 16
DEFAULT_MAX_BACKLOG_RECORDS = 10_000


@dataclass
class _Participant:
    sock: socket.socket
    inbox: bytearray = field(default_factory=bytearray)
    outbox: bytearray = field(default_factory=bytearray)
    said_bye: bool = False
    dropped: int = 0


class Hub:
    """A broadcast hub bound to ``path``; ``start()`` runs it in a daemon thread.

    Parameters
    ----------
    path : str
        Filesystem path of the socket. Must not exist (remove stale files first).
    max_backlog_records : int
        Records queued for one participant before the hub drops frames for it.
    """

    def __init__(self, path: str, max_backlog_records: int = DEFAULT_MAX_BACKLOG_RECORDS) -> None:
        self.path = path
        self._max_backlog_bytes = max_backlog_records * wire.RECORD_SIZE
        self.dropped_frames = 0  # frames not relayed to a participant that did not read (total)
        self._listener, self._inode = socket_path.listen(path, 16)
        self._wake_r, self._wake_w = socket.socketpair(socket.AF_UNIX)
        self._selector = selectors.DefaultSelector()
        self._selector.register(self._listener, selectors.EVENT_READ, "accept")
        self._selector.register(self._wake_r, selectors.EVENT_READ, "wake")
        self._participants: dict[socket.socket, _Participant] = {}
        self._stopping = False
        self._thread: threading.Thread | None = None

    def start(self) -> "Hub":
        """Run the loop in a daemon thread and return self."""
        self._thread = threading.Thread(target=self.serve_forever, name=f"crd-hub:{self.path}", daemon=True)
        self._thread.start()
        return self

    def stop(self, timeout_s: float = 2.0) -> None:
        """Stop the loop, disconnect everyone and remove the socket file. Idempotent."""
        if self._stopping:
            return
        self._stopping = True
        try:
            self._wake_w.send(b"x")
        except OSError:
            pass
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout_s)

    def serve_forever(self) -> None:
        """Relay until ``stop()``; always cleans up."""
        LOG.info("hub listening on %s", self.path)
        try:
            while not self._stopping:
                for key, events in self._selector.select():
                    self._dispatch(key, events)
        finally:
            self._close_all()

    def _dispatch(self, key: selectors.SelectorKey, events: int) -> None:
        if key.data == "accept":
            self._accept()
        elif key.data == "wake":
            self._wake_r.recv(64)
        else:
            participant = key.data
            if events & selectors.EVENT_READ and participant.sock in self._participants:
                self._read(participant)
            if events & selectors.EVENT_WRITE and participant.sock in self._participants:
                self._flush(participant)

    def _accept(self) -> None:
        try:
            sock, _ = self._listener.accept()
        except BlockingIOError:
            return
        if not socket_path.same_user(sock):
            LOG.warning("%s: refused a participant of uid %d (a bus is private to its user)",
                        self.path, socket_path.peer_uid(sock))
            sock.close()
            return
        sock.setblocking(False)
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, SOCKET_BUFFER_BYTES)
        participant = _Participant(sock)
        self._participants[sock] = participant
        self._selector.register(sock, selectors.EVENT_READ, participant)
        LOG.info("participant joined %s (%d connected)", self.path, len(self._participants))
        self._announce_peers()

    def _read(self, participant: _Participant) -> None:
        try:
            chunk = participant.sock.recv(_READ_CHUNK_BYTES)
        except BlockingIOError:
            return
        except OSError:
            chunk = b""
        if not chunk:
            self._drop(participant)
            return
        inbox = participant.inbox
        inbox += chunk
        whole = len(inbox) - len(inbox) % wire.RECORD_SIZE
        for offset in range(0, whole, wire.RECORD_SIZE):
            kind = inbox[offset + 12]
            if kind == wire.KIND_FRAME:
                self._relay(participant, bytes(inbox[offset:offset + wire.RECORD_SIZE]))
            elif kind == wire.KIND_BYE:
                participant.said_bye = True
        del inbox[:whole]
        for other in list(self._participants.values()):
            if other is not participant and other.outbox:
                self._flush(other)

    def _relay(self, sender: _Participant, record: bytes) -> None:
        for other in self._participants.values():
            if other is sender:
                continue
            if len(other.outbox) >= self._max_backlog_bytes:
                other.dropped += 1
                self.dropped_frames += 1
                continue
            if other.dropped and len(other.outbox) < self._max_backlog_bytes // 2:
                other.outbox += wire.pack_control(wire.KIND_OVERRUN, min(other.dropped, 0xFFFFFFFF))
                other.dropped = 0
            other.outbox += record

    def _flush(self, participant: _Participant) -> None:
        if participant.sock not in self._participants:
            return
        try:
            sent = participant.sock.send(participant.outbox) if participant.outbox else 0
        except BlockingIOError:
            sent = 0
        except OSError:
            self._drop(participant)
            return
        del participant.outbox[:sent]
        events = selectors.EVENT_READ | (selectors.EVENT_WRITE if participant.outbox else 0)
        self._selector.modify(participant.sock, events, participant)

    def _drop(self, participant: _Participant) -> None:
        if participant.sock not in self._participants:
            return
        self._selector.unregister(participant.sock)
        del self._participants[participant.sock]
        participant.sock.close()
        lost = not participant.said_bye
        LOG.log(logging.WARNING if lost else logging.INFO, "participant %s %s (%d connected)",
                "lost" if lost else "left", self.path, len(self._participants))
        for other in self._participants.values():
            if lost:
                other.outbox += wire.pack_control(wire.KIND_PEER_LOST)
        self._announce_peers()

    def _announce_peers(self) -> None:
        others = max(len(self._participants) - 1, 0)
        for participant in list(self._participants.values()):
            participant.outbox += wire.pack_control(wire.KIND_PEERS, others)
            self._flush(participant)

    def _close_all(self) -> None:
        for participant in list(self._participants.values()):
            participant.sock.close()
        self._participants.clear()
        self._selector.close()
        self._listener.close()
        self._wake_r.close()
        self._wake_w.close()
        socket_path.unlink_if_ours(self.path, self._inode)
        LOG.info("hub on %s stopped", self.path)


def main(argv: list[str] | None = None) -> int:
    """``python -m can_transport.hub PATH``: run a standalone hub until SIGINT/SIGTERM."""
    import argparse
    import signal

    parser = argparse.ArgumentParser(prog="python -m can_transport.hub", description=__doc__.splitlines()[0])
    parser.add_argument("channel", help="a channel name, e.g. can0 (in your private directory), or a socket path")
    parser.add_argument("-v", "--verbose", action="store_true", help="log joins and leaves")
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING, format="%(asctime)s %(name)s %(message)s")
    path = socket_path.resolve_channel(args.channel)
    with socket_path.channel_lock(path):
        live = socket_path.connect_or_none(path, "a hub")
        if live is not None:
            live.close()
            parser.error(f"{path} is in use: something listens there")
        socket_path.remove_stale_socket(path)
        hub = Hub(path)
    signal.signal(signal.SIGTERM, lambda *_: hub.stop(timeout_s=0))
    signal.signal(signal.SIGINT, lambda *_: hub.stop(timeout_s=0))
    print(f"hub listening on {path}", flush=True)
    hub.serve_forever()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
