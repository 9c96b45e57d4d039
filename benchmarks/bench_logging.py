"""What logging costs a run (issue 25, item 5): ``crd run`` with its default logs against the loop alone.

Run: ``python benchmarks/bench_logging.py [--repeat N] [--strategy S ...] [--with-report]``.

Alternating, ``--repeat`` rounds (default 7), in this one process, the paper scenario for
each strategy (which of the two goes first alternates from round to round):

* **loop only**: :func:`bench_cosim.closed_loop_s`, the figure ``bench_cosim.py`` reports
  (no output directory: the record stays in memory);
* **crd run**: what ``crd run paper_cyclist --strategy S --out DIR`` does for its run
  (:func:`cosim.loop.experiment._run_one`: the default logs ``can.blf`` and
  ``timeseries.csv`` streamed while the run goes, then ``events.json``), in the same
  process, right before or after it.

Printed per strategy (medians over the rounds, min..max):

* ``x real``: simulated s / wall s. For ``crd run`` the wall time is its ``metrics.json``'s
  ``wall_time_s`` (the issue's figure);
* ``ratio (metrics)``: crd run's ``x real`` / the loop's. Goal: >= 0.9;
* ``ratio (to logs closed)``: the same, over the whole call each (the plant loaded, the run,
  and for crd run every log written and closed): logging that finishes after the loop is
  charged too;
* ``ratio (CPU time)``: the same over the CPU time of this process (all its threads, so the
  logging thread's work too): what the logging costs in all, wherever it runs; a shared machine
  disturbs it less than the wall time. The x real over CPU time of each side is printed too;
* ``logging CPU``: CPU time (ms per simulated second) of the logging itself, timed inside the run
  (``time.thread_time`` around ``RunStream.flush`` and ``_stop_all``, which write in the loop's own
  thread); next to it the loop's own CPU time per simulated second. It does not depend on how busy
  the machine is nearly as much as the ratios do;
* the load average (1 min) before the first and after the last round, and its highest value
  seen between rounds: on a shared machine, read the wall-time figures with it;
* ``full collections``: how many full (generation 2) garbage collections started within each
  side, summed over the rounds. Before each side (outside its clocks) the benchmark runs one
  (:func:`gc.collect`), so both start from the same collector state: a full pass walks every
  object of crd's imports (about 30 ms, a tenth of a conservative run) and otherwise falls on
  whichever side crosses the collector's threshold, which in this deterministic sequence of
  runs is the same side of the same strategy round after round (before this: conservative's
  crd run in 4 of 7 rounds, the loop alone in none: its ratio 0.87 instead of 0.93). A pass
  that the logging's own allocations set off still falls within crd run and is counted here.
  ``--no-collect`` measures the old way; ``--in-a-row N`` also runs each side N times in a row
  (no collection between) and counts the full passes: how often a run sets one off in a long
  process (conservative, 15 in a row: 4 for each side, 2026-12-02), so what the loop's own
  objects cost, not the logging;
* ``--with-report``: also ``run_strategies`` (report, plots, ``metrics.json``, config) over
  the loop's whole call, for information: the plots are a fixed cost of about a second.
"""

from __future__ import annotations

import argparse
import gc
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_cosim import _spread, closed_loop_s  # noqa: E402 - the loop-only figure, as bench_cosim measures it

import cosim  # noqa: E402
from cosim.cli.paper import PAPER_SCENARIO  # noqa: E402
from cosim.loop.experiment import _run_one, resolve_fmu, run_strategies  # noqa: E402
from cosim.results.can_logs import check_can_logs  # noqa: E402
from cosim.results.stream import RunStream  # noqa: E402
from cosim.scenarios.loader import load_scenario  # noqa: E402

STRATEGIES = ("none", "conservative", "tightening")


class FullCollections:
    """Within the block, the full (generation 2) garbage collections that start: :attr:`count`."""

    def __enter__(self) -> FullCollections:
        self.count = 0
        gc.callbacks.append(self._seen)
        return self

    def _seen(self, phase: str, info: dict) -> None:
        if phase == "start" and info["generation"] == 2:
            self.count += 1

    def __exit__(self, *exc) -> None:
        gc.callbacks.remove(self._seen)


def loop_only(sc, fmu: Path, strategy: str) -> tuple[float, float, float]:
    """x real of the loop alone: over the run's wall time, over the whole call's wall time and its CPU time."""
    t0, c0 = time.perf_counter(), time.process_time()
    sim_s, wall_s, _cpu_s = closed_loop_s(sc, fmu, strategy, "crd_inproc")
    return sim_s / wall_s, sim_s / (time.perf_counter() - t0), sim_s / (time.process_time() - c0)


class LoggingCpu:
    """Within the block, the CPU time (``time.thread_time``) spent in :class:`RunStream`'s writing (``flush`` and
    ``_stop_all``, in the loop's thread): :attr:`loop_s`."""

    WRAPPED = {"flush": "loop_s", "_stop_all": "loop_s"}

    def __enter__(self) -> LoggingCpu:
        self.loop_s = 0.0
        self._saved = {name: getattr(RunStream, name) for name in self.WRAPPED if hasattr(RunStream, name)}
        for name, fn in self._saved.items():
            setattr(RunStream, name, self._timed(fn, self.WRAPPED[name]))
        return self

    def _timed(self, fn, total: str):
        def timed(*args, **kwargs):
            c0 = time.thread_time()
            try:
                return fn(*args, **kwargs)
            finally:
                setattr(self, total, getattr(self, total) + time.thread_time() - c0)
        return timed

    def __exit__(self, *exc) -> None:
        for name, fn in self._saved.items():
            setattr(RunStream, name, fn)


def crd_run(sc, fmu: Path, strategy: str, out: Path) -> tuple[float, ...]:
    """x real of crd run's run with the default logs: by metrics.json's wall_time_s, over the whole
    call's wall time and over its CPU time (every thread of this process); then the logging's CPU time
    and the loop thread's CPU time but the logging's, in ms per simulated second."""
    with LoggingCpu() as logging_cpu:
        t0, c0, l0 = time.perf_counter(), time.process_time(), time.thread_time()
        record = _run_one(sc, fmu, strategy, out, check_can_logs([]), None, None, plot=False)
        total_s, cpu_s, loop_cpu_s = time.perf_counter() - t0, time.process_time() - c0, time.thread_time() - l0
    m = record.metrics
    per_sim_s = 1e3 / m.sim_time_s
    return (m.sim_time_s / m.wall_time_s, m.sim_time_s / total_s, m.sim_time_s / cpu_s,
            logging_cpu.loop_s * per_sim_s, (loop_cpu_s - logging_cpu.loop_s) * per_sim_s)


def whole_command(sc, strategy: str, out: Path) -> float:
    """x real over ``run_strategies`` (the run, its logs, metrics, report and plots), wall time."""
    t0 = time.perf_counter()
    record = run_strategies(sc, [strategy], out)[0]
    return record.metrics.sim_time_s / (time.perf_counter() - t0)


def one_side(figures: dict, key: tuple, collect: bool, side, *args) -> tuple[float, ...]:
    """``side(*args)``, after a full collection (``collect``); the full collections within it counted under ``key``."""
    if collect:
        gc.collect()
    with FullCollections() as full:
        result = side(*args)
    figures.setdefault(key, []).append(full.count)
    return result


def one_round(sc, fmu: Path, strategies, figures: dict, with_report: bool, loop_first: bool,
              collect: bool = True) -> None:
    """Each strategy's loop alone and crd run, one right after the other (which goes first alternates)."""
    for strategy in strategies:
        with tempfile.TemporaryDirectory() as tmp:
            if loop_first:
                loop_x, loop_total_x, loop_cpu_x = one_side(figures, (strategy, "full loop"), collect, loop_only,
                                                            sc, fmu, strategy)
            run_x, run_total_x, run_cpu_x, *logging_ms = one_side(figures, (strategy, "full run"), collect, crd_run,
                                                                  sc, fmu, strategy, Path(tmp) / "run")
            if not loop_first:
                loop_x, loop_total_x, loop_cpu_x = one_side(figures, (strategy, "full loop"), collect, loop_only,
                                                            sc, fmu, strategy)
            figures.setdefault((strategy, "loop"), []).append(loop_x)
            figures.setdefault((strategy, "run"), []).append(run_x)
            figures.setdefault((strategy, "ratio"), []).append(run_x / loop_x)
            figures.setdefault((strategy, "ratio closed"), []).append(run_total_x / loop_total_x)
            figures.setdefault((strategy, "ratio cpu"), []).append(run_cpu_x / loop_cpu_x)
            figures.setdefault((strategy, "loop cpu"), []).append(loop_cpu_x)
            figures.setdefault((strategy, "run cpu"), []).append(run_cpu_x)
            for key, ms in zip(("log loop ms", "loop ms"), logging_ms):
                figures.setdefault((strategy, key), []).append(ms)
            if with_report:
                command_x = whole_command(sc, strategy, Path(tmp) / "command")
                figures.setdefault((strategy, "ratio command"), []).append(command_x / loop_total_x)


def in_a_row(sc, fmu: Path, strategies, runs: int) -> None:
    """Each side ``runs`` times in a row (one collection before, none between): the full collections counted."""
    print(f"full garbage collections in {runs} runs in a row (one collection before each series, none between)")
    for strategy in strategies:
        counts = []
        with tempfile.TemporaryDirectory() as tmp:
            for side in ("loop", "run"):
                gc.collect()
                with FullCollections() as full:
                    for i in range(runs):
                        if side == "loop":
                            loop_only(sc, fmu, strategy)
                        else:
                            crd_run(sc, fmu, strategy, Path(tmp) / f"run{i}")
                counts.append(full.count)
        print(f"{strategy:<13}loop only {counts[0]}, crd run {counts[1]}")


def report(figures: dict, strategies, rounds: int, with_report: bool, loads: list[float], collect: bool) -> None:
    columns = [("loop x real", "loop", "{:.0f}"), ("crd run x real", "run", "{:.0f}"),
               ("loop x real (CPU)", "loop cpu", "{:.0f}"), ("crd run x real (CPU)", "run cpu", "{:.0f}"),
               ("ratio (metrics)", "ratio", "{:.3f}"), ("ratio (to logs closed)", "ratio closed", "{:.3f}"),
               ("ratio (CPU time)", "ratio cpu", "{:.3f}")]
    if with_report:
        columns.append(("ratio (with report)", "ratio command", "{:.3f}"))
    print(f"medians over {rounds} alternating rounds (min..max); crd run = the default logs (can.blf, timeseries.csv, "
          "events.json)")
    print(f"crd from {Path(cosim.__file__).parent.parent}")
    print(f"load average (1 min): {loads[0]:.2f} before, {loads[-1]:.2f} after, {max(loads):.2f} at most "
          f"(between rounds; {os.cpu_count()} cores)")
    print(f"{'strategy':<13}" + "".join(f"{title:>24}" for title, _, _ in columns))
    for s in strategies:
        print(f"{s:<13}" + "".join(f"{_spread(figures[(s, key)], fmt):>24}" for _, key, fmt in columns))
    print("CPU ms per simulated second in crd run (medians): the logging; the loop's thread without its logging")
    for s in strategies:
        log_ms, rest_ms = (statistics.median(figures[(s, k)]) for k in ("log loop ms", "loop ms"))
        print(f"{s:<13}logging {log_ms:6.2f} ms, loop {rest_ms:7.1f} ms: logging {log_ms / rest_ms:.1%} of the "
              f"loop's CPU time")
    print("full garbage collections within each side, over the rounds ("
          + ("one run before each side" if collect else "--no-collect: none run before a side") + ")")
    for s in strategies:
        print(f"{s:<13}loop only {sum(figures[(s, 'full loop')])}, crd run {sum(figures[(s, 'full run')])}")
    worst = min(strategies, key=lambda s: statistics.median(figures[(s, "ratio")]))
    print(f"lowest ratio ({worst}): crd run / loop only = {statistics.median(figures[(worst, 'ratio')]):.3f} by "
          f"metrics.json's wall time, {statistics.median(figures[(worst, 'ratio closed')]):.3f} to the logs closed, "
          f"{statistics.median(figures[(worst, 'ratio cpu')]):.3f} over CPU time (goal >= 0.9)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7, help="alternating rounds; medians are reported")
    parser.add_argument("--strategy", action="append", choices=STRATEGIES, help="default: all three")
    parser.add_argument("--no-collect", action="store_true",
                        help="no full garbage collection before each side (the figures before 2026-12-02 evening)")
    parser.add_argument("--in-a-row", type=int, default=0, metavar="N",
                        help="also run each side N times in a row and count the full garbage collections")
    parser.add_argument("--with-report", action="store_true", help="also time run_strategies (report and plots)")
    args = parser.parse_args()
    strategies = args.strategy or STRATEGIES
    sc = load_scenario(PAPER_SCENARIO)
    fmu = resolve_fmu(sc)
    with tempfile.TemporaryDirectory() as tmp:  # warm up: imports, the FMU's first load, the writers
        loop_only(sc, fmu, "none")
        crd_run(sc, fmu, "none", Path(tmp) / "warm")
    figures: dict = {}
    loads = [os.getloadavg()[0]]
    for round_ in range(max(1, args.repeat)):
        one_round(sc, fmu, strategies, figures, args.with_report, loop_first=round_ % 2 == 0,
                  collect=not args.no_collect)
        loads.append(os.getloadavg()[0])
    report(figures, strategies, max(1, args.repeat), args.with_report, loads, not args.no_collect)
    if args.in_a_row:
        in_a_row(sc, fmu, strategies, args.in_a_row)


if __name__ == "__main__":
    main()
