"""Run every cell x strategy x radar phase of some catalogues in a process pool, and score them.

Jobs are plain data (a scenario mapping, a strategy, the FMU path), so the
pool is interchangeable: here a :class:`concurrent.futures.ProcessPoolExecutor`
(2 workers by default, one per core of the reference machine); the catalogue
format does not depend on it. Each worker runs the closed loop in process
(ECU on a virtual bus) and returns an :class:`~cosim.matrix.scoring.Outcome`.
"""

from __future__ import annotations

import logging
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any, Callable, Sequence

from ..loop.experiment import resolve_fmu
from ..loop.master import run_scenario
from ..scenarios.config import Scenario
from ..scenarios.loader import scenario_from_dict
from .planar_outcome import planar_outcome
from .catalogue import Catalogue, Cell
from .scoring import RESTRICTING_MODES, Outcome, interventions, worst
from .scorings import score_cell, scoring_named

log = logging.getLogger(__name__)
KMH = 3.6

#: progress(done, total, job, outcome)
Progress = Callable[[int, int, "Job", Outcome], None]


@dataclass(frozen=True)
class Job:
    """One closed-loop run: which cell, strategy and phase, and the scenario as plain data."""

    catalogue: str
    cell_id: str
    strategy: str
    phase: int
    scenario: dict
    fmu_path: str


def outcome_of(record, scenario: Scenario | None = None) -> Outcome:
    """Summarise a run record (see :class:`Outcome`); with its ``scenario``, a planar run's additions too."""
    m = record.metrics
    modes, speeds = record.column("ecu_mode"), record.column("speed_mps")
    low = _low_speed_while_intervening(modes, speeds)
    impact = (m.impact_speed_mps or 0.0) * KMH if m.collided else 0.0
    planar = planar_outcome(record, scenario) if scenario is not None else None
    return Outcome(m.collided, impact, interventions(modes), low, m.min_gap_m, m.end_reason,
                   m.sim_time_s, m.wall_time_s, record.error, planar)


def _low_speed_while_intervening(modes: list, speeds: list, after_cycles: int = 100) -> float | None:
    """Lowest speed (m/s) from the first intervention until ``after_cycles`` (1 s) after the last.

    The second bound leaves out what the driver does later (the Euro NCAP robot has lifted off
    the accelerator for good and the car coasts down); brake pressure has decayed within 0.5 s.
    """
    hits = [i for i, mode in enumerate(modes) if mode in RESTRICTING_MODES]
    return min(speeds[hits[0]:hits[-1] + after_cycles + 1]) if hits else None


def run_job(job: Job) -> Outcome:
    """Run one job (in a worker process)."""
    try:
        scenario = scenario_from_dict(job.scenario)
        record = run_scenario(scenario, Path(job.fmu_path), job.strategy)
    except Exception as exc:  # noqa: BLE001 - one broken cell must not stop the matrix
        log.error("%s %s phase %d: %s", job.cell_id, job.strategy, job.phase, exc)
        return Outcome(False, 0.0, 0, None, None, None, 0.0, 0.0, f"{type(exc).__name__}: {exc}")
    return outcome_of(record, scenario)


def jobs_for(catalogues: Sequence[Catalogue], strategies: Sequence[str], phases: int) -> list[Job]:
    """Every (cell, strategy, phase) job; the FMU is built once here, before any worker starts."""
    fmu: Path | None = None
    jobs = []
    for cat in catalogues:
        for cell in cat.cells:
            for phase in range(phases):
                data = cell.scenario_dict(phase, phases)
                if fmu is None:
                    fmu = resolve_fmu(scenario_from_dict(data))
                jobs.extend(Job(cat.name, cell.cell_id, s, phase, data, str(fmu)) for s in strategies)
    return jobs


def run_jobs(jobs: Sequence[Job], workers: int = 2, progress: Progress | None = None) -> dict[tuple, Outcome]:
    """Outcomes keyed by (catalogue, cell, strategy, phase); ``workers=1`` runs in this process."""
    results: dict[tuple, Outcome] = {}
    key = lambda j: (j.catalogue, j.cell_id, j.strategy, j.phase)  # noqa: E731
    if workers <= 1:
        for n, job in enumerate(jobs, 1):
            results[key(job)] = out = run_job(job)
            if progress:
                progress(n, len(jobs), job, out)
        return results
    with ProcessPoolExecutor(max_workers=workers) as pool:
        futures = {pool.submit(run_job, job): job for job in jobs}
        for n, fut in enumerate(as_completed(futures), 1):
            job = futures[fut]
            results[key(job)] = out = fut.result()
            if progress:
                progress(n, len(jobs), job, out)
    return results


def score_rows(catalogues: Sequence[Catalogue], strategies: Sequence[str], phases: int,
               results: dict[tuple, Outcome]) -> list[dict[str, Any]]:
    """One row per cell and strategy: the worst phase's outcome and the protocol's verdict."""
    rows = []
    for cat in catalogues:
        for cell in cat.cells:
            for strategy in strategies:
                per_phase = [results[(cat.name, cell.cell_id, strategy, p)] for p in range(phases)]
                rows.append(_row(cat, cell, strategy, per_phase))
    return rows


def _row(cat: Catalogue, cell: Cell, strategy: str, per_phase: list[Outcome]) -> dict[str, Any]:
    w = worst(per_phase)
    row = {"catalogue": cat.name, "scoring": cat.scoring, "cell": cell.cell_id, "group": cell.group,
           "test_speed_kmh": cell.ego_speed_kmh, "target_speed_kmh": float(cell.get("target_speed_kmh")),
           "road_friction": float(cell.get("road_friction")), "strategy": strategy,
           "phases": len(per_phase), "impact_kmh_by_phase": [round(o.impact_kmh, 3) for o in per_phase]}
    row.update({k: v for k, v in asdict(w).items() if k not in ("wall_time_s", "planar")})
    if w.planar is not None:  # a planar cell: what it touched, how far it left the road, its thumbnail's trace
        row.update(hit_object=w.planar.hit_object, road_departure_m=w.planar.road_departure_m,
                   trace=w.planar.trace)
    row["wall_time_s"] = sum(o.wall_time_s for o in per_phase)
    row.update(scoring_named(cat.scoring).row_fields(cell.params))
    row.update(score_cell(cat.scoring, cell.params, w))
    return row


def run_matrix(catalogues: Sequence[Catalogue], strategies: Sequence[str], phases: int = 1,
               workers: int = 2, progress: Progress | None = None) -> tuple[list[dict[str, Any]], float]:
    """Run and score everything; returns the rows and the wall time (s) of the runs."""
    t0 = time.perf_counter()
    jobs = jobs_for(catalogues, strategies, phases)
    results = run_jobs(jobs, workers, progress)
    return score_rows(catalogues, strategies, phases, results), time.perf_counter() - t0
