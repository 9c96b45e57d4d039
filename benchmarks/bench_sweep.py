"""Sweep figures (issue 12, "Figures").

Run: ``python benchmarks/bench_sweep.py [--sweep friction_lag_latency] [--subset 48] [--repeat 3] [--skip-full]
[--skip-scaling] [--out DIR]``.

* the whole sweep (default ``friction_lag_latency``, 1008 paper-length runs) on a
  local cluster of 2 worker processes (goal: <= 120 s on the 2-core machine);
* worker memory (RSS of each worker process, sampled every 2 s) over that sweep:
  first, last and peak sample and the growth per 100 runs, a least-squares slope
  over the samples after the first quarter of the runs (goal: flat);
* throughput with 1 worker and with 2 on the same ``--subset`` runs (every k-th
  run of the sweep, so all settings are represented), alternated ``--repeat``
  times, medians side by side (goal: 2 workers >= 1.85 x 1 worker);
* the overhead per task: (a) an empty task returning a row-sized dict, round
  trip per task with 2 workers; (b) inside each sweep task, the time outside the
  closed loop (FMU cache, scenario load, set-up: ``task_wall_s - wall_time_s``),
  median; (c) from the client's side, ``(elapsed x workers - sum task_wall_s) / runs``
  (scheduling, transfer and idle workers at the tail), next to the median run; and the CPU
  time of this process (the client and the local scheduler share it), which competes with
  the workers on a 2-core machine.

The clusters are started before timing (the sweep attaches to them as to any
scheduler), so the figures are the sweep's, not the cluster start-up's.
"""

from __future__ import annotations

import argparse
import bisect
import dataclasses
import statistics
import tempfile
import threading
import time
from pathlib import Path

import psutil
from distributed import Client, LocalCluster

from cosim.sweep.plan import make_plan
from cosim.sweep.runner import ClusterOptions, local_cluster, run_plan
from cosim.sweep.session import open_table
from cosim.sweep.spec import load_sweep


def _cluster(workers: int) -> LocalCluster:
    return local_cluster(workers, dashboard=False)  # the sweep's own local cluster (its Dask settings)


def _rss() -> int:
    return psutil.Process().memory_info().rss


class MemorySampler(threading.Thread):
    """Samples every worker's RSS every ``period_s`` through its own client."""

    def __init__(self, address: str, period_s: float = 2.0) -> None:
        super().__init__(daemon=True)
        self.client = Client(address, set_as_default=False)
        self.period_s = period_s
        self.samples: dict[str, list[tuple[float, int]]] = {}
        self._halt = threading.Event()

    def run(self) -> None:
        t0 = time.perf_counter()
        while not self._halt.wait(self.period_s):
            for worker, rss in self.client.run(_rss).items():
                self.samples.setdefault(worker, []).append((time.perf_counter() - t0, rss))

    def stop(self) -> None:
        self._halt.set()
        self.join()
        self.client.close()


class RunCounter:
    """A SweepProgress that notes (time, runs done) for the memory figure."""

    def __init__(self) -> None:
        self.t0, self.done, self.points = time.perf_counter(), 0, []

    def start(self, total, already, dashboard, note) -> None:
        self.t0 = time.perf_counter()

    def advance(self, row) -> None:
        self.done += 1
        self.points.append((time.perf_counter() - self.t0, self.done))

    def close(self) -> None:
        pass


def timed_run(plan, workers: int, out: Path, sample_memory: bool = False):
    """Run ``plan`` on a fresh cluster; returns (elapsed s, rows, memory samples, runs done over time, client CPU s)."""
    with _cluster(workers) as cluster:
        sampler = MemorySampler(cluster.scheduler_address) if sample_memory else None
        counter = RunCounter()
        if sampler:
            sampler.start()
        table = open_table(plan, out)
        cpu0, t0 = psutil.Process().cpu_times(), time.perf_counter()
        run_plan(plan, table, out, ClusterOptions(scheduler=cluster.scheduler_address), progress=counter)
        elapsed, cpu1 = time.perf_counter() - t0, psutil.Process().cpu_times()
        if sampler:
            sampler.stop()
    client_cpu = cpu1.user + cpu1.system - cpu0.user - cpu0.system
    return elapsed, table.rows(), sampler.samples if sampler else {}, counter.points, client_cpu


def growth_per_100_runs(series: list[tuple[float, int]], points: list[tuple[float, int]], workers: int,
                        total: int) -> float:
    """Least-squares slope of a worker's RSS (MB) against the runs done, after the first quarter of them,
    in MB per 100 of that worker's runs (its share: runs done / workers)."""
    times = [t for t, _ in points]
    xy = [(points[min(bisect.bisect_left(times, t), len(points) - 1)][1] / workers, rss / 2**20)
          for t, rss in series]
    xy = [(x, y) for x, y in xy if x >= total / workers / 4]
    if len(xy) < 3:
        return float("nan")
    mx, my = statistics.fmean(x for x, _ in xy), statistics.fmean(y for _, y in xy)
    sxx = sum((x - mx) ** 2 for x, _ in xy)
    return sum((x - mx) * (y - my) for x, y in xy) / sxx * 100 if sxx else float("nan")


def empty_task_overhead(n: int = 500) -> float:
    """Round trip per task (s) of ``n`` tasks that return a row-sized dict, 2 workers."""
    row = {f"c{i}": float(i) for i in range(20)}
    with _cluster(2) as cluster, Client(cluster.scheduler_address, set_as_default=False) as client:
        client.gather(client.map(lambda i: dict(row, run=i), range(20), pure=False))  # warm up
        t0 = time.perf_counter()
        client.gather(client.map(lambda i: dict(row, run=i), range(n), pure=False))
        return (time.perf_counter() - t0) / n


def report_full(spec_name: str, result: tuple, workers: int) -> None:
    elapsed, rows, samples, points, client_cpu = result
    ok = [r for r in rows if r["status"] == "ok"]
    runs = [r["wall_time_s"] for r in ok]
    inside = [r["task_wall_s"] - r["wall_time_s"] for r in ok]
    client_side = (elapsed * workers - sum(r["task_wall_s"] for r in rows)) / len(rows)
    print(f"full sweep {spec_name}: {len(rows)} runs ({len(rows) - len(ok)} failed) with {workers} workers "
          f"in {elapsed:.1f} s (goal <= 120 s) = {len(rows) / elapsed:.2f} runs/s")
    print(f"  run (closed loop) median {statistics.median(runs):.3f} s, sum {sum(runs):.0f} s; "
          f"sim time sum {sum(r['sim_time_s'] for r in ok):.0f} s")
    print(f"  per-task overhead inside the task (FMU cache, load, set-up): median {statistics.median(inside)*1e3:.1f} ms")
    print(f"  per-task overhead seen by the client ((elapsed x workers - sum task) / runs): {client_side*1e3:.1f} ms")
    print(f"  client and scheduler process CPU over the sweep: {client_cpu:.1f} s")
    for worker, series in samples.items():
        mb = [rss / 2**20 for _, rss in series]
        if len(mb) < 2:
            continue
        growth = growth_per_100_runs(series, points, workers, len(rows))
        print(f"  worker {worker}: RSS first {mb[0]:.0f} MB, last {mb[-1]:.0f} MB, peak {max(mb):.0f} MB over "
              f"{len(mb)} samples; growth after the first quarter (fit) {growth:+.2f} MB per 100 runs")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sweep", default="friction_lag_latency")
    ap.add_argument("--subset", type=int, default=48, help="runs in the 1-vs-2-worker comparison")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--skip-full", action="store_true", help="skip the whole sweep (scaling and overhead only)")
    ap.add_argument("--skip-scaling", action="store_true", help="skip the 1-vs-2-worker comparison")
    ap.add_argument("--out", type=Path, help="keep the whole sweep's results.parquet here (then: crd sweep report DIR)")
    args = ap.parse_args()
    plan = make_plan(load_sweep(args.sweep))
    print(f"{plan.spec.name}: {len(plan.runs)} runs; machine: {psutil.cpu_count()} cores, "
          f"load average {' '.join(f'{x:.1f}' for x in psutil.getloadavg())}")
    print(f"empty task round trip, 2 workers: {empty_task_overhead() * 1e3:.2f} ms per task")
    step = max(1, len(plan.runs) // args.subset)
    subset = dataclasses.replace(plan, runs=plan.runs[::step][:args.subset])
    rates = {1: [], 2: []}
    with tempfile.TemporaryDirectory() as tmp:
        for rep in range(0 if args.skip_scaling else args.repeat):
            for workers in (1, 2):
                elapsed, rows, *_ = timed_run(subset, workers, Path(tmp) / f"s{rep}w{workers}")
                rates[workers].append(len(rows) / elapsed)
        r1, r2 = (statistics.median(rates[w]) if rates[w] else float("nan") for w in (1, 2))
        print(f"subset of {len(subset.runs)} runs, median of {args.repeat}: 1 worker {r1:.2f} runs/s, "
              f"2 workers {r2:.2f} runs/s, ratio {r2 / r1:.2f} (goal >= 1.85); "
              f"all: 1w {[round(x, 2) for x in rates[1]]}, 2w {[round(x, 2) for x in rates[2]]}")
        if not args.skip_full:
            result = timed_run(plan, 2, args.out or Path(tmp) / "full", sample_memory=True)
            report_full(plan.spec.name, result, 2)
    print(f"load average after: {' '.join(f'{x:.1f}' for x in psutil.getloadavg())}")


if __name__ == "__main__":
    main()
