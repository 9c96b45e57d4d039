"""The simulation runs behind the documentation's results, each made once per docgen invocation.

Every result the documentation shows comes from the code path a user runs:
``crd paper``'s runs (:func:`cosim.loop.experiment.run_strategies`), a bundled
sweep through ``crd sweep``'s session on a local Dask cluster
(:func:`cosim.sweep.session.run_sweep`), protocol catalogues through
``crd matrix``'s process pool (:func:`cosim.matrix.runner.run_matrix`). The
runs are deterministic (same result on one worker or many), so a table made
here is the table a user gets. Output files go to a temporary directory that
is removed at the end.
"""

from __future__ import annotations

import functools
import os
import shutil
import tempfile
from pathlib import Path
from typing import Any

WORKERS = max(1, min(2, os.cpu_count() or 1))  #: the CI machine's two cores


class Runs:
    """Lazily made, cached results; one instance per docgen invocation (use it as a context manager)."""

    def __init__(self, workers: int = WORKERS) -> None:
        self.workers = workers
        self._tmp: Path | None = None

    def __enter__(self) -> Runs:
        return self

    def __exit__(self, *exc: object) -> None:
        if self._tmp is not None:
            shutil.rmtree(self._tmp, ignore_errors=True)

    def _dir(self, name: str) -> Path:
        if self._tmp is None:
            self._tmp = Path(tempfile.mkdtemp(prefix="crd-docgen-"))
        return self._tmp / name

    @functools.cache
    def paper(self, with_adaptive: bool = False) -> list:
        """``crd paper``'s records (the three strategies, and ``adaptive`` if asked), on its scenario."""
        from cosim.cli.paper import PAPER_SCENARIO
        from cosim.loop.experiment import run_strategies
        from cosim.results.paper_claims import REQUIRED, verdicts
        from cosim.scenarios.loader import load_scenario

        strategies = list(REQUIRED) + (["adaptive"] if with_adaptive else [])
        return run_strategies(load_scenario(PAPER_SCENARIO), strategies, self._dir(f"paper-{with_adaptive}"),
                              judge=verdicts, concurrent=True)

    @functools.cache
    def sweep(self, name: str) -> tuple[list[dict[str, Any]], dict[str, Any]]:
        """The rows and metadata of a bundled sweep, run as ``crd sweep NAME --workers N`` runs it."""
        from cosim.sweep.runner import ClusterOptions
        from cosim.sweep.session import run_sweep
        from cosim.sweep.spec import load_sweep
        from cosim.sweep.table import RESULTS_NAME, read_results

        out = self._dir(f"sweep-{name}")
        run_sweep(load_sweep(name), out, ClusterOptions(workers=self.workers, dashboard=False), report=False)
        table, meta = read_results(out / RESULTS_NAME)
        return table.to_pylist(), meta

    @functools.cache
    def matrix(self, names: tuple[str, ...], strategies: tuple[str, ...]) -> tuple[list, list[dict[str, Any]]]:
        """The catalogues and their scored rows, as ``crd matrix NAMES --strategy S ...`` makes them (1 phase)."""
        from cosim.matrix.catalogue import load_catalogue
        from cosim.matrix.runner import run_matrix

        catalogues = [load_catalogue(n) for n in names]
        rows, _wall_s = run_matrix(catalogues, list(strategies), phases=1, workers=self.workers)
        return catalogues, rows

    @functools.cache
    def scenario(self, key: tuple) -> Any:
        """One closed-loop run: ``key`` is ``(builder, args..., strategy)``; the builder makes the scenario."""
        from cosim.loop.experiment import resolve_fmu
        from cosim.loop.master import run_scenario

        builder, *args, strategy = key
        scenario = builder(*args)
        return run_scenario(scenario, resolve_fmu(scenario), strategy)
