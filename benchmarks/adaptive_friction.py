"""The four strategies on roads wetter than the ECU's dry peak assumes (issue 14, part 2).

Run: ``python benchmarks/adaptive_friction.py``. The paper scenario with the
plant's ``road_friction`` changed, one ECU parameter set for every row; prints
a Markdown table: outcome per strategy (collision and relative impact speed, or
the final gap and the time the car first comes to rest); then a CCRs-like run
at 45 km/h (a constant-speed approach, which gives no traction evidence).
"""

from __future__ import annotations

import dataclasses
from types import MappingProxyType

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


def ccrs(base, speed_mps: float, mu: float):
    """A UN R152 / Euro NCAP CCRs-like run: cruising at ``speed_mps`` from the start (plant ``v0``)
    toward a stationary car target (ISO 19206-3 length 4.023 m) 60 m ahead."""
    plant = dataclasses.replace(base.plant, road_friction=mu,
                                parameters=MappingProxyType(dict(base.plant.parameters) | {"v0": speed_mps}))
    driver = dataclasses.replace(base.driver, model="cruise", set_speed_mps=speed_mps)
    obj = dataclasses.replace(base.object, position_m=60.0, length_m=4.023)
    scenario = dataclasses.replace(base.scenario, duration_s=15.0)
    return dataclasses.replace(base, scenario=scenario, plant=plant, driver=driver, object=obj)


def table(title: str, rows) -> None:
    print(f"| {title} | " + " | ".join(STRATEGIES) + " |")
    print("|---" * (len(STRATEGIES) + 1) + "|")
    for label, sc, fmu in rows:
        cells = [outcome(run_scenario(sc, fmu, s)) for s in STRATEGIES]
        print(f"| {label} | " + " | ".join(cells) + " |", flush=True)
    print()


def main() -> None:
    base = load_scenario(PAPER_SCENARIO)
    fmu = resolve_fmu(base)
    table("paper scenario, road friction", [
        (mu, dataclasses.replace(base, plant=dataclasses.replace(base.plant, road_friction=mu)), fmu)
        for mu in FRICTIONS])
    table("CCRs-like, cruising at 45 km/h", [(f"mu {mu}", ccrs(base, 12.5, mu), fmu) for mu in (1.0, 0.5)])


if __name__ == "__main__":
    main()
