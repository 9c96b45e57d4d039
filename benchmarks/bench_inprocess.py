"""The paper run's closed loop in process, from several source trees side by side (issue 20: within 15 %).

Run: ``python benchmarks/bench_inprocess.py [--repeat N] TREE [TREE ...]`` where each TREE is a worktree
with its own venv; the first is the reference of the ratios. Example::

    .venv/bin/python benchmarks/bench_inprocess.py --repeat 5 /work/wt/base0 .

Each round starts one process per tree, alternating, which runs the paper scenario's three strategies
(none, conservative, tightening) once each as :class:`cosim.loop.master.ClosedLoop` with the ECU in
process on the ``crd_inproc`` bus, after one warm-up run, and prints each run's simulated time over its
wall and CPU time (``time.process_time``). Per tree: the median (min..max) × real time over all runs,
and the ratio of the medians to the first tree's, with the load average seen before each round.
"""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

from tree_ab import alternate, report, tree_arguments

#: what each tree's own interpreter runs: only API that every tree since d2cf42d has
CHILD = """
import json, time
from cosim.cli.paper import PAPER_SCENARIO
from cosim.link.ecu_link import EcuOptions
from cosim.loop.experiment import resolve_fmu
from cosim.loop.master import ClosedLoop
from cosim.scenarios.loader import load_scenario
scenario = load_scenario(PAPER_SCENARIO)
fmu = resolve_fmu(scenario)
ClosedLoop(scenario, fmu, "none", ecu=EcuOptions(interface="crd_inproc")).run()
runs = []
for strategy in ("none", "conservative", "tightening"):
    loop = ClosedLoop(scenario, fmu, strategy, ecu=EcuOptions(interface="crd_inproc"))
    cpu0, wall0 = time.process_time(), time.perf_counter()
    sim_s = loop.run().metrics.sim_time_s
    runs.append((sim_s / (time.perf_counter() - wall0), sim_s / (time.process_time() - cpu0)))
print(json.dumps(runs))
"""


def one_round(tree: Path) -> list[tuple[float, float]]:
    """(× real over wall, × real over CPU) of each strategy's run in ``tree``'s venv."""
    proc = subprocess.run([str(tree / ".venv" / "bin" / "python"), "-c", CHILD], cwd=tree,
                          capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"{tree}: the in-process run failed:\n{proc.stderr[-2000:]}")
    return [tuple(run) for run in json.loads(proc.stdout)]


def main() -> None:
    trees, repeat = tree_arguments(__doc__.split("\n\n")[0], 5)
    results = alternate(trees, repeat, one_round)
    report(f"paper loop in process, {repeat} alternating rounds x 3 strategies, x real time", trees,
           results, digits=1)


if __name__ == "__main__":
    main()
