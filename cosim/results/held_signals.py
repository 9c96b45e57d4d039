"""SIGINT and SIGTERM held back over a write that must be whole (delivered when it ends).

``crd run`` and ``crd paper`` turn the first SIGINT or SIGTERM into an exception in
the main thread (:mod:`cosim.cli.signals`). Raised in the middle of a write, it can
leave a file's writer half-updated: python-can's ``BLFWriter`` swaps its buffer
before it compresses and writes a container, so an exception during the compression
lost the last simulated second of frames from an interrupted run's ``can.blf``
(seen 2 in 8 runs under load). Within :func:`signals_held` the signals are blocked
for this thread, the operating system keeps them pending, and the handler runs as
soon as the block ends.
"""

from __future__ import annotations

import signal
from contextlib import contextmanager
from typing import Iterator

_HELD = frozenset({signal.SIGINT, signal.SIGTERM})


@contextmanager
def signals_held() -> Iterator[None]:
    """SIGINT and SIGTERM held back within the block (delivered at its end)."""
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, _HELD)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)
