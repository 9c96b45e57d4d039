"""SIGINT and SIGTERM held back where acting on them would leave a half-done piece of work.

``crd run`` and ``crd paper`` turn the first SIGINT or SIGTERM into an exception in
the main thread (:mod:`cosim.cli.signals`), raised at whatever bytecode is running.
Two kinds of work must not be cut in two by it:

* **a write** (:func:`signals_held`): python-can's ``BLFWriter`` swaps its buffer
  before it compresses and writes a container, so an exception during the compression
  lost the last simulated second of frames from an interrupted run's ``can.blf``
  (seen 2 in 8 runs under load). Within the block the signals are blocked for this
  thread, the operating system keeps them pending, and the handler runs as soon as
  the block ends;
* **a co-simulation cycle** (:class:`SafePoints`): raised between the cycle's logged
  frames and its time-series row, the run's ``can.blf`` ended one cycle after its
  ``timeseries.csv`` (1 in 28 runs under load). Within the block a signal is only
  noted; the loop gives it to the handler from before (:meth:`SafePoints.act`) where
  a cycle ends, at a cost of one test of a list per cycle.
"""

from __future__ import annotations

import signal
import threading
from contextlib import contextmanager
from typing import Iterator

#: the signals held back here (and by :mod:`cosim.loop.concurrent`'s workers outside a run)
SIGNALS = frozenset({signal.SIGINT, signal.SIGTERM})


@contextmanager
def signals_held() -> Iterator[None]:
    """SIGINT and SIGTERM held back within the block (delivered at its end).

    The mask is read before it is changed, and changed inside ``try``: ``pthread_sigmask`` runs the
    Python handlers of signals already pending once the new mask is set, so a KeyboardInterrupt can
    leave the call with the signals blocked; the ``finally`` then still restores the mask (before,
    such a signal left SIGINT blocked in the main thread for good: seen under load in the tests)."""
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, ())
    try:
        signal.pthread_sigmask(signal.SIG_BLOCK, SIGNALS)
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


class SafePoints:
    """Within the block, SIGINT and SIGTERM are appended to :attr:`noted` instead of handled; the
    caller calls :meth:`act` at a safe point (the end of a cycle) when :attr:`noted` is not empty.

    :meth:`act` restores the handlers from before the block and raises the first noted signal to
    them (whatever they do, e.g. raise ``KeyboardInterrupt``, happens there); from then on signals
    go to them directly. A second signal before that is acted on at once, wherever the loop is (it
    may be waiting on a stalled ECU), as is one noted but not acted on when the block ends. Only a
    signal with a handler set in Python is held (an ignored one stays ignored, a default one acts
    at once); outside the main thread (which alone receives signals in Python) none is.
    """

    def __init__(self) -> None:
        self.noted: list[int] = []
        self._previous: dict[int, object] = {}

    def __enter__(self) -> SafePoints:
        if threading.current_thread() is threading.main_thread():
            for sig in SIGNALS:
                if callable(signal.getsignal(sig)):
                    self._previous[sig] = signal.signal(sig, self._note)
        return self

    def _note(self, signum: int, _frame) -> None:
        self.noted.append(signum)
        if len(self.noted) > 1:
            self.act()

    def act(self) -> None:
        """Give the first noted signal to the handlers from before the block (restored now)."""
        self._restore()
        first = self.noted[0]
        self.noted.clear()  # acted on (a handler that does not raise is not called again at the next point)
        signal.raise_signal(first)

    def _restore(self) -> None:
        previous, self._previous = self._previous, {}
        for sig, handler in previous.items():
            signal.signal(sig, handler)

    def __exit__(self, *exc_info) -> None:
        if self._previous and self.noted:
            self.act()
        self._restore()
