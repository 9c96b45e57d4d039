"""The socket-path channel shared by ``crd_unix`` and ``crd_pair``: where it lives, who may use it.

A channel is either a *name* (``"can0"``: letters, digits, ``.``, ``_``, ``-``)
or a filesystem path (anything with a ``/``). A name is a socket in the user's
private directory, :func:`private_dir`: ``$XDG_RUNTIME_DIR/crd-can``, or
``$TMPDIR/crd-can-<uid>`` (``/tmp`` when ``TMPDIR`` is unset), created with
mode 0700 and refused when it is a symbolic link, not a directory, not owned
by this user, or open to others. It is removed again when the last socket
or lock file in it goes (:func:`release_private_dir`), so a named channel
leaves nothing behind once its processes have closed their buses.

What the transports refuse, whatever the channel (each a
``can.CanInitializationError`` that names the path):

- a path that holds anything but a socket (a regular file, a directory, a
  symbolic link): it is never deleted or followed;
- a socket owned by another user, and a peer process of another user
  (``SO_PEERCRED`` after ``connect``/``accept``): a user's bus is private to
  that user, root included;
- a lock file ``<path>.lock`` that is a symbolic link (opened with
  ``O_NOFOLLOW``) or owned by another user.

The lock serialises starters that find nobody listening (one of them listens,
the others connect to it). It is removed by whoever holds it when it is done;
a starter that was waiting on a removed lock file takes the lock again on the
new file (the inode check in :func:`channel_lock`), so removal cannot let two
starters in at once.
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import logging
import os
import re
import socket
import stat
import struct
from typing import Iterator

import can

LOG = logging.getLogger(__name__)

MAX_PATH_BYTES = 107  # sizeof(sockaddr_un.sun_path) - 1 on Linux
SOCKET_BUFFER_BYTES = 1 << 20
_NOBODY_LISTENS = (errno.ENOENT, errno.ECONNREFUSED)
_NAME = re.compile(r"[A-Za-z0-9_-][A-Za-z0-9._-]*")
_UCRED = struct.Struct("3i")  # struct ucred: pid, uid, gid


def private_dir_path() -> str:
    """Where the user's private channel directory is (whether or not it exists)."""
    runtime = os.environ.get("XDG_RUNTIME_DIR")
    if runtime:
        return os.path.join(runtime, "crd-can")
    return os.path.join(os.environ.get("TMPDIR") or "/tmp", f"crd-can-{os.getuid()}")


def release_private_dir(path: str) -> None:
    """Remove the private channel directory that holds ``path`` if it is now empty (any other
    directory, or one still in use, is left alone)."""
    folder = os.path.dirname(path)
    if folder == private_dir_path():
        try:
            os.rmdir(folder)
        except OSError:
            pass  # another channel's socket or lock is still in it


def private_dir() -> str:
    """The user's private channel directory (created 0700 if absent); refuse one others could use."""
    path = private_dir_path()
    info = None
    while info is None:
        try:
            os.mkdir(path, 0o700)
        except FileExistsError:
            pass
        except OSError as exc:
            raise can.CanInitializationError(f"cannot create the private channel directory {path}: {exc}") from exc
        try:
            info = os.lstat(path)
        except FileNotFoundError:
            continue  # released by its last user just now (release_private_dir): made again
    problem = None
    if stat.S_ISLNK(info.st_mode) or not stat.S_ISDIR(info.st_mode):
        problem = "is not a directory (a symbolic link or a file)"
    elif info.st_uid != os.getuid():
        problem = f"is owned by uid {info.st_uid}, not this user ({os.getuid()})"
    elif info.st_mode & 0o077:
        problem = f"has mode {stat.S_IMODE(info.st_mode):o}, expected 700"
    if problem:
        raise can.CanInitializationError(f"refusing the private channel directory {path}: it {problem}")
    return path


def resolve_channel(channel: object) -> str:
    """The socket path of ``channel``: a path as given, a name inside :func:`private_dir`."""
    text = os.fspath(channel) if isinstance(channel, (str, os.PathLike)) else None
    if not isinstance(text, str) or not text:
        raise can.CanInitializationError(f"channel must be a name or a socket path, got {channel!r}")
    if "/" not in text:
        if not _NAME.fullmatch(text):
            raise can.CanInitializationError(
                f"channel name must be letters, digits, '.', '_' or '-' (or give a path), got {text!r}")
        text = os.path.join(private_dir(), text + ".sock")
    check_path(text)
    return text


def check_path(path: str) -> None:
    """Raise ``can.CanInitializationError`` unless ``path`` fits a Unix socket address."""
    size = len(os.fsencode(path))
    if not path or size > MAX_PATH_BYTES:
        raise can.CanInitializationError(
            f"channel must be a socket path of 1..{MAX_PATH_BYTES} bytes, got {size} bytes: {path!r}")


def check_existing(path: str) -> bool:
    """True if a socket of this user is at ``path``, False if nothing is; refuse anything else."""
    try:
        info = os.lstat(path)
    except FileNotFoundError:
        return False
    if not stat.S_ISSOCK(info.st_mode):
        kind = "a symbolic link" if stat.S_ISLNK(info.st_mode) else "not a socket"
        raise can.CanInitializationError(f"refusing channel {path}: it is {kind}; remove it or choose another path")
    if info.st_uid != os.getuid():
        raise can.CanInitializationError(
            f"refusing channel {path}: its socket is owned by uid {info.st_uid}, not this user ({os.getuid()})")
    return True


def remove_stale_socket(path: str) -> None:
    """Remove a socket of this user that nobody listens on (the caller holds the channel lock)."""
    if check_existing(path):
        LOG.info("removing stale socket %s", path)
        os.unlink(path)


def peer_uid(sock: socket.socket) -> int:
    """The user id of the process at the other end of a connected Unix socket."""
    _pid, uid, _gid = _UCRED.unpack(sock.getsockopt(socket.SOL_SOCKET, socket.SO_PEERCRED, _UCRED.size))
    return uid


def same_user(sock: socket.socket) -> bool:
    """True when the peer of ``sock`` runs as this process's user."""
    return peer_uid(sock) == os.getuid()


def connect_or_none(path: str, listener: str) -> socket.socket | None:
    """A non-blocking stream socket connected to ``path``; None if nobody listens there.

    ``listener`` names what should be listening, for the error on any other
    failure. Refuses a path that is not this user's socket and a listener
    process of another user.
    """
    if not check_existing(path):
        return None
    sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    try:
        sock.connect(path)
    except OSError as exc:
        sock.close()
        if exc.errno in _NOBODY_LISTENS:
            return None
        raise can.CanInitializationError(f"cannot connect to {listener} at {path}: {exc}") from exc
    uid = peer_uid(sock)
    if uid != os.getuid():
        sock.close()
        raise can.CanInitializationError(
            f"refusing {listener} at {path}: it runs as uid {uid}, not this user ({os.getuid()})")
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, SOCKET_BUFFER_BYTES)
    sock.setblocking(False)
    return sock


def listen(path: str, backlog: int) -> tuple[socket.socket, int]:
    """A non-blocking listening socket at ``path`` (mode 0600 before it exists) and its inode."""
    listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    try:
        os.fchmod(listener.fileno(), 0o600)
        listener.bind(path)
        os.chmod(path, 0o600)
        inode = os.lstat(path).st_ino
        listener.listen(backlog)
        listener.setblocking(False)
    except BaseException:
        listener.close()
        raise
    return listener, inode


def unlink_if_ours(path: str, inode: int) -> None:
    """Remove the socket file at ``path`` if it is still the one with ``inode``."""
    try:
        if os.lstat(path).st_ino == inode:
            os.unlink(path)
    except FileNotFoundError:
        pass
    release_private_dir(path)


@contextlib.contextmanager
def channel_lock(path: str) -> Iterator[None]:
    """Hold the exclusive lock ``<path>.lock`` (never following a symbolic link); remove it after."""
    lock_path = path + ".lock"
    while True:
        try:
            fd = os.open(lock_path, os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW | os.O_CLOEXEC, 0o600)
        except OSError as exc:
            if exc.errno == errno.ENOENT and os.path.dirname(path) == private_dir_path():
                private_dir()  # released by its last user since resolve_channel made it: made again
                continue
            reason = "it is a symbolic link" if exc.errno == errno.ELOOP else str(exc)
            raise can.CanInitializationError(f"refusing the lock file {lock_path}: {reason}") from exc
        try:
            fcntl.flock(fd, fcntl.LOCK_EX)
            held = os.fstat(fd)
            if held.st_uid != os.getuid():
                raise can.CanInitializationError(
                    f"refusing the lock file {lock_path}: owned by uid {held.st_uid}, not this user ({os.getuid()})")
            if _same_file(lock_path, held):
                break
        except BaseException:
            os.close(fd)
            raise
        os.close(fd)  # the holder before us removed that file: lock the current one
    try:
        yield
    finally:
        try:
            os.unlink(lock_path)
        except FileNotFoundError:
            pass
        os.close(fd)
        release_private_dir(lock_path)


def _same_file(path: str, held: os.stat_result) -> bool:
    try:
        now = os.lstat(path)
    except FileNotFoundError:
        return False
    return (now.st_dev, now.st_ino) == (held.st_dev, held.st_ino)
