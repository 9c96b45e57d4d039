"""``crd compare DIR DIR [--out DIR]``: the metric differences of two runs and their speed profiles.

Prints, for each pair of runs, every metric of run A and run B and B − A
(runs pair by strategy; two directories of one run each pair those runs,
whatever their strategies; nothing paired is an error), then writes
``speed_profiles.png`` under ``--out`` with both runs' profiles overlaid
(colour: strategy; line style: run).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ..results.compare import differences
from ..results.run_dir import load_run_dir


def add_subparser(subparsers: argparse._SubParsersAction) -> None:
    p = subparsers.add_parser("compare", help="compare two runs' metrics and overlay their speed profiles")
    p.add_argument("run_a", type=Path, help="output directory of the first run (A)")
    p.add_argument("run_b", type=Path, help="output directory of the second run (B)")
    p.add_argument("--out", type=Path, default=Path("out/compare"),
                   help="where the overlay plot goes (default out/compare)")
    p.set_defaults(func=_do_compare)


def _do_compare(args: argparse.Namespace) -> int:
    a, b = load_run_dir(args.run_a), load_run_dir(args.run_b)
    for line in differences(a, b):
        print(line)
    from ..results.plots import overlay_profiles

    args.out.mkdir(parents=True, exist_ok=True)
    png = args.out / "speed_profiles.png"
    same_object = a.object_position_m == b.object_position_m
    overlay_profiles(png, [("A", a.records), ("B", b.records)], a.object_position_m if same_object else None,
                     title=f"A = {a.path.name or a.path} (solid), B = {b.path.name or b.path} (dashed)",
                     object_name=a.object_name)
    if not same_object:
        where = ["none" if d.object_position_m is None else f"{d.object_position_m:g} m" for d in (a, b)]
        print(f"note: the runs' objects differ (A: {where[0]}, B: {where[1]}), so neither is drawn")
    print(f"\nspeed profiles overlaid: {png}")
    return 0
