"""Runs a :class:`~cosim.sweep.plan.SweepPlan` on Dask distributed.

By default a ``LocalCluster`` of worker *processes*, one per core, one thread
each, with the scheduler, the workers and the dashboard bound to 127.0.0.1
(ports chosen by the OS). ``scheduler`` attaches to an existing scheduler
instead (``tcp://host:port``), which is how a sweep runs on many machines.

The client reads the plant FMU once and registers a worker plugin carrying its
bytes (:class:`cosim.sweep.task.FmuShipper`): every worker, including one that
restarts, caches the file by hash before it takes a run, and the runs name it
by hash. No run depends on data held by another worker, so none is lost with a
dead worker and the scheduler places runs on idle workers only.

Each task runs a *chunk* of runs (:func:`chunk_size`: up to :data:`MAX_CHUNK`,
fewer towards the end) and returns their rows; chunks cut the scheduler round
trips per run, and rows, seeds and keys are per run, so the table does not
depend on the chunking. The client keeps one chunk in flight per cluster
thread, so a worker holds only the chunk it is running (Dask counts a death
against every task assigned to the dying worker). A task whose worker dies
(``KilledWorker``) has its runs put back, each to be retried once *alone*; a
retried run whose worker dies again is recorded as failed. So every run is
attempted at most twice and a run that kills its worker is singled out. The
local scheduler gives up on a task at the first death
(``distributed.scheduler.allowed-failures = 0``) so that the retry is the
client's; an existing scheduler keeps its own setting (Dask's default retries
three times before the client's retry). Rows are handed to the
:class:`~cosim.sweep.table.ResultsTable` as chunks complete; a sweep killed
mid-way loses at most the chunks in flight.
"""

from __future__ import annotations

import importlib.util
import itertools
import logging
import os
import time
from collections import deque
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Protocol

import dask
from distributed import Client, KilledWorker, LocalCluster, as_completed

from .plan import RunSpec, SweepPlan
from .table import ResultsTable, write_timeseries
from .task import FmuShipper, RunTask, failed_row, run_chunk, run_one

log = logging.getLogger(__name__)

LOCALHOST = "127.0.0.1"
MAX_CHUNK = 8  # runs per task at most (see chunk_size)
#: the local cluster's Dask settings: the scheduler gives up on a task at its worker's first death (the
#: client retries, module docstring); the workers' statistical profiler is off (it kept a call tree per
#: second for 1,000 s: worker memory grew ~1 MB per 100 runs over a sweep, and it samples every 10 ms)
LOCAL_CLUSTER_CONFIG = {"distributed.scheduler.allowed-failures": 0, "distributed.worker.profile.enabled": False}


@dataclass(frozen=True)
class ClusterOptions:
    """Where the tasks run: ``workers`` local processes (default: one per core), or an existing scheduler."""

    workers: int | None = None
    scheduler: str | None = None
    dashboard: bool = True


@dataclass
class SweepOutcome:
    """What a sweep did: runs done now, skipped (resume), failed, wall time (s), dashboard address."""

    done: int = 0
    skipped: int = 0
    failed: int = 0
    wall_s: float = 0.0
    dashboard: str | None = None
    notes: list[str] = field(default_factory=list)


class SweepProgress(Protocol):
    """What the runner reports to (the CLI draws a progress bar from it)."""

    def start(self, total: int, already: int, dashboard: str | None, note: str) -> None: ...

    def advance(self, row: dict[str, Any]) -> None: ...

    def close(self) -> None: ...


Task = RunTask


def dashboard_available() -> bool:
    """The Dask dashboard needs bokeh; without it the sweep runs and says the dashboard is unavailable."""
    return importlib.util.find_spec("bokeh") is not None


def local_cluster(workers: int, dashboard: bool = True) -> LocalCluster:
    """``workers`` worker processes of one thread each, everything bound to 127.0.0.1 (OS-chosen ports)."""
    address = f"{LOCALHOST}:0" if dashboard and dashboard_available() else None
    with dask.config.set(LOCAL_CLUSTER_CONFIG):
        return LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, host=LOCALHOST,
                            scheduler_port=0, dashboard_address=address, silence_logs=logging.ERROR)


def open_client(opts: ClusterOptions) -> tuple[Client, LocalCluster | None]:
    """A client on an existing scheduler, or on a new local cluster bound to 127.0.0.1."""
    if opts.scheduler:
        return Client(opts.scheduler, set_as_default=False), None
    cluster = local_cluster(opts.workers or os.cpu_count() or 1, opts.dashboard)
    try:
        return Client(cluster, set_as_default=False), cluster
    except BaseException:
        cluster.close()
        raise


def _dashboard(client: Client) -> tuple[str | None, str]:
    if not dashboard_available():
        return None, "Dask dashboard unavailable (bokeh is not installed)"
    try:
        link = client.dashboard_link
    except Exception:  # noqa: BLE001 - a scheduler without a dashboard
        link = None
    return link, f"Dask dashboard: {link}" if link else "Dask dashboard unavailable"


class _Threads:
    """The cluster's worker threads, asked of the scheduler at most once a second (workers come and go)."""

    def __init__(self, client: Client, period_s: float = 1.0) -> None:
        self.client, self.period_s = client, period_s
        self._value, self._when = 1, -float("inf")

    def __call__(self) -> int:
        if time.monotonic() - self._when >= self.period_s:
            workers = self.client.scheduler_info()["workers"].values()
            self._value = max(1, sum(w.get("nthreads", 1) for w in workers))
            self._when = time.monotonic()
        return self._value


def chunk_size(remaining: int, threads: int, max_chunk: int = MAX_CHUNK) -> int:
    """Runs in the next task: a quarter of each thread's share of what is left, 1..``max_chunk``.

    Large chunks early cut the scheduler round trips; small ones at the end keep the
    workers finishing together (guided self-scheduling).
    """
    return max(1, min(max_chunk, remaining // (4 * threads)))


class _Dispatch:
    """Runs waiting, chunks in flight (one per cluster thread) and the retries after a worker death."""

    def __init__(self, client: Client, submit: Callable[[list[RunSpec]], Any], todo: list[RunSpec]) -> None:
        self.client, self.submit, self.threads = client, submit, _Threads(client)
        self.waiting: deque[tuple[RunSpec, bool]] = deque((run, False) for run in todo)
        self.in_flight: dict[Any, tuple[list[RunSpec], bool]] = {}
        self.completed = as_completed([], loop=client.loop)

    def fill(self) -> None:
        """Submit chunks until each cluster thread has one (a retry goes alone)."""
        while self.waiting and len(self.in_flight) < self.threads():
            run, retry = self.waiting.popleft()
            runs = [run]
            if not retry:
                n = chunk_size(len(self.waiting) + 1, self.threads())
                while len(runs) < n and self.waiting and not self.waiting[0][1]:
                    runs.append(self.waiting.popleft()[0])
            future = self.submit(runs)
            self.in_flight[future] = (runs, retry)
            self.completed.add(future)

    def rows(self, future) -> list[dict[str, Any]]:
        """The rows of a finished chunk; after a worker death its runs wait for one retry each (no rows yet)."""
        runs, retry = self.in_flight.pop(future)
        try:
            rows = future.result()
        except KilledWorker as exc:
            if retry:
                rows = [failed_row(runs[0], f"{type(exc).__name__}: {exc}")]
            else:
                log.warning("a worker died running %d run(s); each is retried once on its own", len(runs))
                self.waiting.extendleft((run, True) for run in reversed(runs))
                rows = []
        except Exception as exc:  # noqa: BLE001 - a lost or cancelled task: its runs are recorded as failed
            rows = [failed_row(run, f"{type(exc).__name__}: {exc}") for run in runs]
        future.release()
        return rows


def _collect(client: Client, submit: Callable[[list[RunSpec]], Any], todo: list[RunSpec], table: ResultsTable,
             out_dir: Path, progress: SweepProgress | None, outcome: SweepOutcome) -> None:
    """Keep one chunk in flight per cluster thread; hand each row to the table as it arrives."""
    dispatch = _Dispatch(client, submit, todo)
    dispatch.fill()
    for future in dispatch.completed:
        rows = dispatch.rows(future)
        dispatch.fill()
        for row in rows:
            series = row.pop("_timeseries", None)
            if series is not None:
                write_timeseries(out_dir, row["run_key"], series)
            table.add(row)
            outcome.done += 1
            outcome.failed += row["status"] != "ok"
            if progress is not None:
                progress.advance(row)


def run_plan(plan: SweepPlan, table: ResultsTable, out_dir: Path, opts: ClusterOptions,
             skip: set[str] = frozenset(), keep_timeseries: bool = False,
             progress: SweepProgress | None = None, task: Task = run_one) -> SweepOutcome:
    """Run every run of ``plan`` not in ``skip`` on Dask; rows go to ``table`` as they finish."""
    from ..world.fmu_share import file_sha256

    todo = [r for r in plan.runs if r.key not in skip]
    outcome = SweepOutcome(skipped=len(plan.runs) - len(todo))
    t0 = time.perf_counter()
    fmu_bytes, fmu_sha = Path(plan.fmu_path).read_bytes(), file_sha256(plan.fmu_path)
    client, cluster = open_client(opts)
    try:
        outcome.dashboard, note = _dashboard(client)
        if progress is not None:
            progress.start(len(plan.runs), outcome.skipped, outcome.dashboard, note)
        if todo:
            shipper, serial = FmuShipper(fmu_bytes, fmu_sha), itertools.count()
            client.register_plugin(shipper)

            def submit(runs: list[RunSpec]):
                return client.submit(run_chunk, task, runs, fmu_sha, keep_timeseries, pure=False,
                                     key=f"crd-runs-{runs[0].key}-{len(runs)}-{next(serial)}")

            _collect(client, submit, todo, table, out_dir, progress, outcome)
            if cluster is None:  # an attached scheduler would hand the FMU to every worker that ever joins
                client.unregister_worker_plugin(shipper.name)
    finally:
        table.close()
        if progress is not None:
            progress.close()
        client.close()
        if cluster is not None:
            cluster.close()
    outcome.wall_s = time.perf_counter() - t0
    return outcome
