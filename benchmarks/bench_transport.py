"""Round-trip latency and throughput of the cross-process loopback CAN transports.

Process A (this script) sends a frame; process B echoes it; A receives it. For
each transport: the median and p99 round-trip time over ``--round-trips``
frames, and the echo throughput with up to ``--window`` frames in flight.

Transports:

- ``crd_pair``: ours (``can_transport.PairSocketBus``), two processes point to
  point, no hub (both ends block in poll, after a short learned poll while
  the machine has a free core; see can_transport/spin.py);
- ``crd_unix``: ours (``can_transport.UnixSocketBus``), hub in this process;
- ``remote``: python-can-remote 0.3 (if installed), its server bound to
  127.0.0.1 on an ephemeral port, one ``virtual`` bus per client inside it;
  measured only, never a dependency of the project;
- ``virtual``: python-can's in-process virtual bus, echo in a thread (baseline;
  it cannot cross processes).

Lock-step turns (``--turns``, crd_pair): A sends a cycle's worth of frames (six
inputs and a clock frame, as the co-simulation with SecOC does) and B answers
with three (an override, its authenticator, a status), as in one lock-step
cycle; median and p99 turn time and the CPU time of both processes per turn,
with each side's frames sent in one write (``bus.batch()``) and one write per
frame, in alternating blocks of 100 turns, side by side in one run.

Every process started here is stopped by its PID at the end.

Run: ``python benchmarks/bench_transport.py [--round-trips 5000] [--frames 20000] [--turns 4000]``
"""

from __future__ import annotations

import argparse
import contextlib
import importlib.util
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import can

REPO_ROOT = Path(__file__).resolve().parents[1]
READY_TIMEOUT_S = 10.0
RECV_TIMEOUT_S = 5.0


TURN_CLOCK_ID = 0x7F1
TURN_OUT, TURN_BACK = 6, 3


def _turn_main(channel: str) -> int:
    """Child mode: answer every clock frame with ``TURN_BACK`` frames (in one write if it says so)."""
    with can.Bus(interface="crd_pair", channel=channel, role="connect") as bus:
        print("READY", flush=True)
        with contextlib.suppress(can.CanOperationError):  # the bus went away: we are done
            while True:
                msg = bus.recv(timeout=None)
                if msg.arbitration_id != TURN_CLOCK_ID:
                    continue
                with bus.batch() if msg.data[0] else contextlib.nullcontext():
                    for i in range(TURN_BACK):
                        bus.send(_frame(i))
    return 0


def measure_turns(turns: int) -> None:
    """Lock-step turns on crd_pair, batched and frame by frame, alternating in blocks of (up to) 100."""
    times: dict[bool, list[float]] = {True: [], False: []}
    cpu: dict[bool, float] = {True: 0.0, False: 0.0}
    children = _Children()
    block = max(1, min(100, turns // 2))
    with tempfile.TemporaryDirectory(prefix="crd-bench-") as tmp:
        channel = os.path.join(tmp, "bus.sock")
        with can.Bus(interface="crd_pair", channel=channel) as bus:
            child = children.start(__file__, "--turn", channel)
            try:
                if child.stdout.readline().strip() != "READY" or not bus.wait_for_peer(READY_TIMEOUT_S):
                    raise RuntimeError("the turn peer did not join")
                for k in range(turns):
                    batched = (k // block) % 2 == 0
                    out = [_frame(i) for i in range(TURN_OUT)]
                    out.append(can.Message(arbitration_id=TURN_CLOCK_ID, is_extended_id=False, data=[batched]))
                    cpu0, start = _cpu_s(child.pid), time.perf_counter()
                    with bus.batch() if batched else contextlib.nullcontext():
                        for msg in out:
                            bus.send(msg)
                    for _ in range(TURN_BACK):
                        _recv_number(bus)
                    times[batched].append((time.perf_counter() - start) * 1e6)
                    cpu[batched] += _cpu_s(child.pid) - cpu0
            finally:
                children.stop_all()
    print(f"lock-step turns on crd_pair ({TURN_OUT} frames + clock out, {TURN_BACK} back), {turns} turns:")
    for batched in (False, True):
        values = sorted(times[batched])
        print(f"  {'one write per turn (batch)' if batched else 'one write per frame':28s} median "
              f"{statistics.median(values):6.1f} µs, p99 {values[int(0.99 * (len(values) - 1))]:7.1f} µs; "
              f"CPU of both {1e6 * cpu[batched] / len(values):6.1f} µs per turn")


def _cpu_s(child_pid: int) -> float:
    """CPU time (user + system, s) of this process and of ``child_pid`` (from /proc, clock ticks)."""
    with open(f"/proc/{child_pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return time.process_time() + (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def _echo_main(interface: str, channel: str) -> int:
    """Child mode: echo every frame until stdin closes."""
    stop = threading.Event()
    threading.Thread(target=lambda: (sys.stdin.read(), stop.set()), daemon=True).start()
    with can.Bus(interface=interface, channel=channel) as bus:
        print("READY", flush=True)
        with contextlib.suppress(can.CanOperationError):  # the bus went away: we are done
            while not stop.is_set():
                msg = bus.recv(timeout=0.05)
                if msg is not None:
                    bus.send(msg)
    return 0


class _Children:
    """Processes started by the benchmark, stopped by PID."""

    def __init__(self) -> None:
        self.procs: list[subprocess.Popen] = []

    def start(self, *args: str) -> subprocess.Popen:
        proc = subprocess.Popen([sys.executable, *args], cwd=REPO_ROOT, stdin=subprocess.PIPE,
                                stdout=subprocess.PIPE, text=True)
        self.procs.append(proc)
        return proc

    def start_echo(self, interface: str, channel: str) -> subprocess.Popen:
        proc = self.start(__file__, "--echo", interface, channel)
        line = proc.stdout.readline().strip()
        if line != "READY":
            raise RuntimeError(f"expected READY from the echo process, got {line!r}")
        return proc

    def stop(self, proc: subprocess.Popen) -> None:
        """Close its stdin (the echo's signal to stop), then SIGTERM, then SIGKILL, by PID."""
        if proc.poll() is None:
            proc.stdin.close()
            for sig in (signal.SIGTERM, signal.SIGKILL):
                try:
                    proc.wait(timeout=3)
                    break
                except subprocess.TimeoutExpired:
                    os.kill(proc.pid, sig)
            proc.wait(timeout=3)
        proc.stdout.close()
        self.procs.remove(proc)

    def stop_all(self) -> None:
        """Stop the latest-started first (echo peers before the servers they use)."""
        for proc in reversed(list(self.procs)):
            self.stop(proc)


def _frame(i: int) -> can.Message:
    return can.Message(arbitration_id=0x100, is_extended_id=False, data=i.to_bytes(8, "little"))


def _wait_for_echo(bus: can.BusABC) -> None:
    """Ping until the echo answers (the peer may still be joining), then drain."""
    deadline = time.monotonic() + READY_TIMEOUT_S
    while time.monotonic() < deadline:
        bus.send(_frame(2**63))
        if bus.recv(timeout=0.2) is not None:
            while bus.recv(timeout=0.2) is not None:
                pass
            return
    raise RuntimeError("the echo peer never answered")


def _recv_number(bus: can.BusABC) -> int:
    msg = bus.recv(timeout=RECV_TIMEOUT_S)
    if msg is None:
        raise RuntimeError(f"no echo within {RECV_TIMEOUT_S} s")
    return int.from_bytes(msg.data, "little")


def measure(bus: can.BusABC, round_trips: int, frames: int, window: int) -> dict[str, float]:
    """Round-trip times (µs) and echoed frames per second on ``bus``."""
    _wait_for_echo(bus)
    rtt_us = []
    for i in range(round_trips):
        start = time.perf_counter()
        bus.send(_frame(i))
        got = _recv_number(bus)
        rtt_us.append((time.perf_counter() - start) * 1e6)
        if got != i:
            raise RuntimeError(f"expected echo {i}, got {got}")
    sent = received = 0
    start = time.perf_counter()
    while received < frames:
        while sent < frames and sent - received < window:
            bus.send(_frame(sent))
            sent += 1
        got = _recv_number(bus)
        if got != received:
            raise RuntimeError(f"expected echo {received} in order, got {got}")
        received += 1
    elapsed_s = time.perf_counter() - start
    rtt_us.sort()
    return {"median_us": statistics.median(rtt_us), "p99_us": rtt_us[int(0.99 * (len(rtt_us) - 1))],
            "frames_per_s": frames / elapsed_s}


@contextlib.contextmanager
def _ours(children: _Children, interface: str):
    """This process opens ``interface`` first (listener or hub), then the echo process joins."""
    with tempfile.TemporaryDirectory(prefix="crd-bench-") as tmp:
        channel = os.path.join(tmp, "bus.sock")
        with can.Bus(interface=interface, channel=channel) as bus:
            echo = children.start_echo(interface, channel)
            try:
                yield bus
            finally:
                children.stop(echo)


def _crd_pair(children: _Children):
    return _ours(children, "crd_pair")


def _crd_unix(children: _Children):
    return _ours(children, "crd_unix")


@contextlib.contextmanager
def _crd_unix_standalone_hub(children: _Children):
    from can_transport import UnixSocketBus

    with tempfile.TemporaryDirectory(prefix="crd-bench-") as tmp:
        channel = os.path.join(tmp, "bus.sock")
        hub = children.start("-m", "can_transport.hub", channel)
        hub.stdout.readline()
        with UnixSocketBus(channel, hub="connect") as bus:
            echo = children.start_echo("crd_unix", channel)
            try:
                yield bus
            finally:
                children.stop(echo)
        os.kill(hub.pid, signal.SIGTERM)
        hub.wait(timeout=3)


@contextlib.contextmanager
def _remote(children: _Children):
    server = children.start("-c", (
        "from can_remote.server import RemoteServer\n"
        "s = RemoteServer('127.0.0.1', 0, interface='virtual', channel='crd-bench')\n"
        "print(s.server_port, flush=True)\n"
        "s.serve_forever()\n"))
    url = f"ws://127.0.0.1:{int(server.stdout.readline())}/"
    echo = children.start_echo("remote", url)
    bus = can.Bus(interface="remote", channel=url)
    try:
        yield bus
    finally:
        children.stop(echo)
        bus.shutdown()


@contextlib.contextmanager
def _virtual(children: _Children):
    stop = threading.Event()
    with can.Bus(interface="virtual", channel="crd-bench") as bus, \
            can.Bus(interface="virtual", channel="crd-bench") as echo:
        def run_echo() -> None:
            while not stop.is_set():
                msg = echo.recv(timeout=0.05)
                if msg is not None:
                    echo.send(msg)

        thread = threading.Thread(target=run_echo, daemon=True)
        thread.start()
        try:
            yield bus
        finally:
            stop.set()
            thread.join(2)


TRANSPORTS = {"crd_pair (ours, 2 processes, point to point)": _crd_pair,
              "crd_unix (ours, 2 processes, hub in A)": _crd_unix,
              "crd_unix (ours, 2 processes + hub process)": _crd_unix_standalone_hub,
              "python-can-remote 0.3 (2 processes + server)": _remote,
              "virtual (in-process baseline, echo thread)": _virtual}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--round-trips", type=int, default=5000)
    parser.add_argument("--frames", type=int, default=20000, help="frames echoed for the throughput figure")
    parser.add_argument("--window", type=int, default=64, help="frames in flight for the throughput figure")
    parser.add_argument("--turns", type=int, default=4000, help="lock-step turns on crd_pair (0: none)")
    parser.add_argument("--echo", nargs=2, metavar=("INTERFACE", "CHANNEL"), help=argparse.SUPPRESS)
    parser.add_argument("--turn", metavar="CHANNEL", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.echo:
        return _echo_main(*args.echo)
    if args.turn:
        return _turn_main(args.turn)
    if args.turns > 0:
        measure_turns(args.turns)
    if args.round_trips <= 0 or args.frames <= 0:
        return 0
    print(f"round trips: {args.round_trips}; throughput: {args.frames} frames echoed, window {args.window}")
    print(f"{'transport':48s} {'RTT median µs':>14s} {'RTT p99 µs':>11s} {'echoed frames/s':>16s}")
    for name, setup in TRANSPORTS.items():
        if "remote" in name and importlib.util.find_spec("can_remote") is None:
            print(f"{name:48s} {'not installed':>14s}")
            continue
        children = _Children()
        try:
            with setup(children) as bus:
                figures = measure(bus, args.round_trips, args.frames, args.window)
            print(f"{name:48s} {figures['median_us']:14.1f} {figures['p99_us']:11.1f} "
                  f"{figures['frames_per_s']:16.0f}")
        except (RuntimeError, can.CanError, OSError) as exc:
            print(f"{name:48s} failed: {exc}")
        finally:
            children.stop_all()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
