"""What a sweep varies, behind one seam: a scenario (one car) or a fleet scene (several cars).

A :class:`SweepSubject` holds everything of a sweep that depends on what its base file is:

* on the client, :meth:`~SweepSubject.prepare` loads the base file into a :class:`SubjectBase`: the plant
  FMU shipped to the workers, the plain mapping every run starts from, and the *schema view* the axis key
  paths are checked against (every key a run may set, with its base value); :meth:`~SweepSubject.check`
  loads one run's mapping the way a worker will, so that a path the view accepts but the loader refuses
  is an error before the sweep starts;
* on a worker, :meth:`~SweepSubject.run` runs one mapping and returns its row's figures: ``strategy``, one
  value per :meth:`~SweepSubject.columns` entry, ``status`` and ``error``;
* for the report: each run's outcome in words, the rates beyond the shared ones (:class:`RateColumn`) and the
  heat maps (:data:`cosim.sweep.maps.METRICS` names).

The registry of subjects, keyed by the ``[sweep]`` key that names the base file, is
:data:`cosim.sweep.subjects.SUBJECTS`; the rest of the sweep machinery (spec, design, plan, runner, table,
report) is written once for all of them.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Protocol

STATUS_OK, STATUS_FAILED = "ok", "failed"


@dataclass(frozen=True)
class SubjectBase:
    """A loaded base file: the object itself, its plant FMU, the runs' starting mapping and the schema view.

    ``base_dir``: the directory relative paths in a run's mapping are read from (the base file's).
    """

    loaded: Any
    fmu_path: Path
    mapping: dict[str, Any]
    schema: dict[str, Any]
    base_dir: str | None = None


@dataclass(frozen=True)
class RateColumn:
    """One column of the report's rates table: ``value`` of a panel's runs with ``status = ok``."""

    key: str
    header: str
    value: Callable[[list[dict]], Any]
    fmt: str = ".2f"


class SweepSubject(Protocol):
    """What a sweep of one kind of base file does (module docstring)."""

    kind: str                           # the [sweep] key naming the base file: "scenario" or "fleet"
    seed_path: str                      # the key path of a run's seed (set per run unless it is an axis)
    seed_limit: int                     # a run's derived seed is below this
    strategy_path: str                  # the key path of the strategy axis (the report's panels)
    timeseries: bool                    # whether --keep-timeseries applies
    map_metrics: tuple[str, ...]        # the report's heat maps (cosim.sweep.maps.METRICS)
    rate_columns: tuple[RateColumn, ...]  # the rates table's columns beyond the shared ones

    def columns(self) -> dict[str, type]: ...

    def prepare(self, path: Path) -> SubjectBase: ...

    def check(self, mapping: dict[str, Any], base_dir: str | None) -> None: ...

    def strategy(self, mapping: dict[str, Any]) -> str: ...

    def run(self, mapping: dict[str, Any], base_dir: str | None, fmu_path: Path,
            keep_timeseries: bool) -> dict[str, Any]: ...

    def outcome(self, row: dict[str, Any]) -> str: ...


def mean(xs: list[float]) -> float | None:
    return sum(xs) / len(xs) if xs else None


def strip_none(node: Any) -> Any:
    """``node`` without the ``None`` values of its tables (TOML has no null)."""
    if isinstance(node, dict):
        return {k: strip_none(v) for k, v in node.items() if v is not None}
    if isinstance(node, list):
        return [strip_none(v) for v in node]
    return node
