"""A fleet run with its files: one directory per vehicle as a one-car run writes it, and the scene's own.

``out_dir/``:

* ``<vehicle>/timeseries.csv``, ``<vehicle>/can.blf`` (and each ``--can-log``), ``<vehicle>/events.json``:
  each vehicle's own, in its own frame, streamed as the run goes (:class:`~cosim.results.stream.RunStream`),
  so a run stopped at any moment keeps them up to the last simulated second;
* ``<vehicle>/config.resolved.toml``: every value the vehicle's run used, as a one-car run writes it (its
  strategy, its way-out rule and patience, its seed, its plant FMU and that FMU's sha256), once it has run;
* ``world.csv``: every vehicle's box centre, heading and speed in the world frame, one row per ECU cycle;
* ``metrics.json``: the status (running, complete, error, interrupted), each vehicle's metrics and the
  dance figures (:mod:`cosim.fleet.dance_metrics`); written before the run and on every way out;
* ``fleet.json``: the scene for its bird's-eye view (``crd animate``): each vehicle's frame, box and road in the
  world, the objects, the conflict zone (:mod:`cosim.fleet.scene_file`);
* ``speeds.png``: every vehicle's speed against time, its contingencies shaded;
* ``report.md``: the dance table and the plot.
"""

from __future__ import annotations

import csv
from pathlib import Path
from typing import Callable, Mapping, Sequence

from ..link.ecu_link import EcuOptions
from ..loop.ecu_config import ecu_config
from ..loop.experiment import resolve_fmu
from ..results.can_logs import check_can_logs
from ..results.stream import RunStream, check_out_dir
from ..results.writer import package_version, provenance, write_events, write_json_atomic, write_resolved_config
from .config import Fleet
from .dance_metrics import SceneDance, scene_dance
from .lockstep import FleetRecord, FleetRun
from .scene_file import FLEET_SCENE_FILE, fleet_scene_of, write_fleet_scene

Show = Callable[[float, float], None]


def world_columns(fleet: Fleet) -> list[str]:
    return ["time_s"] + [f"{n}_{c}" for n in fleet.names for c in ("x_m", "y_m", "yaw_rad", "speed_mps")]


def _status(record: FleetRecord | None) -> str:
    if record is None:
        return "running"
    if any(r.interrupted for r in record.records):
        return "interrupted"
    return "error" if any(r.error for r in record.records) else "complete"


def write_fleet_metrics(out_dir: Path, fleet: Fleet, record: FleetRecord | None, dance: SceneDance | None,
                        error: str | None = None) -> None:
    """``metrics.json`` of the scene (module docstring)."""
    vehicles = {}
    if record is not None:
        for name, r in zip(fleet.names, record.records):
            vehicles[name] = {"strategy": r.strategy, "status": r.status, "error": r.error,
                              **{k: v for k, v in r.metrics.as_dict().items() if k != "strategy"}}
    status = "error" if error else _status(record)
    write_json_atomic(out_dir / "metrics.json", {
        "fleet": fleet.fleet.name, "status": status, "error": error, "vehicles": vehicles,
        "dance": dance.as_dict() if dance is not None else None,
        "provenance": {"package_version": package_version(), "seed": fleet.fleet.seed}})


def _write_world(path: Path, fleet: Fleet, rows: Sequence[tuple[float, ...]]) -> None:
    with open(path, "w", newline="") as handle:
        out = csv.writer(handle)
        out.writerow(world_columns(fleet))
        out.writerows([repr(c) for c in row] for row in rows)


def run_fleet(fleet: Fleet, out_dir: Path | None, strategies: Mapping[str, str] | None = None,
              ecu: EcuOptions | None = None, can_logs: Sequence[str] = (),
              show: Show | None = None, fmu_paths: Mapping[str, Path] | None = None) -> tuple[FleetRecord, SceneDance]:
    """Run ``fleet`` and, with ``out_dir``, write every file of the module docstring (``fmu_paths``: vehicle ->
    plant FMU, default each vehicle's own, :func:`~cosim.loop.experiment.resolve_fmu`)."""
    logs = check_can_logs(can_logs)
    if out_dir is not None:
        check_out_dir(out_dir, fleet.names)
    paths = dict(fmu_paths) if fmu_paths else {v.name: resolve_fmu(v.scenario) for v in fleet.vehicles}
    run = FleetRun(fleet, paths, strategies, ecu)
    streams: list[RunStream] = []
    record = dance = None
    error = None
    try:
        if out_dir is not None:
            out_dir.mkdir(parents=True, exist_ok=True)
            write_fleet_metrics(out_dir, fleet, None, None)
            streams = [RunStream(out_dir / v.name, logs, v.scenario.scenario.start_datetime, loop.record.columns)
                       for v, loop in zip(fleet.vehicles, run.loops)]

        def tick(t_s: float, duration_s: float) -> None:
            for stream, loop in zip(streams, run.loops):
                stream.flush(loop.record)
            if show is not None:
                show(t_s, duration_s)

        record = run.run(tick)
        dance = scene_dance(fleet.names, record.records, record.world_rows, fleet.fleet)
    except BaseException as exc:
        error = str(exc) or type(exc).__name__
        raise
    finally:
        run.close()
        for stream, loop in zip(streams, run.loops):
            stream.close(loop.record)
        if out_dir is not None:
            _write_files(out_dir, fleet, run, record, dance, error)
    return record, dance


def _write_files(out_dir: Path, fleet: Fleet, run: FleetRun, record: FleetRecord | None,
                 dance: SceneDance | None, error: str | None) -> None:
    """Everything but the streamed files, on every way out (``metrics.json`` first)."""
    write_fleet_metrics(out_dir, fleet, record, dance, error)
    for v, loop in zip(fleet.vehicles, run.loops):
        write_events(out_dir / v.name / "events.json", loop.record)
    if record is not None:
        for v, r in zip(fleet.vehicles, record.records):
            write_resolved_config(out_dir / v.name / "config.resolved.toml", v.scenario,
                                  ecu_config(v.scenario, r.strategy), provenance(v.scenario, [r]))
    _write_world(out_dir / "world.csv", fleet, run.world_rows)
    write_fleet_scene(out_dir / FLEET_SCENE_FILE, fleet_scene_of(fleet))
    if record is not None and dance is not None:
        from .plots import speeds_plot
        from .report import write_fleet_report

        speeds_plot(out_dir / "speeds.png", fleet, record)
        write_fleet_report(out_dir / "report.md", fleet, dance)
