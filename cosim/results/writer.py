"""Writers for a run's outputs (``--out DIR``).

* ``metrics.json``: ``{"runs": [...], "provenance": {...}}``;
* ``<strategy>/timeseries.csv`` (one row per 10 ms ECU cycle) and the CAN logs are
  streamed while the run goes by :class:`cosim.results.stream.RunStream`, which uses
  :func:`timeseries_cells` here and :mod:`cosim.results.can_logs`;
* ``<strategy>/events.json``: gateway fallbacks, collision, FMI error;
* ``config.resolved.toml``: every resolved value, loadable by ``crd run``;
  its header and ``metrics.json`` carry the FMU's sha256, the package version
  and the seed.
"""

from __future__ import annotations

import csv
import json
import math
import os
import tempfile
from dataclasses import fields
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Iterable

from .events import event_counts
from .run_record import RunRecord
from ..scenarios.config import Scenario
from ..scenarios.resolve import scenario_to_dict
from ..scenarios.toml_writer import dumps


def package_version() -> str:
    try:
        return version("crd")
    except PackageNotFoundError:
        return "unknown"


def provenance(scenario: Scenario, records: Iterable[RunRecord]) -> dict:
    records = list(records)
    return {
        "package_version": package_version(),
        "seed": scenario.scenario.seed,
        "fmu_path": records[0].fmu_path if records else "",
        "fmu_sha256": records[0].fmu_sha256 if records else "",
        "fmi_version": scenario.plant.fmi_version if scenario.plant.fmu == "builtin" else None,
    }


def _finite(x):
    return None if isinstance(x, float) and not math.isfinite(x) else x


def write_metrics(path: Path, records: Iterable[RunRecord], prov: dict, status: str = "complete",
                  error: str | None = None) -> None:
    """``metrics.json``, replaced in one step; ``status``: running, complete, interrupted or error
    (an exception, or a run that stopped on an error; each run has its own ``status`` too).

    Written before the first run (``running``), after each run, and on every way out of
    :func:`cosim.loop.experiment.run_strategies`, so it always says how far the invocation got.
    """
    runs = []
    for r in records:
        entry = {k: _finite(v) for k, v in r.metrics.as_dict().items()}
        entry["error"] = r.error
        entry.update(run_status(r))
        if r.contact is not None:
            entry["contact"] = r.contact
        runs.append(entry)
    write_json_atomic(path, {"status": status, "error": error, "runs": runs, "provenance": prov})


def write_json_atomic(path: Path, data: object) -> None:
    """``data`` as indented JSON at ``path``, replaced in one step (never half written)."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        umask = os.umask(0o022)
        os.umask(umask)
        os.fchmod(fd, 0o666 & ~umask)  # as open() would create it (mkstemp makes it 0600)
        with os.fdopen(fd, "w") as handle:
            handle.write(json.dumps(data, indent=2) + "\n")
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def run_status(record: RunRecord) -> dict:
    """``status`` (ok, collided, error, interrupted), the signal of an interrupt and the events by kind."""
    return {"status": record.status, "interrupted_by": record.interrupted, "event_counts": event_counts(record)}


def timeseries_cells(row: tuple) -> list:
    """One time-series row as CSV cells: time to 1 ms, other floats to 6 significant digits."""
    return [f"{v:.6g}" if isinstance(v, float) and k else (f"{v:.3f}" if k == 0 else v) for k, v in enumerate(row)]


def write_timeseries(path: Path, record: RunRecord) -> None:
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(record.columns)
        for row in record.rows:
            writer.writerow(timeseries_cells(row))


def write_events(path: Path, record: RunRecord) -> None:
    events = [{"t_s": e.t_s, "kind": e.kind, "detail": e.detail, **(e.data or {})} for e in record.events]
    path.write_text(json.dumps({"events": events, "error": record.error}, indent=2) + "\n")


def write_resolved_config(path: Path, scenario: Scenario, ecu_config, prov: dict) -> None:
    data = scenario_to_dict(scenario, strategy=ecu_config.strategy)
    data["ecu"].update({f.name: getattr(ecu_config, f.name) for f in fields(ecu_config) if f.init})
    header = "\n".join([
        "Resolved scenario: every value used by the run (defaults included); `crd run` reads it.",
        f"package version: {prov['package_version']}",
        f"seed: {prov['seed']}",
        f"plant FMU: {prov['fmu_path']}",
        f"plant FMU sha256: {prov['fmu_sha256']}",
    ])
    path.write_text(dumps(data, header=header))

