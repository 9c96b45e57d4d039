"""From a :class:`~cosim.sweep.spec.SweepSpec` to the list of runs, each a resolved mapping.

The sweep's subject (:mod:`cosim.sweep.subjects`: a scenario or a fleet) loads the base file into the
mapping the runs start from and a *schema view* the axis key paths (and their ``also`` paths) are checked
against; each run is the mapping with its axis values written in, read back by the subject on the worker,
so a value the loader, the ECU or the FMU refuses fails that run only. The base with every path written at its
base value is loaded on the client (:meth:`~cosim.sweep.subject.SweepSubject.check`), so that a path the
loader refuses stops the sweep before it starts.

Run key and seed: ``key = sha256(canonical JSON of {sweep seed, replicate, the run's mapping without its seed})``
(hex, 32 digits), and the run's seed (``scenario.seed``, or a fleet's ``fleet.seed``)
``= int(sha256(key + "/seed")[:16 hex]) mod`` the subject's seed limit (``2**63``, a fleet's ``2**62``),
unless the seed is itself an axis (a fleet's may be): then it is the axis value and part of the key. Both depend
only on the sweep file and the base file, never on the run's position or worker.
"""

from __future__ import annotations

import copy
import hashlib
import json
import logging
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import ConfigError
from . import keypath
from .design import Point, design
from .spec import SweepSpec
from .subject import SubjectBase
from .subjects import subject_of

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class RunSpec:
    """One run: its position in the design, key, seed, axis values and resolved mapping (``scenario``: a
    scenario's, or a fleet's for ``subject = "fleet"``; ``base_dir``: where its relative paths are read from)."""

    index: int
    key: str
    seed: int
    point: Point
    scenario: dict
    subject: str = "scenario"
    base_dir: str | None = None


@dataclass(frozen=True)
class SweepPlan:
    spec: SweepSpec
    base: Any
    fmu_path: Path
    base_values: dict[str, Any]
    runs: tuple[RunSpec, ...]
    duplicates: int = 0


def _typed(base_value: Any, value: Any) -> Any:
    """An integer given for a float key is the float (so 1 and 1.0 are one run)."""
    if isinstance(base_value, float) and isinstance(value, int) and not isinstance(value, bool):
        return float(value)
    return value


def _without(mapping: dict[str, Any], path: str) -> dict[str, Any]:
    """A copy of ``mapping`` without the key at ``path`` (if there)."""
    body = copy.deepcopy(mapping)
    *tables, last = keypath.parse(path)
    node: Any = body
    for step in tables:
        node = node.get(step, {}) if isinstance(node, dict) else {}
    if isinstance(node, dict):
        node.pop(last, None)
    return body


def run_key(mapping: dict[str, Any], sweep_seed: int, replicate: int, seed_path: str | None = "scenario.seed") -> str:
    """The run's key (module docstring); ``seed_path``: the seed left out of it (None: kept, an axis)."""
    body = _without(mapping, seed_path) if seed_path else mapping
    text = json.dumps({"sweep_seed": sweep_seed, "replicate": replicate, "scenario": body},
                      sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[:32]


def run_seed(key: str, limit: int = 2**63) -> int:
    return int(hashlib.sha256(f"{key}/seed".encode()).hexdigest()[:16], 16) % limit


def check_axes(spec: SweepSpec, schema: dict[str, Any]) -> dict[str, Any]:
    """Each written path's base value; an unknown path is a one-line ConfigError naming the sweep file."""
    base = {}
    for i, axis in enumerate(spec.axes):
        for path in (axis.path, *axis.also):
            try:
                base[path] = keypath.check(schema, path)
            except ConfigError as exc:
                where = "path" if path == axis.path else "also"
                raise ConfigError(f"{spec.source}: axis[{i}].{where}: {exc}") from None
    return base


def _mapping(spec: SweepSpec, plain: dict[str, Any], point: Point) -> dict[str, Any]:
    """The base mapping with the point's values written at each axis's path and its ``also`` paths."""
    also = {a.path: a.also for a in spec.axes}
    mapping = copy.deepcopy(plain)
    for path, value in point.values:
        for target in (path, *also[path]):
            keypath.assign(mapping, target, value)
    return mapping


def _check_paths(spec: SweepSpec, base: SubjectBase, base_values: dict[str, Any]) -> None:
    """The base with every path written at its base value loads as a worker loads a run: a path the schema
    view allows but the loader refuses stops the sweep here (a value the loader refuses fails its run only)."""
    mapping = copy.deepcopy(base.mapping)
    for path, value in base_values.items():
        if value is not None:
            keypath.assign(mapping, path, value)
    try:
        subject_of(spec.subject).check(mapping, base.base_dir)
    except ConfigError as exc:
        raise ConfigError(f"{spec.source}: axis paths {', '.join(spec.paths)} on {spec.base.name}: {exc}") from None


def _seed_axis(spec: SweepSpec, seed_path: str) -> bool:
    """Whether the runs' seed is an axis (its values are the seeds); it may not be an ``also`` path."""
    for i, axis in enumerate(spec.axes):
        if seed_path in axis.also:
            raise ConfigError(f"{spec.source}: axis[{i}].also: {seed_path} is a run's seed: give it its own axis")
    given = any(a.path == seed_path for a in spec.axes)
    if given and spec.replicates > 1:
        raise ConfigError(f"{spec.source}: sweep.replicates: the seed is the axis {seed_path}, so every replicate "
                          f"would repeat the same run; give more seeds instead")
    return given


def make_plan(spec: SweepSpec) -> SweepPlan:
    """Load the base file, build its FMU, check the axes and list every run."""
    subject = subject_of(spec.subject)
    base = subject.prepare(spec.base)
    base_values = check_axes(spec, base.schema)
    _check_paths(spec, base, base_values)
    seed_axis = _seed_axis(spec, subject.seed_path)
    runs: list[RunSpec] = []
    seen: set[str] = set()
    points = design(spec, base_values)
    for point in points:
        point = Point(tuple((p, _typed(base_values[p], v)) for p, v in point.values), point.replicate)
        mapping = _mapping(spec, base.mapping, point)
        key = run_key(mapping, spec.seed, point.replicate, None if seed_axis else subject.seed_path)
        if key in seen:
            continue
        seen.add(key)
        seed = point.as_dict()[subject.seed_path] if seed_axis else run_seed(key, subject.seed_limit)
        keypath.assign(mapping, subject.seed_path, seed)
        runs.append(RunSpec(len(runs), key, seed, point, mapping, spec.subject, base.base_dir))
    duplicates = len(points) - len(runs)
    if duplicates:
        log.warning("%s: %d design points repeat an earlier run's scenario; each is run once", spec.name, duplicates)
    return SweepPlan(spec, base.loaded, base.fmu_path, base_values, tuple(runs), duplicates)
