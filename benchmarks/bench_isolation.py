"""Cost of ``[plant] isolation = "process"``: the plant FMU in a child process with a watchdog.

Steps the builtin FMI 3 plant for 40 s of simulated time at the 10 ms ECU
cycle (set + doStep + read each cycle, as the master does), in process and
isolated, alternating ``--repeat`` times, and prints medians of the start-up
and of the cost per cycle, and their ratio.

Run: ``python benchmarks/bench_isolation.py [--repeat 5]``
"""

from __future__ import annotations

import argparse
import statistics
import time

from cosim.cli.paper import PAPER_SCENARIO
from cosim.loop.experiment import resolve_fmu
from cosim.scenarios.loader import load_scenario
from cosim.world.plant_fmu import FmuPlant
from cosim.world.plant_process import IsolatedPlant

CYCLES = 4000
CYCLE_S = 0.01


def _once(make) -> tuple[float, float]:
    t0 = time.perf_counter()
    plant = make()
    t1 = time.perf_counter()
    try:
        for k in range(CYCLES):
            plant.set_actuation(1.0, 0.0)
            plant.step(k * CYCLE_S, CYCLE_S)
            plant.read()
        t2 = time.perf_counter()
    finally:
        plant.close()
    return t1 - t0, (t2 - t1) / CYCLES


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    sc = load_scenario(PAPER_SCENARIO)
    fmu = resolve_fmu(sc)
    makers = {"inprocess": lambda: FmuPlant(sc.plant, fmu), "process": lambda: IsolatedPlant(sc.plant, fmu, 5.0)}
    runs: dict[str, list[tuple[float, float]]] = {name: [] for name in makers}
    for _ in range(args.repeat):
        for name, make in makers.items():
            runs[name].append(_once(make))
    med = {name: (statistics.median(s for s, _ in v), statistics.median(c for _, c in v)) for name, v in runs.items()}
    for name, (start_s, cycle_s) in med.items():
        print(f"{name:10s} start-up {start_s * 1e3:7.1f} ms   per cycle {cycle_s * 1e6:7.1f} us (median of {args.repeat})")
    extra = med["process"][1] - med["inprocess"][1]
    print(f"isolation costs {extra * 1e6:.1f} us per 10 ms cycle"
          f" ({extra / CYCLE_S * 100:.2f} % of real time) and {med['process'][0]:.2f} s to start")


if __name__ == "__main__":
    main()
