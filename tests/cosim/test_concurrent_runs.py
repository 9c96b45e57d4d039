"""Strategy runs side by side in worker processes (:mod:`cosim.loop.concurrent`, ``crd paper``).

* The same files byte for byte (time series, events, CAN log, timelines, speed
  profiles, resolved configuration) and the same records, in order, as one run
  after the other; on a short scenario with radar noise, so that each run's
  result depends on its seed.
* Records come in the order of the strategies, whichever run ends first; the caller's own
  work (``meanwhile``) runs once, in its process, while the first runs go.
* A failing run still reports: the others' records are kept and its error,
  naming the run, is raised; a worker that dies without a word is an error
  naming its strategy and exit status.
* A signal ends every running run with its results so far (exit 130 / 143), and
  no new run starts.

Runs that must overlap or end in a given order wait on events shared through the
fork (a worker inherits its job), never on sleeps.
"""

from __future__ import annotations

import dataclasses
import json
import multiprocessing
import os
import signal
import threading
from pathlib import Path

import pytest

from can_dbc import generate_key, write_key_file
from cosim.link.ecu_link import EcuOptions
from cosim.loop.concurrent import RunFailed, cores, run_concurrently
from cosim.loop.experiment import run_strategies
from cosim.results.run_record import LoggedFrame, RunMetrics, RunRecord
from tests.os_processes import crd_signalled_when, last_time_s
from cosim.scenarios.loader import load_scenario

SHORT = Path(__file__).parent / "sweep_data" / "short_cyclist.toml"
STRATEGIES = ["none", "conservative", "tightening"]
WAIT_S = 60.0  # for an event another worker sets: fails loudly, never reached on a working tree


def _files(out: Path) -> dict[str, bytes]:
    """Every output file but the two that hold wall times."""
    return {str(p.relative_to(out)): p.read_bytes() for p in sorted(out.rglob("*"))
            if p.is_file() and p.name not in ("metrics.json", "report.md")}


@pytest.mark.slow
def test_concurrent_runs_write_the_same_files_and_records(plant_fmu3, tmp_path):
    sc = load_scenario(SHORT)
    ecu = EcuOptions(key_file=str(write_key_file(tmp_path / "run.key", generate_key())))  # same SecOC tags
    one_by_one = run_strategies(sc, STRATEGIES, tmp_path / "seq", ecu=ecu)
    side_by_side = run_strategies(sc, STRATEGIES, tmp_path / "con", ecu=ecu, concurrent=True)
    assert [r.strategy for r in side_by_side] == STRATEGIES
    for a, b in zip(one_by_one, side_by_side):
        assert dataclasses.replace(a.metrics, wall_time_s=0.0) == dataclasses.replace(b.metrics, wall_time_s=0.0)
        assert (a.rows, a.events, a.error) == (b.rows, b.events, b.error) and len(a.rows) > 600
        assert a.frames and b.frames == []  # on disk in can.blf; not sent back
    seq, con = _files(tmp_path / "seq"), _files(tmp_path / "con")
    assert sorted(seq) == sorted(con) and "tightening/timeline.png" in con and "speed_profiles.png" in con
    assert [name for name in seq if seq[name] != con[name]] == []
    metrics = [json.loads((tmp_path / d / "metrics.json").read_text()) for d in ("seq", "con")]
    for m in metrics:
        for run in m["runs"]:
            run.pop("wall_time_s")
    assert metrics[0] == metrics[1] and metrics[1]["status"] == "complete"


def _record(strategy: str) -> RunRecord:
    return RunRecord(strategy, RunMetrics(strategy), rows=[(0.0,)], frames=[LoggedFrame(0.0, 1, b"\x01")])


def _job(strategy: str) -> RunRecord:
    if strategy == "bad":
        raise ValueError("plant.fmu: no such FMU")
    if strategy == "crash":
        os._exit(3)  # as a segfault in the FMU's C code would: no word to the parent
    return _record(strategy)


def _series(strategies: list[str], records: list[RunRecord], job=_job, seen=None) -> list[list[str]]:
    """Run ``strategies`` two at a time into ``records``; the strategies of the records at each ``on_record``
    (``seen``: strategy -> an event set once the records include it)."""
    taken: list[list[str]] = []

    def on_record(record: RunRecord, done: list[RunRecord]) -> None:
        assert record in done
        taken.append([r.strategy for r in done])
        for strategy, event in (seen or {}).items():
            if strategy in taken[-1]:
                event.set()

    run_concurrently(strategies, job, records, on_record, jobs=2)
    return taken


def test_records_come_in_order_whichever_run_ends_first():
    fork = multiprocessing.get_context("fork")
    b_in, a_in = fork.Event(), fork.Event()  # set here, seen by the workers (inherited)

    def job(strategy: str) -> RunRecord:
        if strategy == "a":  # a and b go side by side; a ends once b's record is in
            assert b_in.wait(WAIT_S), "b's record did not come in while a ran"
        if strategy == "c":  # c, started when b ended, ends once a's record is in (else it may come before a)
            assert a_in.wait(WAIT_S), "a's record did not come in while c ran"
        return _record(strategy)

    records: list[RunRecord] = []
    seen = _series(["a", "b", "c", "d"], records, job, seen={"b": b_in, "a": a_in})
    assert [r.strategy for r in records] == ["a", "b", "c", "d"]
    order = ["a", "b", "c", "d"]
    assert all(s == [x for x in order if x in s] for s in seen)  # records so far: always in the strategies' order
    # b came in alone; a next, before c (which waits for it)
    assert seen[0] == ["b"] and seen[1] == ["a", "b"] and seen[-1] == order
    assert records[0].frames == [LoggedFrame(0.0, 1, b"\x01")] and records[0].rows == [(0.0,)]  # sent back whole


def test_meanwhile_runs_here_once_while_the_first_runs_go():
    done = multiprocessing.get_context("fork").Event()
    calls: list[int] = []

    def meanwhile() -> None:  # crd paper: import matplotlib
        calls.append(os.getpid())
        done.set()

    def job(strategy: str) -> RunRecord:
        assert done.wait(WAIT_S), "meanwhile() did not run while the runs went"
        return _record(strategy)

    records: list[RunRecord] = []
    run_concurrently(["a", "b", "c"], job, records, lambda record, done: None, jobs=2, meanwhile=meanwhile)
    assert calls == [os.getpid()] and [r.strategy for r in records] == ["a", "b", "c"]


def test_a_failing_run_still_reports_and_the_others_are_kept():
    records: list[RunRecord] = []
    with pytest.raises(RunFailed, match=r"^bad: plant.fmu: no such FMU$") as failed:
        _series(["a", "bad", "b"], records)
    assert isinstance(failed.value.__cause__, ValueError) and failed.value.strategy == "bad"
    assert [r.strategy for r in records] == ["a", "b"]


def test_a_record_that_cannot_be_taken_fails_its_run_and_the_others_go_on():
    def on_record(record: RunRecord, done: list[RunRecord]) -> None:  # crd paper: its timeline, metrics.json
        if record.strategy == "b":
            raise OSError("No space left on device")

    records: list[RunRecord] = []
    with pytest.raises(RunFailed, match=r"^b: No space left on device$"):
        run_concurrently(["a", "b", "c"], _job, records, on_record, jobs=2)
    assert [r.strategy for r in records] == ["a", "b", "c"]


def test_a_worker_that_dies_is_an_error_naming_its_strategy():
    records: list[RunRecord] = []
    with pytest.raises(RunFailed, match=r"^crash: the worker process ended \(exit status 3\) without reporting$"):
        _series(["a", "crash", "b"], records)
    assert [r.strategy for r in records] == ["a", "b"]


def test_a_signal_ends_the_running_runs_and_no_new_run_starts(tmp_path):
    """In process: run a signals this process (as a Ctrl-C would), which passes it on to a; b never starts."""

    def job(strategy: str) -> RunRecord:
        (tmp_path / strategy).write_text("started")
        try:
            os.kill(os.getppid(), signal.SIGINT)
            threading.Event().wait(WAIT_S)  # until the signal passed on comes
        except KeyboardInterrupt:
            record = _record(strategy)
            record.interrupted = "SIGINT"
            return record
        raise AssertionError("the signal was not passed on within WAIT_S")

    records: list[RunRecord] = []
    run_concurrently(["a", "b"], job, records, lambda record, done: None, jobs=1)
    assert [(r.strategy, r.interrupted) for r in records] == [("a", "SIGINT")]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a"]
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # restored


NO_OBJECT = """
[scenario]
name = "open_road"
duration_s = 3600.0
[object]
enabled = false
"""


@pytest.mark.wallclock
@pytest.mark.parametrize("sig, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_a_signal_ends_every_running_run_with_its_results(plant_fmu3, tmp_path, sig, code):
    """``crd paper`` as a child, signalled once every run has streamed 3 s (a condition on its files).
    Wall-clock: the signal lands wherever the runs are by then, so the check is a range (>= 3 s)."""
    scenario = tmp_path / "open_road.toml"
    scenario.write_text(NO_OBJECT)
    out = tmp_path / "out"
    started = STRATEGIES[:cores()]  # one run per core; the rest never start after a signal
    # the signal goes to crd paper alone: it passes it on to its workers
    returncode, err = crd_signalled_when(["paper", "--scenario", str(scenario), "--out", str(out)],
                                         lambda: min(last_time_s(out / s / "timeseries.csv") for s in started) >= 3.0,
                                         f"{started} streaming 3 s of simulated time", sig)
    assert returncode == code, err
    assert f"interrupted: none interrupted by {sig.name}" in err
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["status"] == "interrupted"
    assert [r["strategy"] for r in metrics["runs"]] == started
    for run in metrics["runs"]:
        assert run["status"] == "interrupted" and run["interrupted_by"] == sig.name and run["sim_time_s"] >= 3.0
        events = json.loads((out / run["strategy"] / "events.json").read_text())["events"]
        assert events[-1]["kind"] == "interrupted"
    assert all(not (out / s / "timeseries.csv").exists() for s in STRATEGIES if s not in started)


@pytest.mark.slow
def test_a_process_with_other_threads_runs_one_after_the_other(plant_fmu3, tmp_path):
    """A fork copies only the calling thread, so a lock another thread holds would stay held in the worker."""
    release = threading.Event()
    other = threading.Thread(target=release.wait)
    other.start()
    try:
        records = run_strategies(load_scenario(SHORT), ["none", "tightening"], tmp_path, concurrent=True)
    finally:
        release.set()
        other.join()
    assert [r.strategy for r in records] == ["none", "tightening"]
    assert all(r.frames for r in records)  # kept: run here (a worker sends its record without them)
