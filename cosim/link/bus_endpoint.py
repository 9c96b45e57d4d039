"""The master's end of a bus shared with an ECU elsewhere: the bus, a spawned ECU, joining, losing it.

One job, shared by :mod:`cosim.link.lock_step` and :mod:`cosim.link.real_time`:
open the bus (a fresh socket in a private temp dir unless a channel is given),
spawn ``crd ecu`` for ``--ecu process``, wait (bounded) for the ECU to join,
send and receive without letting a bus error escape into the loop, and record
``ecu_lost`` when the ECU is gone. Nothing waits without a bound.

Whether the transport can count its participants is a typed capability
(:class:`PeerCounting`, ``crd_unix`` and ``crd_pair`` have it), checked once
when the bus opens; without it (e.g. SocketCAN) joining is seen from the
ECU's first frame.
"""

from __future__ import annotations

import dataclasses
import logging
import shutil
import subprocess
import tempfile
import time
from pathlib import Path
from typing import Callable, Protocol, runtime_checkable

import can

from can_dbc import write_key_file
from ecu import EcuConfig
from ecu.scheduler import PeerCounting

from ..results.events import EventLog
from ..results.run_record import RunEvent
from .ecu_identity import IdentityCheck
from .ecu_link import EcuLinkError, EcuOptions
from .ecu_process import EcuProcess, prepare_spare

log = logging.getLogger(__name__)
_POLL_S = 0.005
_DRAIN_QUIET_S = 0.002
#: how often a join blocked on the bus looks whether the spawned ECU died (s)
_JOIN_CHECK_S = 0.05


@runtime_checkable
class PeerWaiting(Protocol):
    """A bus that can block until its peer joins (``crd_pair``)."""

    def wait_for_peer(self, timeout_s: float) -> bool:
        """Wait up to ``timeout_s`` for the other participant; True once it is there."""


@runtime_checkable
class BatchSending(Protocol):
    """A bus that can send several frames in one write (``crd_pair``), each still its own frame."""

    def begin_batch(self) -> None:
        """Keep the frames sent from now on."""

    def end_batch(self) -> None:
        """Write the kept frames in one go; raise ``can.CanError`` if that fails."""


class BusEndpoint:
    """The bus, the spawned ECU (``--ecu process``) and the ECU-lost bookkeeping."""

    def __init__(self, options: EcuOptions, config: EcuConfig, key: bytes | None = None) -> None:
        self.options = options
        self.keyed = key is not None
        self.process: EcuProcess | None = None
        self.events = EventLog()  # rate-limited: a dead peer fails every frame
        self.ecu_report = ""
        self.lost = False
        self.join_wait_s = 0.0
        self._tmpdir: Path | None = None
        channel = options.channel
        if channel is None:
            self._tmpdir = Path(tempfile.mkdtemp(prefix="crd-ecu-"))
            channel = str(self._tmpdir / "can.sock")
        self.channel = channel
        self.bus: can.BusABC | None = None
        try:
            self.bus = can.Bus(interface=options.interface, channel=channel, receive_own_messages=False)
            self.peers: PeerCounting | None = self.bus if isinstance(self.bus, PeerCounting) else None
            self._batcher: BatchSending | None = self.bus if isinstance(self.bus, BatchSending) else None
            if options.mode == "process":
                self._tmpdir = self._tmpdir or Path(tempfile.mkdtemp(prefix="crd-ecu-"))
                if key is not None and not (options.key_file or config.key_file):  # the run's fresh key, 0600
                    config = dataclasses.replace(config, key_file=str(write_key_file(self._tmpdir / "secoc.key", key)))
                elif options.key_file:
                    config = dataclasses.replace(config, key_file=options.key_file)
                self.process = EcuProcess(options.interface, channel, config, not options.realtime, self._tmpdir)
        except BaseException:
            self.close()
            raise

    @property
    def pid(self) -> int | None:
        return self.process.pid if self.process else None

    def join(self, first_frame_joins: bool, seen: Callable[[can.Message], None] = lambda msg: None) -> None:
        """Wait (at most ``join_timeout_s``) for the ECU; drop anything sent before (after showing it to ``seen``).

        Without a peer count, ``first_frame_joins`` waits for the ECU's first frame (real
        time); otherwise the first cycle's reply wait stands in for joining (lock-step).
        """
        started = time.monotonic()
        deadline = started + self.options.join_timeout_s
        while True:
            if self.process is not None and not self.process.alive():
                self.process.stop()
                raise EcuLinkError(f"crd ecu (pid {self.process.pid}) exited with code {self.process.returncode}"
                                   f" before joining the bus: {self.process.output()[-500:]}")
            if self.peers is not None:
                if self.peers.peer_count >= 1:
                    break
            elif not first_frame_joins:
                break
            elif (first := self.recv(_POLL_S)) is not None:
                seen(first)
                break
            if time.monotonic() >= deadline:
                raise EcuLinkError(f"expected an ECU on {self.options.interface} {self.channel} within "
                                   f"{self.options.join_timeout_s} s, none joined")
            if isinstance(self.bus, PeerWaiting):  # woken by the connection itself, not the next poll
                self.bus.wait_for_peer(min(_JOIN_CHECK_S, max(0.0, deadline - time.monotonic())))
            else:
                time.sleep(_POLL_S)
        self._drop_before_run(first_frame_joins, seen)
        self.join_wait_s = time.monotonic() - started
        if self.process is not None and self.options.spare and not self.options.realtime:
            prepare_spare()  # the next run's ECU starts up now, beside this run (never in real time: jitter)

    def check_ecu(self, identity: IdentityCheck, realtime: bool) -> dict:
        """After :meth:`join`: wait (bounded) for the ECU to announce what it runs and judge it
        (:class:`~cosim.link.ecu_identity.EcuSettingsError` if it does not fit); drop what came meanwhile."""
        started = time.monotonic()
        record = identity.wait(lambda timeout_s: self.recv(timeout_s), self.options.join_timeout_s, self.who())
        self._drop_before_run(realtime, identity.offer)
        self.join_wait_s += time.monotonic() - started
        return {"placement": self.options.mode, **record}

    def _drop_before_run(self, realtime: bool, seen: Callable[[can.Message], None]) -> None:
        """Drop what came before the run, up to a quiet moment (showing each frame to ``seen``).

        A real-time ECU sends each SafetyOverride and its authenticator back to back, and a
        drain ending between the two would hand the gateway an authenticator without its
        frame (a false authentication failure).
        """
        while (msg := self.recv(_DRAIN_QUIET_S if realtime and self.keyed else 0.0)) is not None:
            seen(msg)

    def recv(self, timeout: float, t_s: float = 0.0) -> can.Message | None:
        try:
            return self.bus.recv(timeout=timeout)
        except can.CanError as exc:
            self._bus_error(t_s, exc)
            return None

    def send(self, msg: can.Message, t_s: float) -> None:
        try:
            self.bus.send(msg)
        except can.CanError as exc:
            self._bus_error(t_s, exc)

    def send_all(self, msgs: list[can.Message], t_s: float) -> None:
        """Send ``msgs`` in order; on a bus that batches, in one write (one wake-up of the ECU)."""
        if self._batcher is None:
            for msg in msgs:
                self.send(msg, t_s)
            return
        self._batcher.begin_batch()
        try:
            for msg in msgs:
                self.send(msg, t_s)  # a frame refused at once is a bus error of its own, as unbatched
        finally:
            try:
                self._batcher.end_batch()
            except can.CanError as exc:  # the batch's write failed
                self._bus_error(t_s, exc)

    def drain(self, t_s: float, into: list[can.Message]) -> list[can.Message]:
        """Append every frame already received to ``into``; returns it."""
        while (msg := self.recv(0.0, t_s)) is not None:
            into.append(msg)
        return into

    def who(self) -> str:
        """The ECU, for messages: the spawned process and whether it runs, or the bus it is on."""
        if self.process is None:
            return f"the ECU on {self.options.interface} {self.channel}"
        return f"crd ecu pid {self.process.pid}, {'still running' if self.process.alive() else 'exited'}"

    def _bus_error(self, t_s: float, exc: Exception) -> None:
        if self.events.add(RunEvent(t_s, "bus_error", str(exc))):  # logged as often as kept
            log.warning("t=%.3f s: bus error: %s", t_s, exc)
        gone = self.peers is not None and self.peers.peer_count == 0
        if self.process is not None and gone:
            try:  # it left the bus; give the kernel a moment to report its exit
                self.process.proc.wait(timeout=0.5)
            except subprocess.TimeoutExpired:
                pass
        if self.process is not None and not self.process.alive():
            self.lose(t_s, f"crd ecu (pid {self.process.pid}) exited with code {self.process.proc.returncode}")
        elif gone:
            self.lose(t_s, "no ECU left on the bus")

    def lose(self, t_s: float, detail: str) -> None:
        """Record ``ecu_lost`` once; the master stops waiting and the gateway falls back to the driver."""
        if self.lost:
            return
        self.lost = True
        self.events.append(RunEvent(t_s, "ecu_lost", detail + "; the gateway falls back to the driver"))
        log.warning("t=%.3f s: ECU lost: %s", t_s, detail)

    def close(self) -> None:
        """Stop the spawned ECU (by PID), then leave the bus; idempotent.

        In lock-step the bus is left right after SIGTERM: the ECU, blocked waiting for the
        next ``SimClock``, wakes at the peer's ``BYE`` instead of at its next poll timeout
        (up to 50 ms), and stops, its stop event already set (a real-time ECU still sends
        until it stops, so there the bus is left after it exited).
        """
        try:
            if self.process is not None:
                self.process.signal_stop()
                if not self.options.realtime:
                    self._leave_bus()
                code = self.process.stop(self.options.stop_timeout_s)
                self.ecu_report = self.process.output()
                log.info("crd ecu pid %d exited with %s", self.process.pid, code)
        finally:
            self._leave_bus()
            if self._tmpdir is not None:
                shutil.rmtree(self._tmpdir, ignore_errors=True)
                self._tmpdir = None

    def _leave_bus(self) -> None:
        if self.bus is not None:
            self.bus.shutdown()  # idempotent
