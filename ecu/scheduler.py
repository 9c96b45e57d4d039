"""Schedulers for :class:`ecu.node.EcuNode`: real time on the wall clock, or sim time.

Real time: cycle ``k`` is due at the absolute deadline ``t0 + k * cycle_s``
on ``time.perf_counter`` (never accumulated, so there is no drift); until the
deadline the loop blocks in ``bus.recv`` and takes frames in as they arrive
(stamped with the coming cycle's time ``k * cycle_s``, exactly as the drain
in ``step`` would), then runs ``node.step(k * cycle_s)``. If a cycle
starts a whole period or more late, the cycles it overran are counted as
missed and skipped (the next deadline stays on the grid). The last ``SPIN_S``
(1 ms) of each wait polls the bus instead of blocking, so the cycle does not
start late by an OS wake-up. Figures:

* lag = start - deadline (s);
* jitter = |(start_k - start_{k-1}) - cycle_s| between consecutive cycles (s);
* step = the cycle's own run time (s).

Percentiles are nearest-rank over the most recent ``WINDOW`` cycles (one
hour at 100 Hz); maxima are over the whole run.

Sim time: one cycle per valid ``SimClock`` frame, after the frames received
before it, at ``t_s = SimTimeMs / 1000`` (see ``EcuNode.on_sim_message``).

Runs served by ``crd ecu`` (issue 25, :class:`RunBoundary`): a standalone ECU
serves one run after the other, each by a fresh :class:`~ecu.node.EcuNode`.
A run starts with the first frame the node takes in and is over when its
master has left the bus: on a bus that counts its participants (``crd_unix``,
``crd_pair``) when none is left, and on any bus after ``RUN_GAP_S`` (1 s) of
waiting without a frame (waiting, not wall time: an ECU stopped by
``SIGSTOP`` finds its frames queued when it resumes, and waited for none).
While no run is on, the node announces itself (``EcuIdentity``, waiting) every
``IDLE_ANNOUNCE_S`` and whenever a participant joins, so that a master knows a
fresh node listens before it starts.

Bus errors on receive: a one-off ``can.CanError`` (another participant died,
an overrun) is logged and the loop goes on; the same receive failing twice in
a row means the bus itself is gone (e.g. the hub's process died), and the
error propagates, ending the run (a stranded ECU process exits rather than
spinning).
"""

from __future__ import annotations

import logging
import threading
import time
from collections import deque
from dataclasses import dataclass
from typing import Callable, Iterable, Protocol, runtime_checkable

import can

log = logging.getLogger(__name__)

WINDOW = 360_000
RECV_POLL_S = 0.05
#: a served run is over after this long of waiting without a frame (s): its master has left
RUN_GAP_S = 1.0
#: while no run is on, a standalone node announces itself this often (s) (and when a participant joins)
IDLE_ANNOUNCE_S = 0.25
#: the final part of each wait for a deadline that is spent polling instead of blocking (s)
SPIN_S = 0.001


@dataclass(frozen=True, slots=True)
class Percentiles:
    p50: float
    p99: float
    max: float

    @classmethod
    def of(cls, values: Iterable[float], maximum: float) -> "Percentiles":
        ordered = sorted(values)
        if not ordered:
            return cls(0.0, 0.0, maximum)
        def rank(q: float) -> float:
            return ordered[min(len(ordered) - 1, max(0, int(round(q * len(ordered))) - 1))]
        return cls(rank(0.50), rank(0.99), maximum)

    def ms(self) -> str:
        return f"p50 {self.p50 * 1e3:.3f} p99 {self.p99 * 1e3:.3f} max {self.max * 1e3:.3f} ms"


@dataclass(frozen=True, slots=True)
class RunReport:
    """What a run did and how punctual it was (all durations in s)."""

    scheduling: str  # "real-time" | "sim-time"
    cycles: int
    missed_cycles: int
    lag_s: Percentiles
    jitter_s: Percentiles
    step_s: Percentiles

    def summary(self) -> str:
        return (f"{self.scheduling}: {self.cycles} cycles, {self.missed_cycles} missed; "
                f"lag {self.lag_s.ms()}; jitter {self.jitter_s.ms()}; step {self.step_s.ms()}")


class ScheduledNode(Protocol):
    """What a scheduler needs of a node (:class:`ecu.node.EcuNode` is one); no import of the node."""

    bus: can.BusABC

    def step(self, t_s: float) -> object:
        """Drain the bus and run one cycle at ``t_s`` (s)."""

    def ingest(self, msg: can.Message, t_s: float) -> None:
        """Check ``msg`` now and latch it as received at cycle time ``t_s``."""

    def on_sim_message(self, msg: can.Message) -> object | None:
        """Sim time: buffer ``msg``; a valid ``SimClock`` runs one cycle (returns its outputs, else None)."""


@runtime_checkable
class PeerCounting(Protocol):
    """A bus that knows how many other participants it has (``crd_unix``, ``crd_pair``)."""

    peer_count: int


class RunBoundary:
    """Where a run served by a standalone ECU begins and ends (module docstring), and its idle announcements.

    The scheduler reports what it sees: :meth:`frame` for each frame taken in, :meth:`waited`
    for each wait that brought none, which says whether the run is over. The bus's participants
    are counted only then: while frames come, the master is there.
    """

    def __init__(self, bus: can.BusABC, announce: Callable[[], None], gap_s: float = RUN_GAP_S) -> None:
        self._peers = bus if isinstance(bus, PeerCounting) else None
        self._announce = announce
        self._gap_s = gap_s
        self.started = False
        self._quiet_s = 0.0
        self._since_announce_s = 0.0
        self._peer_count = self._count()

    def _count(self) -> int:
        return self._peers.peer_count if self._peers is not None else 0

    def frame(self) -> None:
        self.started = True
        self._quiet_s = 0.0

    def waited(self, seconds: float) -> bool:
        """``seconds`` spent waiting without a frame; True once the run is over (its master has left).

        While no run is on, the node announces itself when due or when a participant joined.
        """
        count = self._count()
        if self.started:
            self._quiet_s += seconds
            return self._quiet_s >= self._gap_s or (self._peers is not None and count == 0)
        self._since_announce_s += seconds
        if self._since_announce_s >= IDLE_ANNOUNCE_S or count > self._peer_count:
            self._since_announce_s = 0.0
            self._announce()
        self._peer_count = count
        return False


class _Samples:
    def __init__(self) -> None:
        self.values: deque[float] = deque(maxlen=WINDOW)
        self.maximum = 0.0

    def add(self, value: float) -> None:
        self.values.append(value)
        if value > self.maximum:
            self.maximum = value

    def percentiles(self) -> Percentiles:
        return Percentiles.of(self.values, self.maximum)


class _Receiver:
    """``bus.recv`` that tolerates one isolated ``can.CanError`` and raises on two in a row.

    An error once ``stopping`` is set is the end of the run, not news (the master
    leaves the bus right after asking the ECU to stop): it is not logged.
    """

    def __init__(self, bus: can.BusABC, stopping: threading.Event) -> None:
        self.bus = bus
        self.failed = False
        self.stopping = stopping

    def recv(self, timeout: float) -> can.Message | None:
        try:
            msg = self.bus.recv(timeout=timeout)
        except can.CanError as exc:
            if self.stopping.is_set():
                return None
            if self.failed:
                raise
            self.failed = True
            log.warning("bus error (continuing): %s", exc)
            return None
        self.failed = False
        return msg


def run_real_time(node: ScheduledNode, stop_event: threading.Event, cycle_s: float,
                  boundary: RunBoundary | None = None) -> RunReport:
    """Cycle on absolute wall-clock deadlines until ``stop_event`` is set (or ``boundary`` says the run is over)."""
    clock = time.perf_counter
    lag, jitter, duration = _Samples(), _Samples(), _Samples()
    cycles = missed = 0
    k = 0
    previous_start = None
    receiver = _Receiver(node.bus, stop_event)
    t0 = clock()
    while not stop_event.is_set():
        deadline = t0 + k * cycle_s
        received = _receive_until(node, receiver, deadline, k * cycle_s, clock)
        if boundary is not None:
            if received:
                boundary.frame()
            elif boundary.waited(cycle_s):
                break
        start = clock()
        late = start - deadline
        if late >= cycle_s:
            skipped = int(late // cycle_s)
            missed += skipped
            k += skipped
            late -= skipped * cycle_s
            previous_start = None  # the period across a skip is not jitter
        node.step(k * cycle_s)
        duration.add(clock() - start)
        lag.add(late)
        if previous_start is not None:
            jitter.add(abs(start - previous_start - cycle_s))
        previous_start = start
        cycles += 1
        k += 1
    return RunReport("real-time", cycles, missed, lag.percentiles(), jitter.percentiles(),
                     duration.percentiles())


def _receive_until(node: ScheduledNode, receiver: _Receiver, deadline: float, t_s: float, clock) -> int:
    """Wait for the deadline while taking frames in as they arrive (they belong to cycle ``t_s``); how many came.

    Spreading the decoding over the idle time keeps a flood of frames from piling up
    into one long drain at the start of the cycle. The last ``SPIN_S`` before the
    deadline are waited by polling the bus without blocking: waking from a blocking
    wait can cost 0.1 to 2 ms on a virtual machine (both baselines are printed by
    ``benchmarks/bench_ecu.py``); polling costs about 10 % of one core.
    """
    received = 0
    while (remaining := deadline - clock()) > 0.0:
        msg = receiver.recv(remaining - SPIN_S if remaining > SPIN_S else 0.0)
        if msg is not None:
            node.ingest(msg, t_s)
            received += 1
        elif remaining <= SPIN_S:
            time.sleep(0)  # lets another thread of this process (a bus reader, a sender) take the GIL
    return received


@runtime_checkable
class BatchSending(Protocol):
    """A bus that can write several frames at once (``crd_pair``), each still its own frame."""

    def begin_batch(self) -> None:
        """Keep the frames sent from now on."""

    def end_batch(self) -> None:
        """Write the kept frames in one go; raise ``can.CanError`` if that fails."""


def run_sim_time(node: ScheduledNode, stop_event: threading.Event, boundary: RunBoundary | None = None) -> RunReport:
    """One cycle per ``SimClock`` frame until ``stop_event`` is set (or ``boundary`` says the run is over).

    On a bus that batches, the frames a cycle sends (``SafetyOverride``, its
    authenticator, ``EcuStatus``) leave in one write: one wake-up of the master
    per cycle instead of one per frame.
    """
    clock = time.perf_counter
    duration = _Samples()
    cycles = 0
    receiver = _Receiver(node.bus, stop_event)
    batching = isinstance(node.bus, BatchSending)
    begin, end = (node.bus.begin_batch, node.bus.end_batch) if batching else (_nothing, _nothing)
    while not stop_event.is_set():
        msg = receiver.recv(RECV_POLL_S)
        if msg is None:
            if boundary is not None and boundary.waited(RECV_POLL_S):
                break
            continue
        if boundary is not None:
            boundary.frame()
        start = clock()
        begin()
        try:
            ran = node.on_sim_message(msg) is not None
        finally:
            _end_batch(end)
        if ran:
            duration.add(clock() - start)
            cycles += 1
    none = Percentiles(0.0, 0.0, 0.0)
    return RunReport("sim-time", cycles, 0, none, none, duration.percentiles())


def _nothing() -> None:
    pass


def _end_batch(end) -> None:
    try:
        end()
    except can.CanError as exc:  # the batch's write failed (the node saw its sends succeed)
        log.warning("send of a cycle's frames failed: %s", exc)
