"""``crd matrix CATALOGUE... [--strategy S ...] [--phases N] [--out DIR] [--workers W]``.

Runs every cell of the catalogues (bundled names such as ``r152_m1``,
``ncap_ccr``, ``false_positive``, or TOML paths) for each strategy, at N
radar-update phases (the worst is scored), in a process pool; writes
``matrix.csv``, ``matrix.json``, ``report.md`` and plots under ``--out`` and
prints a summary. Exit status 3 when a requirement fails (an R152 limit, a
Euro NCAP avoidance requirement, a false-positive intervention, a standstill
behind a moving target), 1 on an error.
"""

from __future__ import annotations

import argparse
import sys
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

from ..matrix.catalogue import bundled, load_catalogue
from ..matrix.report import summary_lines, write_outputs
from ..matrix.runner import Job, run_matrix
from ..matrix.scoring import Outcome
from ..scenarios.config import PAPER_STRATEGIES, STRATEGIES

EXIT_REQUIREMENT_FAILED = 3


def add_subparser(subparsers: argparse._SubParsersAction) -> None:
    p = subparsers.add_parser("matrix", help="run protocol test catalogues (UN R152, Euro NCAP, false positives) "
                                             "and score them")
    p.add_argument("catalogues", nargs="+", metavar="CATALOGUE",
                   help=f"catalogue TOML file or bundled name ({', '.join(sorted(bundled()))})")
    p.add_argument("--strategy", action="append", choices=STRATEGIES,
                   help="strategy to run (repeat for several; default the paper's three)")
    p.add_argument("--phases", type=int, default=1, help="radar-update phases per cell; the worst is scored")
    p.add_argument("--workers", type=int, default=2, help="worker processes (default 2)")
    p.add_argument("--out", type=Path, default=Path("out/matrix"), help="output directory (default out/matrix)")
    p.set_defaults(func=_do_matrix)


def _progress(done: int, total: int, job: Job, out: Outcome) -> None:
    result = "error" if out.error else (f"hit {out.impact_kmh:.1f} km/h" if out.collided else
                                        f"no contact, {out.interventions} int.")
    print(f"[{done:>4}/{total}] {job.catalogue} {job.cell_id} {job.strategy} phase {job.phase}: {result}",
          file=sys.stderr, flush=True)


def _do_matrix(args: argparse.Namespace) -> int:
    if args.phases < 1 or args.workers < 1:
        raise ValueError(f"--phases and --workers: expected >= 1, got {args.phases} and {args.workers}")
    catalogues = [load_catalogue(c) for c in args.catalogues]
    strategies = args.strategy or list(PAPER_STRATEGIES)
    n_runs = sum(len(c.cells) for c in catalogues) * len(strategies) * args.phases
    print(f"crd matrix: {n_runs} runs on {args.workers} worker(s) -> {args.out}", file=sys.stderr)
    rows, wall_s = run_matrix(catalogues, strategies, args.phases, args.workers, _progress)
    try:
        pkg = version("crd")
    except PackageNotFoundError:
        pkg = "unknown"
    meta = {"strategies": strategies, "phases": args.phases, "workers": args.workers, "runs": n_runs,
            "wall_s": wall_s, "version": pkg, "catalogues": [c.path for c in catalogues]}
    report = write_outputs(args.out, catalogues, rows, meta)
    for line in summary_lines(catalogues, rows):
        print(line)
    print(f"{n_runs} runs in {wall_s:.1f} s on {args.workers} worker(s); report: {report}")
    return EXIT_REQUIREMENT_FAILED if any(not r["passed"] for r in rows) else 0
