"""What a Dask worker runs: sweep runs -> result rows (plain dicts), a chunk of runs per task.

The plant FMU reaches each worker as bytes, once (no shared file system is
assumed): :class:`FmuShipper` is a Dask worker plugin holding the bytes, whose
``setup`` runs on every worker of the cluster, including workers that join or
restart later, and writes the file with :func:`cached_fmu` into the local
temporary directory under its sha256, then prepares it once for every run of
the worker (:func:`cosim.world.fmu_share.share_fmu`: hashed, parsed, extracted
and its library loaded once; each run instantiates and frees its own
instance). Runs name the FMU by hash only, so no task depends on data held by
another worker. :func:`run_chunk` runs several runs in one task (fewer
scheduler round trips), each exactly as :func:`run_one` would. :func:`run_one`
runs a run through its subject (:mod:`cosim.sweep.subjects`: a scenario, or a
fleet scene) and never raises for a failed run: a value the loader, the ECU or the FMU
refuses, an FMI error mid-run, or any other exception becomes a row with
``status = "failed"`` and the error text, so the sweep goes on. (A native
crash that kills the worker is handled by the runner: Dask retries the task
once, then it is recorded as failed.)
"""

from __future__ import annotations

import hashlib
import os
import tempfile
import time
from pathlib import Path
from typing import Any, Callable, Sequence

from distributed.diagnostics.plugin import WorkerPlugin

from ..errors import PlantError
from ..world.fmu_share import file_sha256, share_fmu, unshare_fmu
from .plan import RunSpec
from .subject import STATUS_FAILED
from .subjects import subject_of

_FMU_PATHS: dict[str, Path] = {}  # sha256 -> local file, per worker process


def cached_fmu(sha256: str, data: bytes, cache_dir: Path | None = None) -> Path:
    """The local copy of the shipped FMU, written once (atomically) and checked against its hash."""
    path = _FMU_PATHS.get(sha256)
    if path is not None and path.is_file():
        return path
    cache_dir = cache_dir or Path(tempfile.gettempdir()) / "crd-sweep-fmu"
    cache_dir.mkdir(parents=True, exist_ok=True)
    path = cache_dir / f"{sha256}.fmu"
    if not path.is_file() or file_sha256(path) != sha256:
        if hashlib.sha256(data).hexdigest() != sha256:
            raise PlantError(f"shipped FMU bytes do not match their sha256 {sha256}")
        tmp = path.with_name(f"{path.name}.{os.getpid()}.tmp")
        tmp.write_bytes(data)
        os.replace(tmp, path)
    _FMU_PATHS[sha256] = path
    return path


def local_fmu(sha256: str) -> Path:
    """The FMU this worker process cached under ``sha256`` (by :class:`FmuShipper`)."""
    path = _FMU_PATHS.get(sha256)
    if path is None or not path.is_file():
        raise PlantError(f"plant FMU {sha256[:16]} was not shipped to this worker")
    return path


class FmuShipper(WorkerPlugin):
    """Carries the FMU's bytes to every worker (present and future) and caches them there by hash."""

    def __init__(self, data: bytes, sha256: str) -> None:
        self.data = data
        self.sha256 = sha256
        self.name = f"crd-fmu-{sha256[:16]}"

    def setup(self, worker) -> None:  # in the worker's own directory, removed with it (cosim.sweep.session)
        share_fmu(cached_fmu(self.sha256, self.data, Path(worker.local_directory) / "crd-fmu"))

    def teardown(self, worker) -> None:
        path = _FMU_PATHS.get(self.sha256)
        if path is not None:
            unshare_fmu(path)


def base_row(run: RunSpec) -> dict[str, Any]:
    """The columns a row has whatever happens: identity, seed and axis values."""
    row: dict[str, Any] = {"run": run.index, "run_key": run.key, "seed": run.seed, "replicate": run.point.replicate}
    row.update(run.point.values)
    row["strategy"] = subject_of(run.subject).strategy(run.scenario)
    return row


def failed_row(run: RunSpec, error: str, task_wall_s: float = 0.0) -> dict[str, Any]:
    row = base_row(run)
    row.update(dict.fromkeys(subject_of(run.subject).columns()), status=STATUS_FAILED, error=error,
               task_wall_s=task_wall_s)
    return row


def run_one(run: RunSpec, fmu_sha256: str, keep_timeseries: bool = False) -> dict[str, Any]:
    """Run one sweep run on this worker; returns its row (and its time series when asked)."""
    t0 = time.perf_counter()
    try:
        fmu_path = local_fmu(fmu_sha256)
        figures = subject_of(run.subject).run(run.scenario, run.base_dir, fmu_path, keep_timeseries)
    except Exception as exc:  # noqa: BLE001 - any failure of one run is recorded, the sweep goes on
        return failed_row(run, f"{type(exc).__name__}: {exc}", time.perf_counter() - t0)
    row = base_row(run)
    row.update(figures)
    row["task_wall_s"] = time.perf_counter() - t0
    return row


#: what a task runs per run: ``(run, fmu_sha256, keep_timeseries) -> row`` (:func:`run_one`; tests swap it)
RunTask = Callable[[RunSpec, str, bool], dict]


def run_chunk(task: RunTask, runs: Sequence[RunSpec], fmu_sha256: str, keep_timeseries: bool = False) -> list[dict]:
    """Several runs in one Dask task, one after the other: their rows, in order."""
    return [task(run, fmu_sha256, keep_timeseries) for run in runs]
