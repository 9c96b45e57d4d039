"""No full garbage collection within a run's loop (cosim/loop/collector.py).

A full pass walks every tracked object of the process (26-32 ms after crd's imports); one
that fell within a run made the paper's tightening run 10-15 % slower in 3 of 10 runs.
"""

from __future__ import annotations

import gc
import threading

from cosim.cli.paper import PAPER_SCENARIO
from cosim.loop.collector import full_collections_deferred
from cosim.loop.master import ClosedLoop
from cosim.scenarios.loader import load_scenario


def test_a_run_makes_no_full_collection_and_young_ones_go_on(plant_fmu3):
    loop = ClosedLoop(load_scenario(PAPER_SCENARIO), plant_fmu3, "tightening")
    passes: list[int] = []

    def seen(phase: str, info: dict) -> None:
        if phase == "start":
            passes.append(info["generation"])

    before = gc.get_threshold()
    gc.collect()
    # survivors that the run's young collections move to the oldest generation: more than a quarter
    # of what a full pass found, so one is due within the run (as the records of earlier runs make it)
    gc.disable()  # made without a collection, so the run's young collections move them on
    survivors = [[] for _ in range(len(gc.get_objects()))]  # (an empty dict is not tracked; a list is)
    gc.enable()
    gc.set_threshold(before[0], before[1], 1)
    gc.callbacks.append(seen)
    try:
        record = loop.run()
    finally:
        gc.callbacks.remove(seen)
        gc.set_threshold(*before)
    assert record.error is None and len(survivors) > 0
    assert 2 not in passes and passes.count(0) > 10  # no full pass; the young ones as usual
    assert gc.get_threshold() == before


def test_only_the_main_thread_defers():
    before = gc.get_threshold()
    inside = []

    def other() -> None:
        with full_collections_deferred():
            inside.append(gc.get_threshold())

    thread = threading.Thread(target=other)
    thread.start()
    thread.join()
    assert inside == [before]
    with full_collections_deferred():
        assert gc.get_threshold()[2] > 1_000_000 and gc.get_threshold()[:2] == before[:2]
    assert gc.get_threshold() == before
