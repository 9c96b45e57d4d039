"""Strategy runs side by side in forked workers (:mod:`cosim.loop.concurrent`, issue 10's ``crd paper`` time).

* The same files byte for byte (time series, events, CAN log, timelines, speed
  profiles, resolved configuration) and the same records, in order, as one run
  after the other; on a short scenario with radar noise, so that each run's
  result depends on its seed.
* A failing run still reports: the others' records are kept and its exception
  is raised; a worker that dies without a word is an error naming its strategy.
* A signal ends every running run with its results so far (exit 130 / 143).
"""

from __future__ import annotations

import dataclasses
import json
import os
import signal
import threading
import time
from pathlib import Path

import pytest

from can_dbc import generate_key, write_key_file
from cosim.link.ecu_link import EcuOptions
from cosim.loop.concurrent import Plots, cores, run_concurrently
from cosim.loop.experiment import run_strategies
from cosim.results.plot_worker import PlotWorker
from cosim.results.run_record import LoggedFrame, RunMetrics, RunRecord
from tests.os_processes import crd_signalled_when, last_time_s
from cosim.scenarios.loader import load_scenario

SHORT = Path(__file__).parent / "sweep_data" / "short_cyclist.toml"
STRATEGIES = ["none", "conservative", "tightening"]


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
    ahead = PlotWorker.start()  # as crd paper's: forked before the series, its drawing pickled to it later
    try:
        drawn_ahead = run_strategies(sc, STRATEGIES, tmp_path / "ahead", ecu=ecu, concurrent=True, plot_worker=ahead)
    finally:
        ahead.stop()
    for series in (side_by_side, drawn_ahead):
        assert [r.strategy for r in series] == STRATEGIES
        for a, b in zip(one_by_one, series):
            assert dataclasses.replace(a.metrics, wall_time_s=0.0) == dataclasses.replace(b.metrics, wall_time_s=0.0)
            assert (a.rows, a.events, a.error) == (b.rows, b.events, b.error) and len(a.rows) > 600
            assert a.frames and b.frames == []  # on disk in can.blf; not sent back
    seq = _files(tmp_path / "seq")
    for con in (_files(tmp_path / "con"), _files(tmp_path / "ahead")):
        assert sorted(seq) == sorted(con) and "tightening/timeline.png" in con and "speed_profiles.png" in con
        assert [name for name in seq if seq[name] != con[name]] == []
    metrics = [json.loads((tmp_path / d / "metrics.json").read_text()) for d in ("seq", "con", "ahead")]
    for m in metrics:
        for run in m["runs"]:
            run.pop("wall_time_s")
    assert metrics[0] == metrics[1] == metrics[2] and metrics[1]["status"] == "complete"


def _job(strategy: str) -> RunRecord:
    if strategy == "bad":
        raise ValueError("plant.fmu: no such FMU")
    if strategy == "crash":
        os._exit(3)  # as a segfault in the FMU's C code would: no word to the parent
    return RunRecord(strategy, RunMetrics(strategy), rows=[(0.0,)], frames=[LoggedFrame(0.0, 1, b"\x01")])


def _run(strategies: list[str], tmp_path: Path, records: list[RunRecord], keep_frames: bool = False) -> list:
    def draw(record: RunRecord) -> None:  # in the parent, or in the plot worker for the last ones
        (tmp_path / f"{record.strategy}.drawn").write_text("")

    def finale(every: list[RunRecord]) -> None:  # in the plot worker, beside the last timeline
        with open(tmp_path / "finale.drawn", "a") as handle:
            handle.write(" ".join(r.strategy for r in every) + "\n")

    seen: list[list[str]] = []
    preload = lambda: time.sleep(0.5)  # noqa: E731 - as importing matplotlib: every run is in before a draw
    drawn = run_concurrently(strategies, _job, records, Plots(preload, draw, finale),
                             lambda done: seen.append([r.strategy for r in done]), jobs=2, keep_frames=keep_frames)
    assert drawn == (tmp_path / "finale.drawn").exists()  # else the caller draws it
    return seen


def test_records_come_in_order_and_every_timeline_is_drawn(tmp_path):
    records: list[RunRecord] = []
    seen = _run(["a", "b", "c", "d"], tmp_path, records)
    assert [r.strategy for r in records] == ["a", "b", "c", "d"] and seen[-1] == ["a", "b", "c", "d"]
    assert all(seen[i] == sorted(seen[i], key="abcd".index) for i in range(len(seen)))  # metrics.json in order
    assert sorted(p.stem for p in tmp_path.glob("*.drawn") if p.stem != "finale") == ["a", "b", "c", "d"]
    if (tmp_path / "finale.drawn").exists():  # drawn by the plot worker when timelines were left to draw
        assert (tmp_path / "finale.drawn").read_text() == "a b c d\n"
    assert records[0].frames == [] and records[0].rows == [(0.0,)]
    kept: list[RunRecord] = []
    _run(["a"], tmp_path, kept, keep_frames=True)
    assert kept[0].frames == [LoggedFrame(0.0, 1, b"\x01")]


def test_a_failing_run_still_reports_and_the_others_are_kept(tmp_path):
    records: list[RunRecord] = []
    with pytest.raises(ValueError, match="plant.fmu: no such FMU"):
        _run(["a", "bad", "b"], tmp_path, records)
    assert [r.strategy for r in records] == ["a", "b"]


def test_a_worker_that_dies_is_an_error_naming_its_strategy(tmp_path):
    records: list[RunRecord] = []
    with pytest.raises(RuntimeError, match=r"crash: the worker process ended \(exit status 3\) without reporting"):
        _run(["a", "crash", "b"], tmp_path, records)
    assert [r.strategy for r in records] == ["a", "b"]


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


def test_one_plot_worker_draws_the_finale_once(tmp_path):
    """Two timelines left when the last run comes in: the plot worker is started once, not again for the last."""
    delay_s = {"a": 0.0, "b": 0.05, "c": 0.1}

    def job(strategy: str) -> RunRecord:
        time.sleep(delay_s[strategy])
        return RunRecord(strategy, RunMetrics(strategy))

    def draw(record: RunRecord) -> None:  # slower than the runs: b and c are both in while a is drawn
        time.sleep(0.3)
        (tmp_path / f"{record.strategy}.drawn").write_text("")

    def finale(every: list[RunRecord]) -> None:
        with open(tmp_path / "finale.drawn", "a") as handle:
            handle.write(" ".join(r.strategy for r in every) + "\n")

    records: list[RunRecord] = []
    assert run_concurrently(["a", "b", "c"], job, records, Plots(lambda: None, draw, finale), lambda done: None, jobs=2)
    assert (tmp_path / "finale.drawn").read_text() == "a b c\n"
    assert sorted(p.stem for p in tmp_path.glob("?.drawn")) == ["a", "b", "c"]
