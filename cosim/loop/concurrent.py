"""Independent strategy runs side by side in forked processes (``run_strategies(..., concurrent=True)``).

The runs of ``crd paper`` share nothing: each has its own FMU instance, its own
in-process bus and its own files under ``out_dir/<strategy>/``. The loop is pure
Python (one core per process under the GIL), so on a machine with two cores
two runs take about the time of one. Every run's result depends only on the
scenario and the strategy (time is an integer counter, random sources are
seeded), never on how the runs are scheduled: the files are byte for byte the
ones a sequential run writes and the records are collected in the order of
``strategies`` (``tests/cosim/test_concurrent_runs.py``).

* **fork**, so that a worker starts in milliseconds with the parent's modules
  already imported (a fresh interpreter would import them again: 0.3 s), and
  ``gc.freeze()`` before it, so that the worker's collector never walks (and so
  never copies) the objects it inherits;
* **at most ``jobs`` runs at once** (the number of cores): ``jobs`` run
  workers each take the next strategy not yet taken (a counter in shared
  memory, so no run waits for the busy parent), simulate it, write its
  streamed files and send its record;
* **the plots in a plot worker** (:class:`cosim.results.plot_worker.PlotWorker`,
  started ahead by ``crd paper`` or here beside the run workers): it imports
  matplotlib while the first runs go, draws each run's ``timeline.png`` as its
  record arrives and, when every run is in, the figure of every run beside the
  last timeline. The run workers only simulate: a forked worker that plots
  writes to matplotlib's pages and holds a second copy of them (about 25 MB
  each), and the parent stays free to collect records and pass on signals;
* **signals**: each worker has its own process group, so a terminal's Ctrl-C
  reaches the parent only; the parent passes the SIGINT/SIGTERM it gets to
  every run worker, once. Each ends its run with the results so far
  (:mod:`cosim.cli.signals`) and reports it as interrupted; no new run starts;
  the plot worker draws what it was given before (no timeline of an
  interrupted run, no finale: the caller draws that one);
* **failures**: a run that fails still reports, and the other runs go on (so
  which runs have results does not depend on timing). An exception in a run is
  sent back and raised in the parent after the other runs are collected (their
  records kept); a worker that dies without a word (a crash in the FMU's C
  code) is an error naming the strategy and the exit status, and the other
  workers take the runs it would have taken.

A worker sends its record without the frame log when the frames are on disk
already (``keep_frames=False``: the CAN logs were streamed): the parent uses the
metrics, the time series and the events, and pickling 26 000 frames per run
would cost more CPU than a plot.
"""

from __future__ import annotations

import gc
import multiprocessing
import os
import pickle
import tempfile
from dataclasses import dataclass
from multiprocessing.connection import Connection, wait
from typing import Callable, Sequence

from ..results.plot_worker import Drawing, PlotWorker, Failure, attempt, cores, send
from ..results.run_record import RunRecord

__all__ = ["Job", "Plots", "cores", "run_concurrently"]

#: one run: strategy -> its record
Job = Callable[[str], RunRecord]


@dataclass(frozen=True)
class Plots:
    """What the plot worker draws (a :class:`~cosim.results.plot_worker.Drawing`): ``preload()`` imports
    matplotlib, ``timeline(record)`` draws one run's timeline, ``finale(records)`` the figure of every run
    (drawn when every run has a record). Closures do: a worker forked here inherits them."""

    preload: Callable[[], None]
    timeline: Callable[[RunRecord], None]
    finale: Callable[[list[RunRecord]], None] | None = None


def _lane(conn: Connection, job: Job, strategies: Sequence[str], taken, spool: str, keep_frames: bool) -> None:
    """A run worker: take the next strategy not yet taken, run it, send its record; until none is left.

    The record goes through a file in ``spool`` and the pipe carries its name: a record is
    larger than the pipe's buffer, and the next run should not wait until the parent reads it;
    nor is a record sent before a crash lost. The plot worker reads the same file.
    """
    os.setpgid(0, 0)  # signals come from the parent only (module docstring)
    try:
        while True:
            with taken.get_lock():
                i, taken.value = taken.value, taken.value + 1
            if i >= len(strategies):
                return
            result = attempt(lambda: _run(job, strategies[i], keep_frames))
            if isinstance(result, RunRecord):
                path = os.path.join(spool, f"{i}.pickle")
                with open(path, "wb") as handle:
                    pickle.dump(result, handle, protocol=pickle.HIGHEST_PROTOCOL)
                send(conn, (strategies[i], _Spooled(path)))
                if result.interrupted:
                    return
            else:
                send(conn, (strategies[i], result))
    except (KeyboardInterrupt, BrokenPipeError):
        return  # a signal outside a run's loop (no more runs), or the parent has gone
    finally:
        conn.close()


class _Spooled:
    """A record pickled to ``path`` (removed with the spool directory, once the plot worker is done)."""

    def __init__(self, path: str) -> None:
        self.path = path

    def load(self) -> RunRecord:
        with open(self.path, "rb") as handle:
            return pickle.load(handle)


def _run(job: Job, strategy: str, keep_frames: bool) -> RunRecord:
    record = job(strategy)
    if not keep_frames:
        record.frames = []
    return record


class Workers:
    """Forked run workers and their pipes; each message is (strategy, payload)."""

    def __init__(self) -> None:
        self._context = multiprocessing.get_context("fork")
        self._running: dict[Connection, multiprocessing.process.BaseProcess] = {}
        #: exit statuses of the workers that ended other than normally (a crash, a kill)
        self.crashes: list[int | None] = []

    def count(self) -> int:
        return len(self._running)

    def start(self, target: Callable[..., None], *args: object) -> None:
        """Fork a worker ``target(pipe, *args)``."""
        receive, send_end = self._context.Pipe(duplex=False)
        gc.freeze()  # the worker inherits a frozen heap (module docstring) ...
        try:
            process = self._context.Process(target=target, args=(send_end, *args), daemon=True)
            process.start()
        finally:
            gc.unfreeze()  # ... and the parent keeps collecting as before
            send_end.close()
        try:
            os.setpgid(process.pid, process.pid)  # as the worker does: whichever comes first
        except OSError:
            pass  # the worker has set it already, or has ended
        self._running[receive] = process

    def messages(self) -> list[tuple[str, object]]:
        """Messages from the workers; waits for one, or for a worker to end."""
        found = []
        for conn in wait(list(self._running)):
            try:
                found.append(conn.recv())
                continue
            except EOFError:
                process = self._running.pop(conn)
            conn.close()
            process.join()
            if process.exitcode != 0:
                self.crashes.append(process.exitcode)
        return found

    def forward(self, signum: int) -> None:
        """Pass ``signum`` to every run worker."""
        for process in self._running.values():
            try:
                os.kill(process.pid, signum)
            except ProcessLookupError:
                pass

    def stop(self) -> None:
        """End every worker still running (on the way out of an error in the parent)."""
        for conn, process in list(self._running.items()):
            conn.close()  # first: a worker blocked on sending to us gets EPIPE instead of waiting
            process.terminate()
            process.join()
        self._running.clear()


class _Series:
    """The parent's side of :func:`run_concurrently`."""

    def __init__(self, strategies: Sequence[str], painter: PlotWorker | None,
                 on_record: Callable[[list[RunRecord]], None]) -> None:
        self.order, self.painter, self.on_record = list(strategies), painter, on_record
        self.workers = Workers()
        self.taken = multiprocessing.get_context("fork").Value("i", 0)  # next strategy to start
        self.results: dict[str, RunRecord] = {}
        self.paths: dict[str, str] = {}  # strategy -> its pickled record (read by the plot worker)
        self.failures: list[BaseException] = []
        self.failed: set[str] = set()
        self.interrupt: KeyboardInterrupt | None = None
        self.drawing: Drawing | None = None  # what the painter draws
        self.finale_asked = False

    def records(self) -> list[RunRecord]:
        return [self.results[s] for s in self.order if s in self.results]

    def start(self, job: Job, jobs: int, spool: str, keep_frames: bool) -> None:
        for _ in range(min(max(1, jobs), len(self.order))):
            self.workers.start(_lane, job, self.order, self.taken, spool, keep_frames)

    def unreported(self) -> list[BaseException]:
        """An error for each run started but never reported by a worker that crashed."""
        if not self.workers.crashes:
            return []  # a run ended by a signal outside its loop reports nothing: the interrupt says it
        started = self.order[:min(self.taken.value, len(self.order))]
        status = ", ".join(str(code) for code in self.workers.crashes)
        return [RuntimeError(f"{s}: the worker process ended (exit status {status}) without reporting")
                for s in started if s not in self.results and s not in self.failed]

    def no_new_runs(self) -> None:
        with self.taken.get_lock():
            self.taken.value = len(self.order)

    def loop(self) -> None:
        """Collect the records, each passed on to the plot worker, until every run worker has ended."""
        while self.workers.count():
            try:
                for key, payload in self.workers.messages():
                    self._take(key, payload)
            except KeyboardInterrupt as exc:
                self.interrupted(exc)

    def interrupted(self, exc: KeyboardInterrupt) -> None:
        """Pass an interrupt on to the run workers, once (a second one is raised); no new runs."""
        if self.interrupt is not None:
            raise exc
        self.interrupt = exc
        self.no_new_runs()
        from ..errors import interrupt_signal  # here: cosim.errors imports can_dbc (this module is imported early)

        self.workers.forward(interrupt_signal(exc))

    def _take(self, key: str, payload: object) -> None:
        if isinstance(payload, Failure):
            self.failures.append(payload.exc)
            self.failed.add(key)
        elif isinstance(payload, _Spooled):
            self.results[key], self.paths[key] = payload.load(), payload.path
            self._draw(payload.path)
            self.on_record(self.records())

    def _draw(self, path: str) -> None:
        """Ask for the timeline of the record at ``path``; with the last run's, once every run is in and
        none failed, the figure of every run in the same message (:meth:`PlotWorker.last`: side by side)."""
        if self.painter is None or self.interrupt is not None:
            return
        if (self.drawing is not None and self.drawing.finale is not None and not self.failures
                and len(self.results) == len(self.order)):
            self.painter.last(path, [self.paths[s] for s in self.order])
            self.finale_asked = True
        else:
            self.painter.timeline(path)

    def finish_plots(self) -> None:
        """Wait for the plot worker (an interrupt meanwhile is passed on; a second one is raised)."""
        self.painter.finish()
        while True:
            try:
                self.failures += self.painter.failures()
                return
            except KeyboardInterrupt as exc:
                self.interrupted(exc)


def run_concurrently(strategies: Sequence[str], job: Job, records: list[RunRecord], plots: Drawing | None,
                     on_record: Callable[[list[RunRecord]], None], jobs: int, keep_frames: bool = False,
                     plot_worker: PlotWorker | None = None) -> bool:
    """Run ``strategies``, at most ``jobs`` at once; ``records`` gets their records in that order.

    ``plots`` (None: no plots) is drawn by ``plot_worker`` (started ahead; ``plots`` is then pickled
    to it) or by one forked here: each run's timeline as its record arrives, the finale with the last
    one's when every run is in (:class:`Plots`); the plot worker is stopped on every way out.
    ``on_record(records so far, in order)`` after each run (``metrics.json``).
    ``records`` is filled on every way out; a failure (a run's or a plot's) is raised
    after every run is collected, and an interrupt that reached no run is raised on.
    Returns whether ``plots.finale`` was asked for (a failure to draw it is raised).
    """
    spool = tempfile.TemporaryDirectory(prefix="crd-runs-")
    series = _Series(strategies, None, on_record)
    try:
        try:
            series.start(job, jobs, spool.name, keep_frames)
            if plots is not None:  # after the run workers: they go first
                series.painter = plot_worker or PlotWorker.start(plots)
                series.painter.bind(plots)
                series.drawing = plots
        except KeyboardInterrupt as exc:
            series.interrupted(exc)
        series.loop()
        if series.painter is not None:
            series.finish_plots()
    finally:
        series.workers.stop()
        for painter in {series.painter, plot_worker} - {None}:
            painter.stop()
        spool.cleanup()
        records[:] = series.records()
    failures = series.failures + series.unreported()
    if failures:
        raise failures[0]
    if series.interrupt is not None and not any(r.interrupted for r in records):
        raise series.interrupt
    return series.finale_asked
