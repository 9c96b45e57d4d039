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
  streamed files and send its record; the parent meanwhile imports matplotlib
  (``preload``) and draws each run's ``timeline.png`` as its record arrives. Plotting stays out of the run workers on purpose: a forked
  worker that plots writes to matplotlib's pages and holds a second copy of
  them (about 25 MB each), which would take ``crd paper`` over its memory goal;
* **the last plots in two processes**: when every run is in and two or more
  timelines are still to draw, a forked plot worker draws half of them while
  the parent draws the rest (and then the speed profiles);
* **signals**: each worker has its own process group, so a terminal's Ctrl-C
  reaches the parent only; the parent passes the SIGINT/SIGTERM it gets to
  every run worker, once. Each ends its run with the results so far
  (:mod:`cosim.cli.signals`) and reports it as interrupted; no new run starts;
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
from collections import deque
from dataclasses import dataclass
from multiprocessing.connection import Connection, wait
from typing import Callable, Sequence

from ..errors import interrupt_signal
from ..results.run_record import RunRecord

#: one run: strategy -> its record
Job = Callable[[str], RunRecord]
#: the key of the plot worker's report (not a strategy name: those are identifiers)
PLOTS = "timelines (plot worker)"


class _Failure:
    """What a worker sends instead of a result: the exception (or its text, when it cannot be pickled)."""

    def __init__(self, exc: BaseException) -> None:
        self.exc: BaseException = exc


def cores() -> int:
    """The cores this process may run on (its CPU affinity where the OS tells it, else all of them)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def _attempt(task: Callable[[], object]) -> object:
    try:
        return task()
    except Exception as exc:  # noqa: BLE001 - every failure goes back to the parent
        return _Failure(exc)


def _send(conn: Connection, key: str, message: object) -> None:
    """Send (key, message); an exception that cannot be pickled goes as its text."""
    try:
        conn.send((key, message))
    except BrokenPipeError:
        raise
    except Exception as exc:  # noqa: BLE001 - e.g. pickling
        text = message.exc if isinstance(message, _Failure) else exc
        conn.send((key, _Failure(RuntimeError(f"{type(text).__name__}: {text}"))))


def _lane(conn: Connection, job: Job, strategies: Sequence[str], taken, spool: str, keep_frames: bool) -> None:
    """A run worker: take the next strategy not yet taken, run it, send its record; until none is left.

    The record goes through a file in ``spool`` and the pipe carries its name: a record is
    larger than the pipe's buffer, and the next run should not wait until the parent (busy
    importing matplotlib or drawing) reads it; nor is a record sent before a crash lost.
    """
    os.setpgid(0, 0)  # signals come from the parent only (module docstring)
    try:
        while True:
            with taken.get_lock():
                i, taken.value = taken.value, taken.value + 1
            if i >= len(strategies):
                return
            result = _attempt(lambda: _run(job, strategies[i], keep_frames))
            if isinstance(result, RunRecord):
                path = os.path.join(spool, f"{i}.pickle")
                with open(path, "wb") as handle:
                    pickle.dump(result, handle, protocol=pickle.HIGHEST_PROTOCOL)
                _send(conn, strategies[i], _Spooled(path))
                if result.interrupted:
                    return
            else:
                _send(conn, strategies[i], result)
    except (KeyboardInterrupt, BrokenPipeError):
        return  # a signal outside a run's loop (no more runs), or the parent has gone
    finally:
        conn.close()


class _Spooled:
    """A record pickled to ``path`` (read and removed by the parent)."""

    def __init__(self, path: str) -> None:
        self.path = path

    def load(self) -> RunRecord:
        try:
            with open(self.path, "rb") as handle:
                return pickle.load(handle)
        finally:
            os.unlink(self.path)


def _plotter(conn: Connection, task: Callable[[], object]) -> None:
    """The plot worker: draw, then say so (or send the failure)."""
    os.setpgid(0, 0)
    try:
        _send(conn, PLOTS, _attempt(task))
    except BrokenPipeError:
        pass
    finally:
        conn.close()


def _run(job: Job, strategy: str, keep_frames: bool) -> RunRecord:
    record = job(strategy)
    if not keep_frames:
        record.frames = []
    return record


class Workers:
    """Forked workers and their pipes; each message is (strategy or :data:`PLOTS`, payload)."""

    def __init__(self) -> None:
        self._context = multiprocessing.get_context("fork")
        #: pipe -> (process, is it a run worker)
        self._running: dict[Connection, tuple[multiprocessing.process.BaseProcess, bool]] = {}
        #: exit statuses of the workers that ended other than normally (a crash, a kill)
        self.crashes: list[int | None] = []

    def count(self, lanes: bool = True) -> int:
        return sum(1 for _, lane in self._running.values() if lane or not lanes)

    def start(self, target: Callable[..., None], *args: object, lane: bool) -> None:
        """Fork a worker ``target(pipe, *args)``."""
        receive, send = self._context.Pipe(duplex=False)
        gc.freeze()  # the worker inherits a frozen heap (module docstring) ...
        try:
            process = self._context.Process(target=target, args=(send, *args), daemon=True)
            process.start()
        finally:
            gc.unfreeze()  # ... and the parent keeps collecting as before
            send.close()
        try:
            os.setpgid(process.pid, process.pid)  # as the worker does: whichever comes first
        except OSError:
            pass  # the worker has set it already, or has ended
        self._running[receive] = (process, lane)

    def messages(self, block: bool) -> list[tuple[str, object]]:
        """Messages from the workers (``block``: wait for one, or for a worker to end)."""
        found = []
        for conn in wait(list(self._running), timeout=None if block else 0.0):
            try:
                found.append(conn.recv())
                continue
            except EOFError:
                process, _ = self._running.pop(conn)
            conn.close()
            process.join()
            if process.exitcode != 0:
                self.crashes.append(process.exitcode)
        return found

    def forward(self, signum: int) -> None:
        """Pass ``signum`` to every run worker (the plot worker finishes its plots)."""
        for process, lane in self._running.values():
            if lane:
                try:
                    os.kill(process.pid, signum)
                except ProcessLookupError:
                    pass

    def stop(self) -> None:
        """End every worker still running (on the way out of an error in the parent)."""
        for conn, (process, _) in list(self._running.items()):
            conn.close()  # first: a worker blocked on sending to us gets EPIPE instead of waiting
            process.terminate()
            process.join()
        self._running.clear()


class _Series:
    """The parent's side of :func:`run_concurrently`."""

    def __init__(self, strategies: Sequence[str], plots: Plots,
                 on_record: Callable[[list[RunRecord]], None]) -> None:
        self.order, self.plots, self.on_record = list(strategies), plots, on_record
        self.plotter_started = self.finale_drawn = False  # one plot worker at most
        self.workers = Workers()
        self.taken = multiprocessing.get_context("fork").Value("i", 0)  # next strategy to start
        self.results: dict[str, RunRecord] = {}
        self.undrawn: deque[RunRecord] = deque()
        self.failures: list[BaseException] = []
        self.failed: set[str] = set()
        self.interrupt: KeyboardInterrupt | None = None

    def records(self) -> list[RunRecord]:
        return [self.results[s] for s in self.order if s in self.results]

    def start(self, job: Job, jobs: int, spool: str, keep_frames: bool) -> None:
        for _ in range(min(max(1, jobs), len(self.order))):
            self.workers.start(_lane, job, self.order, self.taken, spool, keep_frames, lane=True)

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
        """Collect records, draw the timelines, until every worker has ended and every timeline is drawn."""
        while self.workers.count(lanes=False) or self.undrawn:
            try:
                for key, payload in self.workers.messages(block=not self.undrawn):
                    self._take(key, payload)
                self._draw_next()
            except KeyboardInterrupt as exc:
                self.interrupted(exc)

    def interrupted(self, exc: KeyboardInterrupt) -> None:
        """Pass an interrupt on to the run workers, once (a second one is raised); no new runs."""
        if self.interrupt is not None:
            raise exc
        self.interrupt = exc
        self.no_new_runs()
        self.undrawn.clear()
        self.workers.forward(interrupt_signal(exc))

    def _take(self, key: str, payload: object) -> None:
        if isinstance(payload, _Failure):
            self.failures.append(payload.exc)
            self.failed.add(key)
        elif isinstance(payload, _Spooled):
            payload = self.results[key] = payload.load()
            if self.interrupt is None:
                self.undrawn.append(payload)
            self.on_record(self.records())

    def _draw_next(self) -> None:
        """One timeline here; once every run is in, the rest (and the finale) shared with a plot worker."""
        if not self.undrawn:
            return
        if len(self.results) + len(self.failed) == len(self.order) and not self.plotter_started:  # all in
            finale = self.plots.finale if not self.failures else None
            share = [self.undrawn.pop() for _ in range((len(self.undrawn) - (finale is not None)) // 2)]
            if finale is not None or share:
                records, draw = self.records(), self.plots.timeline
                self.workers.start(_plotter, lambda: _draw_all(draw, share, finale, records), lane=False)
                self.plotter_started, self.finale_drawn = True, finale is not None
        self.plots.timeline(self.undrawn.popleft())


def _draw_all(draw: Callable[[RunRecord], None], records: Sequence[RunRecord],
              finale: Callable[[list[RunRecord]], None] | None, every: list[RunRecord]) -> None:
    for record in records:
        draw(record)
    if finale is not None:
        finale(every)


@dataclass(frozen=True)
class Plots:
    """What the parent and its plot worker draw: ``preload()`` imports matplotlib, ``timeline(record)``
    draws one run's timeline, ``finale(records)`` the figure of every run (drawn by the plot worker
    beside the last timeline, when every run has a record)."""

    preload: Callable[[], None]
    timeline: Callable[[RunRecord], None]
    finale: Callable[[list[RunRecord]], None] | None = None


def run_concurrently(strategies: Sequence[str], job: Job, records: list[RunRecord], plots: Plots,
                     on_record: Callable[[list[RunRecord]], None], jobs: int, keep_frames: bool = False) -> bool:
    """Run ``strategies``, at most ``jobs`` at once; ``records`` gets their records in that order.

    ``plots.preload()`` while the first runs go; each run's timeline as its record arrives
    (:class:`Plots`); ``on_record(records so far, in order)`` after each run (``metrics.json``).
    ``records`` is filled on every way out; a failure (a run's or a plot's) is raised
    after every run is collected, and an interrupt that reached no run is raised on.
    Returns whether ``plots.finale`` was drawn.
    """
    series = _Series(strategies, plots, on_record)
    spool = tempfile.TemporaryDirectory(prefix="crd-runs-")
    try:
        try:
            series.start(job, jobs, spool.name, keep_frames)
            plots.preload()
        except KeyboardInterrupt as exc:
            series.interrupted(exc)
        series.loop()
    finally:
        series.workers.stop()
        spool.cleanup()
        records[:] = series.records()
    failures = series.failures + series.unreported()
    if failures:
        raise failures[0]
    if series.interrupt is not None and not any(r.interrupted for r in records):
        raise series.interrupt
    return series.finale_drawn
