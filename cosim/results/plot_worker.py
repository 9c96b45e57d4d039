"""A forked process that draws a series' figures while the runs go on (``crd paper``).

Importing matplotlib takes about 0.35 s of CPU and each figure about 0.16 s; the
runs take about 1 s. :class:`PlotWorker` moves all of it off the critical path:

* **started ahead**: ``crd`` forks it before it imports the rest of crd (0.25 s), so
  matplotlib is imported on the second core meanwhile (:func:`cosim.cli.paper.plot_worker_ahead`);
  or :func:`cosim.loop.concurrent.run_concurrently` forks it beside the run workers;
* **told what to draw** (:meth:`PlotWorker.bind`): a :class:`Drawing` (pickled, when the
  worker was started before it existed), then each run's record as it comes in
  (:meth:`timeline`: the path of the record's pickle, so the parent never waits on a
  busy pipe) and, when every run is in, all of them (:meth:`finale`);
* **two figures at once**: once at most one run is left, it forks a spare (which
  shares matplotlib's pages with it, copy on write, instead of importing them);
  the parent sends the finale to the spare as soon as every run is in, so it is
  drawn beside the last timeline even when the worker is still busy with the one
  before. Not earlier: a fork that draws holds its own copy of the pages either
  process writes (about 25 MB), and while two runs go on that would take
  ``crd paper`` over its memory goal;
* **its own process group**, so a terminal's Ctrl-C reaches only ``crd``, which
  decides; SIGTERM (:meth:`stop`) ends it at once; it also ends when ``crd`` has gone
  (its pipe closes);
* **failures** (an exception in a draw) are collected and returned by :meth:`PlotWorker.failures`;
  a worker that dies without a word is an error naming its exit status.

Everything here is standard library: ``crd`` imports this module before anything else.
"""

from __future__ import annotations

import gc
import multiprocessing
import os
import pickle
import signal
from collections import deque
from contextlib import contextmanager
from multiprocessing.connection import Connection, wait
from typing import Callable, Iterator, Protocol, Sequence


class Drawing(Protocol):
    """What the worker draws: ``preload()`` (import matplotlib), each run's ``timeline(record)``, and the
    ``finale(records)`` of every run (None: no such figure)."""

    preload: Callable[[], None]
    timeline: Callable[[object], None]
    finale: Callable[[list], None] | None


class Failure:
    """What a draw returns instead of None: the exception (or its text, when it cannot be pickled)."""

    def __init__(self, exc: BaseException) -> None:
        self.exc: BaseException = exc


def cores() -> int:
    """The cores this process may run on (its CPU affinity where the OS tells it, else all of them)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def attempt(task: Callable[[], object]) -> object:
    """``task()``, or a :class:`Failure` holding what it raised."""
    try:
        return task()
    except Exception as exc:  # noqa: BLE001 - every failure goes back to the parent
        return Failure(exc)


def send(conn: Connection, message: object) -> None:
    """Send ``message``; a failure whose exception cannot be pickled goes as its text."""
    try:
        conn.send(message)
    except BrokenPipeError:
        raise
    except Exception as exc:  # noqa: BLE001 - e.g. pickling
        text = message.exc if isinstance(message, Failure) else exc
        conn.send(Failure(RuntimeError(f"{type(text).__name__}: {text}")))


def _reply(conn: Connection, failures: list[Failure]) -> None:
    """Send ``failures`` (the reply to ``finish``); an exception that cannot be pickled goes as its text."""
    def picklable(failure: Failure) -> Failure:
        try:
            pickle.dumps(failure.exc)
            return failure
        except Exception:  # noqa: BLE001 - e.g. a local class, a lock in its arguments
            return Failure(RuntimeError(f"{type(failure.exc).__name__}: {failure.exc}"))

    conn.send([picklable(f) for f in failures])


def import_matplotlib() -> None:
    """The default ``preload`` of a worker started ahead (imports crd's plotting module and matplotlib)."""
    from .plots import preload_matplotlib

    preload_matplotlib()


def load_record(path: str):
    """A record pickled by a run worker (:mod:`cosim.loop.concurrent`)."""
    with open(path, "rb") as handle:
        return pickle.load(handle)


class PlotWorker:
    """The parent's handle on the plotting process and its spare (module docstring); :meth:`stop` is
    idempotent. Timelines go to the worker, the finale to the spare: each has its own pipe."""

    def __init__(self, process: multiprocessing.process.BaseProcess, conn: Connection, spare: Connection) -> None:
        self._process, self._conn, self._spare = process, conn, spare
        self.bound = False
        self._finale_asked = False

    @property
    def pid(self) -> int:
        return self._process.pid

    @classmethod
    def start(cls, drawing: Drawing | None = None, preload: Callable[[], None] | None = None) -> PlotWorker:
        """Fork the worker; it runs ``preload()`` at once (default: ``drawing.preload``, or
        :func:`import_matplotlib` without a drawing)."""
        if preload is None:
            preload = drawing.preload if drawing is not None else import_matplotlib
        context = multiprocessing.get_context("fork")
        (theirs, ours), (spare_end, spare) = context.Pipe(duplex=True), context.Pipe(duplex=True)
        gc.freeze()  # the worker's collector never walks (so never copies) the pages it inherits
        try:
            process = context.Process(target=_serve, args=(theirs, spare_end, drawing, preload), daemon=True)
            process.start()
        finally:
            gc.unfreeze()
            theirs.close()
            spare_end.close()
        try:
            os.setpgid(process.pid, process.pid)  # as the worker does: whichever comes first
        except OSError:
            pass  # it has set it already, or has ended
        worker = cls(process, ours, spare)
        worker.bound = drawing is not None
        return worker

    def bind(self, drawing: Drawing) -> None:
        """What to draw, for a worker started without it (``drawing`` is pickled: no closures)."""
        if not self.bound:
            for conn in (self._conn, self._spare):
                conn.send(("drawing", drawing))
            self.bound = True

    def timeline(self, record_path: str, runs_left: int) -> None:
        """Draw the timeline of the record pickled at ``record_path``; ``runs_left``: runs not yet in
        (at one or none, the worker forks its spare)."""
        self._conn.send(("timeline", (record_path, runs_left)))

    def finale(self, record_paths: Sequence[str]) -> None:
        """Draw the figure of every run (records pickled at ``record_paths``, in order): the spare does."""
        self._spare.send(("finale", list(record_paths)))
        self._finale_asked = True

    def finish(self) -> None:
        """Say that nothing more comes: the worker (and the spare) draw what is waiting, reply and end."""
        ends = [self._conn] + ([] if self._finale_asked else [self._spare])
        for conn in ends:
            try:
                conn.send(("finish", None))
            except (BrokenPipeError, ConnectionResetError):
                pass  # it has ended: failures() says so

    def failures(self) -> list[BaseException]:
        """Wait for the replies to :meth:`finish`: the draws' failures. A signal meanwhile raises here
        with nothing read (call again to go on waiting)."""
        failures = []
        for conn, who in ((self._conn, "plot worker"), (self._spare, "plot worker's spare")):
            if not conn.closed:
                wait([conn])
                failures += self._reply(conn, who)
        self._process.join()  # it ends once it has replied and its spare has ended
        return failures

    def _reply(self, conn: Connection, who: str) -> list[BaseException]:
        with _signals_held():  # the reply is read whole or not at all
            try:
                reply = [f.exc for f in conn.recv()]
            except (EOFError, ConnectionResetError):
                self._process.join(timeout=0.1)  # the worker's exit status (the spare's goes to the worker)
                status = f" (exit status {self._process.exitcode})" if conn is self._conn else ""
                reply = [RuntimeError(f"the {who} ended{status} before drawing every figure")]
            conn.close()
        return reply

    def stop(self) -> None:
        """End the worker now (if it still runs) and wait for it; its spare ends as its pipe closes."""
        if self._conn.closed and self._spare.closed:
            return
        self._conn.close()
        self._spare.close()
        if self._process.is_alive():
            self._process.terminate()
        self._process.join()


@contextmanager
def _signals_held() -> Iterator[None]:
    """SIGINT and SIGTERM held back within the block (delivered at its end)."""
    held = {signal.SIGINT, signal.SIGTERM}
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, held)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def _serve(conn: Connection, spare_conn: Connection, drawing: Drawing | None, preload: Callable[[], None]) -> None:
    """The worker: preload, then draw each timeline it is sent, until the parent says ``finish`` (or has
    gone); it forks the spare once at most one run is left (or at ``finish``)."""
    os.setpgid(0, 0)
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, signal.SIG_DFL)  # not crd's handlers: the parent decides, and stop() is final
    preload()
    # matplotlib's objects live as long as this process: frozen, the collector's full passes skip them
    # (about a tenth of the drawing's CPU, measured on the paper's four figures)
    gc.freeze()
    queue = _Queue(drawing, conn, spare_conn)
    try:
        while True:
            for kind, payload in _messages(conn, block=not queue.waiting):
                if kind == "drawing":
                    queue.drawing = payload
                elif kind == "finish":
                    _reply(conn, queue.drain())
                    return
                else:
                    queue.add(*payload)
            queue.draw_next()
    except (EOFError, BrokenPipeError):
        return  # the parent has gone
    finally:
        conn.close()
        queue.end_spare()


def _messages(conn: Connection, block: bool) -> list[tuple[str, object]]:
    """The messages waiting (``block``: at least one)."""
    found = [conn.recv()] if block else []
    while conn.poll():
        found.append(conn.recv())
    return found


class _Queue:
    """The timelines asked for and not yet drawn, and the spare (the finale's drawer)."""

    def __init__(self, drawing: Drawing | None, conn: Connection, spare_conn: Connection) -> None:
        self.drawing = drawing
        self.waiting: deque[str] = deque()
        self.failures: list[Failure] = []
        self._records: dict[str, object] = {}  # path -> record, loaded once
        self._conn, self._spare_conn = conn, spare_conn
        self._spare: int | None = None  # its pid

    def add(self, path: str, runs_left: int) -> None:
        self.waiting.append(path)
        if runs_left <= 1:
            self._fork_spare()

    def draw_next(self) -> None:
        if self.waiting:
            self._draw(lambda: self.drawing.timeline(self._record(self.waiting.popleft())))

    def drain(self) -> list[Failure]:
        """Draw every timeline still waiting; the failures."""
        self._fork_spare()  # not forked yet (a run failed or was interrupted): it answers the parent's finish
        while self.waiting:
            self.draw_next()
        return self.failures

    def _draw(self, task: Callable[[], object]) -> None:
        result = attempt(task)
        if isinstance(result, Failure):
            self.failures.append(result)

    def _record(self, path: str):
        if path not in self._records:
            self._records[path] = load_record(path)
        return self._records[path]

    def _fork_spare(self) -> None:
        """Fork the spare (once): it draws the finale the parent sends it, beside this process's last
        timeline. Not before at most one run is left: a fork that draws holds its own copy of the
        matplotlib pages either process writes (about 25 MB), and while two runs go on that would take
        ``crd paper`` over its memory goal. A plain fork (this process is a daemon)."""
        if self._spare is not None or self._spare_conn.closed:
            return
        gc.freeze()  # the spare's collector leaves the inherited pages alone; here they stay frozen (_serve)
        pid = os.fork()
        if pid == 0:  # the spare
            try:
                self._conn.close()
                _serve_spare(self._spare_conn, self.drawing, self._record)
            finally:
                os._exit(0)  # no clean-up of what it inherited
        self._spare = pid
        self._spare_conn.close()  # the spare's now: the parent sees its end when it ends

    def end_spare(self) -> None:
        """Wait for the spare (it ends after its reply, or when the parent's pipe closes)."""
        self._spare_conn.close()
        if self._spare is not None:
            os.waitpid(self._spare, 0)


def _serve_spare(conn: Connection, drawing: Drawing | None, record: Callable[[str], object]) -> None:
    """The spare: the finale (or nothing, at ``finish``), then its reply: the failures."""
    try:
        while True:
            kind, payload = conn.recv()
            if kind == "drawing":
                drawing = payload
            elif kind == "finale":
                result = attempt(lambda: drawing.finale([record(p) for p in payload]))
                _reply(conn, [result] if isinstance(result, Failure) else [])
                return
            else:  # finish
                _reply(conn, [])
                return
    except (EOFError, BrokenPipeError):
        return  # the parent has gone
