"""The four strategies on roads wetter than the ECU's dry peak assumes (issue 14, part 2).

Run: ``python benchmarks/adaptive_friction.py``. The paper scenario with the
plant's ``road_friction`` changed, one ECU parameter set for every row; prints
a Markdown table: outcome per strategy (collision and relative impact speed, or
the final gap and the time the car first comes to rest).
"""

from __future__ import annotations

import dataclasses

from cosim.cli.paper import PAPER_SCENARIO
from cosim.loop.experiment import resolve_fmu
from cosim.loop.master import run_scenario
from cosim.scenarios.loader import load_scenario

STRATEGIES = ("none", "conservative", "tightening", "adaptive")
FRICTIONS = (1.0, 0.9, 0.8, 0.6)  # at 0.3 the spinning wheels keep the car below 11 m/s for all 40 s


def stop_time_s(record) -> float:
    """First time (s) the car is at rest after its top speed."""
    t, v = record.column("time_s"), record.column("speed_mps")
    top = max(range(len(v)), key=v.__getitem__)
    return next((t[i] for i in range(top, len(v)) if v[i] <= 0.01), float("nan"))


def outcome(record) -> str:
    m = record.metrics
    if m.collided:
        return f"hits at {m.impact_speed_mps:.1f} m/s"
    return f"stops {m.final_gap_m:.1f} m short at {stop_time_s(record):.2f} s"


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
