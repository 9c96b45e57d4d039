"""``crd fleet SCENE [--strategy S] [--set VEHICLE=S ...] [--out DIR]``: several equipped cars in one scene.

``SCENE`` is a fleet TOML file (:mod:`cosim.fleet.config`) or the name of a bundled one (``crd fleet
--list``). Each vehicle has its own plant FMU, driver, ECU and CAN bus; ``--ecu process`` starts one ECU
process per vehicle. ``--strategy`` gives every car one strategy; ``--set west=none`` one car its own
(repeatable; after ``--strategy``). Writes each vehicle's files under ``DIR/<vehicle>/``, the world's
``world.csv``, ``metrics.json`` with the dance figures, ``speeds.png`` and ``report.md``
(:mod:`cosim.fleet.output`).

Exit status: 0 without contact, 3 with one (the scene's ``collisions``), 1 on an error (the results up to
it written), 130 / 143 when interrupted.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..errors import ConfigError
from ..fleet.config import load_fleet
from ..fleet.report import dance_table, scene_line
from ..scenarios.config import STRATEGIES
from ecu.core.params import CoreParams
from ecu.settings import keys
from .ecu_options import add_ecu_arguments, ecu_options
from .progress import end_progress, progress_printer
from .scenarios import description
from .signals import interruptible

SCENES_DIR = Path(__file__).resolve().parent.parent / "fleet" / "scenes"
EXIT_COLLIDED = 3
#: the way-out rules, as [ecu] way_out declares them
WAY_OUT = keys(CoreParams)["way_out"].declared.choices


def add_subparser(subparsers: argparse._SubParsersAction) -> None:
    p = subparsers.add_parser("fleet", help="several equipped cars in one scene: the reciprocal dance between them")
    p.add_argument("scene", nargs="?", help="fleet TOML file, or the name of a bundled one (--list)")
    p.add_argument("--list", action="store_true", help="list the bundled fleet scenes and exit")
    p.add_argument("--strategy", choices=STRATEGIES, help="every vehicle's strategy (default: each its [ecu])")
    p.add_argument("--way-out", choices=WAY_OUT, help="every vehicle's [ecu] way_out (default: each its own)")
    p.add_argument("--set", action="append", default=[], metavar="VEHICLE=STRATEGY",
                   help="one vehicle's strategy; repeatable")
    p.add_argument("--out", type=Path, default=Path("out/fleet"), help="output directory (default out/fleet)")
    p.add_argument("--can-log", action="append", default=[], metavar="NAME",
                   help="another CAN log per vehicle besides can.blf; repeatable")
    add_ecu_arguments(p, realtime=False)
    p.set_defaults(func=interruptible(_do_fleet))


def bundled_scenes() -> list[Path]:
    return sorted(SCENES_DIR.glob("*.toml"))


def find_scene(arg: str) -> Path:
    """The file ``arg`` names, else the bundled scene of that name."""
    path = Path(arg)
    if path.is_file():
        return path
    bundled = SCENES_DIR / f"{path.name.removesuffix('.toml')}.toml"
    if path.parent == Path(".") and bundled.is_file():
        return bundled
    names = ", ".join(p.stem for p in bundled_scenes())
    raise ConfigError(f"{arg}: fleet file not found, and no bundled fleet scene of that name (bundled: {names})")


def strategies_of(args: argparse.Namespace, names: tuple[str, ...]) -> dict[str, str]:
    """Vehicle -> strategy from ``--strategy`` and ``--set``; a bad ``--set`` is a one-line error."""
    out = {n: args.strategy for n in names} if args.strategy else {}
    for item in args.set:
        name, _, strategy = item.partition("=")
        if name not in names:
            raise ConfigError(f"--set {item}: no vehicle {name!r} (vehicles: {', '.join(names)})")
        if strategy not in STRATEGIES:
            raise ConfigError(f"--set {item}: expected one of {', '.join(STRATEGIES)}, got {strategy!r}")
        out[name] = strategy
    return out


def _do_fleet(args: argparse.Namespace) -> int:
    from ..fleet.output import run_fleet

    if args.list:
        for path in bundled_scenes():
            print(f"{path.stem:<24} {description(path)}")
        return 0
    if args.scene is None:
        raise ConfigError("crd fleet: expected a SCENE (a fleet TOML file or a bundled name; --list shows them)")
    path = find_scene(args.scene)
    fleet = load_fleet(path, args.way_out)
    strategies = strategies_of(args, fleet.names)
    print(f"crd fleet {path} ({len(fleet.vehicles)} vehicles) -> {args.out}", file=sys.stderr)
    record, dance = run_fleet(fleet, args.out, strategies, ecu_options(args), args.can_log,
                              show=progress_printer(fleet.fleet.name))
    end_progress()
    print(dance_table(dance))
    print(f"scene: {scene_line(dance)}")
    errors = [r.error for r in record.records if r.error]
    if errors:
        raise RuntimeError(f"{errors[0]} (results up to then written to {args.out})")
    print(f"report: {args.out / 'report.md'}")
    return EXIT_COLLIDED if dance.collisions else 0
