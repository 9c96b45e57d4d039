"""Independent strategy runs side by side in worker processes (``run_strategies(..., concurrent=True)``).

The runs of ``crd paper`` share nothing: each has its own FMU instance, its own in-process bus and its
own files under ``out_dir/<strategy>/``. The loop is pure Python (one core per process under the GIL),
so on two cores two runs take about the time of one. Every run's result depends only on the scenario
and the strategy (time is an integer counter, random sources are seeded), never on how the runs are
scheduled: the files are byte for byte those of a sequential run, and the records come in the order
of ``strategies`` (``tests/cosim/test_concurrent_runs.py``).

* **a** :class:`~concurrent.futures.ProcessPoolExecutor` **of one worker per run**, at most ``jobs``
  at once. A worker that dies without a word (a crash in the FMU's C code) breaks its pool, and a broken
  pool sends SIGTERM to its other workers (whose runs would then end with their results and wait for
  ever to send them to a pool that no longer reads). With one pool per run, only that run is lost, the
  error names it, and the other runs go on (so which runs have results does not depend on timing);
* **fork**, so that a worker starts in milliseconds with crd already imported, and inherits the job
  instead of receiving it pickled. A fork copies only the calling thread: the only other threads here
  are the running pools' own (a manager and a queue feeder each), and a worker touches no lock of
  another pool, only its own pool's queues (with any other thread running, ``run_strategies`` runs
  them one after the other);
* **the workers only run**: this process takes each record as it comes (``crd paper`` draws its
  timeline), and does work of its own while the first runs go (``meanwhile``: ``crd paper`` imports
  matplotlib then, which each worker would otherwise import again, and forks the
  :class:`~cosim.loop.plot_process.PlotProcess` that draws its last figure beside the last timeline);
* **signals**: a worker has its own process group, so a terminal's Ctrl-C reaches crd alone. Each
  SIGINT/SIGTERM crd gets while runs go is passed on to every worker: the first ends each run with its
  results so far, and no new run starts; a second one ends the workers at once (SIGKILL), as it ends
  crd (:mod:`cosim.cli.signals`). A worker blocks the two signals outside its run, so one sent before
  its run started ends it before it starts, and one sent after does not cut its reply in two;
* **failures**: a run that raises, or whose worker ends without reporting, is a :class:`RunFailed`
  naming the run, raised after every run has ended (the other runs' records are kept).
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import warnings
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from contextlib import contextmanager
from typing import Callable, Iterator, Sequence

from ..errors import CosimError
from ..results.held_signals import SIGNALS, signals_held
from ..results.run_record import RunRecord

__all__ = ["Job", "OnRecord", "RunFailed", "cores", "forking", "run_concurrently"]

#: one run: strategy -> its record
Job = Callable[[str], RunRecord]
#: what this process does with each record as it comes in: (the record, every record so far in order)
OnRecord = Callable[[RunRecord, list[RunRecord]], None]

#: in a worker process: the job it runs (:func:`_start_worker`)
_job: Job | None = None


class RunFailed(CosimError, RuntimeError):
    """A run failed: it raised in its worker process or taking its record in raised here (the exception is
    the cause), or its worker ended without reporting."""

    def __init__(self, strategy: str, message: object) -> None:
        super().__init__(f"{strategy}: {message}")
        self.strategy = strategy


def _failed(strategy: str, exc: BaseException) -> RunFailed:
    failed = RunFailed(strategy, exc)
    failed.__cause__ = exc
    return failed


def cores() -> int:
    """The cores this process may run on (its CPU affinity where the OS tells it, else all of them)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


@contextmanager
def forking() -> Iterator[None]:
    """Around a fork of this process into a pool's worker (a ``submit`` that starts it). Python 3.12+ warns of
    any fork beside other threads; those here are the running pools' own, whose locks the worker never takes
    (module docstring).

    Not done here (issue 20, measured): freezing the heap for the fork (:func:`gc.freeze`, so that a worker's
    collector never walks what it inherits) took ``crd paper``'s CPU, all processes, from 8.09 to 7.37 s
    (-9 %; 7.15 to 6.74 s beside the freeze at exit of :mod:`cosim.cli.main`), medians of 3 alternating
    rounds at load average 25-29: under the 10 % a piece of machinery must buy."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", r"This process .* is multi-threaded, use of fork\(\)", DeprecationWarning)
        yield


def _start_worker(job: Job) -> None:
    """A worker's set-up: its own process group (module docstring); ``job`` comes through the fork."""
    global _job
    os.setpgid(0, 0)
    _job = job


def _run(strategy: str) -> RunRecord:
    """One run in a worker, SIGINT/SIGTERM unblocked while it goes (a pending one is raised at once)."""
    signal.pthread_sigmask(signal.SIG_UNBLOCK, SIGNALS)
    try:
        return _job(strategy)
    finally:
        signal.pthread_sigmask(signal.SIG_BLOCK, SIGNALS)


class _Worker:
    """One run's pool, its future and its worker process."""

    def __init__(self, strategy: str, job: Job) -> None:
        self.strategy = strategy
        self.pool = ProcessPoolExecutor(max_workers=1, mp_context=multiprocessing.get_context("fork"),
                                        initializer=_start_worker, initargs=(job,))
        known = set(multiprocessing.active_children())
        with forking():
            self.future: Future = self.pool.submit(_run, strategy)  # forks the worker
        self.process = next(p for p in multiprocessing.active_children() if p not in known)

    def signal(self, signum: int) -> None:
        try:
            os.kill(self.process.pid, signum)
        except ProcessLookupError:
            pass  # it has ended

    def outcome(self) -> RunRecord | BaseException:
        """The record, or what went wrong (the run's pool is shut down)."""
        exc = self.future.exception()
        self.pool.shutdown()
        if exc is None:
            return self.future.result()
        if isinstance(exc, KeyboardInterrupt):
            return exc  # a signal outside the run's loop: before it started, or as it returned
        if isinstance(exc, BrokenProcessPool):
            self.process.join()
            return RunFailed(self.strategy, f"the worker process ended (exit status {self.process.exitcode})"
                                            " without reporting")
        return _failed(self.strategy, exc)


@contextmanager
def _passed_on(workers: dict[Future, _Worker]) -> Iterator[list[int]]:
    """Each SIGINT/SIGTERM this process gets within the block goes to the ``workers`` first (a second one as
    SIGKILL), then to the handler from before. Yields the signals received. Only a signal with a handler
    set in Python or its default action is passed on (an ignored one stays ignored); main thread only."""
    received: list[int] = []
    previous: dict[int, object] = {}
    here = os.getpid()

    def pass_on(signum: int, frame) -> None:
        received.append(signum)
        for worker in list(workers.values()) if os.getpid() == here else ():  # a worker inherits this handler
            worker.signal(signum if len(received) == 1 else signal.SIGKILL)
        handler = previous[signum]
        if callable(handler):
            handler(signum, frame)
        else:  # the default action
            signal.signal(signum, signal.SIG_DFL)
            signal.raise_signal(signum)

    for sig in SIGNALS:
        if signal.getsignal(sig) != signal.SIG_IGN:
            previous[sig] = signal.signal(sig, pass_on)
    try:
        yield received
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


class _Series:
    """The parent's side of :func:`run_concurrently`: the runs waiting, running and done."""

    def __init__(self, strategies: Sequence[str], job: Job, meanwhile: Callable[[], None] | None) -> None:
        self.order, self.job, self.meanwhile = list(strategies), job, meanwhile
        self.waiting, self.running = list(strategies), {}
        self.results: dict[str, RunRecord] = {}
        self.failures: list[RunFailed] = []
        self.interrupt: KeyboardInterrupt | None = None

    def records(self) -> list[RunRecord]:
        return [self.results[s] for s in self.order if s in self.results]

    def start(self, jobs: int, received: list[int]) -> None:
        """Start runs until ``jobs`` go (none after a signal); each worker is known before a handler runs."""
        if received or self.interrupt is not None:
            self.waiting.clear()
        while self.waiting and len(self.running) < jobs:
            with signals_held():
                worker = _Worker(self.waiting.pop(0), self.job)
                self.running[worker.future] = worker

    def work_meanwhile(self) -> None:
        """The caller's own work while the first runs go, once, taken whole."""
        task, self.meanwhile = self.meanwhile, None
        if task is not None:
            with signals_held():
                task()

    def collect(self, on_record: OnRecord, jobs: int, received: list[int]) -> None:
        """Wait for runs to end; start the next ones, then take the records (signals held meanwhile)."""
        done, _ = wait(list(self.running), return_when=FIRST_COMPLETED)
        with signals_held():
            records = []
            for worker in [self.running.pop(future) for future in done]:
                outcome = worker.outcome()
                if isinstance(outcome, RunRecord):
                    self.results[worker.strategy] = outcome
                    records.append(outcome)
                elif isinstance(outcome, RunFailed):
                    self.failures.append(outcome)
                else:
                    self.interrupt = self.interrupt or outcome
            self.start(jobs, received)  # before this process's work on the records: no core waits for it
            for record in records:
                self.take(record, on_record)

    def take(self, record: RunRecord, on_record: OnRecord) -> None:
        """``on_record`` for a record; what it raises is a failure of that run, raised after the others."""
        try:
            on_record(record, self.records())
        except Exception as exc:  # noqa: BLE001 - e.g. a timeline that cannot be written: the runs go on
            self.failures.append(_failed(record.strategy, exc))

    def end_running(self) -> None:
        """On the way out of an error here: every run still going ends with its results so far, as on SIGTERM."""
        for worker in self.running.values():
            worker.signal(signal.SIGTERM)
        for worker in self.running.values():
            worker.pool.shutdown()


def run_concurrently(strategies: Sequence[str], job: Job, records: list[RunRecord], on_record: OnRecord,
                     jobs: int, meanwhile: Callable[[], None] | None = None) -> None:
    """Run ``job(strategy)`` for each of ``strategies`` in worker processes, at most ``jobs`` at once.

    ``records`` gets their records, in the order of ``strategies``, on every way out. Here, with SIGINT
    and SIGTERM held: ``meanwhile()`` once the first runs go, and ``on_record(record, records so far)``
    as each run's record comes in. A failed run (:class:`RunFailed`) is raised after every run has
    ended; an interrupt that reached no run's loop is raised on; a second interrupt is raised at once.
    Call from the main thread, with no other thread running (a fork copies only the calling thread).
    """
    series = _Series(strategies, job, meanwhile)
    try:
        with _passed_on(series.running) as received:
            while series.waiting or series.running:
                try:
                    series.start(max(1, jobs), received)
                    series.work_meanwhile()
                    series.collect(on_record, max(1, jobs), received)
                except KeyboardInterrupt as exc:  # passed on to the runs: wait for their records
                    if len(received) > 1:
                        raise
                    series.interrupt = series.interrupt or exc
    finally:
        series.end_running()
        records[:] = series.records()
    if series.failures:
        raise series.failures[0]
    if series.interrupt is not None and not any(r.interrupted for r in records):
        raise series.interrupt
