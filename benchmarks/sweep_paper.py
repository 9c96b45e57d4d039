"""Parameter sweep for the paper scenario: which shared ECU/plant values make the claims hold.

Run: ``python benchmarks/sweep_paper.py``. Prints one line per combination with
each claim's PASS/FAIL. Same parameters for all three strategies.
"""

from __future__ import annotations

import dataclasses
import itertools

from cosim.cli.paper import PAPER_SCENARIO
from cosim.loop.experiment import resolve_fmu
from cosim.loop.master import run_scenario
from cosim.results.paper_claims import REQUIRED, evaluate
from cosim.scenarios.loader import load_scenario

GRID = {
    "actuation_latency_s": (0.1, 0.2, 0.3),
    "proximity_margin_m": (6.0, 10.0, 14.0),
}


def main() -> None:
    base = load_scenario(PAPER_SCENARIO)
    fmu = resolve_fmu(base)
    for values in itertools.product(*GRID.values()):
        sc = dataclasses.replace(base, ecu=dataclasses.replace(base.ecu, **dict(zip(GRID, values))))
        recs = [run_scenario(sc, fmu, s) for s in REQUIRED]
        claims = evaluate(recs)
        summary = " ".join(f"{c.number}:{'P' if c.passed else 'F'}" for c in claims)
        inv = [r.metrics.contingency_invocations for r in recs]
        gaps = [None if r.metrics.collided else round(r.metrics.final_gap_m, 1) for r in recs]
        print(dict(zip(GRID, values)), summary, "inv", inv, "final gaps", gaps)


if __name__ == "__main__":
    main()
