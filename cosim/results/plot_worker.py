"""A forked process that draws a series' figures while the runs go on (``crd paper``).

Importing matplotlib takes about 0.35 s of CPU and each figure about 0.16 s; the
runs take about 1 s. :class:`PlotWorker` moves all of it off the critical path:

* **started ahead**: ``crd`` forks it before it imports the rest of crd (0.25 s), so
  matplotlib is imported on the second core meanwhile (:func:`cosim.cli.paper.plot_worker_ahead`);
  or :func:`cosim.loop.concurrent.run_concurrently` forks it beside the run workers;
* **told what to draw** (:meth:`PlotWorker.bind`): a :class:`Drawing` (pickled, when the
  worker was started before it existed), then each run's record as it comes in
  (:meth:`timeline`: the path of the record's pickle, so the parent never waits on a
  busy pipe) and, with the last run's, all of them (:meth:`last`);
* **two figures at once**: once every run is in (the finale is asked for), with two or
  more figures waiting (the last run's timeline and the finale) it forks a helper for
  one of them and draws the other itself: the helper shares matplotlib's pages with it
  (copy on write) instead of importing them. Not before: while runs go on, both cores
  are busy anyway, and a helper would hold a second copy of the pages it draws with;
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
from multiprocessing.connection import Connection, wait
from typing import Callable, Protocol, Sequence

from .held_signals import signals_held


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
        except Exception:  # noqa: BLE001 - e.g. a local class, a lock among its arguments
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
    """The parent's handle on the plotting process (module docstring). :meth:`stop` is idempotent."""

    def __init__(self, process: multiprocessing.process.BaseProcess, conn: Connection) -> None:
        self._process, self._conn = process, conn
        self.bound = False

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
        theirs, ours = context.Pipe(duplex=True)
        gc.freeze()  # the worker's collector never walks (so never copies) the pages it inherits
        try:
            process = context.Process(target=_serve, args=(theirs, drawing, preload), daemon=True)
            process.start()
        finally:
            gc.unfreeze()
            theirs.close()
        try:
            os.setpgid(process.pid, process.pid)  # as the worker does: whichever comes first
        except OSError:
            pass  # it has set it already, or has ended
        worker = cls(process, ours)
        worker.bound = drawing is not None
        return worker

    def bind(self, drawing: Drawing) -> None:
        """What to draw, for a worker started without it (``drawing`` is pickled: no closures)."""
        if not self.bound:
            self._conn.send((("drawing", drawing),))
            self.bound = True

    def timeline(self, record_path: str) -> None:
        """Draw the timeline of the record pickled at ``record_path``."""
        self._conn.send((("timeline", record_path),))

    def last(self, record_path: str, record_paths: Sequence[str]) -> None:
        """Draw the timeline of the last run's record (at ``record_path``) and the figure of every run
        (records at ``record_paths``, in order), asked for in one message: the worker has both at once,
        so it draws them side by side (asked one after the other, an idle worker started on the
        timeline alone and drew the finale after it: 0.1 s more at the end of ``crd paper``)."""
        self._conn.send((("timeline", record_path), ("finale", list(record_paths))))

    def finish(self) -> None:
        """Say that nothing more comes: the worker draws what is waiting, replies and ends (:meth:`failures`)."""
        try:
            self._conn.send((("finish", None),))
        except (BrokenPipeError, ConnectionResetError):
            pass  # it has ended: failures() says so

    def failures(self) -> list[BaseException]:
        """Wait for the worker's reply to :meth:`finish`: the draws' failures. A signal meanwhile raises
        here with nothing read (call again to go on waiting)."""
        wait([self._conn])
        with signals_held():  # the reply is read whole or not at all
            try:
                failures = [f.exc for f in self._conn.recv()]
            except (EOFError, ConnectionResetError):
                self._process.join()
                failures = [RuntimeError(f"the plot worker ended (exit status {self._process.exitcode})"
                                         " before drawing every figure")]
        self._conn.close()
        self._process.join()  # it ends once it has replied
        return failures

    def stop(self) -> None:
        """End the worker now (if it still runs) and wait for it."""
        if self._conn.closed:
            return
        self._conn.close()
        if self._process.is_alive():
            self._process.terminate()
        self._process.join()


def _serve(conn: Connection, drawing: Drawing | None, preload: Callable[[], None]) -> None:
    """The worker: preload, then draw what the parent asks, until it says ``finish`` (or has gone)."""
    os.setpgid(0, 0)
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, signal.SIG_DFL)  # not crd's handlers: the parent decides, and stop() is final
    preload()
    # matplotlib's objects live as long as this process: frozen, the collector's full passes skip them
    # (about a tenth of the drawing's CPU, measured on the paper's four figures)
    gc.freeze()
    queue = _Queue(drawing)
    try:
        while True:
            for kind, payload in _messages(conn, block=not queue.waiting):
                if kind == "drawing":
                    queue.drawing = payload
                elif kind == "finish":
                    _reply(conn, queue.drain())
                    return
                else:
                    queue.waiting.append((kind, payload))
                    queue.all_in = queue.all_in or kind == "finale"
            queue.draw_next()
    except (EOFError, BrokenPipeError):
        return  # the parent has gone
    finally:
        conn.close()


def _messages(conn: Connection, block: bool) -> list[tuple[str, object]]:
    """The messages waiting (``block``: at least one); each read from the pipe is a tuple of them."""
    found = list(conn.recv()) if block else []
    while conn.poll():
        found.extend(conn.recv())
    return found


class _Queue:
    """The figures asked for and not yet drawn; a forked helper draws one when two or more wait."""

    def __init__(self, drawing: Drawing | None) -> None:
        self.drawing = drawing
        self.waiting: deque[tuple[str, object]] = deque()
        self.failures: list[Failure] = []
        self.all_in = False  # every run is in: a helper may draw beside this process
        self._helper: tuple[int, Connection] | None = None

    def draw_next(self) -> None:
        if not self.waiting:
            return
        if self._helper is not None and self._helper[1].poll():
            self._join_helper()  # done: another may start
        if self.all_in and len(self.waiting) > 1 and self._helper is None:
            self._helper = self._fork(self.waiting.pop())
        self._draw(self.waiting.popleft())

    def drain(self) -> list[Failure]:
        """Draw everything still waiting, wait for the helper; the failures."""
        self.all_in = True
        while self.waiting:
            self.draw_next()
        self._join_helper()
        return self.failures

    def _draw(self, item: tuple[str, object]) -> None:
        result = attempt(lambda: self._call(*item))
        if isinstance(result, Failure):
            self.failures.append(result)
        if not self.all_in:  # while runs go on (the tree's peak memory), not in the last figures' way
            gc.collect()  # a closed figure is a web of cycles: freed now (about 6 MB; 10 ms a figure)

    def _call(self, kind: str, payload) -> None:
        """Draw one item; its records are read from their files each time (kept, they would add to the
        tree's peak memory while runs go on; the finale, usually the helper's, reads them all again)."""
        if kind == "timeline":
            self.drawing.timeline(load_record(payload))
        elif self.drawing.finale is not None:
            self.drawing.finale([load_record(p) for p in payload])

    def _fork(self, item: tuple[str, object]) -> tuple[int, Connection]:
        """A helper (a plain fork: this process is a daemon) that draws ``item`` and sends the outcome."""
        reader, writer = multiprocessing.Pipe(duplex=False)
        gc.freeze()  # the helper's collector leaves the inherited pages alone; here they stay frozen (_serve)
        pid = os.fork()
        if pid == 0:  # the helper
            try:
                reader.close()
                send(writer, attempt(lambda: self._call(*item)))
            finally:
                os._exit(0)  # no clean-up of what it inherited
        writer.close()
        return pid, reader

    def _join_helper(self) -> None:
        if self._helper is None:
            return
        pid, conn = self._helper
        self._helper = None
        try:
            result = conn.recv()
        except EOFError:
            result = Failure(RuntimeError("the plot helper ended without reporting"))
        conn.close()
        os.waitpid(pid, 0)
        if isinstance(result, Failure):
            self.failures.append(result)
