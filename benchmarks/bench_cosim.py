"""Co-simulation figures of issue 10, side by side in one run (medians; the machine is shared).

Run: ``python benchmarks/bench_cosim.py [--repeat N] [--phases] [--skip-paper | --paper-only]
[--paper-baseline DIR] [--idle-wait S]``.

Alternating, ``--repeat`` rounds (default 5), in this one process:

* the paper scenario in process for each strategy, over our ``crd_inproc`` bus
  (the default) and over python-can's ``virtual`` bus: × real time
  (simulated s / wall s; the 300× goal of issue 10 is withdrawn by issue 20);
* the plant alone: the same FMU through fmpy's public slave API, ``set`` the
  inputs + ``doStep`` 1 ms + ``get`` the outputs at every 1 ms step, over the
  same simulated time as that strategy's run. Goal: closed loop ÷ plant alone
  <= 1.0;
* ``crd paper`` as a child process (FMU built): wall time (goal <= 2.5 s, issue 20), its
  CPU time (user + sys of it and its workers: less disturbed by neighbours than
  the wall time), and peak memory (goal <= 150 MB). ``crd paper`` runs the
  strategies in worker processes (forked), so its memory is that of a process tree: the
  goal is judged on the peak of the tree's summed PSS (proportional set size:
  a page shared by n processes counts 1/n in each, so the sum is the memory the
  tree really holds), sampled from ``/proc/<pid>/smaps_rollup`` every 5 ms in
  one extra run after the timed rounds (sampling costs CPU, so the timed
  rounds are not sampled). Printed beside it: the largest single process's
  peak RSS (its ``VmHWM``, read while it runs) and the peak of the summed RSS,
  which counts every shared page once per process (an upper bound). Not
  ``RUSAGE_CHILDREN``'s ``ru_maxrss``: a child forked from this benchmark
  counts the benchmark's own pages before it execs ``crd`` (a 200 MB parent
  gives ``python -c pass`` a 211 MB "peak"), and this benchmark holds about
  140 MB after its closed-loop runs. ``--paper-baseline DIR``: the same from
  an older source tree, alternating with ours in every round (A/B);
  ``--idle-wait S``: before each ``crd paper``, wait up to S s until the
  machine is idle (under 10 % of its cores busy over half a second: on a
  shared machine a neighbour's burst otherwise lands in some rounds and not in
  others); the busy fraction seen before each run is printed.

Every figure is the median over the rounds; the spread (min..max) is printed
too, with the load average, so a noisy run shows itself. Each × real time is
given twice: over wall time (the goal's definition) and over the process's
CPU time (``time.process_time``), which neighbours on a shared machine
disturb much less; on a quiet machine the two agree. ``--phases`` adds
the split of one cycle's cost (an instrumented run per strategy; the timers
add their own overhead, so the total exceeds the plain run's).
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

from fmpy import extract, read_model_description

from cosim.cli.paper import PAPER_SCENARIO
from cosim.link.ecu_link import EcuOptions
from cosim.loop.experiment import resolve_fmu
from cosim.loop.master import PHASES, ClosedLoop, run_scenario
from cosim.scenarios.loader import load_scenario

STRATEGIES = ("none", "conservative", "tightening")
BUSES = ("crd_inproc", "virtual")


def _spread(values: list[float], fmt: str = "{:.0f}") -> str:
    return f"{fmt.format(statistics.median(values))} ({fmt.format(min(values))}..{fmt.format(max(values))})"


def plant_alone_s(scenario, fmu_path: Path, sim_time_s: float) -> tuple[float, float]:
    """Wall and CPU time (s) of fmpy set + doStep + get at every 1 ms step over ``sim_time_s``, the plant alone."""
    from fmpy.fmi2 import FMU2Slave
    from fmpy.fmi3 import FMU3Slave

    md = read_model_description(str(fmu_path))
    vrs = {v.name: v.valueReference for v in md.modelVariables}
    plant, v3 = scenario.plant, md.fmiVersion.startswith("3")
    inputs = [vrs[name] for m in plant.inputs for name in m.names]
    outputs = [vrs[name] for m in plant.outputs for name in m.names]
    unzipdir = extract(str(fmu_path))
    cls = FMU3Slave if v3 else FMU2Slave
    slave = cls(guid=md.instantiationToken if v3 else md.guid, unzipDirectory=unzipdir,
                modelIdentifier=md.coSimulation.modelIdentifier)
    slave.instantiate()
    if not v3:
        slave.setupExperiment(startTime=0.0)
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    set_, get = (slave.setFloat64, slave.getFloat64) if v3 else (slave.setReal, slave.getReal)
    h, values = scenario.scenario.step_s, [1.0, 0.0, 1.0][:len(inputs)]
    t0, c0 = time.perf_counter(), time.process_time()
    for k in range(int(round(sim_time_s / h))):
        set_(inputs, values)
        slave.doStep(k * h, h)
        get(outputs)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    slave.terminate()
    slave.freeInstance()
    return wall, cpu


def _paper_command(out: str) -> list[str]:
    return [sys.executable, "-m", "cosim.cli.main", "paper", "--out", out]


def _env(source: Path | None) -> dict | None:
    """The environment that makes the child import crd from ``source`` (None: as installed)."""
    return None if source is None else dict(os.environ, PYTHONPATH=str(source))


def crd_paper(source: Path | None = None) -> tuple[float, float, int]:
    """(wall s, CPU s of it and its workers, exit code) of ``crd paper`` in a child process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    with tempfile.TemporaryDirectory() as out:
        t0 = time.perf_counter()
        proc = subprocess.run(_paper_command(out), capture_output=True, text=True, env=_env(source),
                              cwd=out if source is not None else None)
        wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, proc.returncode


def _process_tree(pid: int) -> list[int]:
    """``pid`` and its descendants, from ``/proc/<pid>/task/<tid>/children``."""
    pids, i = [pid], 0
    while i < len(pids):
        try:
            for tid in os.listdir(f"/proc/{pids[i]}/task"):
                with open(f"/proc/{pids[i]}/task/{tid}/children") as handle:
                    pids += [int(p) for p in handle.read().split()]
        except OSError:
            pass  # ended meanwhile
        i += 1
    return pids


def _memory_kb(pid: int) -> tuple[int, int, int]:
    """(RSS, PSS, VmHWM) of ``pid`` in kB; zeros once it has ended."""
    try:
        with open(f"/proc/{pid}/smaps_rollup") as handle:
            fields = dict(line.split(":", 1) for line in handle if line.startswith(("Rss:", "Pss:")))
        with open(f"/proc/{pid}/status") as handle:
            fields.update(line.split(":", 1) for line in handle if line.startswith("VmHWM:"))
    except (OSError, ValueError):
        return 0, 0, 0
    return tuple(int(fields.get(k, "0 kB").split()[0]) for k in ("Rss", "Pss", "VmHWM"))  # type: ignore[return-value]


def paper_tree_memory(source: Path | None = None, period_s: float = 0.005) -> tuple[float, float, float]:
    """Peaks (MB) over ``crd paper``'s process tree, sampled: summed PSS, summed RSS, largest VmHWM."""
    peaks = [0, 0, 0]
    with tempfile.TemporaryDirectory() as out:
        proc = subprocess.Popen(_paper_command(out), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                env=_env(source), cwd=out if source is not None else None)

        def sample() -> None:
            while proc.poll() is None:
                memory = [_memory_kb(p) for p in _process_tree(proc.pid)]
                peaks[0] = max(peaks[0], sum(pss for _, pss, _ in memory))
                peaks[1] = max(peaks[1], sum(rss for rss, _, _ in memory))
                peaks[2] = max([peaks[2]] + [hwm for _, _, hwm in memory])
                time.sleep(period_s)

        sampler = threading.Thread(target=sample)
        sampler.start()
        proc.wait()
        sampler.join()
    if proc.returncode != 0:
        raise SystemExit(f"crd paper exited with {proc.returncode}")
    return peaks[0] / 1024.0, peaks[1] / 1024.0, peaks[2] / 1024.0


def closed_loop_s(sc, fmu: Path, strategy: str, bus: str) -> tuple[float, float, float]:
    """(simulated s, wall s, CPU s) of one in-process run (the FMU loaded before the clocks start)."""
    loop = ClosedLoop(sc, fmu, strategy, ecu=EcuOptions(interface=bus))
    c0 = time.process_time()
    m = loop.run().metrics
    return m.sim_time_s, m.wall_time_s, time.process_time() - c0


def _add(figures: dict, key: tuple, value: float) -> None:
    figures.setdefault(key, []).append(value)


def one_round(sc, fmu: Path, figures: dict) -> None:
    """One alternating round: every strategy on every bus, then the plant alone over the same time."""
    for strategy in STRATEGIES:
        for bus in BUSES:
            sim, wall, cpu = closed_loop_s(sc, fmu, strategy, bus)
            _add(figures, (strategy, bus), sim / wall)
            _add(figures, (strategy, bus, "cpu"), sim / cpu)
            if bus == "crd_inproc":
                alone_wall, alone_cpu = plant_alone_s(sc, fmu, sim)
                _add(figures, (strategy, "ratio"), wall / alone_wall)
                _add(figures, (strategy, "ratio", "cpu"), cpu / alone_cpu)
                _add(figures, (strategy, "alone"), sim / alone_wall)


def machine_busy(period_s: float = 0.5) -> float:
    """The fraction of all cores busy over ``period_s`` (``/proc/stat``; between rounds: other processes)."""
    def sample() -> tuple[int, int]:
        with open("/proc/stat") as handle:
            ticks = [int(x) for x in handle.readline().split()[1:]]
        return sum(ticks), ticks[3] + ticks[4]  # total, idle + iowait

    (total0, idle0), _, (total1, idle1) = sample(), time.sleep(period_s), sample()
    return 1.0 - (idle1 - idle0) / max(1, total1 - total0)


def wait_idle(limit_s: float, busy_below: float = 0.1) -> float:
    """Wait (up to ``limit_s``) until the machine is idle (less than ``busy_below`` of its cores busy
    over half a second); the last busy fraction seen."""
    deadline = time.monotonic() + limit_s
    busy = machine_busy()
    while busy >= busy_below and time.monotonic() < deadline:
        busy = machine_busy()
    return busy


def paper_round(figures: dict, baseline: Path | None, idle_wait_s: float) -> None:
    """``crd paper`` (and the baseline's), each after waiting up to ``idle_wait_s`` for an idle machine."""
    children = [("paper", None)] + ([("baseline", baseline)] if baseline is not None else [])
    for name, source in children:
        if idle_wait_s > 0:
            _add(figures, ("busy",), wait_idle(idle_wait_s))
        wall, cpu, code = crd_paper(source)
        if code != 0:
            raise SystemExit(f"crd paper ({name}) exited with {code}")
        for key, value in (("wall", wall), ("cpu", cpu)):
            _add(figures, (name, key), value)


def report(figures: dict, rounds: int, baseline: Path | None = None) -> None:
    print(f"medians over {rounds} alternating rounds (min..max); load average now "
          f"{' '.join(f'{x:.1f}' for x in os.getloadavg())}")
    if ("busy",) in figures:
        busy = figures[("busy",)]
        print(f"machine busy (other processes) over the half second before each crd paper: median "
              f"{statistics.median(busy):.0%}, max {max(busy):.0%}; idle (< 10 %) before "
              f"{sum(b < 0.1 for b in busy)} of {len(busy)}")
    if ("none", "crd_inproc") in figures:
        report_loops(figures)
    if ("paper", "wall") in figures:
        report_paper(figures)
    if ("baseline", "wall") in figures:
        report_paper(figures, "baseline", baseline)


def report_loops(figures: dict) -> None:
    columns = [("x real, crd_inproc", ("crd_inproc",), "{:.0f}"), ("same over CPU", ("crd_inproc", "cpu"), "{:.0f}"),
               ("x real, virtual", ("virtual",), "{:.0f}"), ("same over CPU", ("virtual", "cpu"), "{:.0f}"),
               ("loop / plant alone", ("ratio",), "{:.2f}"), ("same over CPU", ("ratio", "cpu"), "{:.2f}")]
    print(f"{'strategy':<13}" + "".join(f"{title:>20}" for title, _, _ in columns))
    for s in STRATEGIES:
        print(f"{s:<13}" + "".join(f"{_spread(figures[(s, *key)], fmt):>20}" for _, key, fmt in columns))
    slowest = min(STRATEGIES, key=lambda s: statistics.median(figures[(s, "crd_inproc")]))
    print(f"slowest strategy in process ({slowest}): {_spread(figures[(slowest, 'crd_inproc')])}x real time, "
          f"{_spread(figures[(slowest, 'crd_inproc', 'cpu')])}x over CPU time; closed loop / "
          f"plant alone {_spread(figures[(slowest, 'ratio')], '{:.2f}')} (goal <= 1.0)")


def report_paper(figures: dict, name: str = "paper", source: Path | None = None) -> None:
    label = "crd paper" if name == "paper" else f"crd paper from the baseline {source}"
    print(f"{label}: wall {_spread(figures[(name, 'wall')], '{:.2f}')} s (goal <= 2.5 s), "
          f"CPU {_spread(figures[(name, 'cpu')], '{:.2f}')} s (all its processes)")
    pss, rss, hwm = paper_tree_memory(source)
    print(f"{label} memory (one run sampled every 5 ms): peak of the process tree's summed PSS {pss:.0f} MB "
          f"(goal <= 150 MB); largest single process's peak RSS {hwm:.0f} MB; peak summed RSS {rss:.0f} MB "
          f"(counts shared pages once per process)")


def phases(sc, fmu: Path) -> None:
    print(f"{'strategy':<13}" + "".join(f"{p:>9}" for p in PHASES) + "    µs per 10 ms cycle (instrumented)")
    for strategy in STRATEGIES:
        cost = run_scenario(sc, fmu, strategy, profile=True).cycle_cost_s
        print(f"{strategy:<13}" + "".join(f"{cost[p] * 1e6:9.1f}" for p in PHASES)
              + f"    total {sum(cost.values()) * 1e6:.1f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", type=Path, default=PAPER_SCENARIO)
    parser.add_argument("--repeat", type=int, default=5, help="alternating rounds; medians are reported")
    parser.add_argument("--phases", action="store_true", help="also split a cycle's cost into phases")
    parser.add_argument("--skip-paper", action="store_true", help="leave out the crd paper child process")
    parser.add_argument("--paper-only", action="store_true", help="only the crd paper figures")
    parser.add_argument("--paper-baseline", type=Path, metavar="DIR",
                        help="also time crd paper from this source tree (e.g. `git archive main`), alternating")
    parser.add_argument("--idle-wait", type=float, default=0.0, metavar="S",
                        help="before each crd paper, wait up to S s for an idle machine (busy < 10 %%); "
                             "the busy fraction is reported")
    args = parser.parse_args()
    sc = load_scenario(args.scenario)
    fmu = resolve_fmu(sc)
    run_scenario(sc, fmu, "none")  # warm up: imports, the FMU's first load
    if args.paper_baseline is not None:
        crd_paper(args.paper_baseline)  # warm up: the baseline builds its FMU on first use
    figures: dict = {}
    for _ in range(max(1, args.repeat)):
        if not args.paper_only:
            one_round(sc, fmu, figures)
        if not args.skip_paper:
            paper_round(figures, args.paper_baseline, args.idle_wait)
    report(figures, max(1, args.repeat), args.paper_baseline)
    if args.phases:
        phases(sc, fmu)


if __name__ == "__main__":
    main()
