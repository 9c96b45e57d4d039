"""``crd paper`` as a user runs it, from several source trees side by side (issue 20: <= 2.5 s wall).

Run: ``python benchmarks/bench_paper.py [--repeat N] TREE [TREE ...]`` where each TREE is a worktree
with its own venv (``TREE/.venv/bin/crd``); the first is the reference of the ratios. Example::

    .venv/bin/python benchmarks/bench_paper.py --repeat 9 . /work/main /work/wt/base0

Each round runs ``TREE/.venv/bin/crd paper --out <tmp>`` once per tree, alternating, so a neighbour's
burst on a shared machine lands on every tree alike. Per tree: the median (min..max) of the wall time
and of the CPU time (user + sys of ``crd`` and every process it started, from ``RUSAGE_CHILDREN``:
less disturbed by neighbours than the wall time, and the sum of the work on both cores), each tree's
ratio to the first, and the load average seen before each run (so a noisy run shows itself).
"""

from __future__ import annotations

import resource
import subprocess
import tempfile
import time
from pathlib import Path

from tree_ab import alternate, report, tree_arguments


def crd_paper(tree: Path) -> tuple[float, float]:
    """(wall s, CPU s of ``crd paper`` and its children) from ``tree``'s venv; an exit code other than 0 stops."""
    crd = tree / ".venv" / "bin" / "crd"
    with tempfile.TemporaryDirectory() as out:
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        proc = subprocess.run([str(crd), "paper", "--out", out], capture_output=True, text=True)
        wall = time.perf_counter() - t0
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        raise SystemExit(f"{crd} paper exited with {proc.returncode}:\n{proc.stderr[-2000:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def main() -> None:
    trees, repeat = tree_arguments(__doc__.split("\n\n")[0], 7)
    for tree in trees:
        crd_paper(tree)  # warm up: the FMU cache, the page cache
    results = alternate(trees, repeat, lambda tree: [crd_paper(tree)])
    report(f"crd paper, {repeat} alternating rounds, s", trees, results)


if __name__ == "__main__":
    main()
