"""``crd scenarios``: the bundled scenarios, and how ``crd run NAME`` finds them.

A scenario argument is a path when that file exists; otherwise a bundled
scenario's name, with or without ``.toml`` (``crd run paper_cyclist``).
"""

from __future__ import annotations

import argparse
import importlib
from pathlib import Path

from ..errors import ConfigError
from ..scenarios.loader import load_scenario

BUNDLED_DIR = Path(__file__).resolve().parents[1] / "scenarios"


def bundled_scenarios() -> list[Path]:
    """The scenario files shipped with crd, sorted by name."""
    return sorted(BUNDLED_DIR.glob("*.toml"))


def find_scenario(arg: str | Path) -> Path:
    """The file ``arg`` names: an existing path, else a bundled scenario of that name."""
    path = Path(arg)
    if path.is_file():
        return path
    stem = path.name[:-5] if path.name.endswith(".toml") else path.name
    bundled = BUNDLED_DIR / f"{stem}.toml"
    if path.parent == Path(".") and bundled.is_file():
        return bundled
    names = ", ".join(p.stem for p in bundled_scenarios())
    raise ConfigError(f"{arg}: scenario file not found, and no bundled scenario of that name"
                      f" (bundled: {names}; see crd scenarios)")


def description(path: Path) -> str:
    """The first sentence of the file's leading comment block."""
    text = []
    for line in path.read_text().splitlines():
        if not line.startswith("#"):
            break
        text.append(line.lstrip("#").strip())
    sentence = " ".join(text).split(". ")[0].rstrip(".")
    return sentence + "." if sentence else ""


#: ``crd scenarios ACTION``: action name -> module with ``add_action(actions)``
ACTIONS: dict[str, str] = {"export": "cosim.cli.scenarios_export"}


def add_subparser(subparsers: argparse._SubParsersAction) -> None:
    p = subparsers.add_parser("scenarios", help="list the bundled scenarios (crd run NAME runs one); "
                                                "crd scenarios export converts one")
    p.set_defaults(func=_do_scenarios)
    actions = p.add_subparsers(dest="action", metavar="ACTION")
    for module in ACTIONS.values():
        importlib.import_module(module).add_action(actions)


def _do_scenarios(args: argparse.Namespace) -> int:  # noqa: ARG001 - no options
    print(f"{'name':<18} {'duration':>8}  {'strategy':<12} objects")
    for path in bundled_scenarios():
        sc = load_scenario(path)
        where = "; ".join(f"{o.name} {o.position_m:g} m ahead, {o.speed_mps:g} m/s" for o in sc.scene_objects())
        print(f"{path.stem:<18} {sc.scenario.duration_s:>6g} s  {sc.ecu.strategy:<12} {where or 'none'}")
        print(f"    {description(path)}")
    print(f"\nfiles in {BUNDLED_DIR}; run one with: crd run NAME [--strategy S] [--out DIR]")
    return 0
