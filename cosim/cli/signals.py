"""SIGINT and SIGTERM end a run with its results so far written (exit 130 and 143).

:func:`interruptible` wraps a subcommand's handler (``crd run``, ``crd paper``).
While it runs, the first SIGINT or SIGTERM raises
:class:`~cosim.errors.RunInterrupted` in the main thread (a
``KeyboardInterrupt`` carrying the signal number). The master catches it,
marks the run ``interrupted`` and keeps its record;
:func:`cosim.loop.experiment.run_strategies` writes what was run (the
streamed files, ``metrics.json`` with the status, events) and raises it on;
``crd``'s entry point exits ``128 + signal``: 130 for SIGINT, 143 for SIGTERM.

A second signal while the results are being written means "now": the
default action of that signal ends the process (what was streamed is on disk
already). The previous handlers are restored when the handler returns.
"""

from __future__ import annotations

import functools
import os
import signal
from contextlib import contextmanager
from typing import Callable, Iterator

from ..errors import RunInterrupted

SIGNALS = (signal.SIGINT, signal.SIGTERM)


@contextmanager
def signals_interrupt() -> Iterator[None]:
    """Within the block, SIGINT/SIGTERM raise :class:`RunInterrupted` once; a second one ends the process."""
    received: list[int] = []

    def on_signal(signum: int, _frame) -> None:
        received.append(signum)
        if len(received) == 1:
            raise RunInterrupted(signum)
        signal.signal(signum, signal.SIG_DFL)
        os.kill(os.getpid(), signum)

    previous = {sig: signal.signal(sig, on_signal) for sig in SIGNALS}
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


def interruptible(handler: Callable[..., int]) -> Callable[..., int]:
    """``handler`` run inside :func:`signals_interrupt`."""

    @functools.wraps(handler)
    def wrapped(*args, **kwargs) -> int:
        with signals_interrupt():
            return handler(*args, **kwargs)

    return wrapped
