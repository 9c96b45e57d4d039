"""``crd sweep`` on a Dask LocalCluster bound to 127.0.0.1: rows, worker counts, resume, failures.

Short runs (the cyclist 60 m ahead, 7 s simulated, radar noise on so that every
result depends on its run's seed). The whole module takes about 40-60 s on 2 cores.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import functools
import tempfile
import time
from pathlib import Path

import psutil
from distributed import Client
import pyarrow.parquet as pq
import pytest

from tests.loopback import loopback_only  # noqa: F401 - autouse: every socket to loopback

from cosim.loop.master import run_scenario
from cosim.scenarios.loader import scenario_from_dict
from cosim.sweep.plan import make_plan, run_seed
from cosim.sweep.runner import ClusterOptions, chunk_size, local_cluster, open_client
from cosim.sweep.session import run_sweep
from cosim.sweep.spec import load_sweep
from cosim.sweep.task import run_one

BASE = Path(__file__).resolve().parent / "sweep_data" / "short_cyclist.toml"
WALL_COLUMNS = ("wall_time_s", "task_wall_s")
SMALL = f"""
[sweep]
name = "small"
scenario = "{BASE}"
seed = 5
replicates = 2

[[axis]]
path = "plant.road_friction"
values = [0.6, 1.0]

[[axis]]
path = "radar.latency_s"
values = [0.0, 0.15]

[[axis]]
path = "ecu.strategy"
values = ["none", "tightening"]
"""
N_SMALL = 2 * 2 * 2 * 2


def _write(tmp: Path, text: str, name: str = "sweep.toml") -> Path:
    path = tmp / name
    path.write_text(text)
    return path


def _comparable(path: Path) -> list[dict]:
    return [{k: v for k, v in row.items() if k not in WALL_COLUMNS} for row in pq.read_table(path).to_pylist()]


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    """The small sweep run with 1 worker: (sweep file, out dir)."""
    tmp = tmp_path_factory.mktemp("small")
    sweep = _write(tmp, SMALL)
    run_sweep(load_sweep(sweep), tmp / "w1", ClusterOptions(workers=1))
    return sweep, tmp / "w1"


def test_small_sweep_rows_and_values(small) -> None:
    sweep, out = small
    rows = pq.read_table(out / "results.parquet").to_pylist()
    assert len(rows) == N_SMALL and [r["run"] for r in rows] == list(range(N_SMALL))
    assert all(r["status"] == "ok" and r["error"] is None for r in rows)
    combos = [(f, lat, s, rep) for f in (0.6, 1.0) for lat in (0.0, 0.15) for s in ("none", "tightening")
              for rep in (0, 1)]
    assert [(r["plant.road_friction"], r["radar.latency_s"], r["ecu.strategy"], r["replicate"]) for r in rows] == combos
    assert all(r["strategy"] == r["ecu.strategy"] for r in rows)
    assert all(r["seed"] == run_seed(r["run_key"]) for r in rows) and len({r["seed"] for r in rows}) == N_SMALL
    # a row is the run itself: redo one directly from the plan and compare its metrics
    plan = make_plan(load_sweep(sweep))
    spec = plan.runs[5]
    record = run_scenario(scenario_from_dict(spec.scenario), plan.fmu_path)
    m, row = record.metrics, rows[5]
    assert (row["collided"], row["contingency_invocations"], row["sim_time_s"]) == \
        (m.collided, m.contingency_invocations, m.sim_time_s)
    assert row["min_gap_m"] == m.min_gap_m and row["impact_speed_mps"] == m.impact_speed_mps
    # the seed matters: the two replicates of a setting differ somewhere
    assert any(rows[i]["min_gap_m"] != rows[i + 1]["min_gap_m"] for i in range(0, N_SMALL, 2))
    report = (out / "report.md").read_text()
    assert "| none | 8 | 0 |" in report and "| tightening | 8 | 0 |" in report
    assert (out / "maps" / "collision_rate__plant.road_friction__radar.latency_s.png").stat().st_size > 1000


def test_same_table_with_two_workers_and_nothing_left_in_tmp(small, tmp_path, monkeypatch) -> None:
    """The same table; and the cluster's scratch files (Dask's ``dask-scratch-space``, the workers'
    FMU copies) are gone with it (issue 24: ``/tmp/dask-scratch-space`` stayed)."""
    sweep, out1 = small
    scratch = tmp_path / "tmp"
    scratch.mkdir()
    monkeypatch.setenv("TMPDIR", str(scratch))  # the worker processes' temporary directory
    monkeypatch.setattr(tempfile, "tempdir", str(scratch))  # this process's
    run_sweep(load_sweep(sweep), tmp_path / "w2", ClusterOptions(workers=2), report=False)
    assert _comparable(tmp_path / "w2" / "results.parquet") == _comparable(out1 / "results.parquet")
    assert os.listdir(scratch) == []


def _rows_in(path: Path) -> int:
    try:
        return pq.read_metadata(path).num_rows
    except Exception:  # noqa: BLE001 - not written yet
        return -1


@pytest.mark.wallclock
def test_resume_after_the_process_is_killed(small, tmp_path) -> None:
    """Killed (SIGKILL) once its first row is on disk: a condition wait, but where the sweep stands by then
    is a race with its workers (wall-clock), so the check is a range: some rows, not all."""
    sweep, out1 = small
    out = tmp_path / "killed"
    cmd = [sys.executable, "-m", "cosim.cli.main", "sweep", str(sweep), "--workers", "1", "--out", str(out)]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 120
        while _rows_in(out / "results.parquet") < 1:
            assert proc.poll() is None, f"the sweep ended ({proc.returncode}) before its first row was on disk"
            assert time.monotonic() < deadline, "no row on disk within 120 s"
            time.sleep(0.05)
        children = psutil.Process(proc.pid).children(recursive=True)
        os.kill(proc.pid, signal.SIGKILL)
    finally:
        proc.wait(timeout=30)
    _, alive = psutil.wait_procs(children, timeout=20)
    for child in alive:  # ours to stop; their survival is a failure below
        child.kill()
    assert not alive, f"worker processes outlived the killed sweep: {[c.pid for c in alive]}"
    partial = pq.read_table(out / "results.parquet").to_pylist()
    assert 1 <= len(partial) < N_SMALL, f"expected a sweep killed mid-way, got {len(partial)} rows"
    _, outcome = run_sweep(load_sweep(sweep), out, ClusterOptions(workers=2), resume=True, report=False)
    assert (outcome.skipped, outcome.done) == (len(partial), N_SMALL - len(partial))
    assert _comparable(out / "results.parquet") == _comparable(out1 / "results.parquet")
    kept = {r["run_key"]: r["task_wall_s"] for r in pq.read_table(out / "results.parquet").to_pylist()}
    assert all(kept[r["run_key"]] == r["task_wall_s"] for r in partial)  # not run again


def test_failing_runs_are_recorded_and_the_others_run(tmp_path) -> None:
    text = (f'[sweep]\nname = "fails"\nscenario = "{BASE}"\n'
            '[[axis]]\npath = "plant.road_friction"\nvalues = [1.0, 2.0]\n'            # 2.0: the loader refuses
            '[[axis]]\npath = "plant.parameters.brake_dead_time"\nvalues = [0.1, 0.9]\n')  # 0.9: the FMU refuses
    _, outcome = run_sweep(load_sweep(_write(tmp_path, text)), tmp_path / "out", ClusterOptions(workers=1))
    rows = pq.read_table(tmp_path / "out" / "results.parquet").to_pylist()
    assert len(rows) == 4 and outcome.failed == 3
    assert [r["status"] for r in rows] == ["ok", "failed", "failed", "failed"]
    assert rows[0]["sim_time_s"] > 0 and rows[1]["collided"] is None
    assert "brake_dead_time" in rows[1]["error"] or "refused" in rows[1]["error"]
    assert "plant.road_friction" in rows[2]["error"] and "1.5" in rows[2]["error"]
    assert "failed runs" in (tmp_path / "out" / "report.md").read_text().lower()


def crash_on_run_1(marker_dir: Path, run, sha, keep):
    """A task whose worker dies (os._exit stands in for a native crash) on run 1; counts its attempts
    in a file under the test's own ``marker_dir`` (two runs of the test at once must not share it).

    It dies a moment into the run, as a crash in the FMU would: dying within milliseconds of the
    previous task's end would race that task's completion message, and Dask would blame both. Dask
    has no public sign that the message has left the worker, so the moment is a wall-clock pause.
    """
    if run.index == 1:
        with open(marker_dir / f"crd-test-crash-{run.key}", "a") as handle:
            handle.write("attempt\n")
        time.sleep(0.3)
        os._exit(13)
    return run_one(run, sha, keep)


@pytest.mark.wallclock
@pytest.mark.parametrize("workers, n_runs", [(2, 3), (1, 8)], ids=["alone", "in-a-chunk"])
def test_a_task_whose_worker_dies_is_retried_once_then_failed(tmp_path, workers, n_runs) -> None:
    """Run 1 kills its worker. With 2 workers and 3 runs each task is one run; with 1 worker and 8 runs
    the first task is a chunk of 2 (runs 0 and 1): its runs are retried alone, so run 0 ends ok.

    Wall-clock: the crash comes 0.3 s into run 1 (:func:`crash_on_run_1` says why)."""
    latencies = ", ".join(f"{0.02 * i:.2f}" for i in range(n_runs))
    text = f'[sweep]\nname = "crash"\nscenario = "{BASE}"\n[[axis]]\npath = "radar.latency_s"\nvalues = [{latencies}]\n'
    spec = load_sweep(_write(tmp_path, text))
    key = make_plan(spec).runs[1].key
    assert chunk_size(n_runs, workers) == (1 if workers == 2 else 2)
    marker = tmp_path / f"crd-test-crash-{key}"
    _, outcome = run_sweep(spec, tmp_path / "out", ClusterOptions(workers=workers),
                           task=functools.partial(crash_on_run_1, tmp_path), report=False)
    attempts = marker.read_text().count("attempt")
    rows = pq.read_table(tmp_path / "out" / "results.parquet").to_pylist()
    expected = ["ok", "failed"] + ["ok"] * (n_runs - 2)
    assert [r["status"] for r in rows] == expected, [(r["run"], r["run_key"], r["error"]) for r in rows]
    assert outcome.failed == 1 and outcome.done == n_runs
    assert "KilledWorker" in rows[1]["error"]
    assert attempts == 2  # the first try and one retry


def test_cluster_is_bound_to_loopback_and_a_scheduler_can_be_attached(tmp_path) -> None:
    client, cluster = open_client(ClusterOptions(workers=1))
    try:
        info = client.scheduler_info()
        assert cluster.scheduler_address.startswith("tcp://127.0.0.1:")
        assert info["workers"] and all(w.startswith("tcp://127.0.0.1:") for w in info["workers"])
        if client.dashboard_link:
            assert "127.0.0.1" in client.dashboard_link
        text = f'[sweep]\nname = "attach"\nscenario = "{BASE}"\n[[axis]]\npath = "ecu.strategy"\nvalues = ["none"]\n'
        _, outcome = run_sweep(load_sweep(_write(tmp_path, text)), tmp_path / "out",
                               ClusterOptions(scheduler=cluster.scheduler_address), report=False)
        assert outcome.done == 1 and outcome.failed == 0
    finally:
        client.close()
        cluster.close()


def test_report_is_redrawn_from_the_table_alone(small, tmp_path, capsys) -> None:
    from cosim.cli.main import main

    _, out = small
    copy = tmp_path / "copy"
    copy.mkdir()
    (copy / "results.parquet").write_bytes((out / "results.parquet").read_bytes())
    assert main(["sweep", "report", str(copy), "--axes", "radar.latency_s", "plant.road_friction"]) == 0
    assert (copy / "report.md").read_text().count("![") == 2  # the two metrics over the one pair asked for
    assert (copy / "maps" / "mean_impact_speed_mps__radar.latency_s__plant.road_friction.png").is_file()


def _profiler(dask_worker) -> tuple[list[str], int]:
    """The worker's profiling callbacks and the call trees it holds."""
    history = len(dask_worker.profile_history) + len(dask_worker.profile_keys_history)
    return sorted(name for name in dask_worker.periodic_callbacks if name.startswith("profile")), history


def test_local_workers_keep_no_profile_history() -> None:
    """Dask's worker profiler kept a call tree per second (for 1,000 s): the sweep workers' memory grew
    with every run. The local cluster turns it off: its workers have no profiling callback (the sampler
    every 10 ms, the cycle that files a tree every second) and no history after a task."""
    with local_cluster(1, dashboard=False) as cluster, Client(cluster, set_as_default=False) as client:
        client.submit(sum, [1, 2], pure=False).result()
        assert list(client.run(_profiler).values()) == [([], 0)]
