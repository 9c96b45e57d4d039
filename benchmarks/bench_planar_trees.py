"""The planar loop's speed figures of issue 22 from several source trees side by side, alternating.

Run: ``python benchmarks/bench_planar_trees.py [--repeat N] TREE [TREE ...]`` where each TREE is a worktree
with its own venv (the first the reference of the ratios). Example::

    .venv/bin/python benchmarks/bench_planar_trees.py --repeat 5 /work/main .

Each round starts one process per tree, in turn, from a neutral working directory and without writing
bytecode into the tree. The process imports the tree's ``crd`` and this tree's benchmark code (the same
measurement for every tree) and measures, after one warm-up each:

* the planar scene of ``benchmarks/planar_8_objects.toml`` (:mod:`bench_planar`), whole closed loop in
  process, twice: × real time over wall and over CPU time (issue 21: >= 100×, issue 22: >= 50×);
* the core step with 8 tracks (:mod:`bench_region`'s ``step-8-tracks`` and ``step-8-tracks-urgent``,
  issue 22: <= 100 µs) and today's 1-D step, median µs of 1000 calls each.

Per tree: the median (min..max) over the rounds, and the ratio of the medians to the first tree's.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
from pathlib import Path

from tree_ab import alternate, report, tree_arguments

HERE = Path(__file__).resolve().parent
CHILD = """
import json, sys, time
sys.path.insert(0, {here!r})
from bench_ecu import bench_core
from bench_planar import PLANAR_SCENE, run_once
from bench_region import _median_us, _step_case, _tracks, CORE
from cosim.loop.experiment import resolve_fmu
from cosim.scenarios.loader import load_scenario
from ecu.core import CoreParams
scene = load_scenario(PLANAR_SCENE)
fmu = resolve_fmu(scene)
run_once(scene, fmu)
planar = [run_once(scene, fmu) for _ in range(2)]
calm = _step_case(_tracks(80.0, 20.0), 20.0, 0.05, CORE)
urgent = _step_case(_tracks(58.0, 30.0), 30.0, 0.0, CoreParams(steering_authority=True))
step = {{"1-D": bench_core(1000) * 1e6, "calm": _median_us(calm, 1000), "urgent": _median_us(urgent, 1000)}}
print(json.dumps({{"planar": [(s / w, s / c) for s, w, c in planar], "step": step}}))
"""


def one_round(tree: Path, steps: dict) -> list[tuple[float, float]]:
    """The planar scene's (× real over wall, over CPU) runs in ``tree``'s venv; its core-step medians into
    ``steps``."""
    env = dict(os.environ, PYTHONDONTWRITEBYTECODE="1")
    proc = subprocess.run([str(tree / ".venv" / "bin" / "python"), "-c", CHILD.format(here=str(HERE))],
                          cwd="/tmp", env=env, capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"{tree}: the measurement failed:\n{proc.stderr[-2000:]}")
    result = json.loads(proc.stdout)
    for name, us in result["step"].items():
        steps.setdefault(tree, {}).setdefault(name, []).append(us)
    return [tuple(run) for run in result["planar"]]


def main() -> None:
    trees, repeat = tree_arguments(__doc__.split("\n\n")[0], 5)
    steps: dict = {}
    results = alternate(trees, repeat, lambda tree: one_round(tree, steps))
    report(f"planar scene, 8 objects, in process, {repeat} alternating rounds x 2 runs, x real time", trees,
           results, digits=1)
    print("core step, median us of 1000 calls; median (min..max) over the rounds; ratio to the first tree")
    ref = steps[trees[0]]
    for tree in trees:
        cells = [f"{name} {statistics.median(v):6.1f} ({min(v):.1f}..{max(v):.1f}) "
                 f"x{statistics.median(v) / statistics.median(ref[name]):.2f}" for name, v in steps[tree].items()]
        print(f"  {str(tree):<24} " + "   ".join(cells))


if __name__ == "__main__":
    main()
