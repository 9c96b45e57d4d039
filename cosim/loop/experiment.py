"""Runs of a scenario for one or more strategies, with all outputs written.

:func:`resolve_fmu` gives the plant FMU's path (``builtin`` builds ours on
first use via ``fmu_plant.build.ensure_fmu``); :func:`run_strategies` runs
each strategy and writes everything under ``out_dir``; :func:`check_run`
evaluates ``[checks]``.
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Callable, Sequence

from ..link.ecu_link import EcuOptions
from ..errors import PlantError
from .master import Progress, ecu_config, run_scenario
from ..results.plots import speed_profiles, timeline
from ..results.writer import provenance, write_metrics, write_resolved_config, write_run
from ..results.run_record import RunRecord
from ..scenarios.config import Scenario

log = logging.getLogger(__name__)


def resolve_fmu(scenario: Scenario) -> Path:
    """Path of the plant FMU; the builtin plant is built and cached on first use."""
    if scenario.plant.fmu == "builtin":
        from fmu_plant.build import ensure_fmu

        try:
            return Path(ensure_fmu(fmi_version=scenario.plant.fmi_version))
        except Exception as exc:  # noqa: BLE001 - a failed build is one plant error
            raise PlantError(f"cannot build the builtin plant FMU (FMI {scenario.plant.fmi_version}): {exc}") from exc
    path = Path(scenario.plant.fmu)
    if not path.is_file():
        raise PlantError(f"plant.fmu: expected an FMU file, got {str(path)!r} (not found)")
    return path


def check_run(scenario: Scenario, record: RunRecord) -> list[str]:
    """Failed ``[checks]`` expectations of one run, as messages (empty when all hold)."""
    c, m, failed = scenario.checks, record.metrics, []
    if record.error:
        failed.append(f"run stopped on an error: {record.error}")
    if c.no_collision is not None and c.no_collision == m.collided:
        failed.append(f"no_collision: expected collided = {not c.no_collision}, got {m.collided}")
    if c.min_gap_m is not None and (m.min_gap_m is None or m.min_gap_m < c.min_gap_m):
        failed.append(f"min_gap_m: expected >= {c.min_gap_m} m, got {m.min_gap_m}")
    if c.max_impact_speed_mps is not None and m.collided and m.impact_speed_mps > c.max_impact_speed_mps:
        failed.append(f"max_impact_speed_mps: expected <= {c.max_impact_speed_mps}, got {m.impact_speed_mps:.3f}")
    n = m.contingency_invocations
    if c.min_contingency_invocations is not None and n < c.min_contingency_invocations:
        failed.append(f"min_contingency_invocations: expected >= {c.min_contingency_invocations}, got {n}")
    if c.max_contingency_invocations is not None and n > c.max_contingency_invocations:
        failed.append(f"max_contingency_invocations: expected <= {c.max_contingency_invocations}, got {n}")
    return failed


def run_strategies(scenario: Scenario, strategies: Sequence[str], out_dir: Path | None,
                   can_log_name: str = "can.blf",
                   progress: Callable[[str], Progress] | None = None,
                   ecu: EcuOptions | None = None) -> list[RunRecord]:
    """Run each strategy; with ``out_dir``, write metrics, logs, time series, config and plots.

    ``ecu`` says where the ECU runs (default: in process); see :mod:`cosim.link.ecu_link`.
    """
    fmu_path = resolve_fmu(scenario)
    for strategy in strategies:  # fail fast on a bad [ecu] before any run
        ecu_config(scenario, strategy)
    records = []
    for strategy in strategies:
        show = progress(strategy) if progress else None
        record = run_scenario(scenario, fmu_path, strategy, show, ecu=ecu)
        if show is not None:
            show(record.metrics.sim_time_s, record.metrics.sim_time_s)  # final line
        records.append(record)
        if out_dir is not None:
            run_dir = write_run(out_dir, record, can_log_name)
            timeline(run_dir / "timeline.png", record)
    if out_dir is not None:
        prov = provenance(scenario, records)
        write_metrics(out_dir / "metrics.json", records, prov)
        write_resolved_config(out_dir / "config.resolved.toml", scenario, ecu_config(scenario, strategies[0]), prov)
        obj = scenario.object
        speed_profiles(out_dir / "speed_profiles.png", records, obj.position_m if obj.enabled else None)
    return records
