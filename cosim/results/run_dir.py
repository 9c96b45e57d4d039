"""A written run directory read back (``crd compare``, ``crd export``).

A run directory is what ``crd run``/``crd paper --out`` holds: ``metrics.json`` (one entry
per strategy run), ``config.resolved.toml`` and, per strategy, ``timeseries.csv``,
``events.json`` and the CAN logs. :func:`load_run_dir` reads the records (time series,
events, metrics) and the resolved configuration; a file that is not what ``crd`` writes is
a :class:`~cosim.errors.ConfigError` naming it.
"""

from __future__ import annotations

import csv
import json
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import ConfigError
from .run_record import TIMESERIES_COLUMNS, RunEvent, RunMetrics, RunRecord

RESOLVED_CONFIG = "config.resolved.toml"


@dataclass(frozen=True)
class RunDir:
    """A written run: its records (time series, events, metrics), the object's position (m) and name,
    and the resolved configuration as parsed TOML (empty when the file is missing)."""

    path: Path
    records: list[RunRecord]
    object_position_m: float | None
    object_name: str = "object"
    config: dict[str, Any] = field(default_factory=dict)

    def record(self, strategy: str | None = None) -> RunRecord:
        """The run of ``strategy``; without one, the directory's only run."""
        held = [r.strategy for r in self.records]
        if strategy is None and len(held) == 1:
            return self.records[0]
        if strategy is not None and strategy in held:
            return self.records[held.index(strategy)]
        wanted = f"no run of strategy {strategy!r}" if strategy else "several runs; name one with --strategy"
        raise ConfigError(f"{self.path}: {wanted} (it holds {', '.join(held) or 'none'})")


def _read_rows(series: Path) -> tuple[tuple[str, ...], list[tuple]]:
    """The file's columns (:data:`TIMESERIES_COLUMNS`, then a planar run's pose columns) and its rows."""
    with open(series, newline="") as handle:
        reader = csv.DictReader(handle)
        columns = tuple(reader.fieldnames or ())
        missing = [c for c in TIMESERIES_COLUMNS if c not in columns]
        if missing:
            raise ConfigError(f"{series}: expected the columns {', '.join(TIMESERIES_COLUMNS)}; "
                              f"missing {', '.join(missing)}")
        return columns, [tuple(values[c] if c == "ecu_mode" else float(values[c]) for c in columns)
                         for values in reader]


def _record(run_dir: Path, entry: dict) -> RunRecord:
    strategy = entry["strategy"]
    metrics = RunMetrics(**{k: entry[k] for k in RunMetrics.__dataclass_fields__ if k in entry})
    record = RunRecord(strategy, metrics, error=entry.get("error"))
    series = run_dir / strategy / "timeseries.csv"
    if series.is_file():
        record.columns, record.rows = _read_rows(series)
    events = run_dir / strategy / "events.json"
    if events.is_file():
        record.events = [RunEvent(e["t_s"], e["kind"], e["detail"])
                         for e in json.loads(events.read_text())["events"]]
    return record


def load_run_dir(path: Path) -> RunDir:
    """Read a run directory; a missing ``metrics.json`` is a :class:`ConfigError` naming it."""
    metrics = path / "metrics.json"
    if not metrics.is_file():
        raise ConfigError(f"{path}: not a crd run directory (expected {metrics.name} from crd run/paper --out)")
    runs = json.loads(metrics.read_text())["runs"]
    config_path = path / RESOLVED_CONFIG
    config = tomllib.loads(config_path.read_text()) if config_path.is_file() else {}
    table = config.get("object", {})
    obj = table.get("position_m") if table and table.get("enabled", True) else None
    return RunDir(path, [_record(path, entry) for entry in runs], obj, table.get("name", "object"), config)
