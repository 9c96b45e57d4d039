"""The four strategies on roads wetter than the ECU's dry peak assumes (issue 14, part 2).

Run: ``python benchmarks/adaptive_friction.py``. The paper scenario with the
plant's ``road_friction`` changed, one ECU parameter set for every row; prints
a Markdown table: outcome per strategy (collision and relative impact speed, or
the final gap) and, for ``adaptive``, the time to stop (s) on the dry road.
"""

from __future__ import annotations

import dataclasses

from cosim.cli.paper import PAPER_SCENARIO
from cosim.loop.experiment import resolve_fmu
from cosim.loop.master import run_scenario
from cosim.scenarios.loader import load_scenario

STRATEGIES = ("none", "conservative", "tightening", "adaptive")
FRICTIONS = (1.0, 0.9, 0.8, 0.6, 0.3)


def outcome(record) -> str:
    m = record.metrics
    return f"hits at {m.impact_speed_mps:.1f} m/s" if m.collided else f"stops {m.final_gap_m:.1f} m short"


def main() -> None:
    base = load_scenario(PAPER_SCENARIO)
    fmu = resolve_fmu(base)
    print("| road friction | " + " | ".join(STRATEGIES) + " |")
    print("|---" * (len(STRATEGIES) + 1) + "|")
    for mu in FRICTIONS:
        sc = dataclasses.replace(base, plant=dataclasses.replace(base.plant, road_friction=mu))
        cells = [outcome(run_scenario(sc, fmu, s)) for s in STRATEGIES]
        print(f"| {mu} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
