"""``results.parquet``: one row per run, written incrementally and atomically.

Columns: ``run`` (position in the design), ``run_key``, ``seed``,
``replicate``, one column per axis (named by its key path), ``strategy``, the
run's figures (its subject's columns, :mod:`cosim.sweep.subjects`: a scenario's
``metrics.json`` fields, or a fleet's dance figures), ``status``
(``ok``/``failed``), ``error`` and ``task_wall_s`` (the whole task on the
worker: FMU cache, scenario load and run, s). The schema's metadata
``crd.sweep`` (JSON) holds the sweep's name, subject, mode, seed, axes, base values, the
FMU's sha256 and the package version.

Every flush rewrites the whole file to a temporary name and renames it over
the old one, so the file on disk is always a complete table: a sweep killed at
any moment keeps every row flushed before it. Rows are kept sorted by ``run``,
so the table does not depend on the order in which workers finish.
"""

from __future__ import annotations

import json
import os
import time
from pathlib import Path
from typing import Any, Iterable

import pyarrow as pa
import pyarrow.parquet as pq

from ..errors import ConfigError
from ..results.run_record import TIMESERIES_COLUMNS

RESULTS_NAME = "results.parquet"
META_KEY = b"crd.sweep"
_ARROW_BY_HINT = {bool: pa.bool_(), int: pa.int64(), float: pa.float64(), str: pa.string()}
_RESUME_MUST_MATCH = ("name", "seed", "fmu_sha256")


def _arrow_type(value: Any) -> pa.DataType:
    if isinstance(value, bool):
        return pa.bool_()
    if isinstance(value, int):
        return pa.int64()
    if isinstance(value, float):
        return pa.float64()
    return pa.string()


def results_schema(axis_values: dict[str, Any], meta: dict[str, Any], columns: dict[str, type]) -> pa.Schema:
    """The table's schema; ``axis_values``: one example value per axis path (sets its column type); ``columns``:
    the subject's figures and their types."""
    fields = [("run", pa.int64()), ("run_key", pa.string()), ("seed", pa.int64()), ("replicate", pa.int64())]
    fields += [(path, _arrow_type(v)) for path, v in axis_values.items()]
    fields += [("strategy", pa.string())]
    fields += [(name, _ARROW_BY_HINT.get(hint, pa.string())) for name, hint in columns.items()]
    fields += [("status", pa.string()), ("error", pa.string()), ("task_wall_s", pa.float64())]
    return pa.schema(fields, metadata={META_KEY: json.dumps(meta, sort_keys=True).encode()})


def read_results(path: Path) -> tuple[pa.Table, dict[str, Any]]:
    """The table and its ``crd.sweep`` metadata; a missing or foreign file is a one-line error."""
    try:
        table = pq.read_table(path)
    except (FileNotFoundError, OSError, pa.ArrowInvalid) as exc:
        raise ConfigError(f"{path}: cannot read a sweep results table: {exc}") from None
    raw = (table.schema.metadata or {}).get(META_KEY)
    if raw is None:
        raise ConfigError(f"{path}: not a crd sweep table (no {META_KEY.decode()} metadata)")
    return table, json.loads(raw)


class ResultsTable:
    """Rows collected so far, flushed to ``out_dir/results.parquet`` at most every ``flush_s`` seconds."""

    def __init__(self, out_dir: Path, schema: pa.Schema, flush_s: float = 1.0) -> None:
        self.path = Path(out_dir) / RESULTS_NAME
        self.schema = schema
        self.flush_s = flush_s
        self._rows: dict[str, dict[str, Any]] = {}
        self._last_flush = time.monotonic()
        self._dirty = False
        self.path.parent.mkdir(parents=True, exist_ok=True)

    def resume(self, run_index: dict[str, int]) -> set[str]:
        """Load an existing table (same sweep name, seed and FMU); returns the keys already done."""
        if not self.path.exists():
            return set()
        table, meta = read_results(self.path)
        mine = json.loads(self.schema.metadata[META_KEY])
        for key in _RESUME_MUST_MATCH:
            if meta.get(key) != mine.get(key):
                raise ConfigError(f"{self.path}: cannot resume: its {key} is {meta.get(key)!r}, "
                                  f"this sweep's is {mine.get(key)!r}; use another --out")
        names = set(self.schema.names)
        for row in table.to_pylist():
            row = {k: v for k, v in row.items() if k in names}
            row["run"] = run_index.get(row["run_key"], row["run"])
            self._rows[row["run_key"]] = row
        return set(self._rows)

    def add(self, row: dict[str, Any]) -> None:
        self._rows[row["run_key"]] = row
        self._dirty = True
        if time.monotonic() - self._last_flush >= self.flush_s:
            self.flush()

    def __len__(self) -> int:
        return len(self._rows)

    def rows(self) -> list[dict[str, Any]]:
        return sorted(self._rows.values(), key=lambda r: r["run"])

    def flush(self) -> None:
        """Write every row so far: to a temporary file, then renamed over the table."""
        table = pa.Table.from_pylist(self.rows(), schema=self.schema)
        tmp = self.path.with_name(f".{self.path.name}.{os.getpid()}.tmp")
        pq.write_table(table, tmp)
        os.replace(tmp, self.path)
        self._last_flush = time.monotonic()
        self._dirty = False

    def close(self) -> None:
        if self._dirty or not self.path.exists():
            self.flush()


def write_timeseries(out_dir: Path, run_key: str, rows: Iterable[tuple]) -> Path:
    """One run's 10 ms time series as ``out_dir/timeseries/<run_key>.parquet``."""
    path = Path(out_dir) / "timeseries" / f"{run_key}.parquet"
    path.parent.mkdir(parents=True, exist_ok=True)
    columns = list(zip(*rows)) if rows else [[] for _ in TIMESERIES_COLUMNS]
    pq.write_table(pa.table({name: list(col) for name, col in zip(TIMESERIES_COLUMNS, columns)}), path)
    return path
