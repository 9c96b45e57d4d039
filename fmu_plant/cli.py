"""``crd fmu``: build the vehicle plant FMU and print its path."""

from __future__ import annotations

import argparse
from pathlib import Path


def add_subparser(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("fmu", help="build the vehicle plant FMU")
    actions = parser.add_subparsers(dest="fmu_command", metavar="ACTION")
    actions.required = True
    build = actions.add_parser("build", help="build an FMI 2.0 or 3.0 co-simulation FMU from source")
    build.add_argument("--fmi-version", type=int, choices=(2, 3), default=2, help="FMI version (default 2)")
    build.add_argument("--out", type=Path, default=None,
                       help="write the FMU here (default: the source-hash cache in fmu_plant/_build/)")
    parser.set_defaults(func=_do_fmu)


def _do_fmu(args: argparse.Namespace) -> int:
    from fmu_plant.build import build_fmu, ensure_fmu  # deferred: keeps `crd --help` light

    if args.out is None:
        path = ensure_fmu(fmi_version=args.fmi_version)
    else:
        path = build_fmu(args.fmi_version, args.out)
    print(path)
    return 0
