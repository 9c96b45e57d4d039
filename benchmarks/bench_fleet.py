"""Fleet scenes: × real time of the two-car and the eight-car scene (issue 23's goals: >= 50× and >= 10×),
in process and with one ECU process per car, medians, side by side.

Run: ``python benchmarks/bench_fleet.py [--repeat N] [--scenes crossing eight_cars] [--split]``.

Alternating, ``--repeat`` rounds (default 3): each scene run whole (:func:`cosim.fleet.output.run_fleet`, no
files written) with every ECU in process, then with ``--ecu process`` (one ``crd ecu`` process per car, on
its own bus). × real time is the simulated time over the wall time; the CPU figure counts this process only
(the ECU processes' CPU is not in it), so with ECU processes only the wall figure compares.

``--split`` adds, per scene, one in-process run with the ECU core step timed (``ecu.node.core_step`` wrapped,
CPU time): the CPU per car-cycle, the core step's share, and the ceiling the rest of the loop sets, the × real
time the scene would reach if the core step cost nothing (simulated time over the CPU time without it).
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import ecu.node as ecu_node
from cosim.cli.fleet import find_scene
from cosim.fleet.config import load_fleet
from cosim.fleet.output import run_fleet
from cosim.link.ecu_link import EcuOptions


def one(scene: str, mode: str) -> tuple[float, float]:
    """(× real time over wall time, over this process's CPU time)."""
    fleet = load_fleet(find_scene(scene))
    wall0, cpu0 = time.perf_counter(), time.process_time()
    record, _ = run_fleet(fleet, None, ecu=EcuOptions(mode=mode))
    wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
    sim = record.records[0].metrics.sim_time_s
    return sim / wall, sim / cpu


def split(scene: str) -> str:
    """One in-process run with the core step timed: the line of ``--split`` (module docstring)."""
    real_step, spent = ecu_node.core_step, [0, 0]

    def timed(state, inputs, params):
        t0 = time.process_time_ns()
        result = real_step(state, inputs, params)
        spent[0] += time.process_time_ns() - t0
        spent[1] += 1
        return result

    ecu_node.core_step = timed
    try:
        fleet = load_fleet(find_scene(scene))
        cpu0 = time.process_time()
        record, _ = run_fleet(fleet, None, ecu=EcuOptions(mode="inprocess"))
        cpu = time.process_time() - cpu0
    finally:
        ecu_node.core_step = real_step
    sim, core, cycles = record.records[0].metrics.sim_time_s, spent[0] * 1e-9, spent[1]
    return (f"{scene:<12} per car-cycle {cpu / cycles * 1e6:5.0f} us CPU, core step {core / cycles * 1e6:4.0f} us, "
            f"the rest {(cpu - core) / cycles * 1e6:4.0f} us; {sim / cpu:5.1f}x, with a free core step at most "
            f"{sim / (cpu - core):5.1f}x")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--scenes", nargs="+", default=["crossing", "eight_cars"])
    p.add_argument("--split", action="store_true", help="also the core step's share and the rest's ceiling")
    args = p.parse_args()
    results: dict[tuple[str, str], list[tuple[float, float]]] = {}
    for _ in range(args.repeat):
        for scene in args.scenes:
            for mode in ("inprocess", "process"):
                results.setdefault((scene, mode), []).append(one(scene, mode))
    print(f"load average {os.getloadavg()[0]:.2f}; {args.repeat} rounds, medians (min..max)")
    for (scene, mode), rs in results.items():
        wall = [r[0] for r in rs]
        cpu = [r[1] for r in rs]
        print(f"{scene:<12} {mode:<10} wall {statistics.median(wall):6.1f}x ({min(wall):.1f}..{max(wall):.1f})"
              f"   cpu of this process {statistics.median(cpu):6.1f}x")
    for scene in args.scenes if args.split else ():
        print(split(scene))


if __name__ == "__main__":
    main()
