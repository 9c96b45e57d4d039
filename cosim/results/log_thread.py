"""A run's logs written on a background thread, fed by a bounded queue (issue 25, item 5).

:class:`cosim.results.stream.RunStream` hands each second's new time-series rows and CAN frames
(slices of the record: references, no copies of the values) to a :class:`LogThread`, which formats,
packs, compresses and writes them in the order they came. The co-simulation loop then pays only for
the hand-over; zlib and the file writes release the GIL, so on a machine with a spare core they run
beside the loop (the formatting and packing still take the GIL, in turns with the loop).

* **bounded** (:data:`QUEUE_DEPTH`): the loop is at most that many batches ahead of the disk; a slow
  disk slows the run instead of filling the memory, as a write in the loop's own thread did;
* **signals**: the thread is started with SIGINT and SIGTERM blocked and keeps them blocked, so they
  go to the main thread alone, and :func:`~cosim.results.held_signals.signals_held` there still holds
  them (a thread that took them would let Python run the handler inside a held block);
* **a failed write** (a full disk, a file that cannot be written, a bug): the thread keeps the
  exception, writes nothing more and keeps taking batches (so the loop never waits for ever on a full
  queue); the next :meth:`LogThread.put`, or :meth:`LogThread.close`, raises it as
  :class:`LogWriteError`, once. The run stops there, as it stopped at the write before, with what
  was written kept;
* :meth:`LogThread.close` writes every batch handed over, then ends the thread: a run that ends on an
  interrupt or an error keeps its logs complete (the caller closes in a ``finally``).
"""

from __future__ import annotations

import queue
import signal
import threading
from typing import Callable, Generic, TypeVar

from ..errors import CosimError
from .held_signals import SIGNALS, signals_held

#: batches (a simulated second each, from :meth:`RunStream.flush`) the loop may be ahead of the disk
QUEUE_DEPTH = 2

Batch = TypeVar("Batch")
_END = object()


class LogWriteError(CosimError, RuntimeError):
    """A run's logs could not be written (the cause: the exception the writing thread met)."""


class LogThread(Generic[Batch]):
    """Calls ``write(batch)`` on one background thread for each :meth:`put` batch, in order (module docstring)."""

    def __init__(self, write: Callable[[Batch], None], what: str) -> None:
        self._write, self._what = write, what
        self._queue: queue.Queue = queue.Queue(maxsize=QUEUE_DEPTH)
        self.error: BaseException | None = None
        self._reported = False
        self._thread = threading.Thread(target=self._run, name=f"crd logs {what}", daemon=True)
        with signals_held():  # a new thread starts with its creator's signal mask
            self._thread.start()

    def put(self, batch: Batch) -> None:
        """Hand ``batch`` over (waits while :data:`QUEUE_DEPTH` batches are unwritten); raises
        :class:`LogWriteError` if a write has failed."""
        self._raise_error()
        self._queue.put(batch)

    def close(self) -> None:
        """Write every batch handed over and end the thread; raises :class:`LogWriteError` if a write
        failed and no :meth:`put` has said so. Signals are held meanwhile: the files stay whole."""
        with signals_held():
            if self._thread.is_alive():
                self._queue.put(_END)
                self._thread.join()
        self._raise_error()

    def _run(self) -> None:
        signal.pthread_sigmask(signal.SIG_BLOCK, SIGNALS)  # already blocked from the start; never unblocked here
        while (batch := self._queue.get()) is not _END:
            if self.error is None:
                try:
                    self._write(batch)
                except BaseException as exc:  # noqa: BLE001 - kept, raised in the main thread
                    self.error = exc

    def _raise_error(self) -> None:
        if self.error is not None and not self._reported:
            self._reported = True
            raise LogWriteError(f"{self._what}: writing the logs failed: {self.error}") from self.error
