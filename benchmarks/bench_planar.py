"""A planar scene with 8 objects in process: × real time (issue 21's goal: >= 100×), medians, side by side.

Run: ``python benchmarks/bench_planar.py [--repeat N] [--phases]``.

Alternating, ``--repeat`` rounds (default 7), in this one process: the planar scene of
``benchmarks/planar_8_objects.toml`` (a path-following driver with two lane changes, eight objects:
parked, standing, crossing, along the lane, overtaking, oncoming; the 2-D radar feed on) and, for
scale, the 1-D paper scenario (tightening), each a whole closed loop with the ECU in process
(:class:`cosim.loop.master.ClosedLoop`, no files written). Each × real time is printed over wall
time (the goal's definition) and over the process's CPU time (``time.process_time``: what a busy
neighbour on a shared machine disturbs least), median (min..max), with the load average.
``--phases`` adds the split of one cycle's cost for the planar scene (the timers add their own
overhead).
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from pathlib import Path

from cosim.cli.paper import PAPER_SCENARIO
from cosim.loop.experiment import resolve_fmu
from cosim.loop.master import PHASES, ClosedLoop
from cosim.scenarios.loader import load_scenario

PLANAR_SCENE = Path(__file__).resolve().parent / "planar_8_objects.toml"


def run_once(scenario, fmu: Path, strategy: str = "tightening") -> tuple[float, float, float]:
    """(simulated s, wall s, CPU s) of one whole closed loop, ECU in process."""
    loop = ClosedLoop(scenario, fmu, strategy)
    wall0, cpu0 = time.perf_counter(), time.process_time()
    record = loop.run()
    wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
    if record.error:
        raise RuntimeError(record.error)
    return record.metrics.sim_time_s, wall, cpu


def _spread(values: list[float]) -> str:
    return f"{statistics.median(values):.0f} ({min(values):.0f}..{max(values):.0f})"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--phases", action="store_true", help="also the split of one cycle's cost (planar scene)")
    args = ap.parse_args()
    scenes = {"planar, 8 objects": load_scenario(PLANAR_SCENE), "1-D paper (tightening)": load_scenario(PAPER_SCENARIO)}
    n_objects = len(scenes["planar, 8 objects"].scene_objects())
    assert n_objects == 8, f"the planar scene has {n_objects} objects"
    fmu = resolve_fmu(scenes["planar, 8 objects"])
    for scenario in scenes.values():  # warm-up: imports, FMU extraction
        run_once(scenario, fmu)
    walls = {name: [] for name in scenes}
    cpus = {name: [] for name in scenes}
    for _ in range(args.repeat):
        for name, scenario in scenes.items():
            sim, wall, cpu = run_once(scenario, fmu)
            walls[name].append(sim / wall)
            cpus[name].append(sim / cpu)
    print(f"load average {os.getloadavg()[0]:.2f}; {args.repeat} rounds, alternating; × real time, median (min..max)")
    for name in scenes:
        print(f"  {name:<24} wall {_spread(walls[name]):>16}   CPU {_spread(cpus[name]):>16}")
    if args.phases:
        loop = ClosedLoop(scenes["planar, 8 objects"], fmu, "tightening", profile=True)
        record = loop.run()
        print("planar scene, one cycle (µs):", ", ".join(f"{p} {record.cycle_cost_s.get(p, 0.0) * 1e6:.1f}"
                                                       for p in PHASES))


if __name__ == "__main__":
    main()
