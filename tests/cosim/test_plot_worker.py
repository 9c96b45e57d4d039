"""The plot worker (:mod:`cosim.results.plot_worker`, issue 10's ``crd paper`` time): it draws what
it is sent, two figures at once once every run is in, reports failures and a crash, ends when told."""

from __future__ import annotations

import os
import pickle
import time
from pathlib import Path

import pytest

from cosim.results.plot_worker import PlotWorker
from cosim.results.run_record import RunMetrics, RunRecord
from tests.os_processes import process_gone


class PidDrawing:
    """Writes ``<name>.pid`` (the drawing process) per figure; module level, so it can be pickled."""

    def __init__(self, out: Path, draw_s: float = 0.0, fail: str = "") -> None:
        self.out, self.draw_s, self.fail = out, draw_s, fail

    def preload(self) -> None:
        pass

    def timeline(self, record: RunRecord) -> None:
        self._draw(record.strategy)

    def finale(self, records: list[RunRecord]) -> None:
        self._draw("finale-" + "-".join(r.strategy for r in records))

    def _draw(self, name: str) -> None:
        if name == self.fail:
            raise ValueError(f"cannot draw {name}")
        if name == "crash":
            os._exit(5)  # as a segfault in matplotlib's C code would
        time.sleep(self.draw_s)
        (self.out / f"{name}.pid").write_text(str(os.getpid()))


def _spool(tmp_path: Path, *strategies: str) -> list[str]:
    paths = []
    for s in strategies:
        path = tmp_path / f"{s}.pickle"
        path.write_bytes(pickle.dumps(RunRecord(s, RunMetrics(s), rows=[(0.0,)])))
        paths.append(str(path))
    return paths


def _drawn_by(tmp_path: Path) -> dict[str, int]:
    return {p.stem: int(p.read_text()) for p in tmp_path.glob("*.pid")}


def test_a_worker_started_ahead_draws_what_it_is_sent_and_the_last_two_side_by_side(tmp_path):
    worker = PlotWorker.start(preload=lambda: None)  # as crd paper's: the drawing comes later, pickled
    try:
        worker.bind(PidDrawing(tmp_path, draw_s=0.2))
        a, b, c, d = _spool(tmp_path, "a", "b", "c", "d")
        for path in (a, b, c):  # three waiting while runs go on: drawn one after the other, here
            worker.timeline(path)
        deadline = time.monotonic() + 30.0
        while not (tmp_path / "c.pid").exists() and time.monotonic() < deadline:
            time.sleep(0.02)
        time.sleep(0.3)  # the worker is idle (c drawn) when the last run comes in, as in crd paper
        worker.last(d, [a, b, c, d])  # its timeline and the finale at once: drawn side by side
        worker.finish()
        assert worker.failures() == []
    finally:
        worker.stop()
    pids = _drawn_by(tmp_path)
    assert sorted(pids) == ["a", "b", "c", "d", "finale-a-b-c-d"]
    assert pids["a"] == pids["b"] == pids["c"] == pids["d"] == worker.pid != pids["finale-a-b-c-d"]
    assert process_gone(worker.pid) and process_gone(pids["finale-a-b-c-d"])


def test_a_failed_draw_is_reported_and_the_others_are_drawn(tmp_path):
    worker = PlotWorker.start(PidDrawing(tmp_path, fail="b"))
    try:
        paths = _spool(tmp_path, "a", "b", "c")
        for path in paths[:2]:
            worker.timeline(path)
        worker.last(paths[2], paths)
        worker.finish()
        failures = worker.failures()
    finally:
        worker.stop()
    assert [str(f) for f in failures] == ["cannot draw b"]
    assert sorted(_drawn_by(tmp_path)) == ["a", "c", "finale-a-b-c"]


def test_a_worker_that_dies_is_an_error_naming_its_exit_status(tmp_path):
    worker = PlotWorker.start(PidDrawing(tmp_path))
    try:
        worker.timeline(_spool(tmp_path, "crash")[0])
        worker.finish()
        with pytest.raises(RuntimeError, match=r"the plot worker ended \(exit status 5\)"):
            raise worker.failures()[0]
    finally:
        worker.stop()


def test_stop_ends_an_unused_worker_at_once(tmp_path):
    started = time.monotonic()
    worker = PlotWorker.start(PidDrawing(tmp_path), preload=lambda: time.sleep(30))  # as a slow import
    pid = worker.pid
    worker.stop()
    worker.stop()  # idempotent
    assert process_gone(pid) and time.monotonic() - started < 10.0


class _Local(Exception):
    """Cannot be pickled in the worker's reply (it holds a lock)."""

    def __init__(self) -> None:
        import threading

        super().__init__("cannot draw with a lock")
        self.lock = threading.Lock()


class LockedDrawing(PidDrawing):
    def timeline(self, record: RunRecord) -> None:
        raise _Local()


def test_a_failure_that_cannot_be_pickled_comes_back_as_its_text(tmp_path):
    worker = PlotWorker.start(LockedDrawing(tmp_path))
    try:
        worker.timeline(_spool(tmp_path, "a")[0])
        worker.finish()
        failures = worker.failures()
    finally:
        worker.stop()
    assert [str(f) for f in failures] == ["_Local: cannot draw with a lock"]
