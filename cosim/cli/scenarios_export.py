"""``crd scenarios export SCENARIO --format xosc|toml [--out DIR] [--ego NAME]``.

Writes a scenario (a bundled name, a TOML or an ``.xosc`` file) in another
format, from a table of writers: ``xosc`` writes ``NAME.xosc`` and ``NAME.xodr``
(OpenSCENARIO 1.2 and OpenDRIVE, built with scenariogeneration; reading them
back gives the same scenario, docs/openscenario.md), ``toml`` the resolved
scenario file. Prints the paths written.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Callable

from ..errors import ConfigError
from ..scenarios.config import Scenario
from ..scenarios.formats import read_scenario
from ..scenarios.resolve import scenario_to_toml


def _xosc(scenario: Scenario, out: Path, stem: str) -> list[Path]:
    from ..scenarios.openscenario.export import export_xosc  # scenariogeneration: the xosc extra

    return list(export_xosc(scenario, out, stem))  # ExportError (a ConfigError): what the subset cannot carry


def _toml(scenario: Scenario, out: Path, stem: str) -> list[Path]:
    out.mkdir(parents=True, exist_ok=True)
    path = out / f"{stem}.toml"
    path.write_text(scenario_to_toml(scenario, header=f"{stem}: resolved by crd scenarios export"))
    return [path]


WRITERS: dict[str, Callable[[Scenario, Path, str], list[Path]]] = {"xosc": _xosc, "toml": _toml}


def add_action(actions: argparse._SubParsersAction) -> None:
    p = actions.add_parser("export", help="write a scenario as OpenSCENARIO + OpenDRIVE (or resolved TOML)")
    p.add_argument("scenario", help="bundled scenario name, TOML or .xosc file")
    p.add_argument("--format", required=True, choices=sorted(WRITERS), help="xosc: .xosc + .xodr; toml: resolved TOML")
    p.add_argument("--out", type=Path, default=Path("."), help="output directory (default: the current one)")
    p.add_argument("--ego", metavar="NAME", help=".xosc input: the entity that is the equipped car")
    p.set_defaults(func=_do_export)


def _do_export(args: argparse.Namespace) -> int:
    from .scenarios import find_scenario

    path = find_scenario(args.scenario)
    scenario = read_scenario(path, args.ego)
    try:
        written = WRITERS[args.format](scenario, args.out, path.stem)
    except ConfigError as exc:
        raise ConfigError(f"{path}: {exc}") from None
    for file in written:
        print(file)
    return 0
