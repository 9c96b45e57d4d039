"""The cyclic garbage collector's full passes deferred while a run's loop goes.

A full (generation 2) collection walks every object the collector tracks in the process:
about 92,000 after crd's imports, 26-32 ms each time. CPython starts one when the objects
that survived the younger collections have grown by a quarter since the last one, which a
run's records (4,000 rows, 26,000 logged frames in the paper's 40 s) bring about at a cycle
nobody chooses: the paper's tightening run in process took 131-141x real time instead of
151-159x in 3 of 10 runs (``python benchmarks/bench_cosim.py --skip-paper`` showed it as a
spread of 121-158x). Within :func:`full_collections_deferred` generation 2's threshold is out
of reach; the young collections go on as before, so a reference cycle a co-simulation cycle
makes is still freed (a paper run makes about 900 objects in cycles, all in its set-up). The
pass left out comes at the first young collection after the block: it is moved, not saved
(over 30 paper runs in one process the CPU time is 1 % lower, 8 full passes instead of 9).
What it buys is a loop of steady speed, and in real time no 30 ms pause within a 10 ms cycle.

The thresholds belong to the process, so only the main thread defers (a sweep's runs in
Dask's worker threads are left as they are).
"""

from __future__ import annotations

import gc
import threading
from contextlib import contextmanager
from typing import Iterator

_OUT_OF_REACH = 1 << 30  # young collections before a full one: never, within a run


@contextmanager
def full_collections_deferred() -> Iterator[None]:
    """No full collection within the block (main thread only; the thresholds are restored after)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    young0, young1, full = gc.get_threshold()
    gc.set_threshold(young0, young1, _OUT_OF_REACH)
    try:
        yield
    finally:
        gc.set_threshold(young0, young1, full)
