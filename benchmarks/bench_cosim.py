"""Co-simulation figures (issue 5, "Figures").

Run: ``python benchmarks/bench_cosim.py [--scenario F] [--repeat N] [--skip-paper]``.

* each paper run with the full CAN path in-process: × real time (goal >= 200),
  best of ``--repeat`` runs (the machine is shared: the best run is the one
  least disturbed; every run's figure is printed too);
* cost per 10 ms ECU cycle split into FMU, codec, bus, ECU, logging (and the
  driver/radar models), from instrumented runs (the least total of ``--repeat``);
* the plant alone stepped by fmpy over the same simulated time (the same
  doStep calls as the closed loop: one per 10 ms cycle when the FMU declares a
  fixed internal step, else one per plant step; a full read per cycle), and
  the ratio closed loop / plant alone;
* the floor: the unavoidable parts of a cycle timed alone (encode, virtual bus,
  receive checks, core step, the FMU via fmpy) and the speed-up they allow;
* ``crd paper`` wall time (goal <= 10 s once the FMU is built) and peak RSS
  (goal <= 300 MB), measured on a child process.
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from cosim.cli.paper import PAPER_SCENARIO
from cosim.loop.experiment import resolve_fmu
from cosim.loop.master import PHASES, ClosedLoop, run_scenario
from cosim.world.plant_fmu import FmuPlant
from cosim.scenarios.loader import load_scenario


def plant_alone_s(scenario, fmu_path: Path, sim_time_s: float, batched: bool) -> float:
    """Wall time of the plant alone over ``sim_time_s``: the loop's doStep calls, a full read per 10 ms."""
    h = scenario.scenario.step_s
    n_sub = int(round(0.01 / h))
    cycles = int(round(sim_time_s / 0.01))
    with FmuPlant(scenario.plant, fmu_path) as plant:
        t0 = time.perf_counter()
        k = 0
        for _ in range(cycles):
            plant.read()
            plant.set_actuation(1.0, 0.0)
            if batched:
                plant.step(k * h, n_sub * h)
                k += n_sub
                continue
            for _ in range(n_sub):
                plant.step(k * h, h)
                k += 1
        return time.perf_counter() - t0


def bench_runs(scenario_path: Path, repeat: int) -> None:
    sc = load_scenario(scenario_path)
    fmu = resolve_fmu(sc)
    probe = ClosedLoop(sc, fmu, "none")
    batched = probe.batch_steps
    probe.close()
    print(f"scenario {scenario_path.name}, plant {fmu.name} (FMI {sc.plant.fmi_version}), step {sc.scenario.step_s} s,"
          f" {'one doStep per 10 ms cycle (fixedInternalStepSize)' if batched else 'one doStep per step'};"
          f" best of {repeat}; load average {os.getloadavg()[0]:.2f}")
    print(f"{'strategy':<13} {'sim s':>6} {'wall s':>7} {'x real':>7} {'plant s':>7} {'ratio':>6}  "
          + "  ".join(f"{p:>7}" for p in PHASES) + "   (µs per 10 ms cycle)   x real of every run")
    for strategy in ("none", "conservative", "tightening"):
        walls = []
        for _ in range(repeat):
            rec = run_scenario(sc, fmu, strategy)
            walls.append(rec.metrics.wall_time_s)
        sim, wall = rec.metrics.sim_time_s, min(walls)
        costs = [run_scenario(sc, fmu, strategy, profile=True).cycle_cost_s for _ in range(repeat)]
        cost = min(costs, key=lambda c: sum(c.values()))
        alone = min(plant_alone_s(sc, fmu, sim, batched) for _ in range(repeat))
        print(f"{strategy:<13} {sim:6.2f} {wall:7.3f} {sim / wall:7.1f} {alone:7.3f} {wall / alone:6.1f}  "
              + "  ".join(f"{cost[p] * 1e6:7.1f}" for p in PHASES)
              + f"   total {sum(cost.values()) * 1e6:.1f}   " + " ".join(f"{sim / w:.0f}" for w in walls))


def _best_us(fn, number: int = 2000, repeat: int = 7) -> float:
    """Least time per call (µs) over ``repeat`` batches of ``number`` calls: the undisturbed cost."""
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(number):
            fn()
        best = min(best, (time.perf_counter() - t0) / number)
    return best * 1e6


def bench_floor(scenario_path: Path) -> None:
    """The least a 10 ms cycle of the in-process loop can cost: its unavoidable parts, timed alone.

    Per cycle the loop moves 3.3 frames on average (DriverInput and WheelSpeeds, ObjectTrack
    every 5th cycle, SafetyOverride, EcuStatus every 10th): each is encoded once, sent once on
    python-can's virtual bus to one receiver, received once and checked once. Two receives
    find the queue empty (the ECU's drain and the master's). The core steps once; the FMU
    gets one set, one doStep and one read. Everything else the loop does (the driver and
    radar models, the gateway, logging, bookkeeping) is left out, so the sum is a lower bound.
    """
    import can

    from can_dbc import Receiver, encode
    from ecu import EcuConfig
    from ecu.core import CoreInputs, CoreState, step as core_step

    frames_per_cycle = 2 + 1 / 5 + 1 + 1 / 10
    signals = {"WheelSpeedFL": 72.0, "WheelSpeedFR": 72.0, "WheelSpeedRL": 72.0, "WheelSpeedRR": 72.0}
    encode_us = _best_us(lambda: encode("WheelSpeeds", signals, 1))
    msgs = [encode("WheelSpeeds", signals, c) for c in range(15)]
    channel = f"floor-{os.getpid()}"
    with can.Bus(interface="virtual", channel=channel) as tx, can.Bus(interface="virtual", channel=channel) as rx:
        msg = msgs[0]
        bus_us = _best_us(lambda: (tx.send(msg), rx.recv(timeout=0.0)))
        empty_us = _best_us(lambda: rx.recv(timeout=0.0))
    receiver, index = Receiver(), [0]

    def check() -> None:
        index[0] = (index[0] + 1) % 15
        receiver.receive(msgs[index[0]])

    check_us = _best_us(check)
    params, state = EcuConfig(strategy="tightening"), CoreState()
    inputs = CoreInputs(t_s=1.0, wheel_speeds_mps=(20.0, 20.1, 19.9, 20.0), accel_pedal=1.0, object_valid=True,
                        object_range_m=60.0, object_range_rate_mps=-20.0, wheel_rx_t_s=1.0, driver_rx_t_s=1.0,
                        object_rx_t_s=1.0)
    core_us = _best_us(lambda: core_step(state, inputs, params))
    sc = load_scenario(scenario_path)
    with FmuPlant(sc.plant, resolve_fmu(sc)) as plant:
        k = [0]

        def fmu_cycle() -> None:
            plant.set_actuation(1.0, 0.0)
            plant.step(k[0] * 0.01, 0.01)
            k[0] += 1
            plant.read()

        fmu_us = _best_us(fmu_cycle, number=500)
    parts = {"encode": frames_per_cycle * encode_us, "virtual bus": frames_per_cycle * bus_us + 2 * empty_us,
             "receive checks": frames_per_cycle * check_us, "core": core_us, "FMU via fmpy": fmu_us}
    total = sum(parts.values())
    print(f"floor of one in-process cycle (each part timed alone, best of 7): "
          + ", ".join(f"{k} {v:.1f}" for k, v in parts.items())
          + f" -> at least {total:.1f} µs, i.e. at most {10_000 / total:.0f}x real time (goal 200x = 50 µs)")


def bench_paper() -> None:
    with tempfile.TemporaryDirectory() as out:
        t0 = time.perf_counter()
        proc = subprocess.run([sys.executable, "-m", "cosim.cli.main", "paper", "--out", out],
                              capture_output=True, text=True)
        wall = time.perf_counter() - t0
    peak_mb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0
    print(f"crd paper: wall {wall:.2f} s, peak RSS {peak_mb:.0f} MB, exit {proc.returncode}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", type=Path, default=PAPER_SCENARIO)
    parser.add_argument("--repeat", type=int, default=3, help="runs per figure; the best is reported")
    parser.add_argument("--skip-paper", action="store_true")
    args = parser.parse_args()
    bench_runs(args.scenario, max(1, args.repeat))
    bench_floor(args.scenario)
    if not args.skip_paper:
        bench_paper()


if __name__ == "__main__":
    main()
