"""One sweep end to end: plan, run on Dask, write the table, draw the report.

Nothing is left outside ``out_dir``: the local cluster's files (Dask's
``local_directory``: its ``dask-scratch-space`` of lock files and spilled data,
and each worker's copy of the plant FMU, :class:`cosim.sweep.task.FmuShipper`)
go to a temporary directory (``$TMPDIR/crd-sweep-*``) that is removed when the
sweep ends, not to Dask's default ``$TMPDIR/dask-scratch-space``, which stays.
Workers attached through ``--scheduler`` keep their own configuration.
"""

from __future__ import annotations

import contextlib
import tempfile
from pathlib import Path
from typing import Any, Iterator

import dask

from ..errors import ConfigError
from ..results.writer import package_version
from ..world.fmu_share import file_sha256
from .plan import SweepPlan, make_plan
from .report import write_report
from .runner import ClusterOptions, SweepOutcome, SweepProgress, Task, run_plan
from .spec import SweepSpec
from .subjects import subject_of
from .table import ResultsTable, results_schema
from .task import run_one

def table_meta(plan: SweepPlan) -> dict[str, Any]:
    """What ``results.parquet`` records about the sweep that made it (its schema metadata)."""
    spec = plan.spec
    strategy = subject_of(spec.subject).strategy_path
    return {
        "name": spec.name, "description": spec.description, "mode": spec.mode, "seed": spec.seed,
        "subject": spec.subject, "source": str(spec.source), "scenario": str(spec.base),
        "axes": [a.path for a in spec.axes],
        "strategy_axis": strategy if any(a.path == strategy for a in spec.axes) else None,
        "base_values": plan.base_values, "runs": len(plan.runs), "fmu_sha256": file_sha256(plan.fmu_path),
        "package_version": package_version(),
    }


def open_table(plan: SweepPlan, out_dir: Path) -> ResultsTable:
    example = plan.runs[0].point.as_dict() if plan.runs else {}
    return ResultsTable(out_dir, results_schema(example, table_meta(plan), subject_of(plan.spec.subject).columns()))


def run_sweep(spec: SweepSpec, out_dir: Path, opts: ClusterOptions, resume: bool = False,
              keep_timeseries: bool = False, progress: SweepProgress | None = None,
              task: Task = run_one, report: bool = True) -> tuple[SweepPlan, SweepOutcome]:
    """Plan ``spec``, run what is not done yet (``resume``) and write ``out_dir``'s table and report.

    Without ``resume`` an existing ``results.parquet`` in ``out_dir`` is replaced.
    """
    if keep_timeseries and not subject_of(spec.subject).timeseries:
        raise ConfigError(f"--keep-timeseries: a {spec.subject} sweep keeps no time series (its runs' figures are "
                          f"in the table)")
    plan = make_plan(spec)
    table = open_table(plan, out_dir)
    skip = table.resume({r.key: r.index for r in plan.runs}) if resume else set()
    with cluster_scratch(opts):
        outcome = run_plan(plan, table, out_dir, opts, skip, keep_timeseries, progress, task)
    if report:
        write_report(out_dir)
    return plan, outcome


@contextlib.contextmanager
def cluster_scratch(opts: ClusterOptions) -> Iterator[Path | None]:
    """A local cluster's ``temporary-directory``: a fresh ``$TMPDIR/crd-sweep-*``, removed on the way out
    (None, and nothing set, for a scheduler given by address: its workers are configured where they run)."""
    if opts.scheduler:
        yield None
        return
    with tempfile.TemporaryDirectory(prefix="crd-sweep-") as tmp, dask.config.set({"temporary-directory": tmp}):
        yield Path(tmp)
