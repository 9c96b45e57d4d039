"""Runs of a scenario for one or more strategies, with all outputs written.

:func:`resolve_fmu` gives the plant FMU's path (``builtin`` builds ours on
first use via ``fmu_plant.build.ensure_fmu``); :func:`run_strategies` runs
each strategy and writes everything under ``out_dir``, ``report.md`` last;
:func:`check_verdicts` evaluates ``[checks]`` (:func:`check_run` lists the failed ones).

Results survive (issue 15): ``out_dir`` is checked before anything runs, each
run's time series and CAN logs are streamed (:class:`cosim.results.stream.RunStream`),
and ``metrics.json`` (with each run's status) is written before the first
run, after each, and on every way out, including SIGINT/SIGTERM.
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import logging
import signal
import threading
from concurrent.futures import Future
from pathlib import Path
from typing import Callable, Sequence

from ..link.ecu_link import EcuOptions
from ..errors import PlantError, RunInterrupted
from .concurrent import cores, run_concurrently
from .plot_process import PlotProcess
from .master import ClosedLoop, Progress, ecu_config
from ..results import paper_claims
from ..results.can_logs import check_can_logs
from ..results.plots import preload_matplotlib, speed_profiles, timeline
from ..results.report import Verdict, fmt, write_report
from ..results.stream import RunStream, check_out_dir
from ..results.writer import provenance, write_events, write_metrics, write_resolved_config
from ..results.run_record import RunRecord, timeseries_columns
from ..scenarios.config import Scenario
from ..world.plant import isolation_of
from ..world.fmu_share import fmu_shared

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
    for kind in c.expect_events:
        seen = any(e.kind == kind for e in record.events)
        out.append(Verdict(f"expect_events {kind}", seen,
                           f"expect_events: expected {kind}, " + ("it occurred" if seen else "which did not occur")))
    return out


def check_verdicts(scenario: Scenario, records: Sequence[RunRecord]) -> tuple[str, list[Verdict]]:
    """Every ``[checks]`` expectation on every run, passed or not."""
    return "Checks", [Verdict(f"{v.label} ({r.strategy})", v.passed, v.detail)
                      for r in records for v in _check_one(scenario, r)]


def check_run(scenario: Scenario, record: RunRecord) -> list[str]:
    """Failed ``[checks]`` expectations of one run, as messages (empty when all hold)."""
    return [v.detail for v in _check_one(scenario, record) if not v.passed]


def run_strategies(scenario: Scenario, strategies: Sequence[str], out_dir: Path | None,
                   can_logs: Sequence[str] = (), progress: Callable[[str], Progress] | None = None,
                   ecu: EcuOptions | None = None, judge: Judge | None = None,
                   concurrent: bool = False) -> list[RunRecord]:
    """Run each strategy; with ``out_dir``, write metrics, logs, time series, config, plots and ``report.md``.

    With ``out_dir``: the directory is checked before anything runs, the files are written
    as the run goes, and ``metrics.json`` on every way out (module docstring). A run ended
    by SIGINT/SIGTERM stops the series (concurrent: every run): its results are written, then
    :class:`~cosim.errors.RunInterrupted` is raised on.
    ``can_logs``: CAN log files besides ``can.blf`` (checked before any run);
    ``ecu`` says where the ECU runs (default: in process; see :mod:`cosim.link.ecu_link`);
    ``judge`` gives the report's verdicts (default: the scenario's ``[checks]``);
    ``concurrent``: side by side in worker processes (:mod:`cosim.loop.concurrent`) when
    there are several runs, each ECU in process and more than one core.
    """
    logs, fmu_path = _preflight(scenario, strategies, out_dir, can_logs)
    records: list[RunRecord] = []
    status, error, profiles_drawn = "running", None, False
    try:
        if out_dir is not None:
            _start_dir(out_dir, scenario)
        run = functools.partial(_run_one, scenario, fmu_path, out_dir=out_dir, logs=logs, progress=progress, ecu=ecu)
        series = _series(concurrent, strategies, ecu, fmu_path)
        profiles_drawn = series(scenario, strategies, run, records, out_dir)
        status = _series_status(records)
    except KeyboardInterrupt as exc:
        status, error = "interrupted", str(exc)
        raise
    except BaseException as exc:
        status, error = "error", str(exc)
        raise
    finally:
        if out_dir is not None:
            _write_summary(out_dir, scenario, records, judge or (lambda recs: check_verdicts(scenario, recs)),
                           status, error, profiles_drawn)
    if status == "interrupted":
        raise _interrupted(next(r for r in records if r.interrupted), out_dir)
    return records


def _start_dir(out_dir: Path, scenario: Scenario) -> None:
    """The run directory before the first run: ``metrics.json`` (running, no runs yet) and, for a planar
    scenario, ``scene.json``, the bird's-eye view's static part (docs/run-format.md)."""
    out_dir.mkdir(parents=True, exist_ok=True)
    write_metrics(out_dir / "metrics.json", [], provenance(scenario, []), "running")
    if scenario.planar:  # the planar modules imported here: a 1-D run (crd paper) needs none of them
        from ..results.run_view import SCENE_FILE
        from ..results.scene_file import scene_of, write_scene

        write_scene(out_dir / SCENE_FILE, scene_of(scenario))


def _series_status(records: Sequence[RunRecord]) -> str:
    """``interrupted`` if a run was, else ``error`` if a run failed, else ``complete``."""
    if any(r.interrupted for r in records):
        return "interrupted"
    return "error" if any(r.error for r in records) else "complete"


def _run_in_turn(scenario: Scenario, strategies: Sequence[str], run: Callable[..., RunRecord],
                 records: list[RunRecord], out_dir: Path | None) -> bool:
    """One run after the other; stops after a run ended by a signal. ``speed_profiles.png`` is left to the
    summary (False)."""
    for i, strategy in enumerate(strategies):
        record = run(strategy, last=i == len(strategies) - 1)
        records.append(record)
        if record.interrupted:
            break
        if out_dir is not None:
            write_metrics(out_dir / "metrics.json", records, provenance(scenario, records), "running")
    return False


def _series(concurrent: bool, strategies: Sequence[str], ecu: EcuOptions | None,
            fmu_path: Path) -> Callable[..., bool]:
    """Side by side (:func:`_run_concurrently`) when ``concurrent`` and :func:`_can_run_concurrently`,
    else one after the other (:func:`_run_in_turn`)."""
    if concurrent and _can_run_concurrently(strategies, ecu):
        return functools.partial(_run_concurrently, fmu_path=fmu_path)
    return _run_in_turn


def _can_run_concurrently(strategies: Sequence[str], ecu: EcuOptions | None) -> bool:
    """Several runs, more than one core, each run's ECU in its own process's memory, and no other
    thread here (a fork copies only the calling thread: a lock another one holds would stay held)."""
    in_process = ecu is None or (ecu.mode == "inprocess" and not ecu.realtime)
    return len(strategies) > 1 and cores() > 1 and in_process and threading.active_count() == 1


def _run_concurrently(scenario: Scenario, strategies: Sequence[str], run: Callable[..., RunRecord],
                      records: list[RunRecord], out_dir: Path | None, fmu_path: Path) -> bool:
    """The runs in worker processes (:func:`cosim.loop.concurrent.run_concurrently`); here, matplotlib imported
    while the first runs go, then each run's timeline and ``metrics.json`` as its record comes in. When every
    record is in, ``speed_profiles.png`` is drawn in a :class:`~cosim.loop.plot_process.PlotProcess` beside the
    last timeline (True: drawn). A plant in this process is prepared once
    (:func:`~cosim.world.fmu_share.fmu_shared`: hashed, parsed, extracted), and every worker inherits it."""
    job = functools.partial(_frames_on_disk, run) if out_dir is not None else functools.partial(run, plot=False)
    shared = fmu_shared(fmu_path) if isolation_of(scenario.plant) == "inprocess" else contextlib.nullcontext()
    if out_dir is None:
        with shared:
            run_concurrently(strategies, job, records, lambda record, done: None, jobs=cores())
        return False
    profiles: list[Future] = []

    def on_record(record: RunRecord, done: list[RunRecord]) -> None:
        if len(done) == len(strategies):  # the last record: every run's figure there, this timeline here
            profiles.append(plots.submit(speed_profiles, *_speed_profiles_args(out_dir, scenario, done)))
        timeline(out_dir / record.strategy / "timeline.png", record)
        write_metrics(out_dir / "metrics.json", done, provenance(scenario, done), "running")

    def meanwhile() -> None:
        preload_matplotlib()
        plots.start()

    with shared, PlotProcess() as plots:
        run_concurrently(strategies, job, records, on_record, jobs=cores(), meanwhile=meanwhile)
        for future in profiles:
            future.result()
    return bool(profiles)


def _frames_on_disk(run: Callable[..., RunRecord], strategy: str) -> RunRecord:
    """A run in a worker, its record sent back without the frame log: the frames are on disk (``can.blf``),
    and pickling 26,000 frames per run would cost more CPU than a plot."""
    record = run(strategy, plot=False)
    record.frames = []
    return record


def _speed_profiles_args(out_dir: Path, scenario: Scenario, records: Sequence[RunRecord]) -> tuple:
    """The arguments of :func:`~cosim.results.plots.speed_profiles` for ``speed_profiles.png``: every run's
    speed against position (claim 4's split marked for the paper's runs)."""
    obj = scenario.object
    paper = set(paper_claims.REQUIRED) <= {r.strategy for r in records}
    return (out_dir / "speed_profiles.png", records, obj.position_m if obj.enabled else None,
            paper_claims.SPLIT_POSITION_M if paper else None, obj.name)


def _preflight(scenario: Scenario, strategies: Sequence[str], out_dir: Path | None,
               can_logs: Sequence[str]) -> tuple:
    """Everything that can fail before a run, checked before the first one: logs, ``out_dir``, FMU, ``[ecu]``."""
    logs = check_can_logs(can_logs)
    if out_dir is not None:
        check_out_dir(out_dir, strategies)
    fmu_path = resolve_fmu(scenario)
    for strategy in strategies:
        ecu_config(scenario, strategy)
    return logs, fmu_path


def _interrupted(record: RunRecord, out_dir: Path | None) -> RunInterrupted:
    """The interrupt a run recorded, raised on to the CLI (which exits 128 + signal)."""
    where = f"; results so far in {out_dir}" if out_dir is not None else ""
    return RunInterrupted(signal.Signals[record.interrupted], f"{record.strategy} interrupted by "
                          f"{record.interrupted} at t = {record.metrics.sim_time_s:.2f} s{where}")


def _run_one(scenario: Scenario, fmu_path: Path, strategy: str, out_dir: Path | None, logs: Sequence[str],
             progress: Callable[[str], Progress] | None, ecu: EcuOptions | None, plot: bool = True,
             last: bool = False) -> RunRecord:
    """One strategy's run, its files streamed under ``out_dir/<strategy>/`` as it goes (``plot``: and its
    timeline; ``last``: no run follows it, so a spawned ECU gets no spare for the next one)."""
    if last and ecu is not None and ecu.spare:
        ecu = dataclasses.replace(ecu, spare=False)
    show = progress(strategy) if progress else None
    stream = RunStream(out_dir / strategy, logs, scenario.scenario.start_datetime, timeseries_columns(scenario)) \
        if out_dir is not None else None
    loop: ClosedLoop | None = None
    try:
        loop = ClosedLoop(scenario, fmu_path, strategy, ecu=ecu)

        def tick(t_s: float, duration_s: float) -> None:  # every 100 ECU cycles
            if stream is not None:
                stream.flush(loop.record)
            if show is not None:
                show(t_s, duration_s)

        record = loop.run(tick)
    finally:
        if stream is not None:
            stream.close(loop.record if loop is not None else None)
    if show is not None:
        show(record.metrics.sim_time_s, record.metrics.sim_time_s)  # final line
    if out_dir is not None:
        write_events(out_dir / strategy / "events.json", record)
        if plot:
            timeline(out_dir / strategy / "timeline.png", record)
    return record


def _write_summary(out_dir: Path, scenario: Scenario, records: list[RunRecord], judge: Judge, status: str,
                   error: str | None, profiles_drawn: bool = False) -> None:
    """``metrics.json`` first (the one file every way out must leave), then the config, plots and report
    (``profiles_drawn``: ``speed_profiles.png`` is there already)."""
    prov = provenance(scenario, records)
    write_metrics(out_dir / "metrics.json", records, prov, status, error)
    if not records:
        return
    try:
        _write_report(out_dir, scenario, records, judge, prov, profiles_drawn)
    except Exception as exc:  # noqa: BLE001 - on the way out of a failed run, never mask its error
        if status == "complete":
            raise
        log.warning("could not write the summary files after the run stopped (%s): %s", status, exc)


def _write_report(out_dir: Path, scenario: Scenario, records: list[RunRecord], judge: Judge, prov: dict,
                  profiles_drawn: bool) -> None:
    """``config.resolved.toml``, ``speed_profiles.png`` (unless drawn) and ``report.md``."""
    resolved = out_dir / "config.resolved.toml"
    write_resolved_config(resolved, scenario, ecu_config(scenario, records[0].strategy), prov)
    if not profiles_drawn:
        speed_profiles(*_speed_profiles_args(out_dir, scenario, records))
    plots = [("speed against position", "speed_profiles.png")]
    plots += [(f"{r.strategy}: timeline", f"{r.strategy}/timeline.png") for r in records]
    if scenario.planar:
        from ..results.birdseye import plot_run

        plots += plot_run(out_dir, [r.strategy for r in records if (out_dir / r.strategy / "timeseries.csv").is_file()])
    try:
        verdicts = judge(records)
    except (KeyError, ValueError) as exc:  # e.g. a run that stopped on an error before its first sample
        verdicts = ("Verdicts", [Verdict("evaluation", False, f"could not be evaluated: {exc}")])
    title = f"crd report: {scenario.scenario.name} ({', '.join(r.strategy for r in records)})"
    write_report(out_dir / "report.md", title, records, verdicts, plots, resolved.read_text())
