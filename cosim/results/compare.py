"""Two written runs side by side (``crd compare``): their metrics' differences and speed profiles.

A run directory is what ``--out`` holds: ``metrics.json``, ``config.resolved.toml``
and per strategy ``timeseries.csv`` and ``events.json``. Differences are rounded
as in ``report.md`` (:mod:`cosim.results.report`).
"""

from __future__ import annotations

import csv
import json
import tomllib
from dataclasses import dataclass
from pathlib import Path

from ..errors import ConfigError
from .report import fmt
from .run_record import TIMESERIES_COLUMNS, RunEvent, RunMetrics, RunRecord

#: metric key -> (label, decimals; None for a yes/no)
METRICS = {
    "collided": ("collided", None),
    "impact_speed_mps": ("impact speed (m/s)", 2),
    "min_gap_m": ("min gap (m)", 2),
    "final_gap_m": ("final gap (m)", 2),
    "contingency_invocations": ("contingency invocations", 0),
    "max_speed_mps": ("max speed (m/s)", 2),
    "sim_time_s": ("simulated time (s)", 2),
    "wall_time_s": ("wall time (s)", 2),
}


@dataclass(frozen=True)
class RunDir:
    """A written run: its records (time series, events, metrics) and the object's position (m)."""

    path: Path
    records: list[RunRecord]
    object_position_m: float | None


def _row(values: dict[str, str]) -> tuple:
    return tuple(values[c] if c == "ecu_mode" else float(values[c]) for c in TIMESERIES_COLUMNS)


def _record(run_dir: Path, entry: dict) -> RunRecord:
    strategy = entry["strategy"]
    metrics = RunMetrics(**{k: entry[k] for k in RunMetrics.__dataclass_fields__ if k in entry})
    record = RunRecord(strategy, metrics, error=entry.get("error"))
    series = run_dir / strategy / "timeseries.csv"
    if series.is_file():
        with open(series, newline="") as handle:
            record.rows = [_row(values) for values in csv.DictReader(handle)]
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
    obj = None
    config = path / "config.resolved.toml"
    if config.is_file():
        table = tomllib.loads(config.read_text()).get("object", {})
        obj = table.get("position_m") if table.get("enabled", True) else None
    return RunDir(path, [_record(path, entry) for entry in runs], obj)


def _value(key: str, value) -> str:
    digits = METRICS[key][1]
    if digits is None:
        return "yes" if value else "no"
    return fmt(value, digits)


def _delta(key: str, a, b) -> str:
    """B − A of the rounded values; blank when they are equal."""
    digits = METRICS[key][1]
    if _value(key, a) == _value(key, b):
        return ""
    if digits is None or a is None or b is None:
        return "differs"
    return f"{round(b, digits) - round(a, digits):+.{digits}f}"


def differences(a: RunDir, b: RunDir) -> list[str]:
    """Lines of a table: every metric of every strategy both runs have, A, B and B − A."""
    by_a = {r.strategy: r.metrics.as_dict() for r in a.records}
    by_b = {r.strategy: r.metrics.as_dict() for r in b.records}
    lines = [f"A = {a.path}", f"B = {b.path}", "",
             f"{'strategy':<13} {'metric':<24} {'A':>9} {'B':>9} {'B - A':>9}"]
    lines.append("-" * len(lines[-1]))
    changed, compared = 0, 0
    for strategy in [s for s in by_a if s in by_b]:
        for key, (label, _) in METRICS.items():
            va, vb = by_a[strategy][key], by_b[strategy][key]
            delta = _delta(key, va, vb)
            if key != "wall_time_s":
                compared += 1
                changed += _value(key, va) != _value(key, vb)
            lines.append(f"{strategy if key == 'collided' else '':<13} {label:<24} {_value(key, va):>9}"
                         f" {_value(key, vb):>9} {delta:>9}")
    lines += [f"only in {name}: {', '.join(only)}" for name, only in
              (("A", [s for s in by_a if s not in by_b]), ("B", [s for s in by_b if s not in by_a])) if only]
    lines.append(f"{changed} of {compared} metrics differ (wall time aside)" if changed
                 else f"identical in all {compared} metrics (wall time aside)")
    return lines
