"""From a :class:`~cosim.sweep.spec.SweepSpec` to the list of runs, each a resolved scenario.

The *resolved mapping* of the base scenario is every value it uses, defaults
included (:func:`cosim.scenarios.resolve.scenario_to_dict`; ``ecu`` holds every
``EcuConfig`` key). Axis key paths are checked against a *schema view*: that
mapping plus, in every table declared as FMU start values
(:data:`cosim.scenarios.kinds.FMU_START_VALUES`, ``plant.parameters``), the
plant FMU's parameters (read from its model description). Each run is the
mapping with its axis values written in; it reads back through
:func:`cosim.scenarios.loader.scenario_from_dict` on the worker, so a value the
loader, the ECU or the FMU refuses fails that run only.

Run key and seed: ``key = sha256(canonical JSON of {sweep seed, replicate, the
run's resolved mapping without scenario.seed})`` (hex, 32 digits), and the run's
``scenario.seed = int(sha256(key + "/seed")[:16 hex]) mod 2**63``. Both depend
only on the sweep file and the scenario, never on the run's position or worker.
"""

from __future__ import annotations

import copy
import hashlib
import json
import logging
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from fmpy import read_model_description

from ecu.settings import walk

from ..errors import ConfigError
from ..loop.experiment import resolve_fmu
from ..scenarios.config import Scenario
from ..scenarios.kinds import FMU_START_VALUES
from ..scenarios.loader import load_scenario
from ..scenarios.resolve import scenario_to_dict
from . import keypath
from .design import Point, design
from .spec import SweepSpec

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class RunSpec:
    """One run: its position in the design, key, seed, axis values and resolved scenario mapping."""

    index: int
    key: str
    seed: int
    point: Point
    scenario: dict


@dataclass(frozen=True)
class SweepPlan:
    spec: SweepSpec
    base: Scenario
    fmu_path: Path
    base_values: dict[str, Any]
    runs: tuple[RunSpec, ...]
    duplicates: int = 0


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


def _strip_none(node: Any) -> Any:
    if isinstance(node, dict):
        return {k: _strip_none(v) for k, v in node.items() if v is not None}
    if isinstance(node, list):
        return [_strip_none(v) for v in node]
    return node


def _typed(base_value: Any, value: Any) -> Any:
    """An integer given for a float key is the float (so 1 and 1.0 are one run)."""
    if isinstance(base_value, float) and isinstance(value, int) and not isinstance(value, bool):
        return float(value)
    return value


def run_key(mapping: dict[str, Any], sweep_seed: int, replicate: int) -> str:
    body = copy.deepcopy(mapping)
    body.get("scenario", {}).pop("seed", None)
    text = json.dumps({"sweep_seed": sweep_seed, "replicate": replicate, "scenario": body},
                      sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[:32]


def run_seed(key: str) -> int:
    return int(hashlib.sha256(f"{key}/seed".encode()).hexdigest()[:16], 16) % 2**63


def check_axes(spec: SweepSpec, schema: dict[str, Any]) -> dict[str, Any]:
    """Each axis path's base value; an unknown path is a one-line ConfigError naming the sweep file."""
    base = {}
    for i, axis in enumerate(spec.axes):
        try:
            base[axis.path] = keypath.check(schema, axis.path)
        except ConfigError as exc:
            raise ConfigError(f"{spec.source}: axis[{i}].path: {exc}") from None
    return base


def make_plan(spec: SweepSpec) -> SweepPlan:
    """Load the base scenario, build its FMU, check the axes and list every run."""
    base = load_scenario(spec.scenario)
    fmu_path = resolve_fmu(base)
    mapping = resolved_mapping(base)
    base_values = check_axes(spec, schema_view(mapping, fmu_path))
    plain = _strip_none(mapping)
    runs: list[RunSpec] = []
    seen: set[str] = set()
    points = design(spec, base_values)
    for point in points:
        point = Point(tuple((p, _typed(base_values[p], v)) for p, v in point.values), point.replicate)
        scenario = copy.deepcopy(plain)
        for path, value in point.values:
            keypath.assign(scenario, path, value)
        key = run_key(scenario, spec.seed, point.replicate)
        if key in seen:
            continue
        seen.add(key)
        seed = run_seed(key)
        scenario["scenario"]["seed"] = seed
        runs.append(RunSpec(len(runs), key, seed, point, scenario))
    duplicates = len(points) - len(runs)
    if duplicates:
        log.warning("%s: %d design points repeat an earlier run's scenario; each is run once", spec.name, duplicates)
    return SweepPlan(spec, base, fmu_path, base_values, tuple(runs), duplicates)
