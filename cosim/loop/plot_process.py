"""A process that draws a figure while this one draws another (``crd paper``'s last two figures at once).

When the last run of ``crd paper`` ends, two figures are left: its ``timeline.png`` and
``speed_profiles.png``, the figure of every run. Drawn one after the other they take about
0.3 s each on one core while the other core is idle. :class:`PlotProcess` is a
:class:`~concurrent.futures.ProcessPoolExecutor` of one worker, forked once matplotlib is imported
here, so it draws without importing it again; the caller hands it one figure and draws the other
itself (measured: ``benchmarks/paper_phases.py``).

The worker has its own process group (a terminal's Ctrl-C reaches crd alone) and blocks SIGINT and
SIGTERM: a figure it has been given is drawn whole; crd decides what happens on a signal.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
from concurrent.futures import Future, ProcessPoolExecutor
from typing import Callable

from ..results.held_signals import SIGNALS
from .concurrent import forking

__all__ = ["PlotProcess"]


def _start_plot_worker() -> None:
    os.setpgid(0, 0)
    signal.pthread_sigmask(signal.SIG_BLOCK, SIGNALS)


class PlotProcess:
    """One worker process forked at :meth:`start`, inheriting this process's imports; a context manager
    (on the way out, the figures it was given are finished and the worker ends)."""

    def __init__(self) -> None:
        self._pool: ProcessPoolExecutor | None = None

    def start(self) -> None:
        """Fork the worker now (call it once matplotlib is imported), so that no later ``submit`` waits for it."""
        self._pool = ProcessPoolExecutor(max_workers=1, mp_context=multiprocessing.get_context("fork"),
                                         initializer=_start_plot_worker)
        with forking():
            self._pool.submit(os.getpid)  # a fork-context pool starts its worker at the first submit

    def submit(self, draw: Callable[..., None], *args) -> Future:
        """``draw(*args)`` in the worker (``draw`` and ``args`` are pickled: a module-level function and data)."""
        if self._pool is None:
            raise RuntimeError("PlotProcess.submit before start()")
        return self._pool.submit(draw, *args)

    def __enter__(self) -> PlotProcess:
        return self

    def __exit__(self, *exc_info) -> None:
        if self._pool is not None:
            self._pool.shutdown(cancel_futures=True)
