"""A send/expect harness for frame-level tests of the ECU as a black box on a CAN bus.

The harness only talks CAN: it builds input frames through ``can_dbc.encode``
(correct E2E CRC and counters, or deliberately broken ones) and checks the
ECU's frames through a strict ``can_dbc.Receiver``. How the ECU runs and how
time passes is a *backend*, chosen by name from :data:`BACKENDS`:

* ``lockstep`` — the harness owns simulated time: each tick sends the frames
  due, then calls ``EcuNode.step(t)``; deadlines are exact, in sim time;
* ``realtime`` — the ECU runs ``EcuNode.run`` in a thread on the wall clock;
  a harness thread sends periodic frames on the wall clock; deadlines are
  wall-clock and get ``slack_s`` for the OS scheduler.

* ``process`` — the ECU is ``crd ecu`` (real time), a separate OS process on
  the ``crd_unix`` cross-process bus; the harness bus opens first and hosts the
  hub; otherwise as ``realtime`` (a :class:`RealTimeBackend` with another
  launcher). The process is stopped by PID when the test ends.

Tests never see the backend, only :class:`Harness`.
"""

from __future__ import annotations

import shutil
import tempfile
import threading
import time
from pathlib import Path
from dataclasses import dataclass
from typing import Callable, Mapping

import can

from can_dbc import COUNTER_MODULUS, Receiver, encode
from can_dbc.contract import timeout_s
from ecu import ECU_CYCLE_S, EcuConfig, EcuNode

#: what the ECU sends (EcuIdentity: from a standalone ECU, crd ecu)
OUTPUTS = ("SafetyOverride", "SteeringOverride", "EcuStatus", "EcuIdentity")
Signals = Mapping[str, float]


@dataclass
class Received:
    t_s: float
    name: str
    signals: dict


@dataclass
class _Periodic:
    signals: dict
    period_s: float
    counter: int | None
    next_s: float


class Harness:
    """``send``/``expect`` on a bus shared with the ECU under test."""

    def __init__(self, bus: can.BusABC, backend: "Backend") -> None:
        self.bus = bus
        self.backend = backend
        self._rx = Receiver(names=OUTPUTS)
        self._counters: dict[str, int] = {}
        self._periodic: dict[str, _Periodic] = {}
        self._lock = threading.Lock()
        self.last_sent_s: dict[str, float] = {}
        #: every send time (s) of each named message: a wall-clock test tells a stall of this
        #: harness's own sender (the host descheduled it) from the ECU's behaviour with it
        self.sent_times_s: dict[str, list[float]] = {}
        self.received: list[Received] = []
        self.sent = 0

    # -- sending ----------------------------------------------------------
    def send(self, name: str, signals: Signals, *, counter: int | None = None, bad_crc: bool = False) -> None:
        """Send one frame now; ``counter`` overrides the sequence, ``bad_crc`` flips the CRC."""
        with self._lock:
            if counter is None:
                counter = (self._counters.get(name, -1) + 1) % COUNTER_MODULUS
                if not bad_crc:  # a corrupted frame does not use up a counter value
                    self._counters[name] = counter
            msg = encode(name, dict(signals), counter=counter)
            if bad_crc:
                msg.data[0] ^= 0xFF
            self.bus.send(msg)
            now_s = self.last_sent_s[name] = self.backend.now_s()
            self.sent_times_s.setdefault(name, []).append(now_s)
            self.sent += 1

    def send_raw(self, msg: can.Message) -> None:
        with self._lock:
            self.bus.send(msg)
            self.sent += 1

    def periodic(self, name: str, signals: Signals | None, period_s: float = ECU_CYCLE_S,
                 counter: int | None = None) -> None:
        """Send ``name`` every ``period_s`` from now on (first one now); ``None`` stops it."""
        with self._lock:
            if signals is None:
                self._periodic.pop(name, None)
                return
            self._periodic[name] = _Periodic(dict(signals), period_s, counter, self.backend.now_s())
        self.send_due(self.backend.now_s())

    def send_due(self, now_s: float) -> None:
        """Send every periodic frame due at ``now_s`` (called by the backend)."""
        with self._lock:
            due = [(n, p) for n, p in self._periodic.items() if p.next_s <= now_s + 1e-9]
            for _, p in due:
                p.next_s += p.period_s * max(1, int((now_s - p.next_s) // p.period_s) + 1)
        for name, p in due:
            self.send(name, p.signals, counter=p.counter)

    def send_gaps(self, name: str, longer_than_s: float) -> list[tuple[float, float]]:
        """``(start_s, end_s)`` of every gap over ``longer_than_s`` between sends of ``name`` (and since its last, if periodic).

        In lock-step there are none: the harness owns time. On the wall clock such a gap
        means the host stalled this harness's own sender.
        """
        times = self.sent_times_s.get(name, [])
        if name in self._periodic:  # still due: the time since the last send is a gap too
            times = times + [self.backend.now_s()]
        return [(a, b) for a, b in zip(times, times[1:]) if b - a > longer_than_s]

    def own_stalls(self, inputs=("WheelSpeeds", "DriverInput", "ObjectTrack")) -> list[tuple[float, float]]:
        """Windows ``(from_s, to_s)`` where a stall of this harness's own sender explains an input timeout.

        A send gap over the input's timeout less two cycles counts: the ECU stamps a frame
        with the cycle it is taken in, so two frames ``g`` apart can be up to a cycle (and
        the ECU's own lag) further apart. A window runs from the gap's start + that limit to
        its end + the default fault recovery cycles + the backend's slack.
        """
        recovery_s = EcuConfig().fault_recovery_cycles * ECU_CYCLE_S + self.backend.slack_s
        windows = []
        for name in inputs:
            limit_s = timeout_s(name) - 2 * ECU_CYCLE_S
            windows += [(a + limit_s, b + recovery_s) for a, b in self.send_gaps(name, limit_s)]
        return windows

    def unexplained(self, frames: list[Received]) -> list[Received]:
        """``frames`` outside every :meth:`own_stalls` window."""
        stalls = self.own_stalls()
        return [f for f in frames if not any(a <= f.t_s <= b for a, b in stalls)]

    def collect_steady(self, name: str, duration_s: float, tries: int = 3) -> list[Received]:
        """:meth:`collect` over a window that no stall of this harness's own sender touched.

        A wall-clock window that one touched measured the host, not the ECU: it is taken
        again, up to ``tries`` times (an AssertionError after that).
        """
        for _ in range(tries):
            start_s = self.backend.now_s()
            frames = self.collect(name, duration_s)
            end_s = self.backend.now_s()
            if not any(a <= end_s and b >= start_s for a, b in self.own_stalls()):
                return frames
        raise AssertionError(f"the host stalled this harness's sender in each of {tries} windows "
                             f"of {duration_s} s: {self.own_stalls()}")

    # -- receiving ---------------------------------------------------------
    def _pump(self) -> list[Received]:
        new = []
        for msg in self.backend.advance(self):
            frame = self._rx.check(msg)  # the ECU's own frames must be well-formed
            new.append(Received(self.backend.frame_time_s(msg), frame.name, dict(frame.signals)))
        self.received.extend(new)
        return new

    def expect(self, name: str, predicate: Callable[[dict], bool] | Signals, timeout_s: float,
               since_s: float | None = None) -> Received:
        """The first ``name`` frame matching within ``timeout_s`` (+ the backend's slack) of ``since_s``."""
        match = predicate if callable(predicate) else _equals(predicate)
        start = self.backend.now_s() if since_s is None else since_s
        deadline = start + timeout_s + self.backend.slack_s
        seen: list[Received] = []
        while True:
            for rec in self._pump():
                if rec.name != name:
                    continue
                if rec.t_s > deadline + 1e-9:
                    break
                seen.append(rec)
                if match(rec.signals):
                    return rec
            if self.backend.now_s() > deadline + 1e-9:
                tail = [r.signals for r in seen[-3:]]
                raise AssertionError(f"expected a matching {name} within {timeout_s + self.backend.slack_s:.3f} s "
                                     f"of t={start:.3f} s; got {len(seen)} others, last {tail}")

    def collect(self, name: str, duration_s: float) -> list[Received]:
        """Every ``name`` frame received over the next ``duration_s``."""
        end = self.backend.now_s() + duration_s
        frames = []
        while self.backend.now_s() < end - 1e-9:
            frames.extend(r for r in self._pump() if r.name == name)
        return frames

    def close(self) -> None:
        self.backend.stop()
        self.bus.shutdown()


def _equals(expected: Signals) -> Callable[[dict], bool]:
    return lambda s: all(abs(s[k] - v) < 1e-6 for k, v in expected.items())


class LockStepBackend:
    """The harness owns time: a tick sends the due frames, then runs ``node.step(t)``."""

    slack_s = 0.0

    def __init__(self, config: EcuConfig, channel: str) -> None:
        self._bus = can.Bus(interface="virtual", channel=channel)
        self.node = EcuNode(self._bus, config)
        self._k = 0
        self._tx_t_s = 0.0

    def now_s(self) -> float:
        return self._k * ECU_CYCLE_S

    def advance(self, harness: Harness) -> list[can.Message]:
        t = self.now_s()
        harness.send_due(t)
        self.node.step(t)
        self._tx_t_s = t
        self._k += 1
        out = []
        while (msg := harness.bus.recv(timeout=0.0)) is not None:
            out.append(msg)
        return out

    def frame_time_s(self, msg: can.Message) -> float:
        return self._tx_t_s

    def stop(self) -> None:
        self._bus.shutdown()


class ThreadLauncher:
    """Runs ``EcuNode.run`` in a thread of this process."""

    def __init__(self, config: EcuConfig, channel: str) -> None:
        self._bus = can.Bus(interface="virtual", channel=channel)
        self.node = EcuNode(self._bus, config)
        self._stop = threading.Event()
        self.report = None
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self) -> None:
        self.report = self.node.run(self._stop)

    def stop(self) -> None:
        self._stop.set()
        self._thread.join(timeout=5.0)
        self._bus.shutdown()


class RealTimeBackend:
    """Wall-clock time; the ECU runs on its own (launcher); periodic frames from a thread."""

    #: scheduler allowance on every wall-clock deadline (shared CI machines jitter by ~10 ms).
    slack_s = 0.1
    poll_s = 0.002

    def __init__(self, config: EcuConfig, channel: str, launcher=ThreadLauncher) -> None:
        self._t0 = time.perf_counter()
        self._launched = launcher(config, channel)
        self.node = getattr(self._launched, "node", None)
        self._stop = threading.Event()
        self._sender: threading.Thread | None = None

    def attach(self, harness: Harness) -> None:
        def loop() -> None:
            while not self._stop.wait(0.001):
                harness.send_due(self.now_s())
        self._sender = threading.Thread(target=loop, daemon=True)
        self._sender.start()

    def now_s(self) -> float:
        return time.perf_counter() - self._t0

    def advance(self, harness: Harness) -> list[can.Message]:
        msg = harness.bus.recv(timeout=self.poll_s)
        out = []
        while msg is not None:
            out.append(msg)
            msg = harness.bus.recv(timeout=0.0)
        return out

    def frame_time_s(self, msg: can.Message) -> float:
        return self.now_s()

    def stop(self) -> None:
        self._stop.set()
        if self._sender is not None:
            self._sender.join(timeout=5.0)
        self._launched.stop()


class ProcessBackend(RealTimeBackend):
    """``crd ecu`` as its own OS process on ``crd_unix``; the harness's bus hosts the hub."""

    join_timeout_s = 10.0

    def __init__(self, config: EcuConfig, channel: str) -> None:
        from cosim.link.ecu_process import EcuProcess  # the harness launches; the ECU imports nothing of cosim

        self._dir = Path(tempfile.mkdtemp(prefix="crd-hil-"))
        socket_path = str(self._dir / "can.sock")
        self.bus = can.Bus(interface="crd_unix", channel=socket_path)
        try:
            super().__init__(config, socket_path,
                             launcher=lambda cfg, ch: EcuProcess("crd_unix", ch, cfg, False, self._dir))
            deadline = time.monotonic() + self.join_timeout_s
            while self.bus.peer_count < 1:  # a condition wait: each recv blocks until a frame or 10 ms
                if time.monotonic() > deadline or not self._launched.alive():
                    raise RuntimeError(f"expected crd ecu (pid {self._launched.pid}) on {socket_path} within "
                                       f"{self.join_timeout_s} s: {self._launched.output()}")
                self.bus.recv(timeout=0.01)
            while self.bus.recv(timeout=0.0) is not None:  # frames from before the harness starts
                pass
            self._t0 = time.perf_counter()
        except BaseException:
            self.stop()
            raise

    def stop(self) -> None:
        try:
            if hasattr(self, "_launched"):
                super().stop()
        finally:
            self.bus.shutdown()
            shutil.rmtree(self._dir, ignore_errors=True)


Backend = LockStepBackend | RealTimeBackend
BACKENDS: dict[str, Callable[[EcuConfig, str], Backend]] = {
    "lockstep": LockStepBackend,
    "realtime": RealTimeBackend,
    "process": ProcessBackend,
}


def start(mode: str, config: EcuConfig, channel: str) -> Harness:
    """A harness around a fresh ECU on ``channel`` run by the ``mode`` backend."""
    backend = BACKENDS[mode](config, channel)
    bus = getattr(backend, "bus", None) or can.Bus(interface="virtual", channel=channel)
    harness = Harness(bus, backend)
    if hasattr(backend, "attach"):
        backend.attach(harness)
    return harness
