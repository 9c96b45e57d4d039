"""Figures for the ECU as its own process (issue 6, "Figures"; issue 10 item 4; issue 15 finding 5).

1. Lock-step, quiet and busy: the paper scenario (all three strategies) with
   ``crd ecu --sim-time`` as a separate process (``--ecu process``, on
   ``crd_pair``), in ``--rounds`` rounds that alternate a quiet run and a run
   beside two CPU-bound neighbour processes that this script starts and stops
   by PID. Speed-up over real time = simulated s / wall s of the three runs,
   with the ECU's start-up and join (``total``) and without (``cycles``);
   each round starts cold, like one ``crd paper --ecu process``: no spare ECU
   is waiting (:func:`cosim.link.ecu_process.discard_spare`), so the first
   run waits for a whole start-up and the next two claim the spare;
   medians over the rounds, and the busy median as a share of the quiet one
   (goals: quiet >= 60x, busy >= 40 % of quiet). Each round also runs the three
   strategies in process (crd_inproc): the wall time per cycle of both says how
   much of a cycle the second process and the round trip cost. A machine shared
   with other work is never quiet: the load average and runnable tasks are printed.
2. Round trip through the transport and the ECU process, on ``crd_pair`` and
   on ``crd_unix``: the master sends a cycle's input frames and ``SimClock``
   and waits for the ``SafetyOverride`` of that cycle (median, p99 over
   ``--round-trips`` cycles). The bare echo round trip of each transport is
   ``benchmarks/bench_transport.py``.
3. Flood memory: ``crd ecu --sim-time`` on ``crd_unix`` receives valid
   ``WheelSpeeds`` frames at ``--flood-rate`` (12,000/s) for ``--flood-s``
   (60 s) and no ``SimClock``; its resident memory (``/proc/PID/status``
   ``VmRSS``) at the start and the end of the flood (goal: growth <= 10 MB).
4. Real time: the co-simulation paced to the wall clock for ``--realtime-s``
   (default 60 s; an open road, no object, so nothing ends the run early) with
   ``crd ecu`` running ``EcuNode.run`` on ``crd_unix``: cycle lag and jitter
   p50/p99/max of the master and of the ECU (goal: jitter p99 <= 2 ms).

5. ECU process start and stop, ``--starts`` times alternating: ``python -m
   ecu`` (what the master spawns) against ``python -m cosim.cli.main ecu``
   (the ``crd`` dispatcher, with the interpreter's tear-down at exit), no
   spare: wall time from spawn to joined on ``crd_pair``, and from SIGTERM and
   the master's ``BYE`` to the exit (medians).

Every process is started and stopped by PID (the ECU through cosim.link.ecu_process).

Run: ``python benchmarks/bench_hil.py [--rounds 3] [--round-trips 3000] [--flood-s 60] [--realtime-s 60] [--starts 12]``
(a section runs only when its count or duration is above 0).
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import can

from can_dbc import ECU_CYCLE_S, CounterSequence, encode
from cosim.cli.paper import PAPER_SCENARIO
from cosim.link.ecu_link import EcuOptions
from cosim.link.ecu_process import EcuProcess, discard_spare, wait_exit, write_ecu_config
from cosim.loop.experiment import resolve_fmu
from cosim.loop.master import ecu_config, run_scenario
from cosim.scenarios.loader import load_scenario, scenario_from_dict

STRATEGIES = ("none", "conservative", "tightening")
NEIGHBOURS = 2


def _machine() -> str:
    with open("/proc/loadavg") as f:
        fields = f.read().split()
    return f"load average {fields[0]}, runnable tasks now {fields[3].split('/')[0]} on {os.cpu_count()} cores"


def _start_neighbours(count: int) -> list[subprocess.Popen]:
    return [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(count)]


def _stop(procs: list[subprocess.Popen]) -> None:
    for proc in procs:
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait()


def _paper_process_runs(sc, fmu) -> tuple[float, ...]:
    """x real time of the three strategies out of process: with start-up and join, cycles alone, and
    over the CPU time of the master and the ECU processes (what a machine that never made either
    wait for a core or a wake-up would give); then the same three runs in process (the work of a
    cycle without the second process and the transport), and the wall time per cycle of both (µs)."""
    discard_spare()  # a series of runs starts cold, as one crd paper does
    sim_s = wall_s = join_s = 0.0
    cycles = 0
    cpu0 = time.process_time()
    children0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    for strategy in STRATEGIES:
        # as crd paper: each run but the last starts a spare ECU for the next (EcuOptions.spare)
        rec = run_scenario(sc, fmu, strategy, ecu=EcuOptions(mode="process", spare=strategy != STRATEGIES[-1]))
        if rec.error or [e for e in rec.events if e.kind in ("ecu_lost", "bus_error")]:
            raise RuntimeError(f"{strategy}: the out-of-process run failed: {rec.error} {rec.events[:3]}")
        sim_s += rec.metrics.sim_time_s
        wall_s += rec.metrics.wall_time_s
        join_s += rec.ecu_join_wait_s
        cycles += round(rec.metrics.sim_time_s / ECU_CYCLE_S)
    discard_spare()  # none is left (the last run started none): as at crd paper's exit
    children = resource.getrusage(resource.RUSAGE_CHILDREN)  # the ECU processes, reaped by now
    cpu_s = (time.process_time() - cpu0 + children.ru_utime - children0.ru_utime
             + children.ru_stime - children0.ru_stime)
    inproc_wall_s = sum(run_scenario(sc, fmu, strategy).metrics.wall_time_s for strategy in STRATEGIES)
    return (sim_s / wall_s, sim_s / (wall_s - join_s), sim_s / cpu_s, sim_s / inproc_wall_s,
            1e6 * (wall_s - join_s) / cycles, 1e6 * inproc_wall_s / cycles)


def lockstep_quiet_and_busy(rounds: int) -> None:
    sc = load_scenario(PAPER_SCENARIO)
    fmu = resolve_fmu(sc)
    print(f"1. paper scenario, lock-step, ECU out of process (crd_pair), {rounds} rounds alternating quiet and "
          f"{NEIGHBOURS} CPU-bound neighbours; x real time = sim s / wall s of the three runs")
    results: dict[str, list[tuple[float, ...]]] = {"quiet": [], "busy": []}
    for k in range(rounds):
        for label in ("quiet", "busy"):
            neighbours = _start_neighbours(NEIGHBOURS if label == "busy" else 0)
            try:
                time.sleep(0.2)  # let the neighbours get going
                machine = _machine()
                results[label].append(_paper_process_runs(sc, fmu))
            finally:
                _stop(neighbours)
            total, cycles, cpu, inproc, cycle_us, inproc_us = results[label][-1]
            print(f"   round {k + 1} {label:<5}: total {total:5.1f}x  cycles {cycles:5.1f}x  over CPU time "
                  f"{cpu:5.1f}x  in process {inproc:5.1f}x; per cycle {cycle_us:4.0f} us out of process, "
                  f"{inproc_us:4.0f} us in process   ({machine})")
    med = {label: tuple(statistics.median(r[i] for r in runs) for i in range(6)) for label, runs in results.items()}
    for i, what in enumerate(("total (with ECU start-up and join)", "cycles alone", "over CPU time",
                              "in process (no second process, no transport)")):
        print(f"   median {what}: quiet {med['quiet'][i]:5.1f}x, busy {med['busy'][i]:5.1f}x = "
              f"{100.0 * med['busy'][i] / med['quiet'][i]:3.0f} % of quiet")
    print(f"   median wall per cycle, quiet: {med['quiet'][4]:.0f} us out of process (join excluded), "
          f"{med['quiet'][5]:.0f} us in process: {med['quiet'][4] - med['quiet'][5]:.0f} us for the second "
          "process and the round trip")


def _pct(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, max(0, round(q * len(ordered)) - 1))]


def round_trip(n: int, interface: str) -> None:
    sc = load_scenario(PAPER_SCENARIO)
    workdir = Path(tempfile.mkdtemp(prefix="crd-bench-"))
    channel = str(workdir / "can.sock")
    rtts: list[float] = []
    with can.Bus(interface=interface, channel=channel) as bus:
        ecu = EcuProcess(interface, channel, ecu_config(sc, "tightening"), True, workdir)
        try:
            _wait_join(bus, ecu)
            seqs = {name: CounterSequence() for name in ("DriverInput", "WheelSpeeds", "SimClock")}
            for k in range(n):
                frames = [encode("DriverInput", {"AccelPedal": 100.0, "BrakePedal": 0.0,
                                                 "SteeringWheelAngle": 0.0, "SteeringWheelRate": 0.0},
                                 seqs["DriverInput"].next()),
                          encode("WheelSpeeds", {f"WheelSpeed{w}": 50.0 for w in ("FL", "FR", "RL", "RR")},
                                 seqs["WheelSpeeds"].next()),
                          encode("SimClock", {"SimTimeMs": 10 * k}, seqs["SimClock"].next())]
                t0 = time.perf_counter()
                for msg in frames:
                    bus.send(msg)
                while True:
                    msg = bus.recv(timeout=2.0)
                    if msg is None:
                        raise RuntimeError(f"no SafetyOverride for cycle {k}")
                    if msg.arbitration_id == 0x90:
                        break
                rtts.append(time.perf_counter() - t0)
                while bus.recv(timeout=0.0005) is not None:  # this cycle's EcuStatus
                    pass
        finally:
            ecu.stop()
    print(f"2. inputs + SimClock -> SafetyOverride round trip via {interface} and crd ecu --sim-time, {n} cycles: "
          f"median {statistics.median(rtts) * 1e6:.0f} us, p99 {_pct(rtts, 0.99) * 1e6:.0f} us, "
          f"max {max(rtts) * 1e6:.0f} us")


def realtime(duration_s: float) -> None:
    sc = scenario_from_dict({"scenario": {"duration_s": duration_s}, "object": {"enabled": False}})
    fmu = resolve_fmu(sc)
    rec = run_scenario(sc, fmu, "tightening", ecu=EcuOptions(mode="process", realtime=True))
    t = rec.timing
    print(f"4. real time, {rec.metrics.sim_time_s:.1f} s sim in {rec.metrics.wall_time_s:.1f} s wall; events "
          f"{[e.kind for e in rec.events] or 'none'}")
    print(f"   master cycle lag p50 {t['lag_p50_s'] * 1e3:.3f} p99 {t['lag_p99_s'] * 1e3:.3f} max "
          f"{t['lag_max_s'] * 1e3:.3f} ms; jitter p50 {t['jitter_p50_s'] * 1e3:.3f} p99 "
          f"{t['jitter_p99_s'] * 1e3:.3f} max {t['jitter_max_s'] * 1e3:.3f} ms")
    print(f"   ECU process: {rec.ecu_report.splitlines()[-1] if rec.ecu_report else '(no report)'}")


def _rss_kb(pid: int) -> int:
    with open(f"/proc/{pid}/status") as f:
        return next(int(line.split()[1]) for line in f if line.startswith("VmRSS:"))


def flood_memory(duration_s: float, rate_hz: float) -> None:
    """``crd ecu --sim-time`` under a flood of valid frames and no SimClock: its RSS growth."""
    workdir = Path(tempfile.mkdtemp(prefix="crd-bench-"))
    channel = str(workdir / "can.sock")
    with can.Bus(interface="crd_unix", channel=channel) as bus:
        ecu = EcuProcess("crd_unix", channel, ecu_config(load_scenario(PAPER_SCENARIO), "tightening"), True, workdir)
        try:
            _wait_join(bus, ecu)
            seq = CounterSequence()
            frames = [encode("WheelSpeeds", {f"WheelSpeed{w}": 50.0 + i for w in ("FL", "FR", "RL", "RR")},
                             seq.next()) for i in range(60)]
            time.sleep(1.0)
            start_kb, peak_kb, sent = _rss_kb(ecu.pid), 0, 0
            t0 = time.monotonic()
            while (elapsed := time.monotonic() - t0) < duration_s:
                while sent < elapsed * rate_hz:
                    bus.send(frames[sent % 60])
                    sent += 1
                peak_kb = max(peak_kb, _rss_kb(ecu.pid))
                time.sleep(0.005)
            end_kb = _rss_kb(ecu.pid)
        finally:
            ecu.stop()
    print(f"3. crd ecu --sim-time under a {rate_hz:.0f}/s flood of valid WheelSpeeds, no SimClock, {duration_s:.0f} s "
          f"({sent} frames): RSS {start_kb / 1024:.1f} MB at the start, {end_kb / 1024:.1f} MB at the end, "
          f"peak {peak_kb / 1024:.1f} MB: growth {(end_kb - start_kb) / 1024:.1f} MB "
          f"(peak - start {(peak_kb - start_kb) / 1024:.1f} MB)")
    print(f"   ECU process: {ecu.output().splitlines()[-1] if ecu.output() else '(no report)'}")


def _start_stop_once(route: list[str], config_path: Path, channel: str) -> tuple[float, float]:
    """(spawn -> joined, SIGTERM + BYE -> exited) of one ECU process on ``crd_pair`` (s)."""
    with can.Bus(interface="crd_pair", channel=channel) as bus:
        t0 = time.perf_counter()
        proc = subprocess.Popen([sys.executable, *route, "--interface", "crd_pair", "--channel", channel,
                                 "--config", str(config_path), "--sim-time"], stdin=subprocess.DEVNULL,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            if not bus.wait_for_peer(10.0):
                raise RuntimeError(f"{' '.join(route)} did not join")
            t1 = time.perf_counter()
            proc.send_signal(signal.SIGTERM)
            bus.shutdown()
            wait_exit(proc, 10.0)
            return t1 - t0, time.perf_counter() - t1
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()


def start_stop(n: int) -> None:
    discard_spare()
    routes = {"python -m ecu": ["-m", "ecu"], "python -m cosim.cli.main ecu": ["-m", "cosim.cli.main", "ecu"]}
    times: dict[str, list[tuple[float, float]]] = {name: [] for name in routes}
    config = ecu_config(load_scenario(PAPER_SCENARIO), "tightening")
    machine = _machine()
    for _ in range(n):
        for name, route in routes.items():
            workdir = Path(tempfile.mkdtemp(prefix="crd-bench-"))
            try:
                config_path = write_ecu_config(workdir / "ecu.toml", config)
                times[name].append(_start_stop_once(route, config_path, str(workdir / "can.sock")))
            finally:
                shutil.rmtree(workdir, ignore_errors=True)
    print(f"5. ECU process start and stop, {n} of each alternating, no spare ({machine}):")
    for name, pairs in times.items():
        print(f"   {name:<28}: spawn -> joined median {1e3 * statistics.median(p[0] for p in pairs):5.1f} ms, "
              f"SIGTERM + BYE -> exited median {1e3 * statistics.median(p[1] for p in pairs):5.1f} ms")


def _wait_join(bus: can.BusABC, ecu: EcuProcess) -> None:
    deadline = time.monotonic() + 10.0
    while bus.peer_count < 1:
        if time.monotonic() > deadline or not ecu.alive():
            raise RuntimeError(f"crd ecu did not join: {ecu.output()}")
        time.sleep(0.01)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3, help="quiet/busy rounds of the lock-step figure")
    parser.add_argument("--round-trips", type=int, default=3000)
    parser.add_argument("--flood-s", type=float, default=60.0, help="flood length (s)")
    parser.add_argument("--flood-rate", type=float, default=12_000.0, help="flood frames per second")
    parser.add_argument("--realtime-s", type=float, default=60.0, help="real-time run length (s)")
    parser.add_argument("--starts", type=int, default=12, help="ECU process starts and stops of each kind")
    args = parser.parse_args()
    print(f"machine: {_machine()} (shared with other work unless stated)")
    if args.rounds > 0:
        lockstep_quiet_and_busy(args.rounds)
    if args.round_trips > 0:
        for interface in ("crd_pair", "crd_unix"):
            round_trip(args.round_trips, interface)
    if args.flood_s > 0:
        flood_memory(args.flood_s, args.flood_rate)
    if args.realtime_s > 0:
        realtime(args.realtime_s)
    if args.starts > 0:
        start_stop(args.starts)


if __name__ == "__main__":
    main()
