"""How the co-simulation reaches the ECU: in process, or over a bus to a separate process.

:class:`EcuOptions` (``crd run/paper --ecu inprocess|process|attach``):

* ``inprocess`` (default): an :class:`ecu.EcuNode` on an in-process python-can
  virtual bus, stepped by the master (:class:`InProcessLink`);
* ``process``: the master opens the bus first (``crd_pair`` in lock-step:
  point to point, it listens; ``crd_unix`` in real time: it hosts the hub),
  spawns ``crd ecu`` (:mod:`cosim.link.ecu_process`), waits up to
  ``join_timeout_s`` for it to join, and stops it by PID at the end;
* ``attach``: an ECU already running on ``interface``/``channel``; the
  master waits up to ``join_timeout_s`` for it.

Lock-step over a bus (:class:`BusLink`, ``realtime=False``): each cycle the
master sends its frames, then ``SimClock`` (``SimTimeMs = round(t * 1000)``);
the ECU (``crd ecu --sim-time``) runs one cycle on it, after the frames before
it, and the master waits up to ``stall_timeout_s`` (wall time) for that
cycle's ``SafetyOverride`` (and, for a spawned ECU, the ``EcuStatus`` due in
that cycle) before it advances. The ECU sees the same frames at the same cycle
times as in process, so metrics and time series are identical.

Real time (``realtime=True``): the master paces each cycle to the absolute
wall-clock deadline ``t0 + k * 0.01 s`` and takes whatever the ECU (running
``EcuNode.run`` on its own clock) sent since the previous cycle; lag and
jitter of the master's cycle starts are reported (same definitions as
:mod:`ecu.scheduler`).

ECU lost: no frame at all for ``reply_timeout_s`` (real time), or a bus error
after which the spawned process is dead or no peer is left, records an
``ecu_lost`` event; the master then stops waiting and the gateway's
``SafetyOverride`` timeout returns the plant to the driver's commands (the
run exits 4 unless ``[checks] expect_events`` lists ``ecu_lost``). An ECU that
is there but silent in lock-step is a stall (:mod:`cosim.link.stall`): the
master waits up to ``stall_timeout_s`` with simulated time held, then stops
the run with an error. Nothing waits without a bound. Events are rate-limited
(:class:`cosim.results.events.EventLog`): a dead peer fails every frame, and
only the first few ``bus_error`` events and a count are kept and logged.
"""

from __future__ import annotations

import itertools
import logging
import os
import shutil
import subprocess
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import can

from can_dbc import LAYOUTS, CounterSequence, encode
from ecu import EcuConfig, EcuNode, Percentiles

from .ecu_process import EcuProcess
from ..errors import CosimError
from ..results.events import EventLog
from ..results.run_record import RunEvent
from .stall import DEFAULT_STALL_TIMEOUT_S, StallWatch

log = logging.getLogger(__name__)

ECU_MODES = ("inprocess", "process", "attach")
OVERRIDE_ID = LAYOUTS["SafetyOverride"].frame_id
STATUS_ID = LAYOUTS["EcuStatus"].frame_id
_channels = itertools.count()
_POLL_S = 0.005


class EcuLinkError(CosimError, RuntimeError):
    """The out-of-process ECU could not be reached (did not join in time, or exited at start)."""


@dataclass(frozen=True, slots=True)
class EcuOptions:
    """Where the ECU runs and how the master talks to it (times in wall-clock s)."""

    mode: str = "inprocess"
    #: python-can interface; None: ``crd_pair`` for a spawned ECU in lock-step, else ``crd_unix``
    interface: str | None = None
    channel: str | None = None  # process: a fresh socket in a private temp dir when None
    realtime: bool = False
    join_timeout_s: float = 10.0
    reply_timeout_s: float = 1.0
    stop_timeout_s: float = 5.0
    stall_timeout_s: float = DEFAULT_STALL_TIMEOUT_S  # lock-step: longest wait for one cycle's reply

    def __post_init__(self) -> None:
        if self.interface is None:
            pair = self.mode == "process" and not self.realtime
            object.__setattr__(self, "interface", "crd_pair" if pair else "crd_unix")
        if self.mode not in ECU_MODES:
            raise EcuLinkError(f"ecu mode: expected one of {list(ECU_MODES)}, got {self.mode!r}")
        if self.mode == "attach" and not self.channel:
            raise EcuLinkError("ecu mode 'attach': expected the channel of the running ECU's bus, got none")
        if self.realtime and self.mode == "inprocess":
            raise EcuLinkError("--realtime: expected --ecu process or attach (an ECU on its own clock), "
                               "got inprocess")
        for name in ("join_timeout_s", "reply_timeout_s", "stop_timeout_s", "stall_timeout_s"):
            if not getattr(self, name) > 0.0:
                raise EcuLinkError(f"{name}: expected > 0 s, got {getattr(self, name)!r}")


class InProcessLink:
    """The ECU node on an in-process virtual bus, stepped by the master (the reference)."""

    realtime = False

    def __init__(self, config: EcuConfig) -> None:
        channel = f"crd-{os.getpid()}-{next(_channels)}"
        self._bus = can.Bus(interface="virtual", channel=channel, receive_own_messages=False)
        self._ecu_bus = can.Bus(interface="virtual", channel=channel, receive_own_messages=False)
        self.node = EcuNode(self._ecu_bus, config)
        self.events: list[RunEvent] = []
        self.timing: dict[str, float] = {}

    def start(self) -> None:
        pass

    def send(self, t_s: float, cycle: int, frames: list[can.Message], cost: dict | None) -> list[can.Message]:
        """Send ``frames`` and run one ECU cycle; returns the extra frames sent (none here)."""
        clock = time.perf_counter_ns
        c0 = clock()
        for msg in frames:
            self._bus.send(msg)
        c1 = clock()
        self.node.step(t_s)
        if cost is not None:
            cost["bus"] += c1 - c0
            cost["ecu"] += clock() - c1
        return []

    def collect(self, t_s: float, cycle: int, cost: dict | None) -> list[can.Message]:
        """The ECU's frames of this cycle."""
        c0 = time.perf_counter_ns()
        received = []
        while (msg := self._bus.recv(timeout=0.0)) is not None:
            received.append(msg)
        if cost is not None:
            cost["bus"] += time.perf_counter_ns() - c0
        return received

    def close(self) -> None:
        self._ecu_bus.shutdown()
        self._bus.shutdown()


class _Samples:
    def __init__(self) -> None:
        self.values: list[float] = []

    def add(self, v: float) -> None:
        self.values.append(v)

    def percentiles(self) -> Percentiles:
        return Percentiles.of(self.values, max(self.values, default=0.0))


class BusLink:
    """The ECU as another participant on a real python-can bus (process or attach)."""

    def __init__(self, options: EcuOptions, config: EcuConfig, cycle_s: float) -> None:
        self.options = options
        self.realtime = options.realtime
        self._config = config
        self._cycle_s = cycle_s
        self._status_period = config.status_period_cycles if options.mode == "process" else None
        self._tmpdir: Path | None = None
        self.process: EcuProcess | None = None
        self.events = EventLog()
        self.timing: dict[str, float] = {}
        self.ecu_report = ""
        self._stall = StallWatch(options.reply_timeout_s, options.stall_timeout_s)
        self.lost = False
        self.join_wait_s = 0.0
        self._clock_seq = CounterSequence()
        self._lag, self._jitter = _Samples(), _Samples()
        self._t0 = 0.0
        self._prev_start: float | None = None
        self._last_rx_wall = 0.0
        channel = options.channel
        if channel is None:
            self._tmpdir = Path(tempfile.mkdtemp(prefix="crd-ecu-"))
            channel = str(self._tmpdir / "can.sock")
        self.channel = channel
        self.bus: can.BusABC | None = None
        try:
            self.bus = can.Bus(interface=options.interface, channel=channel, receive_own_messages=False)
            if options.mode == "process":
                workdir = self._tmpdir or Path(tempfile.mkdtemp(prefix="crd-ecu-"))
                self._tmpdir = workdir
                self.process = EcuProcess(options.interface, channel, config, not options.realtime, workdir)
        except BaseException:
            self.close()
            raise

    @property
    def pid(self) -> int | None:
        return self.process.pid if self.process else None

    def start(self) -> None:
        """Wait (at most ``join_timeout_s``) for the ECU to join; drop anything sent before."""
        started = time.monotonic()
        deadline = started + self.options.join_timeout_s
        counts = hasattr(self.bus, "peer_count")
        while True:
            if self.process is not None and not self.process.alive():
                self.process.stop()
                raise EcuLinkError(f"crd ecu (pid {self.process.pid}) exited with code {self.process.returncode}"
                                   f" before joining the bus: {self.process.output()[-500:]}")
            if counts and self.bus.peer_count >= 1:
                break
            if not counts and self.realtime and self._recv(_POLL_S) is not None:
                break
            if not counts and not self.realtime:
                break  # the first cycle's reply wait uses the join timeout (see exchange)
            if time.monotonic() >= deadline:
                raise EcuLinkError(f"expected an ECU on {self.options.interface} {self.channel} within "
                                   f"{self.options.join_timeout_s} s, none joined")
            time.sleep(_POLL_S)
        while self._recv(0.0) is not None:
            pass
        self._t0 = time.perf_counter()
        self._last_rx_wall = time.monotonic()
        self.join_wait_s = self._last_rx_wall - started

    # -- one cycle ---------------------------------------------------------------
    def send(self, t_s: float, cycle: int, frames: list[can.Message], cost: dict | None) -> list[can.Message]:
        """Send ``frames`` (then, in lock-step, ``SimClock``); returns the extra frames sent."""
        c0 = time.perf_counter_ns()
        extra: list[can.Message] = []
        for msg in frames:
            self._send(msg, t_s)
        if not self.realtime:
            clock = encode("SimClock", {"SimTimeMs": int(round(t_s * 1000.0))}, self._clock_seq.next())
            self._send(clock, t_s)
            extra.append(clock)
        if cost is not None:
            cost["bus"] += time.perf_counter_ns() - c0
        return extra

    def collect(self, t_s: float, cycle: int, cost: dict | None) -> list[can.Message]:
        """Lock-step: wait (bounded) for this cycle's reply; real time: whatever has arrived."""
        c0 = time.perf_counter_ns()
        received = self._collect(t_s, cycle)
        if cost is not None:
            cost["bus"] += time.perf_counter_ns() - c0
        return received

    def pace(self, cycle: int) -> None:
        """Real time: wait for cycle ``cycle``'s wall-clock deadline; record lag and jitter."""
        deadline = self._t0 + cycle * self._cycle_s
        while (remaining := deadline - time.perf_counter()) > 0.0:
            time.sleep(remaining if remaining > 0.002 else 0.0)
        start = time.perf_counter()
        self._lag.add(start - deadline)
        if self._prev_start is not None:
            self._jitter.add(abs(start - self._prev_start - self._cycle_s))
        self._prev_start = start

    def _collect(self, t_s: float, cycle: int) -> list[can.Message]:
        received: list[can.Message] = []
        if self.realtime or self.lost:
            while (msg := self._recv(0.0, t_s)) is not None:
                received.append(msg)
            now = time.monotonic()
            if received:
                self._last_rx_wall = now
            elif self.realtime and not self.lost and now - self._last_rx_wall > self.options.reply_timeout_s:
                self._lose(t_s, f"no frame from the ECU for {now - self._last_rx_wall:.3f} s wall time "
                                f"(timeout {self.options.reply_timeout_s} s)")
            return received
        wanted = {OVERRIDE_ID}
        if self._status_period is not None and cycle % self._status_period == 0:
            wanted.add(STATUS_ID)
        first = cycle == 0 and not hasattr(self.bus, "peer_count")
        wait_s = self.options.join_timeout_s if first else self.options.stall_timeout_s
        started = time.monotonic()
        deadline = started + wait_s
        while wanted and not self.lost:
            remaining = deadline - time.monotonic()
            if remaining <= 0.0:
                raise self._stall.expired(t_s, time.monotonic() - started, self._who())
            msg = self._recv(remaining, t_s)
            if msg is not None:
                received.append(msg)
                wanted.discard(msg.arbitration_id)
        if not first:
            self._stall.waited(t_s, time.monotonic() - started, self.events)
        while (msg := self._recv(0.0, t_s)) is not None:  # e.g. a second ECU's frames
            received.append(msg)
        return received

    def _recv(self, timeout: float, t_s: float = 0.0) -> can.Message | None:
        try:
            return self.bus.recv(timeout=timeout)
        except can.CanError as exc:
            self._bus_error(t_s, exc)
            return None

    def _send(self, msg: can.Message, t_s: float) -> None:
        try:
            self.bus.send(msg)
        except can.CanError as exc:
            self._bus_error(t_s, exc)

    def _who(self) -> str:
        if self.process is None:
            return f"the ECU on {self.options.interface} {self.channel}"
        return f"crd ecu pid {self.process.pid}, {'still running' if self.process.alive() else 'exited'}"

    def _bus_error(self, t_s: float, exc: Exception) -> None:
        if self.events.add(RunEvent(t_s, "bus_error", str(exc))):  # rate-limited: a dead peer fails every frame
            log.warning("t=%.3f s: bus error: %s", t_s, exc)
        gone = getattr(self.bus, "peer_count", 1) == 0
        if self.process is not None and gone:
            try:  # it left the bus; give the kernel a moment to report its exit
                self.process.proc.wait(timeout=0.5)
            except subprocess.TimeoutExpired:
                pass
        dead = self.process is not None and not self.process.alive()
        if dead:
            self._lose(t_s, f"crd ecu (pid {self.process.pid}) exited with code {self.process.proc.returncode}")
        elif gone:
            self._lose(t_s, "no ECU left on the bus")

    def _lose(self, t_s: float, detail: str) -> None:
        if self.lost:
            return
        self.lost = True
        self.events.append(RunEvent(t_s, "ecu_lost", detail + "; the gateway falls back to the driver"))
        log.warning("t=%.3f s: ECU lost: %s", t_s, detail)

    def close(self) -> None:
        """Stop the spawned ECU (by PID), then leave the bus; idempotent."""
        try:
            if self.process is not None:
                code = self.process.stop(self.options.stop_timeout_s)
                self.ecu_report = self.process.output()
                log.info("crd ecu pid %d exited with %s", self.process.pid, code)
        finally:
            if self._lag.values:
                lag, jit = self._lag.percentiles(), self._jitter.percentiles()
                self.timing = {"lag_p50_s": lag.p50, "lag_p99_s": lag.p99, "lag_max_s": lag.max,
                               "jitter_p50_s": jit.p50, "jitter_p99_s": jit.p99, "jitter_max_s": jit.max}
            if self.bus is not None:
                self.bus.shutdown()
            if self._tmpdir is not None:
                shutil.rmtree(self._tmpdir, ignore_errors=True)
                self._tmpdir = None


def open_link(options: EcuOptions, config: EcuConfig, cycle_s: float) -> InProcessLink | BusLink:
    """The link for ``options.mode``."""
    if options.mode == "inprocess":
        return InProcessLink(config)
    return BusLink(options, config, cycle_s)
