"""Figures for the ECU as its own process (issue 6, "Figures").

1. The paper scenario (all three strategies) in sim-time lock-step with
   ``crd ecu --sim-time`` as a separate process (``--ecu process``, on
   ``crd_pair``): wall time and speed-up over real time (goal >= 30x), next to
   the in-process run; the wall time includes waiting for the spawned ECU to
   start and join, which is also shown apart with the speed of the cycles alone.
2. Round trip through the transport and the ECU process, on ``crd_pair`` and
   on ``crd_unix``: the master sends a cycle's input frames and ``SimClock``
   and waits for the ``SafetyOverride`` of that cycle (median, p99 over
   ``--round-trips`` cycles). The bare echo round trip of each transport is
   ``benchmarks/bench_transport.py``.
3. Real time: the co-simulation paced to the wall clock for ``--realtime-s``
   (default 60 s; an open road, no object, so nothing ends the run early) with
   ``crd ecu`` running ``EcuNode.run`` on ``crd_unix``: cycle lag and jitter
   p50/p99/max of the master and of the ECU (goal: jitter p99 <= 2 ms).

Every ECU process is started and stopped by PID (cosim.link.ecu_process).

Run: ``python benchmarks/bench_hil.py [--realtime-s 60] [--round-trips 3000] [--skip-paper]``
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time
from pathlib import Path

import can

from can_dbc import CounterSequence, encode
from cosim.cli.paper import PAPER_SCENARIO
from cosim.link.ecu_link import EcuOptions
from cosim.link.ecu_process import EcuProcess
from cosim.loop.experiment import resolve_fmu
from cosim.loop.master import ecu_config, run_scenario
from cosim.scenarios.loader import load_scenario, scenario_from_dict

STRATEGIES = ("none", "conservative", "tightening")


def paper_lockstep() -> None:
    sc = load_scenario(PAPER_SCENARIO)
    fmu = resolve_fmu(sc)
    print("1. paper scenario, sim-time lock-step (sim s / wall s = x real time; the process run's wall time"
          " includes waiting for the spawned ECU to start and join, shown apart)")
    for strategy in STRATEGIES:
        line = [f"   {strategy:<13}"]
        for mode in ("inprocess", "process"):
            rec = run_scenario(sc, fmu, strategy, ecu=EcuOptions(mode=mode))
            m = rec.metrics
            line.append(f"{mode}: {m.sim_time_s:5.2f} s sim in {m.wall_time_s:5.2f} s = "
                        f"{m.sim_time_s / m.wall_time_s:5.1f}x")
            if mode == "process":
                cycles_s = m.wall_time_s - rec.ecu_join_wait_s
                line.append(f"(interface {EcuOptions(mode=mode).interface}; join {rec.ecu_join_wait_s:4.2f} s,"
                            f" cycles alone {m.sim_time_s / cycles_s:5.1f}x)")
        print("  ".join(line))


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
            deadline = time.monotonic() + 10.0
            while bus.peer_count < 1:
                if time.monotonic() > deadline:
                    raise RuntimeError(f"crd ecu did not join: {ecu.output()}")
                time.sleep(0.01)
            seqs = {name: CounterSequence() for name in ("DriverInput", "WheelSpeeds", "SimClock")}
            for k in range(n):
                frames = [encode("DriverInput", {"AccelPedal": 100.0, "BrakePedal": 0.0, "SteeringWheelAngle": 0.0},
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
    print(f"3. real time, {rec.metrics.sim_time_s:.1f} s sim in {rec.metrics.wall_time_s:.1f} s wall; events "
          f"{[e.kind for e in rec.events] or 'none'}")
    print(f"   master cycle lag p50 {t['lag_p50_s'] * 1e3:.3f} p99 {t['lag_p99_s'] * 1e3:.3f} max "
          f"{t['lag_max_s'] * 1e3:.3f} ms; jitter p50 {t['jitter_p50_s'] * 1e3:.3f} p99 "
          f"{t['jitter_p99_s'] * 1e3:.3f} max {t['jitter_max_s'] * 1e3:.3f} ms")
    print(f"   ECU process: {rec.ecu_report.splitlines()[-1] if rec.ecu_report else '(no report)'}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--realtime-s", type=float, default=60.0, help="real-time run length (s)")
    parser.add_argument("--round-trips", type=int, default=3000)
    parser.add_argument("--skip-paper", action="store_true")
    args = parser.parse_args()
    print(f"machine: {os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f}")
    if not args.skip_paper:
        paper_lockstep()
    for interface in ("crd_pair", "crd_unix"):
        round_trip(args.round_trips, interface)
    realtime(args.realtime_s)


if __name__ == "__main__":
    main()
