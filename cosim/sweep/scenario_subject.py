"""A sweep over one scenario (one car): ``[sweep] scenario = ...``.

The runs start from the base scenario's *resolved mapping*: every value it uses, defaults included
(:func:`cosim.scenarios.resolve.scenario_to_dict`; ``ecu`` holds every ``EcuConfig`` key). Axis key
paths are checked against that mapping plus, in every table declared as FMU start values
(:data:`cosim.scenarios.kinds.FMU_START_VALUES`, ``plant.parameters``), the plant FMU's parameters (read
from its model description). A worker reads a run back through
:func:`cosim.scenarios.loader.scenario_from_dict`, so a value the loader, the ECU or the FMU refuses fails
that run only. A row's figures are the fields of ``metrics.json`` (:class:`~cosim.results.run_record.RunMetrics`).
"""

from __future__ import annotations

import copy
import dataclasses
import json
import typing
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from fmpy import read_model_description

from ecu.settings import walk

from ..loop.experiment import resolve_fmu
from ..loop.master import run_scenario
from ..results.run_record import RunMetrics
from ..scenarios.config import Scenario
from ..scenarios.kinds import FMU_START_VALUES
from ..scenarios.loader import load_scenario, scenario_from_dict
from ..scenarios.resolve import scenario_to_dict
from . import keypath
from .subject import STATUS_FAILED, STATUS_OK, RateColumn, SubjectBase, strip_none

#: metrics.json fields copied into each row: every RunMetrics field but the strategy (its own column)
METRIC_COLUMNS = tuple(f.name for f in dataclasses.fields(RunMetrics) if f.name != "strategy")


def resolved_mapping(scenario: Scenario) -> dict[str, Any]:
    """Every value the scenario uses, as plain nested dicts (``None`` = not set)."""
    return json.loads(json.dumps(scenario_to_dict(scenario)))  # tuples -> lists, plain types only


def _start_value(var: Any) -> Any:
    """A model variable's start value in its own type (fmpy keeps it as the XML string)."""
    text = var.start
    if text is None:
        return None
    if var.type == "Boolean":
        return str(text).lower() in ("true", "1")
    if var.type in ("Integer", "Int32", "Int64", "Enumeration"):
        return int(text)
    if var.type in ("Real", "Float64", "Float32"):
        return float(text)
    return text


def _fmu_parameters(fmu_path: Path) -> dict[str, Any]:
    md = read_model_description(str(fmu_path))
    return {v.name: _start_value(v) for v in md.modelVariables if v.causality == "parameter"}


def schema_view(mapping: dict[str, Any], fmu_path: Path) -> dict[str, Any]:
    """The mapping plus every FMU parameter in each table of FMU start values: every key an axis may name."""
    schema = copy.deepcopy(mapping)
    for path, key in walk(Scenario):
        if key.declared.kind is FMU_START_VALUES:
            node = schema
            for step in keypath.parse(path):
                node = node.setdefault(step, {})
            for name, start in _fmu_parameters(fmu_path).items():
                node.setdefault(name, start)
    return schema


def _column_types() -> dict[str, type]:
    """Column types from RunMetrics' annotations (``float | None`` -> float), so new metrics follow."""
    hints = typing.get_type_hints(RunMetrics)
    out = {}
    for name in METRIC_COLUMNS:
        args = [a for a in typing.get_args(hints[name]) if a is not type(None)] or [hints[name]]
        out[name] = args[0]
    return out


@dataclass(frozen=True)
class ScenarioSubject:
    """One closed-loop run per sweep run (:func:`cosim.loop.master.run_scenario`)."""

    kind: str = "scenario"
    seed_path: str = "scenario.seed"
    seed_limit: int = 2**63
    strategy_path: str = "ecu.strategy"
    timeseries: bool = True
    map_metrics: tuple[str, ...] = ("collision_rate", "mean_impact_speed_mps")
    rate_columns: tuple[RateColumn, ...] = (
        RateColumn("runs_with_fault", "runs with FAULT", lambda ok: sum(1 for r in ok if r.get("fault_entries")),
                   "d"),)

    def columns(self) -> dict[str, type]:
        return _column_types()

    def prepare(self, path: Path) -> SubjectBase:
        base = load_scenario(path)
        fmu_path = resolve_fmu(base)
        mapping = resolved_mapping(base)
        return SubjectBase(base, fmu_path, strip_none(mapping), schema_view(mapping, fmu_path))

    def check(self, mapping: dict[str, Any], base_dir: str | None) -> None:
        """Nothing before the sweep: a value the loader refuses fails its run only."""

    def strategy(self, mapping: dict[str, Any]) -> str:
        return mapping.get("ecu", {}).get("strategy", "tightening")

    def run(self, mapping: dict[str, Any], base_dir: str | None, fmu_path: Path,
            keep_timeseries: bool) -> dict[str, Any]:
        record = run_scenario(scenario_from_dict(mapping), fmu_path)
        row: dict[str, Any] = {"strategy": record.metrics.strategy}
        row.update({k: getattr(record.metrics, k) for k in METRIC_COLUMNS})
        row.update(status=STATUS_FAILED if record.error else STATUS_OK, error=record.error)
        if keep_timeseries:
            row["_timeseries"] = record.rows
        return row

    def outcome(self, row: dict[str, Any]) -> str:
        """``collides 4.3 m/s, 4 inv`` / ``stops 1.9 m short, 21 inv``."""
        inv = row["contingency_invocations"]
        if row["collided"]:
            return f"collides {row['impact_speed_mps']:.1f} m/s, {inv} inv"
        gap = row["final_gap_m"]
        return f"stops {gap:.1f} m short, {inv} inv" if gap is not None else f"no collision, {inv} inv"


SCENARIO = ScenarioSubject()
