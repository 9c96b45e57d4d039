"""A sweep over a fleet scene (several equipped cars, issue 23): ``[sweep] fleet = ...``.

Axis key paths address the fleet file's parsed TOML (:mod:`cosim.fleet.config`): ``vehicles[1].y_m`` (where
a car starts: its arrival offset), ``vehicle.plant.initial_speed_mps`` (every car's, unless a car overrides
it), ``vehicle.ecu.strategy``, ``vehicles[0].ecu.way_out``, ``fleet.conflict_radius_m``. They are checked
against a *schema view* of the scene: ``fleet`` every :class:`~cosim.fleet.config.FleetSection` key;
``vehicles[i]`` its placement and every key of its resolved scenario tables (defaults included, the plant
FMU's parameters under ``plant.parameters``, as a one-car sweep sees them); ``vehicle`` the same tables,
with the first car's values where ``[vehicle]`` does not give one; ``objects`` as written. A run is the
file's data with its values written in, loaded by :func:`~cosim.fleet.config.fleet_from_dict`; the plan
loads the first run so on the client (:meth:`FleetSubject.check`).

A run's seed is ``fleet.seed`` (vehicle ``i``'s random sources, its way-out patience among them, take
``seed + i``): derived from the run's key like a scenario's, unless ``fleet.seed`` is an axis. Every vehicle
must use one plant FMU (the one shipped to the workers). A row's figures are the dance's
(:class:`~cosim.fleet.dance_metrics.SceneDance`): see :data:`COLUMNS`.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

from ecu.settings import load_toml

from ..errors import ConfigError
from ..fleet.config import VEHICLE_TABLES, Fleet, fleet_from_dict
from ..fleet.dance_metrics import SceneDance
from ..fleet.output import run_fleet
from ..loop.experiment import resolve_fmu
from .scenario_subject import resolved_mapping, schema_view
from .subject import STATUS_FAILED, STATUS_OK, RateColumn, SubjectBase, mean

#: a row's dance figures: column -> type (None where the figure has no value)
COLUMNS: dict[str, type] = {
    "collisions": int,                # vehicles in contact when the scene ended
    "collided": bool,                 # any contact
    "impact_speed_mps": float,        # the highest relative impact speed among them
    "deadlock_s": float,              # time in deadlock (dance_metrics)
    "time_to_clear_s": float,         # first contingency (else intervention) to all cleared
    "all_cleared": bool,              # every vehicle left the conflict zone
    "all_cleared_s": float,           # when the last one did
    "first_contingency_s": float,
    "first_intervention_s": float,
    "contingency_invocations": int,   # over all vehicles
    "min_decelerations": int,         # the fewest separate decelerations of any vehicle
    "max_decelerations": int,         # the most
    "end_time_s": float,              # the scene's last simulated time
}
_WORLD_TABLES = ("object", "objects")  # given as written (a vehicle's resolved scenario holds the world's too)


def _overlay(base: dict[str, Any], given: Mapping[str, Any]) -> dict[str, Any]:
    out = dict(base)
    for key, value in given.items():
        out[key] = _overlay(out[key], value) if isinstance(value, Mapping) and isinstance(out.get(key), dict) \
            else value
    return out


def schema(raw: Mapping[str, Any], fleet: Fleet, fmu_path: Path) -> dict[str, Any]:
    """Every key an axis may name, with its base value (module docstring)."""
    vehicles = []
    for v, table in zip(fleet.vehicles, raw.get("vehicles", [])):
        resolved = schema_view(resolved_mapping(v.scenario), fmu_path)
        tables = {k: resolved[k] for k in VEHICLE_TABLES if k in resolved and k not in _WORLD_TABLES}
        tables.update({k: table[k] for k in _WORLD_TABLES if k in table})
        vehicles.append({**dataclasses.asdict(v.placement), **tables})
    first = {k: t for k, t in vehicles[0].items() if k in VEHICLE_TABLES and k not in _WORLD_TABLES}
    return {"fleet": dataclasses.asdict(fleet.fleet), "vehicle": _overlay(first, raw.get("vehicle", {})),
            "vehicles": vehicles, "objects": list(raw.get("objects", []))}


def _strategies(mapping: Mapping[str, Any]) -> list[tuple[str, str]]:
    shared = mapping.get("vehicle", {}).get("ecu", {}).get("strategy", "tightening")
    return [(str(t.get("name", i)), t.get("ecu", {}).get("strategy", shared))
            for i, t in enumerate(mapping.get("vehicles", [])) if isinstance(t, Mapping)]


def strategy_label(pairs: list[tuple[str, str]]) -> str:
    """The strategy column: the one strategy of every car, else ``name=strategy`` per car."""
    distinct = {s for _, s in pairs}
    return next(iter(distinct)) if len(distinct) == 1 else ",".join(f"{n}={s}" for n, s in pairs)


def figures(dance: SceneDance, end_time_s: float) -> dict[str, Any]:
    """A row's :data:`COLUMNS` from the dance."""
    hits = [v.impact_speed_mps for v in dance.vehicles if v.collided and v.impact_speed_mps is not None]
    decels = [v.decelerations for v in dance.vehicles]
    return {"collisions": dance.collisions, "collided": dance.collisions > 0,
            "impact_speed_mps": max(hits) if hits else None, "deadlock_s": dance.deadlock_s,
            "time_to_clear_s": dance.time_to_clear_s, "all_cleared": dance.all_cleared_s is not None,
            "all_cleared_s": dance.all_cleared_s, "first_contingency_s": dance.first_contingency_s,
            "first_intervention_s": dance.first_intervention_s,
            "contingency_invocations": sum(v.contingency_invocations for v in dance.vehicles),
            "min_decelerations": min(decels), "max_decelerations": max(decels), "end_time_s": end_time_s}


def _clear_times(ok: list[dict]) -> list[float]:
    return [r["time_to_clear_s"] for r in ok if r["time_to_clear_s"] is not None]


@dataclass(frozen=True)
class FleetSubject:
    """One fleet run per sweep run (:func:`cosim.fleet.output.run_fleet`, no files)."""

    kind: str = "fleet"
    seed_path: str = "fleet.seed"
    seed_limit: int = 2**62  # [fleet] seed's range
    strategy_path: str = "vehicle.ecu.strategy"
    timeseries: bool = False
    map_metrics: tuple[str, ...] = ("collision_rate", "mean_deadlock_s")
    rate_columns: tuple[RateColumn, ...] = (
        RateColumn("mean_deadlock_s", "mean deadlock s", lambda ok: mean([r["deadlock_s"] for r in ok])),
        RateColumn("runs_with_deadlock", "runs with deadlock", lambda ok: sum(1 for r in ok if r["deadlock_s"] > 0),
                   "d"),
        RateColumn("runs_all_cleared", "runs all cleared", lambda ok: sum(1 for r in ok if r["all_cleared"]), "d"),
        RateColumn("mean_time_to_clear_s", "mean time to clear s (cleared runs)",
                   lambda ok: mean(_clear_times(ok))))

    def columns(self) -> dict[str, type]:
        return dict(COLUMNS)

    def prepare(self, path: Path) -> SubjectBase:
        raw = load_toml(path, lambda data: data, "fleet")
        fleet = load_toml(path, lambda data: fleet_from_dict(data, base_dir=path.parent), "fleet")
        fmus = {resolve_fmu(v.scenario) for v in fleet.vehicles}
        if len(fmus) != 1:
            raise ConfigError(f"{path}: a fleet sweep runs one plant FMU for every vehicle, this scene has "
                              f"{len(fmus)}: {sorted(str(f) for f in fmus)}")
        fmu_path = fmus.pop()
        return SubjectBase(fleet, fmu_path, raw, schema(raw, fleet, fmu_path), str(path.parent))

    def check(self, mapping: dict[str, Any], base_dir: str | None) -> None:
        fleet_from_dict(mapping, Path(base_dir) if base_dir else None)

    def strategy(self, mapping: dict[str, Any]) -> str:
        return strategy_label(_strategies(mapping))

    def run(self, mapping: dict[str, Any], base_dir: str | None, fmu_path: Path,
            keep_timeseries: bool) -> dict[str, Any]:
        fleet = fleet_from_dict(mapping, Path(base_dir) if base_dir else None)
        record, dance = run_fleet(fleet, None, fmu_paths={n: fmu_path for n in fleet.names})
        errors = [f"{n}: {r.error}" for n, r in zip(fleet.names, record.records) if r.error]
        row: dict[str, Any] = {"strategy": strategy_label([(v.name, r.strategy) for v, r in
                                                           zip(fleet.vehicles, record.records)])}
        end_time_s = record.world_rows[-1][0] if record.world_rows else 0.0
        row.update(figures(dance, end_time_s))
        row.update(status=STATUS_FAILED if errors else STATUS_OK, error="; ".join(errors) or None)
        return row

    def outcome(self, row: dict[str, Any]) -> str:
        """``collides 4.3 m/s`` / ``clears, 2.1 s, 2 inv`` / ``deadlock 10.2 s, not cleared, 4 inv``."""
        inv = row["contingency_invocations"]
        if row["collided"]:
            return f"collides {row['impact_speed_mps'] or 0.0:.1f} m/s, {inv} inv"
        stuck = f"deadlock {row['deadlock_s']:.1f} s, " if row["deadlock_s"] else ""
        if not row["all_cleared"]:
            return f"{stuck}not cleared, {inv} inv"
        clear = row["time_to_clear_s"]
        return f"{stuck}clears{f' in {clear:.1f} s' if clear is not None else ''}, {inv} inv"


FLEET = FleetSubject()
