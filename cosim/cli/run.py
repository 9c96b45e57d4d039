"""``crd run SCENARIO [--strategy S] [--out DIR] [--can-log NAME ...]``: one scenario.

``SCENARIO`` is a TOML file or the name of a bundled scenario (``crd scenarios``).
``--can-log`` adds a CAN log besides ``can.blf`` and may be given several times
(``.blf``, ``.asc``, ``.mf4``, ...; checked before the run starts). Writes
``report.md`` with the table, the checks, the plots and the resolved configuration.

Exit status 0 when every ``[checks]`` expectation holds, 3 when one fails
(each printed), 4 when frames failed SecOC authentication or a foreign
``SafetyOverride`` was seen (``auth_failure``/``ecu_security_fault`` events), 1 on an error (bad scenario, missing/broken FMU, FMI error:
results up to the error are still written).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..loop.experiment import check_run, run_strategies
from ..results.can_logs import LOG_FORMATS
from ..scenarios.config import STRATEGIES
from ..scenarios.loader import load_scenario
from .ecu_options import add_ecu_arguments, ecu_options, security_exit, timing_lines
from .progress import end_progress, progress_printer, results_table
from .scenarios import find_scenario

EXIT_CHECK_FAILED = 3


def add_subparser(subparsers: argparse._SubParsersAction) -> None:
    p = subparsers.add_parser("run", help="run one closed-loop scenario (plant FMU + CAN + ECU)")
    p.add_argument("scenario", help="scenario TOML file, or the name of a bundled one (crd scenarios)")
    p.add_argument("--strategy", choices=STRATEGIES, help="override the scenario's [ecu] strategy")
    p.add_argument("--out", type=Path, default=Path("out/run"), help="output directory (default out/run)")
    p.add_argument("--can-log", action="append", default=[], metavar="NAME",
                   help="another CAN log besides can.blf; repeatable; the suffix picks the format"
                        f" ({', '.join(LOG_FORMATS)}; .mf4 needs crd[mdf])")
    add_ecu_arguments(p, realtime=True)
    p.set_defaults(func=_do_run)


def _do_run(args: argparse.Namespace) -> int:
    path = find_scenario(args.scenario)
    scenario = load_scenario(path)
    strategy = args.strategy or scenario.ecu.strategy
    print(f"crd run {path} (strategy {strategy}) -> {args.out}", file=sys.stderr)
    records = run_strategies(scenario, [strategy], args.out, args.can_log, progress=progress_printer,
                              ecu=ecu_options(args))
    end_progress()
    print(results_table(records))
    for line in timing_lines(records):
        print(line)
    record = records[0]
    if record.error:
        raise RuntimeError(f"{record.error} (results up to then written to {args.out})")
    failed = check_run(scenario, record)
    for message in failed:
        print(f"CHECK FAILED: {message}")
    print(f"report: {args.out / 'report.md'}")
    return EXIT_CHECK_FAILED if failed else security_exit(records)
