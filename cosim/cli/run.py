"""``crd run SCENARIO [--strategy S] [--out DIR] [--can-log NAME ...]``: one scenario.

``SCENARIO`` is a TOML file, an OpenSCENARIO ``.xosc`` file (``--ego NAME`` picks
the equipped car; docs/openscenario.md) or the name of a bundled scenario (``crd scenarios``).
``--can-log`` adds a CAN log besides ``can.blf`` and may be given several times
(``.blf``, ``.asc``, ``.mf4``, ...; checked before the run starts). Writes
``report.md`` with the table, the checks, the plots and the resolved configuration.
``--video`` adds the bird's-eye video ``<strategy>/birdseye.mp4`` (``crd animate``'s, drawn from the run's
files); a planar run's ``birdseye.png`` is drawn with or without it.

Exit status:

* 0: every ``[checks]`` expectation holds and no fault event occurred;
* 1: an error (bad scenario, unwritable ``--out``, missing/broken FMU, FMI
  error, NaN output, a lock-step ECU stalled past ``--stall-timeout``; for an
  error during the run the results up to it are written);
* 3: a ``[checks]`` expectation failed (each printed);
* 4: a fault event occurred that ``[checks] expect_events`` does not list:
  ``ecu_lost``, ``second_ecu``, ``auth_failure`` or ``ecu_security_fault``
  (each printed as ``FAULT: ...``);
* 130 / 143: interrupted by SIGINT / SIGTERM; the results so far are written
  and ``metrics.json`` says ``interrupted``.

The output directory is checked before the run; the time series and the CAN
log are written while the run goes, ``metrics.json`` on every way out.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..loop.experiment import check_run, run_strategies
from ..results.can_logs import LOG_FORMATS
from ..scenarios.config import STRATEGIES
from ..scenarios.formats import read_scenario
from .ecu_options import add_ecu_arguments, ecu_options, timing_lines
from .export import add_record_option, check_record, record_run
from .progress import end_progress, progress_printer, results_table
from .signals import interruptible
from ..results.events import EXIT_FAULT_EVENT, unexpected_faults
from .animate import write_video
from .scenarios import find_scenario

EXIT_CHECK_FAILED = 3


def add_subparser(subparsers: argparse._SubParsersAction) -> None:
    p = subparsers.add_parser("run", help="run one closed-loop scenario (plant FMU + CAN + ECU)")
    p.add_argument("scenario", help="scenario TOML or OpenSCENARIO .xosc file, or the name of a bundled one "
                                    "(crd scenarios)")
    p.add_argument("--ego", metavar="NAME", help=".xosc: the entity that is the equipped car (default Ego/hero)")
    p.add_argument("--strategy", choices=STRATEGIES, help="override the scenario's [ecu] strategy")
    p.add_argument("--out", type=Path, default=Path("out/run"), help="output directory (default out/run)")
    p.add_argument("--can-log", action="append", default=[], metavar="NAME",
                   help="another CAN log besides can.blf; repeatable; the suffix picks the format"
                        f" ({', '.join(LOG_FORMATS)}; .mf4 needs crd[mdf])")
    p.add_argument("--video", action="store_true",
                   help="also write the bird's-eye video <strategy>/birdseye.mp4 (as crd animate does)")
    add_ecu_arguments(p, realtime=True)
    add_record_option(p)
    p.set_defaults(func=interruptible(_do_run))


def _do_run(args: argparse.Namespace) -> int:
    path = find_scenario(args.scenario)
    scenario = read_scenario(path, args.ego)
    strategy = args.strategy or scenario.ecu.strategy
    check_record(args)
    print(f"crd run {path} (strategy {strategy}) -> {args.out}", file=sys.stderr)
    records = run_strategies(scenario, [strategy], args.out, args.can_log, progress=progress_printer,
                              ecu=ecu_options(args))
    end_progress()
    record_run(args)
    print(results_table(records))
    for line in timing_lines(records):
        print(line)
    record = records[0]
    if record.error:
        raise RuntimeError(f"{record.error} (results up to then written to {args.out})")
    failed = check_run(scenario, record)
    for message in failed:
        print(f"CHECK FAILED: {message}")
    faults = unexpected_faults(records, scenario.checks.expect_events)
    for line in faults:
        print(f"FAULT: {line}")
    if args.video:
        for line in write_video(args.out, [strategy]):
            print(line)
    print(f"report: {args.out / 'report.md'}")
    return EXIT_CHECK_FAILED if failed else (EXIT_FAULT_EVENT if faults else 0)
