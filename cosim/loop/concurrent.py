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
* **at most ``jobs`` runs at once** (the number of cores), each in a worker
  that only simulates and writes its streamed files; the parent meanwhile
  imports matplotlib (``preload``) and draws each run's ``timeline.png`` as its
  record arrives. Plotting stays out of the run workers on purpose: a forked
  worker that plots writes to matplotlib's pages and holds a second copy of
  them (about 25 MB each), which would take ``crd paper`` over its memory goal;
* **the last plots in two processes**: when every run is in and two or more
  timelines are still to draw, a forked plot worker draws half of them while
  the parent draws the rest (and then the speed profiles);
* **signals**: each worker has its own process group, so a terminal's Ctrl-C
  reaches the parent only; the parent passes the SIGINT/SIGTERM it gets to
  every run worker, once. Each ends its run with the results so far
  (:mod:`cosim.cli.signals`) and reports it as interrupted; no new run starts;
* **failures**: a run that fails still reports. An exception in a worker is
  sent back and raised in the parent after the other runs are collected (their
  records kept); a worker that dies without a word (a crash in the FMU's C
  code) is an error naming the strategy and the exit status.

A worker sends its record without the frame log when the frames are on disk
already (``keep_frames=False``: the CAN logs were streamed): the parent uses the
metrics, the time series and the events, and pickling 26 000 frames per run
would cost more CPU than a plot.
"""

from __future__ import annotations

import gc
import multiprocessing
import os
from collections import deque
from multiprocessing.connection import Connection, wait
from typing import Callable, Sequence

from ..errors import interrupt_signal
from ..results.run_record import RunRecord

#: one run: strategy -> its record
Job = Callable[[str], RunRecord]
#: the key of the plot worker among the run workers (not a strategy name: those are identifiers)
PLOTS = "timelines (plot worker)"


class _Failure:
    """What a worker sends instead of a result: the exception (or its text, when it cannot be pickled)."""

    def __init__(self, exc: BaseException) -> None:
        self.exc: BaseException = exc


def _child(conn: Connection, task: Callable[[], object]) -> None:
    """A forked worker: ``task()``, then its result (or failure) to the parent."""
    os.setpgid(0, 0)  # signals come from the parent only (module docstring)
    try:
        try:
            message = task()
        except BaseException as exc:  # noqa: BLE001 - every failure goes back to the parent
            message = _Failure(exc)
        try:
            conn.send(message)
        except BrokenPipeError:
            pass  # the parent has gone or given up on us
        except Exception as exc:  # noqa: BLE001 - e.g. an exception that cannot be pickled
            text = message.exc if isinstance(message, _Failure) else exc
            conn.send(_Failure(RuntimeError(f"{type(text).__name__}: {text}")))
    finally:
        conn.close()


class Workers:
    """Forked workers, each known by a key (its strategy, or :data:`PLOTS`), each sending one result."""

    def __init__(self) -> None:
        self._context = multiprocessing.get_context("fork")
        self._running: dict[Connection, tuple[str, multiprocessing.process.BaseProcess]] = {}

    def keys(self) -> list[str]:
        return [key for key, _ in self._running.values()]

    def start(self, key: str, task: Callable[[], object]) -> None:
        """Fork a worker that runs ``task()`` and sends what it returns."""
        receive, send = self._context.Pipe(duplex=False)
        gc.freeze()  # the worker inherits a frozen heap (module docstring) ...
        try:
            process = self._context.Process(target=_child, args=(send, task), name=f"crd {key}", daemon=True)
            process.start()
        finally:
            gc.unfreeze()  # ... and the parent keeps collecting as before
            send.close()
        try:
            os.setpgid(process.pid, process.pid)  # as the worker does: whichever comes first
        except OSError:
            pass  # the worker has set it already, or has ended
        self._running[receive] = (key, process)

    def next_results(self, block: bool) -> list[tuple[str, object]]:
        """(key, result or :class:`_Failure`) of the workers that have reported (``block``: wait for one)."""
        results = []
        for conn in wait(list(self._running), timeout=None if block else 0.0):
            key, process = self._running.pop(conn)
            try:
                results.append((key, conn.recv()))
            except EOFError:  # died without a word: a crash
                process.join()
                results.append((key, _Failure(RuntimeError(
                    f"{key}: the worker process ended (exit status {process.exitcode}) without reporting"))))
            conn.close()
            process.join()
        return results

    def forward(self, signum: int) -> None:
        """Pass ``signum`` to every run worker still running (the plot worker finishes its plots)."""
        for key, process in self._running.values():
            if key != PLOTS:
                try:
                    os.kill(process.pid, signum)
                except ProcessLookupError:
                    pass

    def stop(self) -> None:
        """End every worker still running (on the way out of an error in the parent)."""
        for conn, (_, process) in list(self._running.items()):
            conn.close()  # first: a worker blocked on sending to us gets EPIPE instead of waiting
            process.terminate()
            process.join()
        self._running.clear()


def cores() -> int:
    """The cores this process may run on (its CPU affinity where the OS tells it, else all of them)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def _run(job: Job, strategy: str, keep_frames: bool) -> RunRecord:
    record = job(strategy)
    if not keep_frames:
        record.frames = []
    return record


class _Series:
    """The parent's side of :func:`run_concurrently`."""

    def __init__(self, strategies: Sequence[str], job: Job, draw: Callable[[RunRecord], None],
                 on_record: Callable[[list[RunRecord]], None], jobs: int, keep_frames: bool) -> None:
        self.order, self.queue = list(strategies), deque(strategies)
        self.job, self.draw, self.on_record = job, draw, on_record
        self.jobs, self.keep_frames = max(1, jobs), keep_frames
        self.workers = Workers()
        self.results: dict[str, RunRecord | _Failure] = {}
        self.undrawn: deque[RunRecord] = deque()
        self.failures: list[BaseException] = []
        self.interrupt: KeyboardInterrupt | None = None

    def records(self) -> list[RunRecord]:
        return [r for r in (self.results.get(s) for s in self.order) if isinstance(r, RunRecord)]

    def fill(self) -> None:
        """Start runs up to ``jobs`` at once (none after an interrupt)."""
        while self.queue and self.interrupt is None and len(self.workers.keys()) < self.jobs:
            strategy = self.queue.popleft()
            self.workers.start(strategy, lambda s=strategy: _run(self.job, s, self.keep_frames))

    def loop(self) -> None:
        """Collect results, start the next runs, draw the timelines, until all is done."""
        while self.workers.keys() or self.undrawn:
            try:
                for key, result in self.workers.next_results(block=not self.undrawn):
                    self._take(key, result)
                self.fill()
                self._draw_next()
            except KeyboardInterrupt as exc:
                self.interrupted(exc)

    def interrupted(self, exc: KeyboardInterrupt) -> None:
        """Pass an interrupt on to the run workers, once (a second one is raised)."""
        if self.interrupt is not None:
            raise exc
        self.interrupt = exc
        self.undrawn.clear()
        self.workers.forward(interrupt_signal(exc))

    def _take(self, key: str, result: object) -> None:
        if isinstance(result, _Failure):
            self.failures.append(result.exc)
        if key == PLOTS:
            return
        self.results[key] = result  # type: ignore[assignment]
        if isinstance(result, RunRecord):
            if self.interrupt is None:
                self.undrawn.append(result)
            self.on_record(self.records())

    def _draw_next(self) -> None:
        """One timeline here; the last ones shared with a plot worker once every run is in."""
        if not self.undrawn:
            return
        if not self.queue and not self.workers.keys() and len(self.undrawn) >= 2:
            share = [self.undrawn.pop() for _ in range(len(self.undrawn) // 2)]
            self.workers.start(PLOTS, lambda: [self.draw(r) for r in share] and None)
        self.draw(self.undrawn.popleft())


def run_concurrently(strategies: Sequence[str], job: Job, records: list[RunRecord],
                     draw: Callable[[RunRecord], None], preload: Callable[[], None],
                     on_record: Callable[[list[RunRecord]], None], jobs: int, keep_frames: bool = False) -> None:
    """Run ``strategies``, at most ``jobs`` at once; ``records`` gets their records in that order.

    ``preload()`` imports matplotlib while the first runs go; ``draw`` draws a run's
    timeline; ``on_record(records so far, in order)`` after each run (``metrics.json``).
    ``records`` is filled on every way out; a failure (a run's or a plot's) is raised
    after every run is collected, and an interrupt that reached no run is raised on.
    """
    series = _Series(strategies, job, draw, on_record, jobs, keep_frames)
    try:
        try:
            series.fill()
            preload()
        except KeyboardInterrupt as exc:
            series.interrupted(exc)
        series.loop()
    finally:
        series.workers.stop()
        records[:] = series.records()
    if series.failures:
        raise series.failures[0]
    if series.interrupt is not None and not any(r.interrupted for r in records):
        raise series.interrupt
