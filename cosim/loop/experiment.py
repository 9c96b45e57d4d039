"""Runs of a scenario for one or more strategies, with all outputs written.

:func:`resolve_fmu` gives the plant FMU's path (``builtin`` builds ours on
first use via ``fmu_plant.build.ensure_fmu``); :func:`run_strategies` runs
each strategy and writes everything under ``out_dir``, ``report.md`` last;
:func:`check_verdicts` evaluates ``[checks]`` (:func:`check_run` lists the failed ones).
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Callable, Sequence

from ..link.ecu_link import EcuOptions
from ..errors import PlantError
from .master import Progress, ecu_config, run_scenario
from ..results import paper_claims
from ..results.can_logs import check_can_logs
from ..results.plots import speed_profiles, timeline
from ..results.report import Verdict, fmt, write_report
from ..results.writer import provenance, write_metrics, write_resolved_config, write_run
from ..results.run_record import RunRecord
from ..scenarios.config import Scenario

#: what a run is judged by in ``report.md``: (heading, verdicts) from the records
Judge = Callable[[Sequence[RunRecord]], tuple[str, list[Verdict]]]

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


def _check_one(scenario: Scenario, record: RunRecord) -> list[Verdict]:
    c, m, out = scenario.checks, record.metrics, []
    n = m.contingency_invocations
    if record.error:
        out.append(Verdict("run", False, f"run stopped on an error: {record.error}"))
    if c.no_collision is not None:
        out.append(Verdict("no_collision", c.no_collision != m.collided,
                           f"no_collision: expected collided = {not c.no_collision}, got {m.collided}"))
    if c.min_gap_m is not None:
        out.append(Verdict("min_gap_m", m.min_gap_m is not None and m.min_gap_m >= c.min_gap_m,
                           f"min_gap_m: expected >= {c.min_gap_m} m, got {fmt(m.min_gap_m, unit='m')}"))
    if c.max_impact_speed_mps is not None:
        out.append(Verdict("max_impact_speed_mps", not m.collided or m.impact_speed_mps <= c.max_impact_speed_mps,
                           f"max_impact_speed_mps: expected <= {c.max_impact_speed_mps},"
                           f" got {fmt(m.impact_speed_mps if m.collided else None)}"))
    if c.min_contingency_invocations is not None:
        out.append(Verdict("min_contingency_invocations", n >= c.min_contingency_invocations,
                           f"min_contingency_invocations: expected >= {c.min_contingency_invocations}, got {n}"))
    if c.max_contingency_invocations is not None:
        out.append(Verdict("max_contingency_invocations", n <= c.max_contingency_invocations,
                           f"max_contingency_invocations: expected <= {c.max_contingency_invocations}, got {n}"))
    return out


def check_verdicts(scenario: Scenario, records: Sequence[RunRecord]) -> tuple[str, list[Verdict]]:
    """Every ``[checks]`` expectation on every run, passed or not."""
    return "Checks", [Verdict(f"{v.label} ({r.strategy})", v.passed, v.detail)
                      for r in records for v in _check_one(scenario, r)]


def check_run(scenario: Scenario, record: RunRecord) -> list[str]:
    """Failed ``[checks]`` expectations of one run, as messages (empty when all hold)."""
    return [v.detail for v in _check_one(scenario, record) if not v.passed]


def run_strategies(scenario: Scenario, strategies: Sequence[str], out_dir: Path | None,
                   can_logs: Sequence[str] = (),
                   progress: Callable[[str], Progress] | None = None,
                   ecu: EcuOptions | None = None, judge: Judge | None = None) -> list[RunRecord]:
    """Run each strategy; with ``out_dir``, write metrics, logs, time series, config, plots and ``report.md``.

    ``can_logs``: CAN log files besides ``can.blf`` (checked before any run);
    ``ecu`` says where the ECU runs (default: in process; see :mod:`cosim.link.ecu_link`);
    ``judge`` gives the report's verdicts (default: the scenario's ``[checks]``).
    """
    logs = check_can_logs(can_logs)
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
            run_dir = write_run(out_dir, record, scenario.scenario.start_datetime, logs)
            timeline(run_dir / "timeline.png", record)
    if out_dir is not None:
        _write_summary(out_dir, scenario, records, judge or (lambda recs: check_verdicts(scenario, recs)))
    return records


def _write_summary(out_dir: Path, scenario: Scenario, records: list[RunRecord], judge: Judge) -> None:
    prov = provenance(scenario, records)
    write_metrics(out_dir / "metrics.json", records, prov)
    resolved = out_dir / "config.resolved.toml"
    write_resolved_config(resolved, scenario, ecu_config(scenario, records[0].strategy), prov)
    obj = scenario.object
    paper = set(paper_claims.REQUIRED) <= {r.strategy for r in records}
    speed_profiles(out_dir / "speed_profiles.png", records, obj.position_m if obj.enabled else None,
                   split_m=paper_claims.SPLIT_POSITION_M if paper else None)
    plots = [("speed against position", "speed_profiles.png")]
    plots += [(f"{r.strategy}: timeline", f"{r.strategy}/timeline.png") for r in records]
    try:
        verdicts = judge(records)
    except (KeyError, ValueError) as exc:  # e.g. a run that stopped on an error before its first sample
        verdicts = ("Verdicts", [Verdict("evaluation", False, f"could not be evaluated: {exc}")])
    title = f"crd report: {scenario.scenario.name} ({', '.join(r.strategy for r in records)})"
    write_report(out_dir / "report.md", title, records, verdicts, plots, resolved.read_text())
