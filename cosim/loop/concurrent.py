"""Independent strategy runs side by side in forked processes (``run_strategies(..., jobs=N)``).

The runs of ``crd paper`` share nothing: each has its own FMU instance, its own
in-process bus and its own files under ``out_dir/<strategy>/``. The loop is pure
Python (one core per process under the GIL), so on a machine with two cores
two runs take about the time of one. Every run's result depends only on the
scenario and the strategy (time is an integer counter, random sources are
seeded), never on how the runs are scheduled: the records are the ones a
sequential run gives (``tests/cosim/test_concurrent_runs.py``), collected in
the order of ``strategies``.

* **fork**, so that a worker starts in milliseconds with the parent's modules
  already imported (a fresh interpreter would import them again: 0.3 s);
* **matplotlib once**: the first runs start before the parent imports it
  (``preload``); the later ones are forked after and inherit it, so they draw
  their own ``timeline.png``; the parent draws the first ones' timelines while
  the others simulate;
* **signals**: each worker has its own process group, so a terminal's Ctrl-C
  reaches the parent only; the parent passes the SIGINT/SIGTERM it gets to
  every worker, once. Each worker ends its run with the results so far
  (:mod:`cosim.cli.signals`) and reports it as interrupted;
* **failures**: a run that fails still reports. An exception in a worker is
  sent back and raised in the parent after the other runs are collected (their
  records kept); a worker that dies without a word (a crash in the FMU's C
  code) is an error naming the strategy and the exit status.

A worker sends its record without the frame log when the frames are on disk
already (``keep_frames=False``: the CAN logs were streamed): the parent uses the
metrics, the time series and the events, and pickling 26 000 frames per run
costs more than the plots it saves.
"""

from __future__ import annotations

import logging
import multiprocessing
import os
from multiprocessing.connection import Connection, wait
from typing import Callable, Sequence

from ..errors import interrupt_signal
from ..results.run_record import RunRecord

#: one run: (strategy, draw its timeline) -> its record
Job = Callable[[str, bool], RunRecord]

log = logging.getLogger(__name__)


class _Failure:
    """What a worker sends instead of a record: the exception, or its text when it cannot be pickled."""

    def __init__(self, exc: BaseException) -> None:
        self.exc: BaseException = exc


def _worker(conn: Connection, job: Job, strategy: str, plot: bool, keep_frames: bool) -> None:
    """A forked worker: run ``strategy``, send its record (or the failure) and close the pipe."""
    os.setpgid(0, 0)  # signals come from the parent only (module docstring)
    try:
        record = job(strategy, plot)
        if not keep_frames:
            record.frames = []
        message: object = record
    except BaseException as exc:  # noqa: BLE001 - every failure goes back to the parent
        message = _Failure(exc)
    try:
        try:
            conn.send(message)
        except BrokenPipeError:
            return  # the parent has gone or given up on us
        except Exception as exc:  # noqa: BLE001 - e.g. an exception that cannot be pickled
            text = message.exc if isinstance(message, _Failure) else exc
            conn.send(_Failure(RuntimeError(f"{type(text).__name__}: {text}")))
    finally:
        conn.close()


class Workers:
    """The forked workers of one series of runs, each known by its strategy."""

    def __init__(self, job: Job, keep_frames: bool) -> None:
        self._job, self._keep_frames = job, keep_frames
        self._context = multiprocessing.get_context("fork")
        self._running: dict[Connection, tuple[str, multiprocessing.process.BaseProcess]] = {}

    def __bool__(self) -> bool:
        return bool(self._running)

    def start(self, strategy: str, plot: bool) -> None:
        """Fork a worker for ``strategy`` (``plot``: it draws its own timeline)."""
        receive, send = self._context.Pipe(duplex=False)
        process = self._context.Process(target=_worker, name=f"crd-{strategy}", daemon=True,
                                        args=(send, self._job, strategy, plot, self._keep_frames))
        process.start()
        send.close()
        try:
            os.setpgid(process.pid, process.pid)  # as the worker does: whichever comes first
        except OSError:
            pass  # the worker has set it already, or has ended
        self._running[receive] = (strategy, process)

    def next_result(self) -> tuple[str, RunRecord | _Failure]:
        """Block until a worker reports; (strategy, its record or failure)."""
        while True:
            for conn in wait(list(self._running)):
                strategy, process = self._running.pop(conn)
                try:
                    result = conn.recv()
                except EOFError:
                    process.join()
                    result = _Failure(RuntimeError(f"{strategy}: the worker process ended (exit status "
                                                   f"{process.exitcode}) without reporting its run"))
                conn.close()
                process.join()
                return strategy, result

    def forward(self, interrupt: KeyboardInterrupt) -> KeyboardInterrupt:
        """Pass the signal behind ``interrupt`` to every worker still running; returns ``interrupt``."""
        signum = interrupt_signal(interrupt)
        for _, process in self._running.values():
            try:
                os.kill(process.pid, signum)
            except ProcessLookupError:
                pass
        return interrupt

    def stop(self) -> None:
        """End every worker still running (on the way out of an error in the parent)."""
        for conn, (_, process) in list(self._running.items()):
            conn.close()  # first: a worker blocked on sending to us gets EPIPE instead of waiting
            process.terminate()
            process.join()
        self._running.clear()


def run_concurrently(strategies: Sequence[str], job: Job, records: list[RunRecord],
                     draw: Callable[[RunRecord], None], preload: Callable[[], None],
                     on_record: Callable[[list[RunRecord]], None], keep_frames: bool = False,
                     early: int = 1) -> None:
    """Run every strategy in its own worker; ``records`` gets theirs in the order of ``strategies``.

    The first ``early`` runs start before ``preload()`` (importing matplotlib) and the
    parent draws their timelines with ``draw``; the rest are forked after it and draw
    their own. ``on_record(records so far, in order)`` after each run (``metrics.json``).
    ``records`` is filled on every way out; a failed run's exception is raised after all
    the runs are collected, and an interrupt that reached no run is raised on.
    """
    workers = Workers(job, keep_frames)
    results: dict[str, RunRecord | _Failure] = {}
    interrupt: KeyboardInterrupt | None = None
    try:
        try:
            for strategy in strategies[:early]:
                workers.start(strategy, plot=False)
            preload()
            for strategy in strategies[early:]:
                workers.start(strategy, plot=True)
        except KeyboardInterrupt as exc:
            interrupt = workers.forward(exc)
        while workers:
            try:
                _collect(workers, results, strategies, early, draw, on_record, interrupt is None)
            except KeyboardInterrupt as exc:
                if interrupt is not None:
                    raise
                interrupt = workers.forward(exc)
    finally:
        workers.stop()
        records[:] = _ordered(results, strategies)
    failure = next((r for r in (results.get(s) for s in strategies) if isinstance(r, _Failure)), None)
    if failure is not None:
        raise failure.exc
    if interrupt is not None and not any(r.interrupted for r in records):
        raise interrupt


def _ordered(results: dict, strategies: Sequence[str]) -> list[RunRecord]:
    return [r for r in (results.get(s) for s in strategies) if isinstance(r, RunRecord)]


def _collect(workers: Workers, results: dict, strategies: Sequence[str], early: int,
             draw: Callable[[RunRecord], None], on_record: Callable[[list[RunRecord]], None],
             drawing: bool) -> None:
    """Take one worker's result; draw its timeline here if it started before matplotlib."""
    strategy, result = workers.next_result()
    results[strategy] = result
    if isinstance(result, RunRecord):
        if drawing and strategy in strategies[:early]:
            draw(result)
        on_record(_ordered(results, strategies))
