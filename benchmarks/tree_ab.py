"""Side-by-side measurement of several source trees (each a worktree with its own ``.venv``), alternating.

Used by ``bench_paper.py`` (``crd paper`` as a user runs it) and ``bench_inprocess.py`` (the paper loop in
process): each round measures every tree once, in turn, so a neighbour's burst on a shared machine lands
on every tree alike; the report gives per tree the median (min..max) of the wall and CPU figures and the
ratio of the medians to the first tree's, with the load average seen before each measurement.
"""

from __future__ import annotations

import argparse
import os
import statistics
from pathlib import Path
from typing import Callable, Iterable

#: one measurement of one tree: (wall figure, CPU figure) pairs (one per run it made)
Measure = Callable[[Path], Iterable[tuple[float, float]]]


def alternate(trees: list[Path], repeat: int, measure: Measure) -> tuple[dict, dict, list[float]]:
    """``repeat`` rounds of ``measure`` over every tree: (wall by tree, CPU by tree, load averages)."""
    wall: dict[Path, list[float]] = {t: [] for t in trees}
    cpu: dict[Path, list[float]] = {t: [] for t in trees}
    loads: list[float] = []
    for _ in range(max(1, repeat)):
        for tree in trees:
            loads.append(os.getloadavg()[0])
            for w, c in measure(tree):
                wall[tree].append(w)
                cpu[tree].append(c)
    return wall, cpu, loads


def report(title: str, trees: list[Path], results: tuple[dict, dict, list[float]], digits: int = 2) -> None:
    """Print ``title``, the load average and per tree the medians, spreads and ratios to the first tree."""
    wall, cpu, loads = results
    ref = trees[0]

    def spread(values: list[float]) -> str:
        return f"{statistics.median(values):6.{digits}f} ({min(values):.{digits}f}..{max(values):.{digits}f})"

    print(f"{title}; median (min..max); ratio to {ref}")
    print(f"load average (1 min) before each measurement: median {statistics.median(loads):.2f}, "
          f"{min(loads):.2f}..{max(loads):.2f}, on {os.cpu_count()} cores")
    for tree in trees:
        rw = statistics.median(wall[tree]) / statistics.median(wall[ref])
        rc = statistics.median(cpu[tree]) / statistics.median(cpu[ref])
        print(f"  {str(tree):<24} wall {spread(wall[tree])} x{rw:.2f}   CPU {spread(cpu[tree])} x{rc:.2f}")


def tree_arguments(description: str, repeat: int) -> tuple[list[Path], int]:
    """The command line both tree benchmarks take: the worktrees (the first the reference) and ``--repeat``."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("trees", nargs="+", type=Path, help="worktrees with a venv; the first is the reference")
    parser.add_argument("--repeat", type=int, default=repeat, help=f"rounds (default {repeat})")
    args = parser.parse_args()
    return [t.resolve() for t in args.trees], args.repeat
